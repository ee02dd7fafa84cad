"""Issue 16, class 1: no wrong answer reported as converged, and a Newton
run that stopped making progress stops (class 4).

Independent references: the same problem in other units (the answer of a
problem in force units scaled by a is a·λ with the same u: plain
arithmetic); u = K⁻¹f by SciPy's sparse LU where no node touches the
obstacle; Clarabel (an interior-point QP solver sharing no code with ours,
see tests/test_qp_crosscheck.py) for the ill-conditioned spring grid; and
the contact conditions recomputed here from u with numpy, not through
``result.verification``.
"""

import dataclasses
import time
import warnings

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from solver import solve_friction, solve_frictionless
from solver.contact import contact_geometry
from solver.contact import ContactGeometry
from solver.errors import KinematicsWarning
from solver.ncp import solve_ncp
from solver.problem import ContactProblem, load_problem

METHODS = ("min", "fb")
#: start / system of solve_frictionless: nested and free are condensed
SYSTEMS = {"nested": {}, "free": {"start": "free"},
           "full": {"condense": False}}


@pytest.fixture(scope="module")
def block(exported):
    return load_problem(exported(118)[0])


def scaled(problem, stiffness=1.0, load=1.0):
    """The problem with K × stiffness and f × stiffness × load: force units
    changed (load = 1), or a different load (stiffness = 1)."""
    return dataclasses.replace(problem, K=problem.K * stiffness,
                               f=problem.f * stiffness * load)


def contact_conditions(problem, result):
    """(penetration, min λ, max |min(λ, k(s − u_n))|, equilibrium) from u,
    recomputed with numpy (forces relative to ‖f‖ + ‖λ‖, lengths to
    ‖f‖/k)."""
    free = np.isfinite(result.gap)
    dofs = problem.contact_dofs[free]
    nu, s = result.normal[free], result.gap[free]
    lam = result.contact_force[free]
    k = problem.K.diagonal()[dofs].mean()
    force = norm(problem.f) + norm(lam)
    un = (nu * result.u[dofs]).sum(axis=1)
    contact = np.zeros(problem.n_dofs)
    np.add.at(contact, dofs[:, 0], -lam * nu[:, 0])
    np.add.at(contact, dofs[:, 1], -lam * nu[:, 1])
    residual = problem.K @ result.u - problem.f - contact
    return (max((un - s).max(), 0.0) * k / force, lam.min() / force,
            np.abs(np.minimum(lam, k * (s - un))).max() / force,
            norm(residual) / force)


def norm(v):
    """‖v‖₂ without overflow (f × 1e152 has ‖f‖² > 1e308)."""
    top = np.abs(v).max()
    return top * np.linalg.norm(v / top) if top > 0 else 0.0


# ---------------------------------------------------------------------------
# units: K, f × 1e±14 (force units), lengths × β


@pytest.mark.parametrize("factor", [1e-14, 1e14])
@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("system", ["nested", "free"])
def test_force_units_condensed_same_iterates(block, system, method, factor):
    """Condensed (c = k̄, unit-free descent test): the same verdict, the
    same Jacobian count and the same u; λ scales with the units."""
    reference = solve_frictionless(block, method, **SYSTEMS[system])
    result = solve_frictionless(scaled(block, factor), method,
                                **SYSTEMS[system])
    assert reference.success and result.success, result.message
    assert result.njev == reference.njev
    assert result.levels == [] or [lv["njev"] for lv in result.levels] == \
        [lv["njev"] for lv in reference.levels]
    scale = np.abs(reference.u).max()
    assert np.abs(result.u - reference.u).max() <= 1e-9 * scale
    np.testing.assert_allclose(result.contact_force / factor,
                               reference.contact_force,
                               atol=1e-9 * reference.contact_force.max())
    np.testing.assert_array_equal(result.in_contact, reference.in_contact)
    assert result.verification["passed"]
    assert result.stopping["relative"] <= 1e-10
    np.testing.assert_allclose(result.stopping["scale"],
                               factor * reference.stopping["scale"])


