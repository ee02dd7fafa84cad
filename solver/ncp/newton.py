r"""Semismooth Newton methods for mixed nonlinear complementarity problems.

The problem (thesis (15), with equality rows as in (67)): find x ∈ Rⁿ with

.. math::
    E(x) = 0, \qquad A(x) \ge 0,\ B(x) \ge 0,\ A(x)^T B(x) = 0,

E with m_e rows, A and B with m_c, m_e + m_c = n. With an NCP function φ
(:mod:`solver.ncp.functions`) it is the square nonsmooth system
Φ(x) = [E(x); φ(A(x), B(x))] = 0, solved by

- ``method="min"``: the damped Newton method of thesis §2.2.1 with
  φ_min: J d = −Φ, x ← x + αd with α = 1 halved while ‖Φ‖ does not
  decrease (the thesis's "α = ε/2" is a typo for α/2); below
  ``alpha_min`` the search gives up, records it in
  ``history["line_search_failed"]`` and takes the full step, as the thesis
  reports doing (§4);
- ``method="fb"``: the method of De Luca, Facchinei and Kanzow (1996),
  thesis §2.2.2: merit ψ = ½‖Φ_FB‖² (24); Newton direction unless J d = −Φ
  is singular or fails the descent test ∇ψᵀd ≤ −ρ‖d‖ᵖ (26), then
  d = −∇ψ = −JᵀΦ; Armijo backtracking ψ(x + 2⁻ⁱd) ≤ ψ(x) + β2⁻ⁱ∇ψᵀd (27);
  ρ = 1e-8, p = 2.1, β = 1e-4 (32); on the degenerate set
  γ = {A_i = B_i = 0} the Jacobian rows of (31) with direction z.
  Option ``watchdog`` = k > 0 (off by default) relaxes the monotone
  search: a Newton step that (27) refuses at t = 1 is taken whole, and
  up to k − 1 more full Newton steps follow; as soon as an iterate
  decreases ψ by (27) relative to the point it left (the anchor), the
  iteration goes on from there, otherwise it returns to the anchor and
  takes (27)'s step from it (the watchdog technique: Chamberlain, Powell,
  Lemaréchal, Pedersen, Math. Programming Stud. 16 (1982) 1-17; for
  complementarity, Dirkse & Ferris's PATH, Optim. Methods Softw. 5 (1995)
  123-156). The anchors' ψ decrease monotonically, so DFK's convergence
  argument holds; a problem whose Newton step from a far start leaves
  the region where ψ is smooth (Coulomb friction's all-stick start, where
  the first kink of the projection lies a small fraction of the step
  away) converges in the iterations of φ_min's full steps instead of
  crawling.

``jac`` returns sparse blocks (J d = −Φ by SuperLU), dense blocks (a
condensed system: LAPACK) or a structured Jacobian that solves its own
Newton systems: an object with ``JA``, ``JB`` (for rule (31)) and
``combine(w_a, w_b)``, which returns [JE; diag(w_a)JA + diag(w_b)JB] as an
object with ``direction(F)`` (d with J d = −F, or None if singular) and
``rmatvec(F)`` (JᵀF). The iterations run with one OpenBLAS thread
(:mod:`solver.linalg.threads`).

References
----------
T. De Luca, F. Facchinei, C. Kanzow: A semismooth equation approach to the
solution of nonlinear complementarity problems. Math. Programming 75 (1996)
407-439.
A. Fischer: A special Newton-type optimization method. Optimization 24
(1992) 269-284."""

import time

import numpy as np
from scipy.optimize import OptimizeResult

from ..linalg.threads import single_blas_thread
from .direction import newton_direction
from .evaluation import Counted
from .functions import NCP_FUNCTIONS

__all__ = ["solve_ncp", "MESSAGES", "DEFAULT_OPTIONS", "stable_norm",
           "LocalReduction"]

