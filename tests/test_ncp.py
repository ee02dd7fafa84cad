"""NCP functions and the two semismooth Newton methods, FE-free.

References: the defining property of an NCP function (φ = 0 ⇔ a, b ≥ 0,
ab = 0), finite differences for Jacobian rows away from kinks, and LCP
solutions checked by their own complementarity conditions.
"""

import numpy as np
import pytest
import scipy.sparse as sp

from solver.ncp import derivative_weights, phi, solve_ncp

METHODS = ("min", "fb")


@pytest.mark.parametrize("kind", METHODS)
def test_phi_vanishes_exactly_on_complementarity(kind):
    rng = np.random.default_rng(1)
    a, b = rng.normal(size=(2, 1000))
    on = np.r_[np.abs(a[:500]), np.zeros(500)]
    off = np.r_[np.zeros(500), np.abs(b[500:])]
    np.testing.assert_allclose(phi(on, off, kind), 0.0, atol=1e-15)
    np.testing.assert_allclose(phi(off, on, kind), 0.0, atol=1e-15)
    both_positive = phi(np.abs(a) + 0.1, np.abs(b) + 0.1, kind)
    assert np.all(np.abs(both_positive) > 0)
    negative = phi(-np.abs(a) - 0.1, b, kind)
    assert np.all(np.abs(negative) > 0)


@pytest.mark.parametrize("kind", METHODS)
def test_weights_match_finite_differences(kind):
    rng = np.random.default_rng(2)
    a, b = rng.normal(size=(2, 200))
    a[np.abs(a - b) < 1e-3] += 0.01  # stay away from the min kink a = b
    h = 1e-7
    wa, wb, _ = derivative_weights(a, b, kind)
    np.testing.assert_allclose(wa, (phi(a + h, b, kind) - phi(a - h, b, kind))
                               / (2 * h), atol=1e-6)
    np.testing.assert_allclose(wb, (phi(a, b + h, kind) - phi(a, b - h, kind))
                               / (2 * h), atol=1e-6)


def test_min_rule_of_thesis():
    # Thesis §2.2.1: J_i = ∇B_i if A_i > B_i, else ∇A_i (ties take ∇A_i).
    wa, wb, tie = derivative_weights(np.array([2.0, 1.0, 1.0]),
                                     np.array([1.0, 2.0, 1.0]), "min")
    np.testing.assert_array_equal(wa, [0, 1, 1])
    np.testing.assert_array_equal(wb, [1, 0, 0])
    np.testing.assert_array_equal(tie, [False, False, True])


def test_fb_z_rule_at_the_kink():
    # DFK (31): at a = b = 0 use (∇Aᵀz, ∇Bᵀz) in place of (a, b); this is
    # the limit of rule (30) along x + εz, which we check directly.
    za, zb = np.array([1.0, 1.0, 0.0]), np.array([0.0, 2.0, 3.0])
    wa, wb, gamma = derivative_weights(np.zeros(3), np.zeros(3), "fb", za, zb)
    assert gamma.all()
    eps = 1e-9
    la, lb, _ = derivative_weights(eps * za, eps * zb, "fb")
    np.testing.assert_allclose(wa, la, rtol=1e-12)
    np.testing.assert_allclose(wb, lb, rtol=1e-12)
    # the rows are elements of the generalised Jacobian: (wa+1)²+(wb+1)² = 1
    np.testing.assert_allclose((wa + 1) ** 2 + (wb + 1) ** 2, 1.0)


def lcp(M, q):
    """x ≥ 0, Mx + q ≥ 0, xᵀ(Mx + q) = 0 as a mixed NCP without equalities."""
    M = sp.csr_matrix(M)
    empty = sp.csr_matrix((0, M.shape[0]))
    eye = sp.identity(M.shape[0], format="csr")
    return (lambda x: (np.zeros(0), x, M @ x + q),
            lambda x: (empty, eye, M))


@pytest.mark.parametrize("method", METHODS)
def test_random_spd_lcps(method):
    rng = np.random.default_rng(3)
    for _ in range(50):
        n = rng.integers(2, 15)
        G = rng.normal(size=(n, n))
        M = G @ G.T + 0.5 * np.eye(n)
        q = rng.normal(size=n)
        fun, jac = lcp(M, q)
        result = solve_ncp(fun, jac, np.zeros(n), method=method, tol=1e-12,
                           max_iter=200)
        assert result.success, result.message
        x = result.x
        w = M @ x + q
        assert x.min() >= -1e-10 and w.min() >= -1e-10
        assert abs(x @ w) <= 1e-9
        assert result.njev == result.nit and result.nfev >= result.nit + 1


def test_history_and_counts_are_consistent():
    M = np.array([[2.0, 1.0], [1.0, 2.0]])
    fun, jac = lcp(M, np.array([-1.0, 1.0]))
    result = solve_ncp(fun, jac, np.array([5.0, 5.0]), method="fb")
    assert result.success
    h = result.history
    assert len(h["residual"]) == len(h["alpha"]) == result.nit
    np.testing.assert_allclose(h["merit"], 0.5 * np.array(h["residual"]) ** 2)
    # FB decreases the merit function in every iteration (Armijo, (27)).
    merits = h["merit"] + [0.5 * result.residual ** 2]
    assert all(b < a for a, b in zip(merits, merits[1:]))
    np.testing.assert_allclose(result.x, [0.5, 0.0], atol=1e-12)


