"""Two bodies (dual mortar) on the iterative path (issue 33 point 1):
the active set method on the nodewise problem in v = Tu, each Newton
system by CG with smoothed aggregation of K̃ = T⁻ᵀKT⁻¹ whose near-null
space is each body's rigid-body modes transformed, T B
(solver.contact.two_body.near_null_space).

Independent reference: the factorisation path (condensed onto the slave
nodes, another algorithm and another linear solver) on the same problems,
assembled here without SfePy (2D: the Hertz cylinders and the
non-matching patch; 3D: the non-matching stacked boxes, both slave
orders) and on the two unequal spheres exported by SfePy (a/h ≈ 6)."""

import numpy as np
import pytest

from solver import solve
from solver.contact import TwoBodyMap
from solver.linalg import amg
from tet_two_body import stacked_boxes
from tri_elasticity import stacked_blocks, two_cylinders

pytestmark = pytest.mark.skipif(not amg.available(),
                                reason="pyamg not installed (.[amg])")


def cylinders():
    return two_cylinders((1.0, 1.5), ((1.0, 0.3), (2.0, 0.25)),
                         squeeze=0.01)[0]


def patch2d():
    return stacked_blocks(n_upper=(40, 20), n_lower=(90, 30),
                          materials=((1.0, 0.3), (3.0, 0.2)),
                          slave="upper")[0]


def boxes(slave):
    return lambda: stacked_boxes(slave=slave)[0]


@pytest.mark.parametrize("make", [cylinders, patch2d, boxes("upper"),
                                  boxes("lower")],
                         ids=["cylinders2d", "patch2d", "boxes3d-upper",
                              "boxes3d-lower"])
def test_two_bodies_amg_equals_the_factorisation(make):
    """The same u as the factorisation to 1e-7 (relative; measured
    2e-11–6e-11), verified on every node, the same contact set, on a
    hierarchy of at least two levels."""
    problem = make()
    direct = solve(problem)
    iterative = solve(problem, backend="amg")
    assert iterative.success and iterative.verification["passed"], \
        iterative.message
    assert iterative.linear_solver == "amg"
    assert iterative.engine["levels"] >= 2
    error = np.linalg.norm(iterative.u - direct.u) / np.linalg.norm(direct.u)
    assert error < 1e-7
    assert np.array_equal(iterative.in_contact, direct.in_contact)


def test_auto_takes_amg_for_two_bodies_when_the_factor_does_not_fit(
        monkeypatch):
    """``backend="auto"`` on two bodies: with the machine's memory it
    factorises; with (pretend) 100 kB available the AMG path runs, says
    why, and gives the factorisation's u (1e-7, relative)."""
    problem = patch2d()
    direct = solve(problem)
    assert direct.linear_solver != "amg"
    monkeypatch.setattr(amg, "available_memory", lambda: 1e5)
    chosen = solve(problem)
    assert chosen.linear_solver == "amg" and chosen.success
    assert "AMG" in chosen.linear_solver_reason
    error = np.linalg.norm(chosen.u - direct.u) / np.linalg.norm(direct.u)
    assert error < 1e-7


def test_near_null_space_is_the_kernel_of_the_glued_stiffness():
    """K̃ (T B) = T⁻ᵀ K B: zero on the rows of nodes away from the
    supports (a rigid motion of one body has no strain), for the 6 modes
    of each of the two boxes; the columns are independent."""
    problem = stacked_boxes()[0]
    equivalent = TwoBodyMap(problem).equivalent
    B = equivalent.near_null_space()
    assert B.shape == (problem.n_dofs, 12)
    assert np.linalg.matrix_rank(B) == 12
    KB = equivalent.K @ B
    node = problem.dof_map[:, 0]
    held = np.bincount(node, minlength=len(problem.nodes)) < 3
    cells = np.asarray(problem.cells)
    near = np.zeros(len(problem.nodes), bool)  # shares a cell with a
    near[cells[held[cells].any(axis=1)]] = True  # prescribed DOF
    inner = ~near[node]
    assert inner.sum() > 0.1 * problem.n_dofs
    scale = np.abs(equivalent.K).sum(axis=1).max() * np.abs(B).max()
    assert np.abs(KB[inner]).max() < 1e-10 * scale