#: Termination messages keyed by ``status`` (4 and 5 get the detail of the
#: case appended; 6 is set by the contact solvers, which verify answers).
MESSAGES = {
    0: "converged: residual ≤ tol",
    1: "not converged: maximum number of iterations reached",
    2: "not converged: line search found no acceptable step",
    3: "not converged: singular Jacobian",
    4: "not converged: non-finite residual",
    5: "not converged: no progress, the residual stopped decreasing "
       "(tol too small?)",
    6: "not converged: the answer fails verification",
}

#: Stagnation (status 5): STALL_ITERATIONS iterations in a row in which
#: neither ‖Φ‖ nor the stopping measure falls below STALL_DECREASE times
#: its best value (twice the longest such run that still converged on the
#: thesis's meshes, in φ_FB's gradient phases).
STALL_ITERATIONS = 30
STALL_DECREASE = 0.9

#: A relative residual below this is at round-off level: when a run stalls
#: there, its message says that tol is below what floating point reaches.
ROUNDOFF_LEVEL = 1e-12

#: Options of each method (thesis §2.2 and (32)); ``alpha_min`` = 2⁻¹⁰
#: reproduces the thesis's behaviour on the §4 block.
DEFAULT_OPTIONS = {
    "min": {"alpha_min": 2.0 ** -10},
    "fb": {"rho": 1e-8, "p": 2.1, "beta": 1e-4, "max_halvings": 60,
           "z": None, "typical": None, "watchdog": 0},
}


#: φ_min's Jacobian is singular at some B-subdifferential elements of a
#: degenerate formulation (the thesis's split where p = 0): rows whose
#: |A_i − B_i| is below this fraction of max(|A|, |B|) are then read as
#: exact ties and their ∇A_i row tried (one more Jacobian, counted), so
#: that the round-off sign of a tie does not decide the run.
TIE_RTOL = 1e-12


#: A vector at least this long (a mesh-sized load or displacement) is
#: normed with one BLAS thread (:mod:`solver.linalg.threads`: OpenBLAS's
#: threads cost more than they save on it). Shorter vectors (Γc's, in the
#: Newton loops) keep the call free of the thread switch.
SINGLE_THREAD_NORM = 1 << 14


def stable_norm(v):
    """‖v‖₂ without overflow or underflow of the squares (entries of 1e200
    or 1e-200 are fine; inf and NaN propagate)."""
    v = np.asarray(v, dtype=float)
    with np.errstate(over="ignore", under="ignore"):
        if v.size >= SINGLE_THREAD_NORM:
            with single_blas_thread():
                plain = float(np.linalg.norm(v))
        else:
            plain = float(np.linalg.norm(v))
    if (np.isfinite(plain) and plain > 1e-150) or not v.size:
        return plain  # no over- or underflow: the usual value, bit for bit
    top = float(np.max(np.abs(v)))
    if top == 0.0 or not np.isfinite(top):
        return top
    return top * float(np.linalg.norm(v / top))


