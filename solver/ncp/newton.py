r"""Semismooth Newton methods for mixed nonlinear complementarity problems.

The problem (thesis (15), with equality rows as in (67)): find x ∈ Rⁿ with

.. math::
    E(x) = 0, \qquad A(x) \ge 0,\ B(x) \ge 0,\ A(x)^T B(x) = 0,

where E has m_e rows and A, B have m_c rows, m_e + m_c = n. With an NCP
function φ (:mod:`solver.ncp.functions`) it is the square nonsmooth system
Φ(x) = [E(x); φ(A(x), B(x))] = 0, solved by

- ``method="min"``: the damped Newton method of thesis §2.2.1 with
  φ_min: J d = −Φ, x ← x + αd with α = 1 halved while ‖Φ‖ does not decrease
  (the thesis prints "α = ε/2", a typo for α/2). Below ``alpha_min`` the
  search gives up, records it in ``history["line_search_failed"]`` and takes
  the full step, as the thesis reports doing once (§4). The thesis does not
  give its bound; ``alpha_min`` = 2⁻¹⁰ reproduces its behaviour on the §4
  block (exactly one failed search per solve, 4/6/7 Jacobians on the
  118/454/1878 meshes against its 6/8/10). With bounds below 2⁻¹⁶ the search
  instead accepts tiny steps (α ≈ 2⁻¹⁶…2⁻⁴⁰) that barely decrease ‖Φ‖ and
  the count grows past 20 (measured);
- ``method="fb"``: the method of De Luca, Facchinei and Kanzow (1996), thesis
  §2.2.2: merit ψ = ½‖Φ_FB‖² (24); Newton direction unless J d = −Φ is
  singular or fails the descent test ∇ψᵀd ≤ −ρ‖d‖ᵖ (26), then d = −∇ψ =
  −JᵀΦ; Armijo backtracking ψ(x + 2⁻ⁱd) ≤ ψ(x) + β2⁻ⁱ∇ψᵀd (27); ρ = 1e-8,
  p = 2.1, β = 1e-4 (32); on the degenerate set γ = {A_i = B_i = 0} the
  Jacobian rows of (31) with direction z.

Both take callables ``fun(x) -> (E, A, B)`` and ``jac(x) -> (JE, JA, JB)``
(sparse matrices with n columns), know nothing of finite elements, and use
sparse LU (SuperLU) for J d = −Φ: no dense n×n matrix is ever formed.

References
----------
T. De Luca, F. Facchinei, C. Kanzow: A semismooth equation approach to the
solution of nonlinear complementarity problems. Math. Programming 75 (1996)
407-439.
A. Fischer: A special Newton-type optimization method. Optimization 24
(1992) 269-284.
"""

import time

import warnings

import numpy as np
import scipy.sparse as sp
import scipy.linalg as sla_dense
import scipy.sparse.linalg as sla
from scipy.optimize import OptimizeResult

from .functions import NCP_FUNCTIONS, derivative_weights, phi

__all__ = ["solve_ncp", "MESSAGES", "DEFAULT_OPTIONS"]

#: Termination messages keyed by ``status``.
MESSAGES = {
    0: "converged: residual ≤ tol",
    1: "not converged: maximum number of iterations reached",
    2: "not converged: line search found no acceptable step",
    3: "not converged: singular Jacobian",
    4: "not converged: non-finite residual",
    5: "not converged: no progress, the residual is at round-off level "
       "(tol too small?)",
}

#: Options of each method (thesis §2.2 and (32)).
DEFAULT_OPTIONS = {
    "min": {"alpha_min": 2.0 ** -10},
    "fb": {"rho": 1e-8, "p": 2.1, "beta": 1e-4, "max_halvings": 60,
           "z": None},
}


class _Counted:
    """Wraps ``fun`` and ``jac`` to count evaluations (Table 1's metrics)."""

    def __init__(self, fun, jac, kind):
        self.fun, self.jac, self.kind = fun, jac, kind
        self.nfev = self.njev = 0

    def residual(self, x):
        """Φ(x) and the pieces (E, A, B)."""
        self.nfev += 1
        E, A, B = (np.asarray(v, dtype=float) for v in self.fun(x))
        return np.concatenate([E, phi(A, B, self.kind)]), (E, A, B)

    def jacobian(self, x, parts, z=None):
        """J ∈ ∂_B Φ(x) (CSC) and the number of predicted contacts."""
        self.njev += 1
        JE, JA, JB = self.jac(x)
        E, A, B = parts
        za = zb = None
        if self.kind == "fb":
            gamma = (A == 0.0) & (B == 0.0)
            if gamma.any():
                direction = z(gamma) if z is not None else _default_z(
                    JA, gamma)
                za, zb = JA @ direction, JB @ direction
        wa, wb, _ = derivative_weights(A, B, self.kind, za, zb)
        rows = sp.diags(wa) @ sp.csr_matrix(JA) + sp.diags(wb) @ \
            sp.csr_matrix(JB)
        J = sp.vstack([sp.csr_matrix(JE), rows], format="csc")
        return J, int(np.count_nonzero(A > B))


