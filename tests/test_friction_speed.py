"""The condensed friction solve's reduced Newton systems
(:mod:`solver.contact.friction.newton`) against the full Jacobian.

Reference: the full Newton system J d = −Φ of the projection formulation
(:meth:`ProjectionSystem._jacobian`, sparse, solved densely here), which the
solver used before the reduction; the reduction is exact block elimination,
so directions agree to round-off and the runs take the same Newton steps.
"""

import numpy as np
import pytest
import scipy.sparse as sp

from solver import solve_friction
from solver.contact.friction import newton as friction_newton
from solver.contact.friction.projection import ProjectionSystem
from solver.contact.friction.split import SplitSystem
from solver.problem import load_problem

CASES = [(coulomb, method) for coulomb in ("lagged", "implicit")
         for method in ("min", "fb")]


def _full_jacobian(system, x):
    """(JE, JA, JB) of the full system at x (sparse, as before), with the
    forces r of the solver's own residual: where λ_i is at round-off level
    the implicit bound's active set follows its sign."""
    r = system._force(x[:system.n])
    RK, system.RK = system.RK, sp.csr_matrix(system.RK)
    system.reduced, system._force = False, lambda du: r
    try:
        return system.jacobian(x)
    finally:
        system.RK, system.reduced = RK, True
        del system._force


@pytest.mark.parametrize("dual", [True, False])
@pytest.mark.parametrize("coulomb, method", CASES)
def test_reduced_direction_is_the_full_newton_direction(
        exported, monkeypatch, coulomb, method, dual):
    """At every iterate of a run (454 block, f_c = 0.3): the reduced
    direction (through the flexibility where smaller, or always the
    primal M_FF) solves the full J d = −Φ with a backward error at
    round-off level, and JᵀΦ agrees."""
    problem = load_problem(exported(454)[0])
    monkeypatch.setattr(friction_newton, "DUAL", dual)
    seen = {"primal": 0, "dual": 0}
    forward, backward = [], []
    direction = friction_newton._Combined.direction
    rmatvec = friction_newton._Combined.rmatvec

    def checked(self, F):
        d = direction(self, F)
        jac = self.jac
        JE, JA, JB = _full_jacobian(jac.system, jac.x)
        J = sp.vstack([JE, sp.diags(self.wa) @ JA + sp.diags(self.wb) @ JB])
        J = J.toarray()
        reference = np.linalg.solve(J, -F)
        norm = np.linalg.norm
        forward.append(norm(d - reference) / norm(reference))
        backward.append(norm(J @ d + F) / (norm(J, 2) * norm(d) + norm(F)))
        g = J.T @ F
        forward.append(norm(rmatvec(self, F) - g) / norm(g))
        return d

    def counted(self, A, h, symmetric, kind):
        seen[kind] += 1
        return solve(self, A, h, symmetric, kind)

    solve = ProjectionSystem._reduced_solve
    monkeypatch.setattr(friction_newton._Combined, "direction", checked)
    monkeypatch.setattr(ProjectionSystem, "_reduced_solve", counted)
    result = solve_friction(problem, 0.3, steps=30, formulation="projection",
                            coulomb=coulomb, method=method)
    assert result.success and result.condensed
    # backward error near round-off, forward error within cond(J) ≈ 300
    # of it: ≤ 2e-15 and 1e-14 measured, except the dual form (through the
    # explicit C = T⁻¹, error ~cond(T)·eps) with φ_FB and the implicit
    # bound (unsymmetric LU): 1.9e-12 and 4.3e-11
    assert max(backward) <= 1e-11
    assert max(forward) <= 1e-9
    # few contact constraints: the dual form whenever allowed (both bounds
    # at f_c = 0.3 ≤ DUAL_MAX_FRICTION, friction_newton.direction)
    assert seen["dual"] > 0 if dual else seen["dual"] == 0
    assert seen["primal"] > 0 or dual


