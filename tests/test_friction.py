"""Coulomb friction by load steps (thesis §5-§6).

Independent references: the closed form of the 2-DOF bar derived below, the
frictionless solver (f_c → 0), and Coulomb's law itself checked node by node.

Closed form of the bar (K = k I, k = 9e4, f = (1000, −1000), s = 0.005,
ν = (0, −1), 100 steps, tangent = +x): step κ loads (10κ, −10κ).
- κ ≤ 45: free, u = (10κ, −10κ)/k, λ = 0, g_t = 0 (the gap closes at 45).
- κ > 45: u_y = −s, λ_κ = 10κ − 450. Holding u_x needs a friction force
  growing by 10 per step, the normal force grows by 10 per step: f_c > 1
  sticks, f_c < 1 slips (every step, by induction on the trial force).
  * slip, bound f_c p with p = λ_{κ−1} (lagged) or λ_κ (implicit):
    g_t = −f_c p, u_x = (10κ − f_c p)/k;
  * stick, lagged: step 46 has p = λ_45 = 0 and slides freely to
    u_x = 460/k; from 47 on u_x = 460/k, g_t = 460 − 10κ;
  * stick, implicit: stuck from 46 on, u_x = 450/k, g_t = 450 − 10κ.
(M = [1], so tractions equal nodal forces.)
"""

import numpy as np
import pytest

from conftest import THESIS_MESHES
from solver.contact import solve_friction, solve_frictionless
from solver.errors import SolverError
from solver.problem import load_problem

K_BAR = 9e4


def bar_closed_form(kappa, fc, coulomb):
    """(u_x, u_y, λ, g_t) of the bar at step κ, see the module docstring."""
    if kappa <= 45:
        return 10 * kappa / K_BAR, -10 * kappa / K_BAR, 0.0, 0.0
    lam = 10.0 * kappa - 450
    if fc < 1:
        p = max(10.0 * (kappa - 1) - 450, 0) if coulomb == "lagged" else lam
        return (10 * kappa - fc * p) / K_BAR, -0.005, lam, -fc * p
    if coulomb == "lagged":
        if kappa == 46:
            return 460 / K_BAR, -0.005, lam, 0.0
        return 460 / K_BAR, -0.005, lam, 460.0 - 10 * kappa
    return 450 / K_BAR, -0.005, lam, 450.0 - 10 * kappa


CASES = [(form, coulomb, method)
         for form in ("thesis", "projection")
         for coulomb in ("lagged", "implicit")
         for method in ("fb", "min")]


@pytest.mark.parametrize("fc", [10.0, 0.5])
@pytest.mark.parametrize("formulation, coulomb, method", CASES)
def test_bar_closed_form_every_step(bar_problem, fc, formulation, coulomb,
                                    method):
    result = solve_friction(bar_problem, fc, steps=100,
                            formulation=formulation, coulomb=coulomb,
                            method=method, tol=1e-13)
    assert result.success, result.message
    reference = np.array([bar_closed_form(k, fc, coulomb)
                          for k in range(1, 101)])
    got = np.c_[result.displacement[:, 0, 0], result.displacement[:, 0, 1],
                result.contact_force[:, 0], result.friction_traction[:, 0]]
    scale = np.abs(reference).max(axis=0)
    np.testing.assert_array_less(np.abs(got - reference).max(axis=0),
                                 1e-10 * scale)
    # stick/slip classification: f_c = 10 sticks, 0.5 slips (after contact)
    contact = result.in_contact[:, 0]
    assert contact.sum() == 55  # steps 46..100 (λ_45 = 0)
    if fc < 1:
        assert result.slip[contact, 0].all()
    else:
        first = 1 if coulomb == "lagged" else 0  # lagged 46 slides freely
        assert result.stick[contact, 0][first:].all()