@pytest.mark.parametrize("factor", [1e-14, 1e14])
@pytest.mark.parametrize("method", METHODS)
def test_force_units_full_system(block, method, factor):
    """The thesis's full system with c = 1 compares a force with a length in
    φ(λ, s − u_n): its path depends on the units, its verdict must not lie.
    With c (and φ_FB's force scale) changed along with the units it takes
    the same iterates; with the thesis's c = 1 it either converges to the
    same verified u or says it did not converge."""
    reference = solve_frictionless(block, method, condense=False)
    options = {"typical": (factor, 1.0)} if method == "fb" else None
    same = solve_frictionless(scaled(block, factor), method, condense=False,
                              gap_scale=factor, options=options)
    assert same.success and same.njev == reference.njev
    scale = np.abs(reference.u).max()
    assert np.abs(same.u - reference.u).max() <= 1e-9 * scale
    default = solve_frictionless(scaled(block, factor), method,
                                 condense=False)
    if default.success:
        assert default.verification["passed"]
        assert np.abs(default.u - reference.u).max() <= 1e-8 * scale
    else:
        assert default.status in (1, 2, 5) and "not converged" in \
            default.message
    assert method == "fb" or default.success  # φ_min: converges anyway


@pytest.mark.parametrize("method", METHODS)
def test_length_units(block, method):
    """Gaps × β and f × β (K unchanged: a 2D stiffness does not change
    when all lengths do): u × β, the same λ/β and the same iterates."""
    geometry = contact_geometry(block)
    beta = 1e-3
    small = ContactGeometry(geometry.index, geometry.dofs,
                            geometry.gap * beta, geometry.normal,
                            geometry.foot, geometry.mode)
    reference = solve_frictionless(block, method, geometry=geometry)
    result = solve_frictionless(scaled(block, load=beta), method,
                                geometry=small)
    assert result.success and result.njev == reference.njev
    scale = np.abs(reference.u).max()
    assert np.abs(result.u / beta - reference.u).max() <= 1e-9 * scale
    np.testing.assert_array_equal(result.in_contact, reference.in_contact)


@pytest.mark.parametrize("factor", [1e-14, 1e14])
@pytest.mark.parametrize("formulation, coulomb, method", [
    ("projection", "lagged", "fb"), ("projection", "implicit", "min")])
def test_force_units_friction(bar_problem, formulation, coulomb, method,
                              factor):
    """The §6 bar with friction, condensed (the projection form's default):
    every step converges in any units, to the same load path (the closed
    form is checked in test_friction), with Jacobian counts equal up to a
    round-off tie."""
    reference = solve_friction(bar_problem, 0.5, steps=100,
                               formulation=formulation, coulomb=coulomb,
                               method=method, tol=1e-12)
    result = solve_friction(scaled(bar_problem, factor), 0.5, steps=100,
                            formulation=formulation, coulomb=coulomb,
                            method=method, tol=1e-12)
    assert reference.success and result.success, result.message
    assert abs(result.njev - reference.njev) <= 2
    np.testing.assert_allclose(result.u, reference.u, rtol=0,
                               atol=1e-10 * np.abs(reference.u).max())
    np.testing.assert_allclose(result.friction_traction / factor,
                               reference.friction_traction, rtol=0,
                               atol=1e-9 * np.abs(
                                   reference.friction_traction).max())
    assert result.verification["passed"] and all(
        r["verified"] for r in result.records)


# ---------------------------------------------------------------------------
# a tiny load is a load; no load is exactly u = 0


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("system", list(SYSTEMS))
def test_tiny_load_gives_K_inverse_f(block, system, method):
    """f × 1e-12: u ~ 1e-13 ≪ the gaps (≥ 0.05), no contact, so the answer
    is u = K⁻¹f (SciPy's sparse LU), not u = 0 after 0 iterations."""
    problem = scaled(block, load=1e-12)
    result = solve_frictionless(problem, method, **SYSTEMS[system])
    assert result.success, result.message
    expected = sla.spsolve(problem.K.tocsc(), problem.f)
    assert np.abs(result.u - expected).max() <= 1e-8 * np.abs(expected).max()
    assert result.n_contact == 0
    assert np.abs(result.contact_force).max() <= \
        1e-12 * np.linalg.norm(problem.f)  # round-off of λ = 0
    if system == "full":
        assert result.nit >= 1  # from u = 0, which is not the answer


