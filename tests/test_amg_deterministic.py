"""The AMG path gives the same iterates from run to run (bit for bit):
pyamg smooths the tentative prolongator with ω = 4/(3ρ(D⁻¹A)), ρ
estimated by Lanczos/Arnoldi from ``np.random.rand``, so an unseeded
hierarchy, and with it every CG iterate and, on a nearly singular case,
the active sets, changed with the state of NumPy's global generator
(solver/linalg/amg.py ``seeded``; benchmarks/README.md, the two Hertz
cylinders with friction).

Independent reference: the run itself under another state of the
global generator (the property asserted is equality, not a value), and
the caller's random stream, which the build must leave as it found it."""

import hashlib

import numpy as np
import pytest

import solver
from solver.linalg import amg
from tri_elasticity import floor_block

pytestmark = pytest.mark.skipif(not amg.available(),
                                reason="pyamg not installed (.[amg])")


def _digest(*arrays):
    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(a, float).tobytes())
    return h.hexdigest()


def test_hierarchy_is_the_same_under_any_global_random_state():
    """Two builds of K's hierarchy after different seeds of the global
    generator: every level's operator and prolongator identical bit for
    bit, one V-cycle identical, and the global stream after the build
    the one it would have been without it."""
    problem = floor_block(n=(40, 20))
    modes = amg.rigid_body_modes(problem.nodes[problem.dof_map[:, 0]],
                                 problem.dof_map[:, 1])
    built, after = [], []
    for seed in (1, 2):
        np.random.seed(seed)
        ml = amg.Multigrid(problem.K, modes, singular=True)
        after.append(np.random.rand())
        np.random.seed(seed)
        assert after[-1] == np.random.rand()  # the caller's stream kept
        r = np.linspace(-1.0, 1.0, problem.n_dofs)
        built.append(_digest(*[A.toarray() for A in ml.operators()],
                             *[P.toarray() for P in ml.prolongators()],
                             ml(r)))
    assert ml.levels >= 2
    assert built[0] == built[1]


@pytest.mark.parametrize("load, friction, options", [
    ((0.0, -1.0), None, {}),
    ((0.2, -1.0), 0.3, dict(coulomb="implicit", steps=2))],
    ids=["frictionless", "implicit friction"])
def test_floating_block_same_iterates_run_to_run(load, friction, options):
    """The floating block (held by contact only, K singular) under its
    weight, or pushed sideways within the cone with friction, on AMG,
    solved twice after different global seeds: the same u, contact and
    stick sets and the same CG iteration counts, bit for bit."""
    problem = floor_block(n=(40, 20), load=load)
    runs = []
    for seed in (1, 2):
        np.random.seed(seed)
        r = solver.solve(problem, friction=friction, backend="amg",
                         **options)
        assert r.success, r.message
        runs.append(r)
    a, b = runs
    assert _digest(a.u) == _digest(b.u)
    np.testing.assert_array_equal(a.in_contact, b.in_contact)
    if friction:
        np.testing.assert_array_equal(a.stick, b.stick)
    counts = [[rec["krylov"] for rec in r.records] if friction
              else r.history["krylov"] for r in runs]
    assert counts[0] and counts[0] == counts[1]
