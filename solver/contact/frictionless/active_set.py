r"""The frictionless system (67) on the full primal system, by the
primal–dual active set method with inexact Newton systems solved by
AMG-preconditioned projected CG: the iterative path (``backend="amg"``),
which factorises nothing mesh-sized.

Semismooth Newton with φ_min on (67) *is* the primal–dual active set method
(Hintermüller, Ito & Kunisch, SIAM J. Optim. 13, 2002; for contact Hüeber,
Stadler & Wohlmuth, SISC 30, 2008): at the iterate u with normal contact
forces λ = −Y(RKu − Rf) (:mod:`.system`) the active set is

.. math::  A = \{ i : λ_i − c (s_i − u_{n,i}) > 0 \},

and the Newton step solves K u = f − C_Aᵀ λ_A with u_n = s on A and λ = 0
off A, C the normal rows of R. Eliminating λ_A leaves the SPD problem
P_A K u = P_A f on the affine set C_A u = s_A; λ follows from u. R is
orthogonal (unless a roller's normal leaves its free plane), so in
y = R u the constraints fix the active normal DOFs and the system is the
principal submatrix K̂_FF y_F = (R f − K̂ y_A)_F of K̂ = R K Rᵀ
(:func:`~solver.contact.geometry.rotate_stiffness`), an elasticity
operator with a Dirichlet-like condition on the contact zone. Its CG is
preconditioned by a V-cycle of K̂_FF built from the one hierarchy of K
(built once per solve) by :meth:`solver.linalg.amg.Multigrid.eliminated`:
the same aggregates, only the Galerkin products renewed per active set.
The projected CG with K's own V-cycle, P M P
(:func:`solver.linalg.amg.projected_cg`), needs CG counts that grow like
h^(−1/2) (the active set's Schur complement; :mod:`solver.linalg.amg`);
it remains the path when R is not orthogonal (:data:`ORTHOGONAL_TOL`).
Every system is warm-started from the previous u moved onto the new
constraints.

The first active set (issue 33). From u = 0 the first Newton system has
A = ∅ and gives the free solution u_f; the method's own next set, every
node u_f penetrates, overshoots: on a smooth, non-conforming contact the
free interference is d(r) = δ − r²/(2R) (δ the approach, R the relative
radius of curvature), which is positive to r = √(2Rδ), while Hertz's
contact radius is a = √(Rδ) (Johnson, *Contact mechanics*, 1985, §4.2).
From such an overshoot the set
shrinks by the zone where the constrained pressure turns negative, which
halves the excess area per step (for a paraboloid pressed to a radius
b > a the pressure is zero at r² = (b² + a²)/2), so the Newton count grows
as log₂(a/h). Hertz's contact edge is where the interference is half the
approach, d(a) = δ/2; so the second set is :func:`hertz_start`, the nodes
whose free interference is at least :data:`START_FRACTION` of the
largest. It is Hertz's circle to O(h) for an axisymmetric paraboloid,
an ellipse somewhat rounder than Hertz's for an elliptic one, every
penetrating node for a flat punch (uniform interference); where the
contact is not Hertzian it is a start that the method corrects. The free solution is solved to η_0 =
:data:`ETA_MAX` (its bulk is a rigid translation, which the near-null
space carries: a few CG iterations).

A body held by contact only (issue 33; K singular, its kernel the
rigid-body modes R that no support stops): there is no free solution.
The first iterate is the rigid body put onto the obstacle by the load (a
linear programme, :class:`~solver.contact.strategies.floating.
RigidPlacement`), the first active set its touching nodes, which hold
every mode the contact can hold (the factorisation paths' start,
:mod:`~solver.contact.strategies.floating`); every later set is kept
holding them (nodes of largest λ − c(s − u_n) added while the active
normals see fewer modes than all normals do), so each K̂_FF is regular
except along the modes V that no contact normal sees (a flat on a flat
pushed along itself), which lie in its kernel and carry no load (checked
before the solve, the factorisation paths' one-line refusal otherwise):
CG runs on their orthogonal complement and the answer has no share along
them, as the factorisation path removes it. The V-cycles' coarsest
level inherits the kernel and is solved by its pseudo-inverse
(:class:`~solver.linalg.amg.Multigrid`, ``singular``).

Inexact Newton: while the active set changes, the system is solved to
‖P_A(f − Ku)‖ ≤ η_k·err_k with Eisenstat & Walker's (SISC 17, 1996)
choice 2, η_k = γ (err_k / err_{k−1})², safeguarded by γη_{k−1}² when that
exceeds 0.1 and kept within [:data:`ETA_MIN`, :data:`ETA_MAX`]. The cap is
tight because from Hertz's first set each step moves only a few nodes at
the edge of the zone, and the signs of their forces are what the next set
is made of: a loosely solved system gets some of them wrong and costs
further Newton systems (benchmarks/README.md, issue 33). Once the active
set repeats, the system is the last one (unless a sign is wrong) and is
solved to :data:`FINAL_FRACTION` of the stopping test's bound. The
stopping test and the verification are those of every other path
(:mod:`solver.contact.verify`)."""