@pytest.mark.parametrize("method", ["min", "fb"])
def test_reduced_run_equals_full_run(exported, monkeypatch, method):
    """The thesis's 100 load steps, lagged bound (454 block): the same
    answers to 1e-12 and the same Jacobian and residual counts in every
    step as with the full Newton systems."""
    problem = load_problem(exported(454)[0])
    kwargs = dict(steps=100, formulation="projection", method=method)
    ours = solve_friction(problem, 0.3, **kwargs)
    monkeypatch.setattr(ProjectionSystem, "reduced_newton", False)
    full = solve_friction(problem, 0.3, **kwargs)
    assert ours.success and full.success
    for key in ("u", "contact_force", "friction_traction"):
        scale = np.abs(full[key]).max()
        assert np.abs(ours[key] - full[key]).max() <= 1e-12 * scale, key
    counts = [[(r["njev"], r["nfev"]) for r in res.records]
              for res in (ours, full)]
    assert counts[0] == counts[1]
    np.testing.assert_array_equal(ours.stick, full.stick)
    np.testing.assert_array_equal(ours.slip, full.slip)


def test_thesis_split_keeps_the_full_system(exported):
    """The reduction is of the projection form only: the thesis's split
    (110)/(111), condensed, still solves its full Newton systems."""
    from solver.contact import contact_geometry
    from solver.contact.strategies.reduction import condense_onto_contact
    problem = load_problem(exported(118)[0])
    geometry = contact_geometry(problem)
    condensation, local = condense_onto_contact(problem, geometry)
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()[geometry.index]
    args = (condensation.S, condensation.load(problem.f)[0], local, lumped,
            0.3)
    assert not SplitSystem(*args).reduced
    assert ProjectionSystem(*args).reduced
    assert not ProjectionSystem(problem.K, problem.f, geometry, lumped,
                                0.3).reduced


@pytest.mark.parametrize("method", ["min", "fb"])
def test_implicit_dual_run_equals_full_run(exported, monkeypatch, method):
    """The implicit bound at f_c = 0.3 (≤ DUAL_MAX_FRICTION: its reduced
    systems go through the flexibility), 100 load steps on the 454 block:
    the answers of the full Newton systems (SciPy's LU of the assembled J,
    the solver before the reduction) to 1e-12, the same stick and slip
    sets, and the Jacobian count within one of theirs (the implicit
    bound's active set a_i = [λ_i > 0] at a λ_i of round-off size decides
    one iteration: φ_min 108 against 109 measured, the primal M_FF 110)."""
    problem = load_problem(exported(454)[0])
    kwargs = dict(steps=100, formulation="projection", coulomb="implicit",
                  method=method)
    seen = []
    solve = ProjectionSystem._reduced_solve

    def counted(self, A, h, symmetric, kind):
        seen.append(kind)
        return solve(self, A, h, symmetric, kind)

    monkeypatch.setattr(ProjectionSystem, "_reduced_solve", counted)
    ours = solve_friction(problem, 0.3, **kwargs)
    assert "dual" in seen
    monkeypatch.setattr(ProjectionSystem, "reduced_newton", False)
    full = solve_friction(problem, 0.3, **kwargs)
    assert ours.success and full.success
    for key in ("u", "contact_force", "friction_traction"):
        scale = np.abs(full[key]).max()
        assert np.abs(ours[key] - full[key]).max() <= 1e-12 * scale, key
    assert abs(ours.njev - full.njev) <= 1
    np.testing.assert_array_equal(ours.stick, full.stick)
    np.testing.assert_array_equal(ours.slip, full.slip)


def test_implicit_dual_only_up_to_its_friction_limit(exported, monkeypatch):
    """Above DUAL_MAX_FRICTION the implicit bound's slip rows (f_c·q_n)
    stay out of the dual form: every reduced system is the primal M_FF;
    the lagged bound still takes the dual form at the same f_c."""
    problem = load_problem(exported(454)[0])
    f_c = 2.0 * friction_newton.DUAL_MAX_FRICTION
    solve = ProjectionSystem._reduced_solve
    for coulomb in ("implicit", "lagged"):
        seen = []

        def counted(self, A, h, symmetric, kind):
            seen.append(kind)
            return solve(self, A, h, symmetric, kind)

        monkeypatch.setattr(ProjectionSystem, "_reduced_solve", counted)
        result = solve_friction(problem, f_c, steps=10,
                                formulation="projection", coulomb=coulomb,
                                method="min")
        assert result.success
        if coulomb == "implicit":
            assert seen and set(seen) == {"primal"}
        else:
            assert "dual" in seen
