"""Coulomb friction on the iterative path (issue 33 point 1): each load
step by the primal–dual active set method, its Newton systems by
AMG-preconditioned projected CG (``backend="amg"``,
:mod:`solver.contact.friction.active_set`).

Independent references: the factorisation path (the default: condensed
onto Γc, semismooth Newton with a line search on the projection
formulation, dense or sparse direct Newton systems) on the thesis's §4
block (2D) and the a/h 4 Hertz sphere (3D, rollers on its symmetry
planes); Coulomb's law at full slip (the total friction force is f_c times
the normal force of the bound, against the drag) and global equilibrium
at full stick (the friction force balances the drag: K annihilates the
rigid translations) on a dragged 3D block.
"""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

from test_amg import hertz_sphere  # noqa: E402
from test_friction3d import dragged_block, friction_vector  # noqa: E402
from solver import solve  # noqa: E402
from solver.linalg import amg  # noqa: E402
from solver.problem import load_problem  # noqa: E402

pytestmark = pytest.mark.skipif(not amg.available(),
                                reason="pyamg not installed (.[amg])")


@pytest.fixture(scope="module")
def block_454(exported):
    return load_problem(exported(454)[0])


@pytest.fixture(scope="module")
def sphere_4(tmp_path_factory):
    return hertz_sphere(tmp_path_factory, 4)


def same_answer(iterative, direct):
    """Both converged and verified on every node; u of every step within
    1e-7 (relative), the same contact, stick and slip sets in every step;
    returns the largest relative difference of u."""
    for result in (iterative, direct):
        assert result.success, result.message
        assert result.verification["passed"]
    assert iterative.linear_solver == "amg" != direct.linear_solver
    assert iterative.steps_completed == direct.steps_completed
    worst = 0.0
    for a, b in zip(iterative.displacement, direct.displacement):
        worst = max(worst, np.linalg.norm(a - b) / np.linalg.norm(b))
    assert worst < 1e-7
    for key in ("in_contact", "stick", "slip"):
        for a, b in zip(getattr(iterative, key), getattr(direct, key)):
            assert np.array_equal(a, b), key
    return worst


@pytest.mark.parametrize("fc", [0.05, 0.3])
def test_block_2d_equals_the_factorisation(block_454, fc):
    """The thesis's block, 10 load steps, lagged bound: the same u and
    sets as the factorisation path."""
    direct = solve(block_454, friction=fc, steps=10)
    iterative = solve(block_454, friction=fc, steps=10, backend="amg")
    same_answer(iterative, direct)
    assert iterative.slip[-1].any()
    records = iterative.records
    assert all(r["krylov"] >= r["njev"] for r in records)


def test_sphere_3d_equals_the_factorisation(sphere_4, monkeypatch):
    """The a/h 4 Hertz sphere (rollers on x = 0 and y = 0), f_c = 0.3,
    10 load steps: the same u and sets as the factorisation path, with
    stick and slip nodes both present; the AMG hierarchy of K is built
    once for all steps."""
    built = []
    original = amg.Multigrid.__init__

    def counted(self, *args, **kwargs):
        built.append(1)
        original(self, *args, **kwargs)

    monkeypatch.setattr(amg.Multigrid, "__init__", counted)
    direct = solve(sphere_4, friction=0.3, steps=10)
    iterative = solve(sphere_4, friction=0.3, steps=10, backend="amg")
    same_answer(iterative, direct)
    assert iterative.stick[-1].sum() >= 5 and iterative.slip[-1].sum() >= 2
    assert len(built) == 1
    assert iterative.engine["levels"] >= 2
    assert max(r["njev"] for r in iterative.records) <= 10


def full_slip(theta, coulomb="lagged"):
    """A block pressed, then dragged along (cos θ, sin θ, 0) on the AMG
    path with ``coulomb``: every node in contact slips, Σ D g_t = f_c ×
    the bound's normal force to 1e-8, opposite to the drag; the
    factorisation's u to 1e-7. Returns (the result, f_c, the bound's
    total normal force Σ D b / f_c)."""
    angle = np.radians(theta)
    problem, geometry, _, _ = dragged_block(angle, 0.05)
    fc = 0.3
    result = solve(problem, friction=fc, geometry=geometry, backend="amg",
                   coulomb=coulomb, tol=1e-12)
    assert result.success, result.message
    assert result.verification["passed"]
    contact = result.in_contact[-1]
    assert contact.sum() >= 0.8 * len(geometry.index)
    assert np.array_equal(result.slip[-1], contact)
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()
    normal_total = (lumped * result.friction_bound[-1]).sum()
    vector = friction_vector(problem, geometry, result)
    size = np.linalg.norm(vector)
    assert abs(size / normal_total - 1) <= 1e-8
    drag = np.array([np.cos(angle), np.sin(angle), 0.0])
    assert vector @ drag / size <= -(1 - 1e-6)
    direct = solve(problem, friction=fc, geometry=geometry, tol=1e-12,
                   coulomb=coulomb)
    assert np.linalg.norm(result.u - direct.u) \
        <= 1e-7 * np.linalg.norm(direct.u)
    return result, fc, normal_total / fc


@pytest.mark.parametrize("theta", [30.0, 120.0])
def test_full_slip_friction_is_fc_times_normal_force(theta):
    """A block pressed, then dragged along (cos θ, sin θ, 0): every node
    in contact slips and Σ D g_t = f_c × the bound's normal force to 1e-8,
    opposite to the drag; the factorisation's u to 1e-7."""
    full_slip(theta)


def test_full_stick_balances_the_drag():
    """A small drag: every node in contact sticks and the friction force
    balances the force on the top face (global equilibrium)."""
    angle = np.radians(30.0)
    problem, geometry, K, top = dragged_block(angle, 1e-5, steps=(1, 2))
    result = solve(problem, friction=0.3, geometry=geometry, backend="amg",
                   tol=1e-12)
    assert result.success, result.message
    contact = result.in_contact[-1]
    assert contact.sum() >= 0.8 * len(geometry.index)
    assert np.array_equal(result.stick[-1], contact)
    internal = (K @ result.displacement[-1].ravel()).reshape(-1, 3)
    drag = internal[top, :2].sum(axis=0)
    vector = friction_vector(problem, geometry, result)
    np.testing.assert_allclose(-vector[:2], drag, rtol=1e-8,
                               atol=1e-10 * np.abs(drag).max())


def test_auto_takes_amg_for_friction_when_the_factor_does_not_fit(
        block_454, monkeypatch):
    """``backend="auto"`` with friction, both bounds: with (pretend)
    100 kB available the iterative path runs and says why, with the
    factorisation's answer (the implicit bound by GMRES)."""
    default = solve(block_454, friction=0.3, steps=5)
    assert default.linear_solver != "amg"
    monkeypatch.setattr(amg, "available_memory", lambda: 1e5)
    chosen = solve(block_454, friction=0.3, steps=5)
    assert chosen.linear_solver == "amg" and chosen.success
    assert "AMG" in chosen.linear_solver_reason
    assert np.linalg.norm(chosen.u - default.u) < \
        1e-7 * np.linalg.norm(default.u)
    monkeypatch.undo()
    implicit = solve(block_454, friction=0.3, steps=5, coulomb="implicit")
    assert implicit.linear_solver != "amg" and implicit.success
    monkeypatch.setattr(amg, "available_memory", lambda: 1e5)
    chosen = solve(block_454, friction=0.3, steps=5, coulomb="implicit")
    assert chosen.linear_solver == "amg" and chosen.success
    assert np.linalg.norm(chosen.u - implicit.u) < \
        1e-7 * np.linalg.norm(implicit.u)