def solve_ncp(fun, jac, x0, method="min", tol=1e-10, max_iter=100,
              options=None, callback=None, error=None, scale=None,
              reduction=None):
    r"""Solve a mixed NCP by a semismooth Newton method.

    Parameters
    ----------
    fun, jac : callable
        ``fun(x) -> (E, A, B)``: the equality residual and the complementary
        pair (thesis (15)); ``jac(x) -> (JE, JA, JB)`` their Jacobians (sparse
        or dense, n columns) or a structured Jacobian (module docstring).
    x0 : (n,) array
        Starting point.
    method : {"min", "fb"}
        Damped Newton with φ_min (thesis §2.2.1) or the Fischer–Burmeister
        method of De Luca, Facchinei and Kanzow (§2.2.2).
    tol, max_iter
        The stopping test error(x) ≤ tol·scale(x), error = ‖Φ(x)‖₂ (thesis
        Step 1) and scale = 1 unless the callables below are given (with both
        homogeneous of one degree in the problem's units, verdict and iterates
        do not depend on them); at most ``max_iter`` Jacobians.
    options : dict, optional
        :data:`DEFAULT_OPTIONS`: ``alpha_min`` (min); ``rho``, ``p``,
        ``beta``, ``max_halvings``, ``z`` (``z(gamma)``: rule (31)'s direction
        on the mask γ) and ``typical`` (fb; (force, length) of Φ and x: the
        descent test (26) then reads ∇ψᵀd/force² ≤ −ρ(‖d‖/length)ᵖ).
    callback : callable, optional
        ``callback(x, record)`` after every iteration.
    error, scale : callable, optional
        ``error(E, A, B)``, the stopping measure, for rows of Φ in different
        units (the iteration itself still works with Φ); ``scale(E, A, B)``,
        the problem's own size at x in the units of ``error``.
    reduction : object, optional
        For x, Φ distributed over the ranks of MPI (each rank calls
        ``solve_ncp`` on its own rows at once, ``fun`` and ``jac``
        collective): ``norm(v)``, ‖v‖₂ over all ranks, and ``all(flag)``,
        whether ``flag`` holds on every rank, so that every decision
        (stopping test, line search, stall) is the same on every rank
        (:class:`LocalReduction` by default; ``method="min"`` only).

    Returns
    -------
    OptimizeResult
        ``x``, ``success``, ``status`` (:data:`MESSAGES`), ``message``,
        ``nit``, ``njev``, ``nfev``, ``fun`` (Φ at x), ``residual``, ``error``,
        ``stopping`` (``test``, ``tol``, ``scale``, ``absolute``,
        ``relative``), ``method``, ``time`` and ``history`` (per iteration:
        ``residual``, ``error``, ``merit``, ``alpha``, ``step``, ``active``,
        ``line_search_failed``). A run that stops making progress ends with
        status 5 (:data:`STALL_ITERATIONS`), a non-finite value with status 4.
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
    if reduction is not None and method != "min":
        raise ValueError("a distributed solve_ncp (reduction=) runs "
                         "method='min' only")
    with single_blas_thread():  # dense algebra of Γc's size
        return _iterate(fun, jac, x0, method, tol, max_iter, opts,
                        callback, error, scale,
                        reduction or LocalReduction())


class LocalReduction:
    """:func:`solve_ncp`'s reductions on one process: x and Φ whole."""

    @staticmethod
    def norm(v):
        return stable_norm(v)

    @staticmethod
    def all(flag):
        return bool(flag)