@pytest.mark.parametrize("formulation", ["thesis", "projection"])
def test_tiny_load_friction(block, formulation):
    problem = scaled(block, load=1e-12)
    result = solve_friction(problem, 0.3, steps=2, formulation=formulation)
    assert result.success, result.message
    expected = sla.spsolve(problem.K.tocsc(), problem.f)
    assert np.abs(result.u[-1] - expected).max() <= \
        1e-8 * np.abs(expected).max()
    assert not result.in_contact.any()
    if formulation == "thesis":  # the condensed start is already exact
        assert result.records[0]["nit"] >= 1


@pytest.mark.parametrize("system", list(SYSTEMS))
def test_zero_load_is_exactly_zero(block, system):
    result = solve_frictionless(scaled(block, load=0.0), "min",
                                **SYSTEMS[system])
    assert result.success and result.nit == 0
    assert not result.u.any() and result.verification["passed"]


# ---------------------------------------------------------------------------
# overflow


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("system", list(SYSTEMS))
def test_huge_load_never_converged_with_inf(block, system, method):
    """f × 1e152: ‖Φ‖² overflows. Either a finite answer that passes the
    checks (recomputed here: no penetration, equilibrium), or status 4 /
    6 with a message that says what happened; never "converged" with
    ‖Φ‖ = inf (the nested start did)."""
    problem = scaled(block, load=1e152)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = solve_frictionless(problem, method, **SYSTEMS[system])
    if result.success:
        # the body slides by ~1e149 along the curved obstacle: said, once
        said = [w for w in caught if w.category is KinematicsWarning]
        assert len(said) == 1 and "slides" in str(said[0].message)
        assert np.isfinite(result.residual) and np.isfinite(result.error)
        assert np.all(np.isfinite(result.u))
        assert result.verification["passed"]
        penetration, lam_min, comp, equilibrium = contact_conditions(
            problem, result)
        assert penetration <= 1e-8 and lam_min >= -1e-8
        assert comp <= 1e-8 and equilibrium <= 1e-8
    else:
        assert result.status in (4, 6), result.message
        assert "not finite" in result.message or "overflow" in \
            result.message or "verification" in result.message


# ---------------------------------------------------------------------------
# nearly singular K


def spring_grid(n=12, k=1e5, support=1e-10, gap=0.05, load=1e3):
    """An n×n grid of springs (both DOFs of neighbouring nodes tied by k: a
    vector graph Laplacian) whose bottom row is held by springs of only
    support·k: translation is almost free, cond(K) ≈ 1e12 for support =
    1e-10 (just inside the pivot check of solver.linalg, which refuses
    1e-11). Contact: the right column against a wall at gap s, ν = (1, 0);
    load (load, 0) at the top-left node pushes the body into it."""
    idx = np.arange(n * n).reshape(n, n)
    pairs = np.r_[np.c_[idx[:, :-1].ravel(), idx[:, 1:].ravel()],
                  np.c_[idx[:-1, :].ravel(), idx[1:, :].ravel()]]
    A = sp.coo_matrix((np.ones(len(pairs)), tuple(pairs.T)),
                      shape=(n * n, n * n))
    A = A + A.T
    ground = np.zeros(n * n)
    ground[idx[0]] = support
    L = sp.diags(np.asarray(A.sum(axis=1)).ravel() + ground) - A
    K = sp.kron(k * L, sp.identity(2)).tocsr()
    f = np.zeros(2 * n * n)
    f[2 * idx[-1, 0]] = load
    right = idx[:, -1]
    M = sp.diags([np.full(n - 1, 1 / 6), np.r_[1 / 3, np.full(n - 2, 2 / 3),
                                               1 / 3], np.full(n - 1, 1 / 6)],
                 [-1, 0, 1]).tocsr()
    return ContactProblem(K=K, f=f, M=M,
                          contact_dofs=np.c_[2 * right, 2 * right + 1],
                          gap=np.full(n, gap),
                          normal=np.tile([1.0, 0.0], (n, 1)),
                          meta={"description": "spring grid, weak support"}
                          ).validate()