@pytest.mark.parametrize("formulation", ["thesis", "projection"])
@pytest.mark.parametrize("coulomb", ["lagged", "implicit"])
def test_body_coulomb_law_holds(exported, formulation, coulomb):
    problem = load_problem(exported(118)[0])
    result = solve_friction(problem, 0.3, steps=25, formulation=formulation,
                            coulomb=coulomb)
    assert result.success, result.message
    scale = np.linalg.norm(problem.f)
    g, bound = result.friction_traction, result.friction_bound
    # |g_t| ≤ f_c p at every node and step
    assert np.all(np.abs(g) <= bound + 1e-9 * scale)
    # out of contact there is no friction
    assert np.all(np.abs(g[~result.in_contact]) <= 1e-9 * scale)
    # slip only at the bound, opposite to the friction traction
    dut = np.diff(np.nan_to_num(result.tangential_displacement), axis=0,
                  prepend=0.0)
    moving = np.abs(dut) > 1e-9 * np.abs(result.u).max()
    moving &= result.in_contact
    assert np.all(np.abs(np.abs(g[moving]) - bound[moving])
                  <= 1e-6 * scale)
    loaded = moving & (bound > 1e-9 * scale)  # bound 0: g_t = 0, no sign
    assert np.all(np.sign(dut[loaded]) == -np.sign(g[loaded]))
    # stick nodes do not move in the step
    stuck = result.stick & (bound > 1e-9 * scale)
    assert np.all(np.abs(dut[stuck]) <= 1e-9 * np.abs(result.u).max())


@pytest.mark.parametrize("formulation", ["thesis", "projection"])
def test_zero_friction_is_frictionless(exported, formulation):
    problem = load_problem(exported(454)[0])
    reference = solve_frictionless(problem, method="min")
    result = solve_friction(problem, 0.0, steps=10, formulation=formulation)
    assert result.success
    err = np.abs(result.u[-1] - reference.u).max() / np.abs(reference.u).max()
    assert err <= 1e-8
    np.testing.assert_array_equal(result.in_contact[-1],
                                  reference.in_contact)


@pytest.mark.parametrize("formulation, coulomb, method", [
    ("thesis", "lagged", "fb"), ("projection", "lagged", "fb"),
    ("projection", "implicit", "min")])
def test_large_friction_freezes_tangential_motion(exported, formulation,
                                                  coulomb, method):
    """f_c = 1e6: a node keeps the tangential displacement it has at the
    step it first touches. (FB with the implicit bound and f_c ≥ 100 does
    not converge on this mesh: the bound's slope f_c·k is too steep for its
    merit function; it reports so, exit 3 on the command line.)"""
    problem = load_problem(exported(454)[0])
    result = solve_friction(problem, 1e6, steps=20, formulation=formulation,
                            coulomb=coulomb, method=method)
    assert result.success, result.message
    ut = result.tangential_displacement
    scale = np.abs(result.u).max()
    for node in np.flatnonzero(result.in_contact.any(axis=0)):
        first = np.argmax(result.in_contact[:, node])
        frozen = ut[first:, node] - ut[first, node]
        assert np.abs(frozen).max() <= 1e-8 * scale, node


def test_formulations_agree_where_unique(exported):
    """Small f_c on the body: the thesis's split and the projection form
    give the same load path."""
    problem = load_problem(exported(118)[0])
    a = solve_friction(problem, 0.05, steps=20, formulation="thesis")
    b = solve_friction(problem, 0.05, steps=20, formulation="projection")
    assert a.success and b.success
    scale = np.abs(a.u).max()
    assert np.abs(a.u - b.u).max() <= 1e-8 * scale
    np.testing.assert_array_equal(a.in_contact, b.in_contact)


def test_thesis_split_is_singular_for_min(exported):
    """Errata: with p = 0 the split leaves Δu_t± non-unique, J is singular;
    φ_min has no gradient fallback and reports it instead of pretending."""
    problem = load_problem(exported(118)[0])
    result = solve_friction(problem, 0.3, steps=10, formulation="thesis",
                            method="min")
    assert not result.success
    assert result.failed_step == 1 and result.steps_completed == 0
    assert "singular Jacobian" in result.message


def test_bad_arguments():
    from solver.examples import two_dof_bar

    with pytest.raises(SolverError, match="friction coefficient"):
        solve_friction(two_dof_bar(), -0.1)
    with pytest.raises(SolverError, match="load steps"):
        solve_friction(two_dof_bar(), 0.1, steps=0)
    with pytest.raises(SolverError, match="formulation"):
        solve_friction(two_dof_bar(), 0.1, formulation="tresca")