def _default_z(JA, gamma):
    """DFK's z with z_i = 1 on γ, read in the variables of A.

    DFK (1996) pose x ≥ 0, F(x) ≥ 0, so ∇A_i = e_i and z = Σ_{i∈γ} e_i. For
    general A we take z = Σ_{i∈γ} ∇A_i / ‖∇A_i‖², which gives ∇A_iᵀz = 1 when
    the rows of γ are orthogonal (as for distinct contact nodes).
    """
    JA = sp.csr_matrix(JA)[np.flatnonzero(gamma)]
    norms2 = np.asarray(JA.multiply(JA).sum(axis=1)).ravel()
    norms2[norms2 == 0.0] = 1.0
    return np.asarray(JA.T @ (1.0 / norms2)).ravel()


#: Jacobians with more than this fraction of nonzeros (and at least
#: DENSE_MIN_SIZE rows) are factorised by LAPACK instead of SuperLU: those of
#: the systems condensed onto Γc (:class:`solver.linalg.Condensation`) are
#: dense blocks, where SuperLU is several times slower than LAPACK.
DENSE_FRACTION = 0.2
DENSE_MIN_SIZE = 64


def _newton_direction(J, F):
    """Solve J d = −F (SuperLU, or LAPACK for a dense J); None if J is
    (numerically) singular."""
    n = J.shape[0]
    if n >= DENSE_MIN_SIZE and J.nnz > DENSE_FRACTION * n * n:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", sla_dense.LinAlgWarning)
            lu, piv = sla_dense.lu_factor(J.toarray(), check_finite=False)
            if not np.all(np.diagonal(lu)):
                return None
            d = sla_dense.lu_solve((lu, piv), -F, check_finite=False)
    else:
        try:
            d = sla.splu(J).solve(-F)
        except RuntimeError:  # "Factor is exactly singular"
            return None
    return d if np.all(np.isfinite(d)) else None