def clarabel_grid(problem):
    """min ½uᵀKu − fᵀu s.t. u_x ≤ s on the right column, by Clarabel."""
    import clarabel

    n, m = problem.n_dofs, problem.n_contact
    k = problem.K.diagonal().mean()
    C = sp.csc_matrix((np.ones(m), (np.arange(m), problem.contact_dofs[:, 0])),
                      shape=(m, n))
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = settings.tol_gap_rel = settings.tol_feas = 1e-12
    solution = clarabel.DefaultSolver(
        sp.triu(problem.K / k).tocsc(), -problem.f / k, C, problem.gap,
        [clarabel.NonnegativeConeT(m)], settings).solve()
    return np.asarray(solution.x)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("system", list(SYSTEMS))
def test_nearly_singular_K_is_not_converged_with_penetration(system,
                                                             method):
    """cond(K) ≈ 1e12: the condensed solve meets its stopping test, but the
    displacement recovered from K⁻¹f (a huge rigid translation) and the
    Schur complement penetrates the wall by ~1e-4 (measured) and is out of
    equilibrium. It must not be reported as converged: status 6 naming the
    failed checks, or (the full system, which never forms K⁻¹f) a verified
    answer that agrees with Clarabel."""
    problem = spring_grid()
    result = solve_frictionless(problem, method, **SYSTEMS[system])
    penetration, lam_min, comp, equilibrium = contact_conditions(problem,
                                                                 result)
    if result.success:
        assert penetration <= 1e-8 and comp <= 1e-8
        assert equilibrium <= 1e-8 and lam_min >= -1e-8
        reference = clarabel_grid(problem)
        assert np.abs(result.u - reference).max() <= \
            1e-5 * np.abs(reference).max()
    else:
        assert result.status == 6, result.message
        assert "fails verification" in result.message
        assert result.verification["failed"]
        assert max(penetration, comp, equilibrium) > 1e-8  # really wrong
        assert len(result.history["residual"]) == result.nit > 0
    if system != "full":
        assert not result.success  # measured: the condensed answer is off


# ---------------------------------------------------------------------------
# a tol floating point cannot reach


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("system", list(SYSTEMS))
def test_unreachable_tol_stops_with_status_5(block, system, method):
    clock = time.perf_counter()
    result = solve_frictionless(block, method, tol=1e-300,
                                max_iter=10 ** 9, **SYSTEMS[system])
    assert time.perf_counter() - clock < 10
    assert result.status == 5 and not result.success
    assert "no progress" in result.message and "tol too small?" in \
        result.message
    assert "below what floating point reaches" in result.message
    assert len(result.history["residual"]) == result.nit > 0
    assert result.stopping["relative"] < 1e-12  # it did solve the problem


def test_unreachable_tol_friction(block):
    clock = time.perf_counter()
    result = solve_friction(block, 0.3, steps=2, tol=1e-300,
                            max_iter=10 ** 9, formulation="projection")
    assert time.perf_counter() - clock < 10
    assert not result.success and result.failed_step == 1
    record = result.records[-1]
    assert record["status"] == 5 and record["residual_history"]
    assert "below what floating point reaches" in result.message


@pytest.mark.parametrize("method", METHODS)
def test_stagnation_without_roundoff_is_reported(method):
    """FE-free: an NCP whose residual cannot decrease (a constant equality
    row 1 = 0 next to a solvable pair): status 5 within STALL_ITERATIONS,
    not max_iter = 10⁹, and the message says the residual is not at
    round-off level."""
    from solver.ncp.newton import STALL_ITERATIONS

    fun = lambda x: (np.array([1.0 + 0.0 * x[0]]), x[1:], x[1:] + 1.0)
    jac = lambda x: (sp.csr_matrix([[1e-300, 0.0]]),
                     sp.csr_matrix([[0.0, 1.0]]), sp.csr_matrix([[0.0, 1.0]]))
    result = solve_ncp(fun, jac, np.zeros(2), method=method, tol=1e-10,
                       max_iter=10 ** 9)
    assert not result.success and result.status == 5
    assert result.nit == STALL_ITERATIONS
    assert "above tol" in result.message and "round-off" not in \
        result.message