def _iterate(fun, jac, x0, method, tol, max_iter, opts, callback, error,
             scale, reduction):
    """The iterations of :func:`solve_ncp` (arguments checked)."""
    start = time.perf_counter()
    counted = Counted(fun, jac, method)
    history = {k: [] for k in ("residual", "error", "merit", "alpha", "step",
                               "active", "line_search_failed")}

    def measure(F, parts):
        norm = reduction.norm(F)
        err = norm if error is None else float(error(*parts))
        size = 1.0 if scale is None else float(scale(*parts))
        return norm, err, size

    x = np.array(x0, dtype=float)
    F, parts = counted.residual(x)
    status, detail = 1, ""
    best, quiet = [np.inf, np.inf], 0
    watch = None  # φ_FB's watchdog: the anchor of a run of full steps
    while True:
        norm, err, size = measure(F, parts)
        if not (np.isfinite(norm) and np.isfinite(err) and np.isfinite(size)
                and reduction.all(np.all(np.isfinite(x)))):
            status, detail = 4, _nonfinite(x, norm, err, size)
            break
        if err <= tol * size:
            status = 0
            break
        if norm < STALL_DECREASE * best[0] or err < STALL_DECREASE * best[1]:
            quiet = 0
        else:
            quiet += 1
        best = [min(best[0], norm), min(best[1], err)]
        if quiet >= STALL_ITERATIONS:
            status, detail = 5, _stalled(err, size, tol, (
                f"the residual did not decrease in {quiet} iterations"))
            break
        if len(history["residual"]) >= max_iter:
            status = 1
            break
        J, active = counted.jacobian(x, parts, opts.get("z"))
        previous = x
        if method == "min":
            step = _min_step(counted, x, F, parts, J, opts, reduction)
            if step[3].get("status") == 3:  # singular: break round-off ties
                E_, A_, B_ = parts
                ties = TIE_RTOL * max(np.abs(A_).max(initial=0.0),
                                      np.abs(B_).max(initial=0.0))
                J, active = counted.jacobian(x, parts, opts.get("z"), ties)
                step = _min_step(counted, x, F, parts, J, opts, reduction)
            x, F, parts, record = step
        else:
            x, F, parts, record, watch = _fb_step(counted, x, F, parts, J,
                                                  opts, watch)
        with np.errstate(over="ignore"):
            merit = 0.5 * np.float64(norm) ** 2
        record.update(residual=norm, error=err, merit=float(merit),
                      active=active)
        for key in history:
            history[key].append(record[key])
        if callback is not None:
            callback(x, record)
        if record.get("status"):
            status, detail = record["status"], record.get("detail", "")
            break
        if reduction.all(np.array_equal(x, previous)):
            norm, err, size = measure(F, parts)
            status, detail = 5, _stalled(err, size, tol, "the Newton step "
                                         "no longer changes x")
            break
    norm, err, size = measure(F, parts)
    message = MESSAGES[status] + (f": {detail}" if detail else "")
    relative = err / size if size > 0 else (0.0 if err == 0 else np.inf)
    stopping = dict(test="‖Φ(x)‖₂ ≤ tol" if error is None and scale is None
                    else "error(x) ≤ tol·scale(x)", tol=float(tol),
                    scale=float(size), absolute=float(err),
                    relative=float(relative))
    return OptimizeResult(
        x=x, success=status == 0, status=status, message=message,
        nit=len(history["residual"]), njev=counted.njev, nfev=counted.nfev,
        fun=F, residual=norm, error=err, stopping=stopping, method=method,
        history=history, time=time.perf_counter() - start)


def _nonfinite(x, norm, err, size):
    """Which value of the stopping test is not finite (status 4)."""
    if not np.all(np.isfinite(x)):
        return "the iterate x has non-finite entries"
    names = [name for name, v in (("‖Φ‖", norm), ("the stopping measure",
                                                  err), ("the scale", size))
             if not np.isfinite(v)]
    return (" and ".join(names) + " not finite (an overflow: are the "
            "problem's values within the floating-point range?)")


def _stalled(err, size, tol, what):
    """The detail of status 5: how far the residual got, and whether tol
    is below what floating point reaches."""
    relative = err / size if size > 0 else np.inf
    if relative <= ROUNDOFF_LEVEL:
        return (f"{what}; the residual is at round-off level (relative "
                f"{relative:.1e}): tol = {tol:.1e} is below what floating "
                "point reaches for this problem")
    return (f"{what}; the relative residual {relative:.1e} is above "
            f"tol = {tol:.1e}")


def _min_step(counted, x, F, parts, J, opts, reduction):
    """One damped Newton iteration with φ_min (thesis §2.2.1, steps 2-4);
    ``reduction``'s norm over the ranks (:func:`solve_ncp`)."""
    d = newton_direction(J, F)
    if d is None:
        return x, F, parts, dict(alpha=0.0, step="newton",
                                 line_search_failed=False, status=3)
    norm, alpha = reduction.norm(F), 1.0
    while True:
        trial = x + alpha * d
        F_trial, trial_parts = counted.residual(trial)
        if reduction.norm(F_trial) < norm:
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