def solve_ncp(fun, jac, x0, method="min", tol=1e-10, max_iter=100,
              options=None, callback=None, error=None):
    r"""Solve a mixed NCP by a semismooth Newton method.

    Parameters
    ----------
    fun : callable
        ``fun(x) -> (E, A, B)``: equality residual and the complementary
        pair (thesis (15)).
    jac : callable
        ``jac(x) -> (JE, JA, JB)``: their Jacobians, sparse, n columns each.
    x0 : (n,) array
        Starting point.
    method : {"min", "fb"}
        Damped Newton with φ_min (thesis §2.2.1) or the Fischer–Burmeister
        method of De Luca, Facchinei and Kanzow (§2.2.2).
    tol : float
        Stop when ‖Φ(x)‖₂ ≤ tol (thesis Step 1), or ``error(E, A, B)`` ≤ tol
        if ``error`` is given.
    max_iter : int
        Maximum number of Newton iterations (Jacobian evaluations).
    options : dict, optional
        Method options, see :data:`DEFAULT_OPTIONS`: ``alpha_min`` (min);
        ``rho``, ``p``, ``beta``, ``max_halvings`` and ``z`` (fb; ``z(gamma)``
        returns the direction of rule (31) for the boolean mask γ).
    callback : callable, optional
        ``callback(x, record)`` after every iteration.
    error : callable, optional
        ``error(E, A, B) -> float``, the measure of the stopping test. Use it
        when the rows of Φ have different units (forces and gaps): the
        iteration itself (directions, line search) still works with Φ.

    Returns
    -------
    OptimizeResult
        ``x``, ``success``, ``status`` (see :data:`MESSAGES`), ``message``,
        ``nit`` (iterations), ``njev`` (Jacobian evaluations), ``nfev``
        (residual evaluations, line search included), ``fun`` (Φ at x),
        ``residual`` (‖Φ(x)‖), ``error`` (the stopping measure at x),
        ``method``, ``time`` (wall seconds) and ``history``: a dict of
        per-iteration lists ``residual`` (‖Φ‖ before the step), ``error``
        (the stopping measure before the step), ``merit`` (ψ = ½‖Φ‖²),
        ``alpha`` (step length), ``step``
        ("newton" or "gradient"), ``active`` (rows with A_i > B_i, i.e.
        predicted contacts) and ``line_search_failed``.
    """
    if method not in NCP_FUNCTIONS:
        raise ValueError(f"unknown method {method!r}; use one of "
                         f"{NCP_FUNCTIONS}")
    opts = dict(DEFAULT_OPTIONS[method])
    unknown = set(options or {}) - set(opts)
    if unknown:
        raise ValueError(f"unknown options for method {method!r}: "
                         f"{sorted(unknown)}")
    opts.update(options or {})
    start = time.perf_counter()
    counted = _Counted(fun, jac, method)
    history = {k: [] for k in ("residual", "error", "merit", "alpha", "step",
                               "active", "line_search_failed")}

    def measure(F, parts):
        return np.linalg.norm(F) if error is None else float(error(*parts))

    x = np.array(x0, dtype=float)
    F, parts = counted.residual(x)
    status = 1
    for _ in range(max_iter):
        norm, err = np.linalg.norm(F), measure(F, parts)
        if not (np.isfinite(norm) and np.isfinite(err)):
            status = 4
            break
        if err <= tol:
            status = 0
            break
        J, active = counted.jacobian(x, parts, opts.get("z"))
        previous = x
        if method == "min":
            x, F, parts, record = _min_step(counted, x, F, parts, J, opts)
        else:
            x, F, parts, record = _fb_step(counted, x, F, parts, J, opts)
        record.update(residual=norm, error=err, merit=0.5 * norm ** 2,
                      active=active)
        for key in history:
            history[key].append(record[key])
        if callback is not None:
            callback(x, record)
        if record.get("status"):
            status = record["status"]
            break
        if np.array_equal(x, previous):
            status = 5
            break
    else:
        if measure(F, parts) <= tol:
            status = 0
    norm, err = np.linalg.norm(F), measure(F, parts)
    return OptimizeResult(
        x=x, success=status == 0, status=status, message=MESSAGES[status],
        nit=len(history["residual"]), njev=counted.njev, nfev=counted.nfev,
        fun=F, residual=norm, error=err, method=method, history=history,
        time=time.perf_counter() - start)


def _min_step(counted, x, F, parts, J, opts):
    """One damped Newton iteration with φ_min (thesis §2.2.1, steps 2-4)."""
    d = _newton_direction(J, F)
    if d is None:
        return x, F, parts, dict(alpha=0.0, step="newton",
                                line_search_failed=False, status=3)
    norm, alpha = np.linalg.norm(F), 1.0
    while True:
        trial = x + alpha * d
        F_trial, trial_parts = counted.residual(trial)
        if np.linalg.norm(F_trial) < norm:
            return trial, F_trial, trial_parts, dict(
                alpha=alpha, step="newton", line_search_failed=False)
        if alpha / 2 < opts["alpha_min"]:
            break
        alpha /= 2
    # No acceptable α: take the full Newton step anyway (thesis §4).
    trial = x + d
    F_trial, trial_parts = counted.residual(trial)
    return trial, F_trial, trial_parts, dict(alpha=1.0, step="newton",
                                             line_search_failed=True)


def _fb_step(counted, x, F, parts, J, opts):
    """One iteration of the DFK method (thesis §2.2.2, steps 2-4)."""
    grad = J.T @ F  # ∇ψ = JᵀΦ (28)
    d = _newton_direction(J, F)
    step = "newton"
    if d is None or grad @ d > -opts["rho"] * np.linalg.norm(d) ** opts["p"]:
        d, step = -grad, "gradient"  # (26) failed or J singular
    psi, slope = 0.5 * F @ F, grad @ d
    t = 1.0
    for _ in range(opts["max_halvings"] + 1):
        trial = x + t * d
        F_trial, trial_parts = counted.residual(trial)
        if 0.5 * F_trial @ F_trial <= psi + opts["beta"] * t * slope:  # (27)
            return trial, F_trial, trial_parts, dict(
                alpha=t, step=step, line_search_failed=False)
        t /= 2
    return x, F, parts, dict(alpha=0.0, step=step, line_search_failed=True,
                            status=2)