def test_nonfinite_residual_is_status_4():
    fun = lambda x: (np.array([np.inf]), x[1:], x[1:])
    jac = lambda x: (sp.csr_matrix([[1.0, 0.0]]), sp.csr_matrix([[0.0, 1.0]]),
                     sp.csr_matrix([[0.0, 1.0]]))
    result = solve_ncp(fun, jac, np.zeros(2), max_iter=0)
    assert result.status == 4 and "not finite" in result.message
    assert not result.success


def test_scale_makes_tol_relative():
    """solve_ncp with scale: the LCP x ≥ 0, x − 1e-14 ≥ 0 (answer x =
    1e-14) is 'solved' at x = 0 by the absolute test ‖Φ‖ ≤ 1e-10, not by
    the relative one."""
    q = 1e-14
    fun = lambda x: (np.zeros(0), x, x - q)
    jac = lambda x: (sp.csr_matrix((0, 1)), sp.identity(1, format="csr"),
                     sp.identity(1, format="csr"))
    absolute = solve_ncp(fun, jac, np.zeros(1), tol=1e-10)
    assert absolute.success and absolute.x[0] == 0.0  # the old behaviour
    relative = solve_ncp(fun, jac, np.zeros(1), tol=1e-10,
                         scale=lambda E, A, B: q)
    assert relative.success and abs(relative.x[0] - q) <= 1e-10 * q
    assert relative.stopping["scale"] == q
    assert relative.stopping["relative"] <= 1e-10


# ---------------------------------------------------------------------------
# a wrong answer is caught


def perturbed(monkeypatch, module, shift):
    """Make ``module.solve_ncp`` return a 'converged' x + shift(x)."""
    original = module.solve_ncp

    def wrong(fun, jac, x0, **kwargs):
        result = original(fun, jac, x0, **kwargs)
        result.x = result.x + shift(result.x)
        return result

    monkeypatch.setattr(module, "solve_ncp", wrong)


@pytest.mark.parametrize("system", ["free", "full"])
def test_wrong_answer_fails_verification(block, system, monkeypatch):
    """x shifted by 1e-3 of its size after a converged solve (the stopping
    test passed on the true x): status 6, the history kept, the failed
    checks named with their values."""
    import solver.contact.frictionless.driver as module

    perturbed(monkeypatch, module, lambda x: 1e-3 * np.abs(x).max())
    result = solve_frictionless(block, "min", **SYSTEMS[system])
    assert not result.success and result.status == 6
    assert "fails verification" in result.message
    assert result.verification["passed"] is False
    assert "max_penetration" in result.verification["failed"]
    assert result.nit > 0 and len(result.history["residual"]) == result.nit


def test_wrong_friction_step_fails_verification(bar_problem, monkeypatch):
    import solver.contact.friction.steps as module  # its solve_ncp

    perturbed(monkeypatch, module, lambda x: 1e-3 * np.abs(x).max())
    result = solve_friction(bar_problem, 0.5, steps=100,
                            formulation="projection", method="min")
    assert not result.success
    record = result.records[-1]
    assert record["status"] == 6 and record["verified"] is False
    assert "fails verification" in result.message
    assert result.steps_completed == result.failed_step - 1
    assert all(r["verified"] for r in result.records[:-1])


def test_verification_reported_on_success(block):
    result = solve_frictionless(block, "fb")
    v = result.verification
    assert v["passed"] and v["finite"] and v["failed"] == []
    for key in ("max_penetration", "complementarity", "equilibrium"):
        assert 0 <= v[key] <= v["tolerances"][key]
    assert v["min_multiplier"] >= v["tolerances"]["min_multiplier"]
    friction = solve_friction(block, 0.3, steps=5, formulation="projection")
    assert friction.success and friction.verification["passed"]
    assert 0 <= friction.verification["friction_bound_violation"] <= 1e-8
    assert friction.stopping["relative"] <= 1e-10
