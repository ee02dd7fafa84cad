"""Coulomb friction on candidate nodes with roller nodes (nodes on symmetry
planes, one or no free tangent; issue 18, ROLL18B).

References, each independent of what is tested:

* the same run condensed onto every DOF of every contact node
  (``candidates=False``: no screening) and the run on the full sparse
  system (``condense=False``: no condensation, no traction elimination,
  SciPy's sparse LU of FrictionSystem's whole Jacobian);
* for the Newton direction with the tractions eliminated
  (:mod:`solver.contact.friction.disc`), the sparse Jacobian that
  :class:`~solver.contact.friction.system.FrictionSystem` assembles (its
  roller rows are checked against finite differences in
  tests/test_rollers.py);
* the whole (mirrored) model, in tests/test_rollers.py, which now runs the
  half model on candidates by default.

Problems: tests/test_rollers.py's half and quarter blocks on a paraboloid,
pressed, then dragged along the plane x = 0 (a load path: rollers stick
and slip along y).
"""

import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

sys.path.insert(0, str(Path(__file__).resolve().parent))

from test_friction_candidates import assert_same_run  # noqa: E402
from test_rollers import FC, dragged_3d  # noqa: E402
from solver import solve_friction  # noqa: E402
from solver.contact import contact_geometry

RUN = dict(formulation="projection", tol=1e-13)


@pytest.fixture(scope="module")
def problems():
    return {part: dragged_3d(part, 0.02) for part in ("half", "quarter")}


def rollers_of(problem):
    """Γc positions of the roller nodes (a Dirichlet component, in
    contact's geometry)."""
    geometry = contact_geometry(problem, "obstacle", rollers=True)
    return geometry.index[geometry.rollers]


@pytest.mark.parametrize("coulomb", ["lagged", "implicit"])
@pytest.mark.parametrize("method", ["min", "fb"])
@pytest.mark.parametrize("part", ["half", "quarter"])
def test_candidates_with_rollers_equal_every_contact_dof(problems, part,
                                                         method, coulomb):
    """The default 3D path (candidates, rollers included) = every DOF of
    Γc, to 1e-10 in every step's fields; rollers touch (so they are among
    the candidates) and fewer nodes than Γc are condensed."""
    problem = problems[part]
    kw = dict(RUN, method=method, coulomb=coulomb)
    result = solve_friction(problem, FC, **kw)
    reference = solve_friction(problem, FC, candidates=False, **kw)
    assert result.condensation == "candidates"
    assert "condensation" not in reference
    rolling = rollers_of(problem)
    assert result.in_contact[-1][rolling].any()
    assert result.candidates["n_candidates"] < len(rolling) + (
        ~np.isin(np.arange(problem.n_contact), rolling)).sum()
    assert result.verification["passed"]
    assert_same_run(result, reference)


def test_candidates_with_rollers_equal_the_full_system(problems):
    """... and the run on the full sparse system (no condensation)."""
    problem = problems["quarter"]
    kw = dict(RUN, method="min", coulomb="implicit")
    result = solve_friction(problem, FC, **kw)
    reference = solve_friction(problem, FC, condense=False, **kw)
    assert_same_run(result, reference, 1e-9)


def test_candidates_with_rollers_grow_and_restart(problems):
    """margin = 0 (the frictionless contact set at the final load): the
    dragged half touches outside it earlier, the set grows, the run
    restarts, and it is still every DOF's run to 1e-10 (non-candidate
    rollers' tangential displacements included)."""
    problem = problems["half"]
    kw = dict(RUN, method="min")
    result = solve_friction(problem, FC, margin=0.0, **kw)
    reference = solve_friction(problem, FC, candidates=False, **kw)
    assert result.candidates["enlarged"] >= 1
    assert_same_run(result, reference)