import time

import numpy as np
import scipy.sparse as sp

from ...linalg.amg import projected_cg, projected_gmres
from ...linalg.threads import single_blas_thread
from ...ncp import MESSAGES, stable_norm
from ..geometry import rotate_stiffness, rotation
from ..verify import force_scale

__all__ = ["solve_active_set", "hertz_start", "eliminated_step",
           "is_orthogonal", "record_krylov", "forcing_term", "ETA_MIN",
           "ETA_MAX",
           "ETA_GAMMA", "FINAL_FRACTION", "KRYLOV_MAX", "START_FRACTION",
           "ORTHOGONAL_TOL"]

#: η_0 and the cap of the forcing terms (module docstring: the signs at
#: the edge of the zone).
ETA_MAX = 1e-3
#: The floor of the forcing terms while the active set changes: a system
#: whose active set is still wrong is not worth solving more accurately.
ETA_MIN = 1e-4
#: γ of Eisenstat–Walker's choice 2.
ETA_GAMMA = 0.9
#: The last Newton system is solved to this fraction of tol·F.
FINAL_FRACTION = 0.5
#: CG iterations at most per Newton system.
KRYLOV_MAX = 2000
#: The first active set takes the nodes whose free interference is at
#: least this fraction of the largest (Hertz: d(a) = δ/2).
START_FRACTION = 0.5
#: The Newton systems are solved on the eliminated K̂_FF when
#: max |R Rᵀ − I| is at most this (module docstring), else projected.
ORTHOGONAL_TOL = 1e-12


def forcing_term(eta, err, previous_error, safeguard=True):
    """Eisenstat & Walker's (SISC 17, 1996) choice 2 for the next Newton
    system (module docstring): η_k = γ (err_k / err_{k−1})², with
    ``safeguard`` at least γη_{k−1}² where that exceeds 0.1 and kept
    within [:data:`ETA_MIN`, :data:`ETA_MAX`], ``eta`` = η_{k−1};
    without it only capped at :data:`ETA_MAX` (Newton's own rate, the
    friction path's last systems while 3D slip directions still turn).
    Shared by every inexact Newton of the project, in process and under
    ``mpiexec`` (:class:`solver.mpi.full.ForcingTerm`)."""
    eta_new = ETA_GAMMA * (err / previous_error) ** 2
    if not safeguard:
        return min(eta_new, ETA_MAX)
    if ETA_GAMMA * eta ** 2 > 0.1:
        eta_new = max(eta_new, ETA_GAMMA * eta ** 2)
    return min(max(eta_new, ETA_MIN), ETA_MAX)


def hertz_start(interference):
    """The first active set (module docstring) from the free solution's
    ``interference`` d = u_n − s at the contact nodes: d ≥
    :data:`START_FRACTION` · max d, or None when nothing penetrates (the
    method's own rule then applies)."""
    deepest = float(np.max(interference, initial=0.0))
    if not deepest > 0:
        return None
    return interference >= START_FRACTION * deepest


def solve_active_set(problem, geometry, multigrid, tol, max_iter, x0,
                     gap_scale, stiffness, load_norm, floating=None):
    """Solve (67) for ``problem`` (its reduced K, f) and the contact
    ``geometry`` by the active set method of the module, with the
    preconditioner ``multigrid`` (a V-cycle of K), from ``x0`` (None: u =
    0) and c = ``gap_scale``. Returns (result, λ, u_n): the NCP result
    fields (``x``, ``success``, ``status``, ``message``, ``nit``, ``njev``
    = Newton systems solved, ``nfev``, ``history`` with ``krylov`` per
    system, ``krylov`` in total, ``stopping``) and the answer's normal
    forces and displacements at the nodes of ``geometry``. ``floating``:
    a body held by contact only, its :class:`~solver.contact.strategies.
    floating.RigidPlacement` (module docstring)."""
    with single_blas_thread():  # vectors: BLAS threads only spin
        return _iterate(problem, geometry, multigrid, tol, max_iter, x0,
                        gap_scale, stiffness, load_norm, floating)