def _fb_step(counted, x, F, parts, J, opts, watch=None):
    """One iteration of the DFK method (thesis §2.2.2, steps 2-4), with
    the watchdog (module docstring) when ``opts["watchdog"]`` > 0:
    ``watch`` is None or the anchor (x, F, parts, d, ψ, slope, step, full
    steps left) of a run of full Newton steps. Returns (x, F, parts,
    record, watch)."""
    if watch is not None:
        x0, F0, parts0, d0, psi0, slope0, step0, left = watch
        psi = 0.5 * F @ F
        if np.isfinite(psi) and psi <= psi0 + opts["beta"] * slope0:
            watch = None  # (27) holds against the anchor: go on from x
        elif left <= 0:  # no decrease: back to the anchor, (27)'s step
            return _armijo(counted, x0, F0, parts0, d0, psi0, slope0,
                           step0, opts) + (None,)
    found = _fb_direction(J, F, opts)
    if isinstance(found, dict):
        return x, F, parts, found, None
    d, step, psi, slope = found
    if watch is not None:  # the run of full steps goes on
        trial = _full_step(counted, x, d, step)
        if trial is None:  # not finite: back to the anchor
            return _armijo(counted, x0, F0, parts0, d0, psi0, slope0,
                           step0, opts) + (None,)
        return trial + (watch[:7] + (left - 1,),)
    if opts.get("watchdog", 0) > 0 and step == "newton":
        trial = _full_step(counted, x, d, step)
        if trial is not None:
            if trial[3]["psi"] <= psi + opts["beta"] * slope:
                return trial + (None,)  # (27) at t = 1: an ordinary step
            anchor = (x, F, parts, d, psi, slope, step,
                      opts["watchdog"] - 1)
            return trial + (anchor,)
    return _armijo(counted, x, F, parts, d, psi, slope, step, opts) \
        + (None,)


def _fb_direction(J, F, opts):
    """(d, step kind, ψ, ∇ψᵀd) of the DFK method: the Newton direction
    unless it is singular or fails (26), then −∇ψ; or the record of a
    failure (an overflow)."""
    grad = J.rmatvec(F) if hasattr(J, "rmatvec") else J.T @ F  # ∇ψ (28)
    d = newton_direction(J, F)
    step = "newton"
    force, length = map(np.float64, opts["typical"] or (1.0, 1.0))
    with np.errstate(over="ignore", invalid="ignore"):
        descent = d is not None and (grad @ d) / force ** 2 <= -opts["rho"] * (
            np.linalg.norm(d) / length) ** opts["p"]  # (26)
    if not descent:
        d, step = -grad, "gradient"  # (26) failed or J singular
    with np.errstate(over="ignore", invalid="ignore"):
        psi, slope = 0.5 * F @ F, grad @ d
    if not (np.isfinite(psi) and np.isfinite(slope)):
        return dict(
            alpha=0.0, step=step, line_search_failed=False, status=4,
            detail="the merit function ψ = ½‖Φ‖² or its slope overflows "
                   "(are the problem's values within the floating-point "
                   "range?)")
    return d, step, psi, slope


def _full_step(counted, x, d, step):
    """x + d with its residual, or None if that is not finite."""
    trial = x + d
    F_trial, trial_parts = counted.residual(trial)
    with np.errstate(over="ignore", invalid="ignore"):
        psi_trial = 0.5 * F_trial @ F_trial
    if not np.isfinite(psi_trial):
        return None
    return trial, F_trial, trial_parts, dict(
        alpha=1.0, step=step, line_search_failed=False, psi=psi_trial)


def _armijo(counted, x, F, parts, d, psi, slope, step, opts):
    """The backtracking (27) from x along d: (x, F, parts, record)."""
    t = 1.0
    for _ in range(opts["max_halvings"] + 1):
        trial = x + t * d
        F_trial, trial_parts = counted.residual(trial)
        with np.errstate(over="ignore", invalid="ignore"):
            psi_trial = 0.5 * F_trial @ F_trial
        if psi_trial <= psi + opts["beta"] * t * slope:  # (27)
            return trial, F_trial, trial_parts, dict(
                alpha=t, step=step, line_search_failed=False)
        t /= 2
    return x, F, parts, dict(alpha=0.0, step=step, line_search_failed=True,
                             status=2)
