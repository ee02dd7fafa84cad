r"""Nested iteration on Γc: a coarse-to-fine start for the condensed system.

From the cold start λ = 0 every penetrating node looks active; Newton
with φ_min (the primal-dual active set method here) releases only part of
that excess per iteration, so its count grows like log Nc. Nested
iteration (full multigrid's start, as Hüeber and Wohlmuth use it) removes
that growth: solve with constraints at every other node of Γc, then every
other of those, …, down to a handful of nodes, from the coarsest (cold)
to the finest, each level started from the one below. A level of m nodes
costs O(m³): all coarser levels together cost less than one more
iteration on the finest.

The coarse problems are exact: level ℓ + 1 keeps the nodes ``keep`` of
level ℓ and condenses the others (r) out with no contact force on them,

.. math:: S_{ℓ+1} = S_{kk} − S_{kr} S_{rr}^{-1} S_{rk}, \qquad
          w_{ℓ+1} = (w_ℓ)_k,

w = K⁻¹f (g̃ = S w); a solution is prolonged by that same equilibrium,
u_r = w_r − S_{rr}^{-1}S_{rk}(u_k − w_k). The gap rows are scaled by k̄
(with c = 1 φ_min's line search rejects good steps from such a start).
The coarsening follows Γc's order along the 2D curve; a 3D surface has
none and starts free.

References
----------
S. Hüeber, B. Wohlmuth: A primal-dual active set strategy for non-linear
multibody contact problems. Comput. Methods Appl. Mech. Engrg. 194 (2005)
3147-3166.
M. Hintermüller, K. Ito, K. Kunisch: The primal-dual active set strategy as
a semismooth Newton method. SIAM J. Optim. 13 (2002) 865-888."""

import time

import numpy as np
import scipy.linalg as sla

from ...linalg.threads import single_blas_thread
from ...ncp import solve_ncp
from ..frictionless.system import FrictionlessSystem

__all__ = ["COARSEST", "ContactLevel", "contact_levels", "solve_nested",
           "add_run", "run_level"]

#: Coarsening stops when a level has at most this many contact nodes.
COARSEST = 8


class ContactLevel:
    """One level of the hierarchy, the condensed problem on a node subset:
    ``nodes`` (positions in the finest level's list), ``S`` (the Schur
    complement of K on their DOFs), ``w`` (K⁻¹f there), ``geometry``
    (renumbered to them), ``keep`` (the nodes the next coarser level keeps;
    None on the coarsest) and ``X`` (S_rr⁻¹S_rk, prolonging a coarser
    level's u to the dropped DOFs)."""

    def __init__(self, nodes, S, w, geometry):
        self.nodes, self.S, self.w, self.geometry = nodes, S, w, geometry
        self.keep = self.X = None

    def prolong(self, u_coarse):
        """This level's u from the next coarser level's u: the kept DOFs
        take it, the others follow from equilibrium without contact force."""
        kept = self.keep[_owner(self.geometry)]
        u = np.empty(len(self.w))
        u[kept] = u_coarse
        u[~kept] = self.w[~kept] - self.X @ (u_coarse - self.w[kept])
        return u


def _subset(geometry, nodes):
    """``geometry`` (of the finest level, local DOFs) at ``nodes``,
    renumbered to the level's DOFs."""
    return geometry.subset(nodes).compact()


def _owner(geometry):
    """The node of each condensed DOF (d per node; fewer at a roller)."""
    counts = (geometry.node_dofs >= 0).sum(axis=1)
    return np.repeat(np.arange(len(counts)), counts)


def contact_levels(S, w, geometry, coarsest=COARSEST):
    """The hierarchy, finest first: level 0 is (S, w, geometry) itself, each
    next level keeps every other node along Γc (and the last one) until at
    most ``coarsest`` nodes remain. S: the Schur complement of K on the
    free contact DOFs, w: K⁻¹f there, ``geometry`` renumbered to them
    (:func:`~.reduction.condense_onto_contact`)."""
    m = len(geometry.gap)
    levels = [ContactLevel(np.arange(m), S, np.asarray(w, float), geometry)]
    with single_blas_thread():  # dense, at most the size of S
        while len(levels[-1].nodes) > coarsest:
            levels.append(_coarsen(levels[-1], geometry))
    return levels