def test_max_iter_reported_not_pretended():
    M = np.array([[2.0, 1.0], [1.0, 2.0]])
    fun, jac = lcp(M, np.array([-1.0, 1.0]))
    result = solve_ncp(fun, jac, np.array([50.0, 50.0]), method="fb",
                       max_iter=1)
    assert not result.success and result.status == 1
    assert "maximum number of iterations" in result.message
    assert len(result.history["residual"]) == 1


def test_singular_jacobian_min():
    # Equality row 0·x = 1 makes J singular: status 3, no exception.
    fun = lambda x: (np.array([1.0]), x[1:], x[1:] + 1)
    jac = lambda x: (sp.csr_matrix((1, 2)), sp.csr_matrix([[0.0, 1.0]]),
                     sp.csr_matrix([[0.0, 1.0]]))
    result = solve_ncp(fun, jac, np.zeros(2), method="min")
    assert result.status == 3 and not result.success


@pytest.mark.parametrize("method", METHODS)
def test_dense_lcps_take_the_lapack_path(method, monkeypatch):
    """A dense 80×80 LCP (the Jacobian's density is above DENSE_FRACTION,
    so LAPACK factorises it): the solution satisfies the LCP, and the same
    problem with one dependent row reports a singular Jacobian (status 3)."""
    from solver.ncp import direction

    n = 80
    assert n >= direction.DENSE_MIN_SIZE

    def no_superlu(*args, **kwargs):
        raise AssertionError("SuperLU called for a dense Jacobian")

    monkeypatch.setattr(direction.sla, "splu", no_superlu)
    rng = np.random.default_rng(7)
    G = rng.normal(size=(n, n))
    M = G @ G.T + n * np.eye(n)
    q = rng.normal(size=n)
    fun, jac = lcp(M, q)
    result = solve_ncp(fun, jac, np.zeros(n), method=method, tol=1e-12)
    assert result.success, result.message
    w = M @ result.x + q
    assert result.x.min() >= -1e-10 and w.min() >= -1e-10
    assert abs(result.x @ w) <= 1e-8 * np.abs(q).max()
    # equality rows 0 = 1 at two unknowns that only they involve: singular
    E = sp.csr_matrix((2, n + 2))
    A = sp.hstack([sp.csr_matrix(M), sp.csr_matrix((n, 2))], format="csr")
    singular = solve_ncp(
        lambda x: (np.ones(2), x[:n], M @ x[:n] + q),
        lambda x: (E, sp.hstack([sp.identity(n), sp.csr_matrix((n, 2))],
                                format="csr"), A),
        np.zeros(n + 2), method="min")
    assert singular.status == 3 and not singular.success


def test_bad_method_and_options():
    fun, jac = lcp(np.eye(2), np.ones(2))
    with pytest.raises(ValueError, match="unknown method"):
        solve_ncp(fun, jac, np.zeros(2), method="newton")
    with pytest.raises(ValueError, match="unknown options"):
        solve_ncp(fun, jac, np.zeros(2), method="min", options={"rho": 1})


def test_fb_is_evaluated_without_cancellation():
    # A contact force of 550 against a gap of 1e-13: the naive form
    # √(a²+b²) − (a+b) loses b entirely; the stable form keeps it.
    a, b = np.array([550.0]), np.array([1e-13])
    np.testing.assert_allclose(phi(a, b, "fb"), -1e-13, rtol=1e-12)
    rng = np.random.default_rng(4)
    a, b = rng.normal(size=(2, 1000))
    np.testing.assert_allclose(phi(a, b, "fb"), np.hypot(a, b) - (a + b),
                               rtol=1e-12, atol=1e-15)


def test_fb_watchdog_returns_to_its_anchor():
    """φ_FB's watchdog (option ``watchdog``): full Newton steps, and back
    to the anchor with (27)'s step when ψ has not decreased after k of
    them. E(x) = arctan(x) from x = 3: Newton's full steps diverge
    (|x| > 1.39, the classical example), so the run must come back to 3
    after 4 full steps, take the Armijo step there and still reach the
    root x = 0, as the monotone method does; the first four steps are
    full (α = 1) and the fifth the Armijo step from the anchor."""
    def fun(x):
        return np.arctan(x), np.zeros(0), np.zeros(0)

    def jac(x):
        return (np.array([[1.0 / (1.0 + x[0] ** 2)]]), np.zeros((0, 1)),
                np.zeros((0, 1)))

    plain = solve_ncp(fun, jac, np.array([3.0]), method="fb", tol=1e-12)
    watched = solve_ncp(fun, jac, np.array([3.0]), method="fb", tol=1e-12,
                        options={"watchdog": 4})
    for result in (plain, watched):
        assert result.success, result.message
        assert abs(result.x[0]) <= 1e-12
    alphas = watched.history["alpha"]
    assert alphas[:4] == [1.0] * 4 and alphas[4] < 1.0
    # the Armijo step from the anchor is the monotone method's first
    assert alphas[4] == plain.history["alpha"][0]
