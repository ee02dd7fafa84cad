r"""The start of a condensed load step: the step's predictor Δu (Γc moving
as the unconstrained body) with its normal contact forces corrected.

The normal contact problem of the step is solved with the friction
tractions held at the previous step's: the increment e = −C_{:,n} z (C =
R S⁻¹ Rᵀ, the flexibility; z the change of the normal forces) with

.. math::  λ + z \ge 0, \quad s − u_n + C_{nn} z \ge 0, \quad
           (λ + z)^T (s − u_n + C_{nn} z) = 0,

λ and s − u_n those of the predictor. Why: the predictor pushes the nodes
in contact into the obstacle by the step's whole free motion, far from the
complementarity set, where φ_FB is curved and its Newton step removes only
part of the penetration per iteration; started on the set, both methods
meet φ_FB's curvature only where the step changes the contact set. The
linear complementarity problem (C_nn SPD) is solved by the primal-dual
active set method (Hintermüller, Ito & Kunisch, SIAM J. Optim. 13 (2002)
865-888) from the penetrating nodes. Only for the projection formulation
on a condensed system: the full system starts from Δu = 0 as in the
thesis, and the thesis's split keeps the predictor (its condensed Newton
path is sensitive to the start).

In 3D (:class:`~.disc.DiscSystem`) the predictor is extrapolated
(:func:`extrapolated`) before the correction: within a stretch of equal
load increments the step's Δu and g_t are predicted as the previous
step's plus its increment, u_κ ≈ u_{κ−1} + Δu_{κ−1}, g_κ ≈ g_{κ−1} +
(g_{κ−1} − g_{κ−2}), the secant predictor of path-following methods.
From the free motion alone, which holds g_t, the first Newton steps of
each load step on the Hertz sphere were damped (α = 2⁻⁵…2⁻¹); from the
secant predictor they are full steps (benchmarks/README.md, "3D
friction: the extrapolated start"). 2D keeps the free motion for now:
the extrapolated start cuts its Jacobians too, but the 2D counts the
README and notebooks quote have not all been re-run with it."""

import numpy as np
import scipy.linalg as sla

from ...linalg.threads import single_blas_thread

__all__ = ["contact_corrected", "extrapolated", "START_PASSES",
           "EXTRAPOLATE"]

#: Passes of the primal-dual active set iteration; without convergence
#: the predictor is returned as it is (a start only).
START_PASSES = 50

#: Extrapolate the 3D predictor from the previous step (module
#: docstring); False: the free motion only (the tests' reference).
EXTRAPOLATE = True


def extrapolated(system, state, free):
    """(Δu, g_t) to start a step of a condensed 3D projection ``system``
    from, before :func:`contact_corrected`: ``free`` is the step's free
    motion of Γc (w_κ − w_{κ−1} on the system's unknowns) and ``state``
    the run's (u, g of step κ−1; ``free_last``, ``du_last``, ``g_last``
    of step κ−1 once it exists). Where the step's free motion equals the
    previous step's (equal load increments, to 1e-12), the previous
    step's increment Δu_{κ−1} and g_{κ−1} + (g_{κ−1} − g_{κ−2}) (module
    docstring); else ``free`` and g_{κ−1}, as without extrapolation."""
    last = getattr(state, "free_last", None)
    if not EXTRAPOLATE or system.dim != 3 or last is None \
            or system.formulation != "projection" \
            or not np.allclose(free, last, rtol=0.0,
                               atol=1e-12 * np.abs(free).max(initial=0.0)):
        return free, state.g
    return state.du_last.copy(), 2.0 * state.g - state.g_last


def contact_corrected(system, du):
    """The predictor ``du`` of a condensed projection ``system``'s step
    (after its :meth:`~.system.FrictionSystem.set_step`) with its normal
    contact forces corrected (module docstring); ``du`` itself where the
    correction does not apply or nothing touches."""
    du = np.asarray(du, float)
    if not system.m or system.formulation != "projection" \
            or not system.dense_schur:
        return du
    nr = system.n_rows
    lam = -system._force(du)[nr]
    gap = system.geometry.gap - (system.R @ (system.u_previous + du))[nr]
    if not (gap < 0.0).any() and not (lam > 0.0).any():
        return du  # nothing touches: the predictor is the step's answer
    with single_blas_thread():  # Γc's size, as solve_ncp's algebra
        return _corrected(system, du, lam, gap)


def _corrected(system, du, lam, gap):
    """:func:`contact_corrected` once something touches."""
    C_n, M = _normal_flexibility(system)
    q = gap - M @ lam
    rho = 1.0 / np.diagonal(M)
    active = gap < 0.0
    for _ in range(START_PASSES):
        y = np.zeros(system.m)
        if active.any():
            y[active] = sla.solve(M[np.ix_(active, active)], -q[active],
                                  assume_a="pos", check_finite=False)
        following = y - rho * (q + M @ y) > 0.0
        if np.array_equal(following, active):
            break
        active = following
    else:
        return du
    return du - system.RT @ (C_n @ (y - lam))


def _normal_flexibility(system):
    """(C[:, n], C[n, n]) of the flexibility C = R S⁻¹ Rᵀ, in rotated
    components (made once per system and kept on it)."""
    cached = getattr(system, "normal_flexibility", None)
    if cached is None:
        nr = system.n_rows
        if system.reduced or getattr(system, "shares_flexibility", False):
            C_n = system.flexibility()[:, nr]
        else:
            factor = sla.cho_factor(system.K.toarray(), overwrite_a=True,
                                    check_finite=False)
            C_n = system.R @ sla.cho_solve(factor, system.R[nr].T.toarray(),
                                           check_finite=False)
        C_n = np.ascontiguousarray(C_n)
        cached = system.normal_flexibility = (C_n, C_n[nr])
    return cached