def is_orthogonal(R):
    """Whether the sparse R is orthogonal to :data:`ORTHOGONAL_TOL`."""
    E = (R @ R.T - sp.identity(R.shape[0], format="csr")).tocsr()
    return bool((abs(E).max() if E.nnz else 0.0) <= ORTHOGONAL_TOL)


def eliminated_step(K_hat, f_hat, R, multigrid, fixed, start, atol,
                    spring=None, coupling=None, free=None, hold=None):
    """One Newton system on the eliminated K̂_FF (module docstring): the
    DOFs ``fixed`` of y = R ``start`` keep their values, the others solve
    K̂_FF y_F = (f̂ − K̂ y_fixed)_F by CG preconditioned with
    ``multigrid.eliminated`` to ‖·‖ ≤ ``atol`` (the norm of P_A(f − Ku),
    R being orthogonal). ``spring``: S (n, n) in y, zero on the fixed rows
    and columns, added to K̂ (friction's slip springs). ``coupling``: a
    nonsymmetric sparse N (n, n) in y added to K̂ + S (friction's implicit
    bound, :mod:`..friction.active_set`): the system is then solved by
    right-preconditioned GMRES with the same V-cycle, that of the
    symmetric K̂ + S. ``free``: the rigid-body modes (n, k) in u that no
    fixed DOF sees (a body held by contact only, :class:`~solver.contact.
    strategies.floating.RigidPlacement`), in the kernel of K̂_FF: the
    Krylov method runs on their orthogonal complement (the projection C
    = W_Fᵀ, W = R ``free`` orthonormalised; the load has no share along
    them, checked before the solve), so the answer has none. ``hold``:
    sparse rows Z (k, n) on u instead, Z u = Z ``start`` kept (friction's
    modes that no constraint sees, :meth:`~solver.contact.strategies.
    floating.RigidPlacement.unheld`; Z on DOFs that R does not rotate),
    by the orthogonal projection onto the null space of Z Rᵀ's rows
    orthonormalised. Returns (the
    KrylovResult, with ``setup`` the seconds of the hierarchy, and u =
    Rᵀ y)."""
    keep = np.ones(len(f_hat), bool)
    keep[fixed] = False
    y = R @ start
    y_fixed = np.where(keep, 0.0, y)
    b = (f_hat - K_hat @ y_fixed)[keep]
    preconditioner = multigrid.eliminated(K_hat, R, keep, spring)
    C, x0 = None, y[keep]
    if free is not None and free.shape[1]:
        W, _ = np.linalg.qr(np.asarray(R @ free)[keep])
        C = sp.csr_matrix(W.T)
        x0 = x0 - W @ (W.T @ x0)
    elif hold is not None and hold.shape[0]:
        W, _ = np.linalg.qr((hold @ R.T)[:, keep].toarray().T)
        C = sp.csr_matrix(W.T)
    if coupling is None:
        krylov = projected_cg(preconditioner.matrix, b, preconditioner,
                              x0, C, atol=atol, maxiter=KRYLOV_MAX)
    else:
        coupling = sp.csr_matrix(coupling)
        b = b - (coupling @ y_fixed)[keep]
        A = (preconditioner.matrix + coupling[keep][:, keep]).tocsr()
        krylov = projected_gmres(A, b, preconditioner, x0, C, atol=atol,
                                 maxiter=KRYLOV_MAX)
    krylov.setup = preconditioner.setup_time
    y[keep] = krylov.x
    return krylov, R.T @ y


def record_krylov(history, krylov, atol, err):
    """Append what one Newton system's CG (``krylov``, a KrylovResult)
    did to ``history``: ``krylov`` iterations, ``forcing`` atol/err,
    ``krylov_decades`` of residual gained, ``setup`` seconds of its
    hierarchy. Returns why it failed (a sentence), or None."""
    history["krylov"].append(krylov.iterations)
    history["forcing"].append(atol / err if err > 0 else 0.0)
    history["krylov_decades"].append(
        float(np.log10(krylov.initial / krylov.residual))
        if krylov.residual > 0 and krylov.initial > 0 else 0.0)
    history["setup"].append(krylov.setup)
    if krylov.converged:
        return None
    return (f"{krylov.method} did not reach its tolerance in "
            f"{krylov.iterations} iterations")