def _coarsen(level, geometry):
    """The next coarser level of ``level`` (sets its ``keep`` and X)."""
    keep = np.zeros(len(level.nodes), dtype=bool)
    keep[::2] = keep[-1] = True
    kept = keep[_owner(level.geometry)]
    k, r = np.flatnonzero(kept), np.flatnonzero(~kept)
    S_rk = level.S[np.ix_(r, k)]
    level.keep = keep
    level.X = sla.cho_solve(sla.cho_factor(level.S[np.ix_(r, r)]), S_rk)
    S_k = level.S[np.ix_(k, k)] - S_rk.T @ level.X
    nodes = level.nodes[keep]
    return ContactLevel(nodes, 0.5 * (S_k + S_k.T), level.w[k],
                        _subset(geometry, nodes))


def add_run(totals, history, result, label, value):
    """Add one NCP run's counts to ``totals`` and its history to ``history``,
    with ``value`` (its level or round) per iteration in ``history[label]``."""
    for key in totals:
        totals[key] += result[key]
    for key, values in result.history.items():
        history.setdefault(key, []).extend(values)
    history.setdefault(label, []).extend([value] * result.nit)


def solve_nested(levels, method="min", tol=1e-10, max_iter=100,
                 gap_scale=1.0, stiffness=1.0, options=None, load_norm=None):
    """Solve the condensed frictionless system level by level, coarsest
    (from λ = 0) to finest (from the prolonged coarser solution).

    ``tol`` is relative as in :func:`~..frictionless.driver.run_frictionless`,
    with ‖f‖₂ = ``load_norm`` (default: the finest level's) on every level.
    ``max_iter`` bounds the iterations of all levels together: once spent,
    the last iterate is prolonged to the finest level and reported there as
    not converged (status 1). A coarse level that stops for another reason
    is dropped (the next starts from λ = 0 again). If λ = 0 already solves
    the finest level, no coarse level runs.

    Returns (OptimizeResult, FrictionlessSystem) of the finest level, with
    the counts and ``history`` of every level (``history["level"]``: each
    iteration's number of nodes) and ``levels``: per level, coarsest first,
    ``n_nodes``, counts, ``success`` and ``time``."""
    fine = levels[0]
    fine_system = _system(fine, gap_scale, stiffness, load_norm)
    load_norm = fine_system.load_norm
    start = time.perf_counter()
    probe = solve_ncp(fine_system.residual, fine_system.jacobian, fine.w,
                      method=method, tol=tol, max_iter=0, options=options,
                      error=fine_system.error, scale=fine_system.scale)
    if probe.success or probe.status == 4:  # solved, or overflow at λ = 0
        probe.history["level"] = []
        probe.update(levels=[dict(
            n_nodes=len(fine.nodes), nit=0, njev=0, nfev=probe.nfev,
            success=bool(probe.success), time=time.perf_counter() - start)])
        return probe, fine_system
    u, report, budget = None, [], max_iter
    totals, history = dict(nit=0, njev=0, nfev=probe.nfev), {}
    for depth in range(len(levels) - 1, -1, -1):
        level = levels[depth]
        x0 = level.w if u is None else level.prolong(u)
        if depth and not budget:  # out of iterations: carry the iterate up
            u = x0
            continue
        system = fine_system if depth == 0 else _system(
            level, gap_scale, stiffness, load_norm)
        result = run_level(system, x0, len(level.nodes), method, tol,
                           budget, options, (totals, history, report))
        budget -= result.nit
        u = result.x if result.success or result.status == 1 else None
    result.update(totals, history=history, levels=report)
    return result, system


def run_level(system, x0, n_nodes, method, tol, budget, options, tally):
    """Newton on one level's ``system`` from ``x0`` (at most ``budget``
    iterations), its counts added to ``tally`` = (totals, history,
    report): :func:`add_run` and one ``report`` entry (n_nodes, counts,
    success, time). Returns the NCP result."""
    totals, history, report = tally
    start = time.perf_counter()
    result = solve_ncp(system.residual, system.jacobian, x0, method=method,
                       tol=tol, max_iter=budget, options=options,
                       error=system.error, scale=system.scale)
    add_run(totals, history, result, "level", n_nodes)
    report.append(dict(n_nodes=n_nodes, nit=result.nit, njev=result.njev,
                       nfev=result.nfev, success=bool(result.success),
                       time=time.perf_counter() - start))
    return result


def _system(level, gap_scale, stiffness, load_norm=None):
    """(67) on a level: K → S_ℓ, f → S_ℓ w_ℓ."""
    return FrictionlessSystem(level.S, level.S @ level.w, level.geometry,
                              gap_scale, stiffness, load_norm)
