"""Rigid limit (issue 19): the thesis's block against an elastic body
shaped like its parabola, E of that body 10², 10⁴, 10⁶ × the block's,
tends to the rigid obstacle (both assembled here, tests/tri_elasticity.py).

Two references. (1) The same mortar coupling against a master that does
not move (every DOF prescribed): the difference in u falls as 1/E, the
compliance of the obstacle body. (2) The existing rigid-obstacle solver
with gaps along the body's normals (``gap="body"``, the mortar's normal
n_j = (1, 0) on the straight edge): the difference is that compliance plus
the O(h²) difference between the weighted gap g̃_j / D_jj (the gap
averaged with ψ_j) and the nodal gap, h²/12 × the parabola's x'' = 0.01
(measured at the contact nodes: 3.3e-3, 9.2e-4, 2.1e-4 on the 118, 454
and 1878 blocks). ``gap="obstacle"`` measures along the obstacle's normal
instead, another constraint (1 % apart in u, not shrinking with h)."""

import numpy as np
import pytest

from solver.contact import solve_frictionless
from solver.contact.two_body import solve_two_body
from tri_elasticity import block_on_parabola_body, thesis_block


def relative(a, b):
    return np.abs(a - b).max() / np.abs(b).max()


@pytest.fixture(scope="module")
def block_1878():
    rigid, _ = thesis_block("block_1878.mesh")
    reference = solve_frictionless(rigid, gap="body", tol=1e-12)
    fixed = solve_two_body(block_on_parabola_body(
        1, mesh="block_1878.mesh", rigid=True), tol=1e-12)
    assert reference.success and fixed.success
    return len(rigid.nodes), reference, fixed


def test_rigid_limit(block_1878):
    """×10⁴: ≤ 1e-3 relative to the rigid solver (measured 7.7e-4) and
    ≤ 1e-5 to the fixed master (measured 4.8e-6); ×10², ×10⁶ to the fixed
    master 100 times more and less (1/E)."""
    n, reference, fixed = block_1878
    to_fixed = {}
    for ratio in (1e2, 1e4, 1e6):
        result = solve_two_body(block_on_parabola_body(
            ratio, mesh="block_1878.mesh"), tol=1e-12)
        assert result.success
        u = result.displacement[:n]
        to_fixed[ratio] = relative(u, fixed.displacement[:n])
        if ratio == 1e4:
            assert relative(u, reference.displacement) <= 1e-3
            assert result.n_contact == reference.n_contact
    assert to_fixed[1e4] <= 1e-5
    assert 90 < to_fixed[1e2] / to_fixed[1e4] < 110
    assert 90 < to_fixed[1e4] / to_fixed[1e6] < 110


def test_newton_counts_next_to_the_rigid_case(block_1878):
    """The mortar solve takes the rigid solve's Newton iterations (φ_min,
    nested start; measured 8 and 8)."""
    _, reference, fixed = block_1878
    assert abs(fixed.nit - reference.nit) <= 1