def _iterate(problem, geometry, multigrid, tol, max_iter, x0, gap_scale,
             stiffness, load_norm, floating):
    clock = time.perf_counter()
    K, f, s = problem.K, problem.f, geometry.gap
    n = problem.n_dofs
    R, _, _, normal_rows = rotation(n, geometry)
    other = np.ones(n, bool)
    other[normal_rows] = False
    C = R[normal_rows].tocsr()
    row_norm = np.asarray(C.multiply(C).sum(axis=1)).ravel()
    eliminate = is_orthogonal(R)
    if eliminate:
        K_hat = rotate_stiffness(K, R, geometry.free_dofs())
        f_hat = R @ f
    if floating is not None and not eliminate:
        from ...errors import SolverError

        raise SolverError(
            "backend='amg' needs an orthogonal rotation of the contact "
            "frames for a body held by contact only (a roller's normal "
            "leaves its free plane here): use a factorisation")
    u = np.zeros(n) if x0 is None else np.array(x0, float)
    if floating is not None and x0 is None:  # the rigid placement
        u = floating.u.copy()
    history = {k: [] for k in ("residual", "error", "merit", "alpha",
                               "step", "active", "line_search_failed",
                               "krylov", "forcing", "krylov_decades",
                               "setup")}
    previous_set, previous_error, eta = None, None, ETA_MAX
    free = False  # the last system solved gave the free solution
    status, detail, njev, nfev = 1, "", 0, 0
    while True:
        Rr = R @ (K @ u - f)
        E, lam = Rr[other], -Rr[normal_rows]
        un = C @ u
        comp = np.minimum(lam, stiffness * (s - un))
        err = float(np.hypot(stable_norm(E), stable_norm(comp)))
        residual = float(np.hypot(stable_norm(E), stable_norm(
            np.minimum(lam, gap_scale * (s - un)))))
        scale = force_scale(load_norm, lam)
        if not np.isfinite(err) or not np.all(np.isfinite(u)):
            status, detail = 4, "the iterate is not finite"
            break
        nfev += 1
        if err <= tol * scale:
            status = 0
            break
        if njev >= max_iter:
            break
        score = lam - gap_scale * (s - un)
        active = score > 0
        if free:  # the free solution was just solved: Hertz's set
            free, first = False, hertz_start(un - s)
            if first is not None:
                active = first
        if floating is not None:  # the placement's nodes, then held
            if njev == 0 and x0 is None:
                active = floating.touching
            active = floating.hold(active, score)
        history["residual"].append(residual)  # before each Newton step
        history["error"].append(err)
        history["merit"].append(0.5 * residual ** 2)
        history["active"].append(int(active.sum()))
        final = previous_set is not None and np.array_equal(active,
                                                            previous_set)
        if previous_error is not None and not final:
            eta = forcing_term(eta, err, previous_error)
        floor = FINAL_FRACTION * tol * scale
        atol = floor if final else max(eta * err, floor)
        free = x0 is None and njev == 0 and not active.any() \
            and floating is None
        rows = np.flatnonzero(active)
        CA = C[rows]
        start = u + CA.T @ ((s[rows] - un[rows]) / row_norm[rows])
        if eliminate and rows.size:
            krylov, x = eliminated_step(
                K_hat, f_hat, R, multigrid, normal_rows[rows], start, atol,
                free=None if floating is None else floating.free)
        else:
            krylov = projected_cg(K, f, multigrid, start, CA, atol=atol,
                                  maxiter=KRYLOV_MAX)
            x = krylov.x
        njev += 1
        history["step"].append(float(np.linalg.norm(x - u)))
        history["alpha"].append(1.0)
        history["line_search_failed"].append(False)
        failure = record_krylov(history, krylov, atol, err)
        u = x
        previous_set, previous_error = active, err
        if failure:
            status, detail = 5, failure
            break
    message = MESSAGES[status] + (f": {detail}" if detail else "")
    result = dict(
        x=u, success=status == 0, status=status, message=message,
        nit=njev, njev=njev, nfev=nfev, residual=residual, error=err,
        method="min",
        krylov=int(sum(history["krylov"])), history=history, levels=[],
        stopping=dict(test="error(x) ≤ tol·scale(x)", tol=float(tol),
                      scale=float(scale), absolute=float(err),
                      relative=float(err / scale) if scale > 0 else 0.0),
        time=time.perf_counter() - clock)
    return result, lam, un