@pytest.mark.parametrize("coulomb", ["lagged", "implicit"])
@pytest.mark.parametrize("part", ["half", "quarter"])
def test_disc_direction_with_rollers_solves_the_whole_jacobian(
        problems, part, coulomb):
    """DiscJacobian with rollers: its direction solves J d = −F of the
    sparse J that FrictionSystem assembles (one equilibrium row per free
    tangent, g_c ≡ 0 along e_c) to round-off, and rmatvec is JᵀF, at an
    iterate where rollers stick, slip near the disc's edge and slip far
    from it (the last take dĝ from their own rows)."""
    from solver.contact.friction.disc import DiscSystem
    from solver.contact.friction.projection import ProjectionSystem
    from solver.contact.strategies.reduction import condense_onto_contact

    problem = problems[part]
    geometry = contact_geometry(problem, "obstacle", rollers=True)
    condensation, local = condense_onto_contact(problem, geometry, "superlu")
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()[geometry.index]
    system = DiscSystem(condensation.S, condensation.load(problem.f)[0],
                        local, lumped, FC, coulomb, 100.0, 100.0)
    assert system.dense and system.rollers
    rng = np.random.default_rng(18)
    m, n, free = system.m, system.n, system.t_free
    system.set_step(rng.normal(0, 1e-3, n), 0.5, rng.uniform(0.5, 2, m))
    du = rng.normal(0, 1e-4, n)
    b = system.bound(system._force(du), False)[0]
    factor = np.array([0.5, 1.5, 3.0])[np.arange(m) % 3] * np.maximum(b, .1)
    w = rng.normal(size=(m, 2)) * free.reshape(m, 2)  # 0 along e_c
    size = np.linalg.norm(w, axis=1)
    w *= np.divide(factor, size, out=np.zeros(m), where=size > 0)[:, None]
    g = w.ravel() + system.c_t * system.tangential(system.R @ du)
    x = np.concatenate([du, g / system.c_t])
    jac = system.jacobian(x)
    rolling = ~free.reshape(m, 2).all(axis=1)
    one_free = free.reshape(m, 2).any(axis=1) & rolling
    slip = ~np.all(jac.P == np.eye(2) * free.reshape(m, 1, 2), axis=(1, 2))
    assert (one_free & slip).any() and (one_free & ~slip).any()
    assert (one_free & jac.own).any() and (one_free & slip & ~jac.own).any()
    JE, JA, JB = ProjectionSystem.jacobian(system, x)
    # DiscSystem's projection rows are D(g − P(w)) (nodal forces): its
    # residual, Jacobian and stopping measure are ProjectionSystem's so
    rows = sp.diags(np.concatenate([np.ones(JE.shape[0] - system.mt),
                                    system.lumped_t]))
    mine, theirs = system.residual(x), ProjectionSystem.residual(system, x)
    np.testing.assert_array_equal(mine[0], rows @ theirs[0])
    assert system.error(*mine) == pytest.approx(
        ProjectionSystem.error(system, *theirs), rel=1e-14)
    assert JE.shape[0] == free.sum() + system.mt
    for wa, wb in [(rng.uniform(-1, 0, m), rng.uniform(-1, 0, m)),
                   ((rng.random(m) < 0.5) * 1.0, None)]:
        wb = 1.0 - wa if wb is None else wb
        J = sp.vstack([rows @ JE, sp.diags(wa) @ JA
                       + sp.diags(wb) @ JB]).toarray()
        F = rng.normal(size=J.shape[0])
        combined = jac.combine(wa, wb)
        d = combined.direction(F)
        assert np.linalg.norm(J @ d + F) <= 1e-10 * (
            np.linalg.norm(J) * np.linalg.norm(d) + np.linalg.norm(F))
        np.testing.assert_allclose(combined.rmatvec(F), J.T @ F,
                                   rtol=0, atol=1e-12 * np.abs(J).max()
                                   * np.abs(F).sum())


@pytest.mark.parametrize("method, coulomb", [
    ("fb", "implicit"), ("fb", "lagged"), ("min", "lagged")])
def test_same_newton_path_in_any_length_unit(method, coulomb):
    """The dragged half block in metres and in millimetres (every length
    × 1e-3: K ∝ L, the Γc areas D ∝ L², forces ∝ L², tractions fixed):
    the same Jacobian count in every step and the same displacements / L.
    The merit ‖Φ‖ of the line searches sees the projection rows as nodal
    forces D(g − P(w)), like every other row; as tractions g − P(w) they
    weighed 1/L² more, and in millimetres φ_FB with the implicit bound
    stalled at step 2 (the lagged φ_min stall of the Hertz sphere at a/h
    16, benchmarks/README.md, had the same cause: the full Newton step cut
    the normal rows' residual from 60 to 1.5 N-units and was rejected for
    tractions of 9e3 at nodes that move from stick to slip). φ_min with
    the implicit bound still takes other counts (its first step: 1
    against 4 Jacobians; same solution), from another scale dependence,
    not this one."""
    runs = []
    for scale in (1.0, 1e-3):
        problem = dragged_3d("half", 0.02, scale=scale)
        result = solve_friction(problem, FC, method=method, coulomb=coulomb,
                                **RUN)
        assert result.success, result.message
        runs.append((result, scale))
    (a, _), (b, scale) = runs
    assert [r["njev"] for r in a.records] == [r["njev"] for r in b.records]
    np.testing.assert_allclose(b.u / scale, a.u, rtol=0,
                               atol=1e-9 * np.abs(a.u).max())
