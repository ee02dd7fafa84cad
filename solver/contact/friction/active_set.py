r"""Coulomb friction on the iterative path (``backend="amg"``): each load
step of the projection formulation (:mod:`.projection`, lagged or
implicit bound) by the primal–dual active set method of Hüeber, Stadler
& Wohlmuth (SISC 30, 2008), its Newton systems by AMG-preconditioned CG
(GMRES for the implicit bound) on the primal system with the constrained
DOFs eliminated (or projected); nothing mesh-sized is factorised.

The step's unknowns are u = u_{κ−1} + Δu and the tractions g; the
tangential equilibrium rows r_t(u) = D g (r = R(Ku − f_κ), D the lumped
boundary matrix) are linear, so g = r_t(u)/D is eliminated exactly and
the Newton iterates live in u alone. At the iterate, with w = g −
c_t Δu_t (c_t of :class:`~.system.FrictionSystem`) and the lagged radius
b = f_c p_{κ−1}, every contact node falls into one of the sets of the
method (semismooth Newton with φ_min on the projection rows g = P(w)):

* normal: active A = {λ − c(s − u_n) > 0} (u_n = s) or inactive (λ = 0),
  c = k̄ as on the frictionless path (:mod:`..frictionless.active_set`);
* stick |w| < b: Δu_t = 0, the tangential rows constrained;
* slip |w| ≥ b: with ŵ = w/|w|, q = b/|w| ≤ 1, the Newton step of
  g = P(w), ∂P/∂w = q(I − ŵŵᵀ), gives

  .. math::  g·ŵ = b, \qquad g·e = −\frac{q}{1 − q}\, c_t\, Δu·e

  for the tangent e ⟂ ŵ (3D; none in 2D or at a roller, whose other
  tangent is prescribed), because w·e = 0 at the iterate: the slip
  direction carries the bound as a load, and the direction across it a
  spring k_e = D c_t q/(1 − q) ≥ 0. In 2D the slip rows are pure loads.
  A zero radius (b = 0: no contact at step κ−1) leaves the node free.
  A slip node whose direction turned back against the last iterate's
  (ŵ·ŵ_prev < 0) twice in a row is put in the stick set for the next
  system: a node whose answer sticks can otherwise alternate between two
  opposite slip directions for ever, the sets unchanged and the error
  constant (in 2D, where ŵ is a sign: the Hertz cylinders between two
  bodies, 40 systems without progress; in 3D: the two unequal spheres,
  ŵ = −ŵ_prev to three digits on every system until the Newton limit).
  Like the spring, this shapes only the Newton path; the stopping test
  is the formulation's.

Two bodies (dual mortar) come as their nodewise equivalent in v = T u
(:mod:`solver.contact.two_body`): the slave node's v is its displacement
relative to the master's, so the same sets, rows and eliminations apply
to the weighted slip, with K̃ = T⁻ᵀKT⁻¹ and each body's rigid modes
through T as the hierarchy's near-null space.

The "nonsymmetric" linearised slip term of Hüeber, Stadler & Wohlmuth is
symmetric here because g has been eliminated with the lagged radius: the
Newton system is the SPD K + Σ k_e v vᵀ (v = R_tᵀe, one rank-one spring
per 3D slip node) on the affine set of the normal and stick constraints.
The spring only shapes the Newton path: at a fixed point g·e = 0, so the
answer is that of the factorisation path.

The implicit bound b = f_c p(u) (``coulomb="implicit"``): p = −r_n/D is
linear in u, so the slip rows g·ŵ = b are the linear rows
r_t·ŵ + f_c r_n = 0, the normal reaction's row added f_c ŵ times to the
node's tangential rows (N of :func:`bound_rows`): the Newton matrix is
K + S + Rᵀ N R K, nonsymmetric, and is solved by right-preconditioned
GMRES (:func:`~solver.linalg.amg.projected_gmres`) with the V-cycle of
its symmetric part K + S, the same hierarchy as the lagged bound's. The
sets are decided with the bound measured as the active set is,
b = f_c max(λ − c(s − u_n), 0)/D (the quantity of the normal sets, as
in Hüeber, Stadler & Wohlmuth's bound), which equals f_c p at a fixed
point; a node leaving the
active set thus carries no friction, and a node entering it has a bound
from its first Newton system on (with f_c λ/D the pressing step of a
dragged block cycled between two sets).

Where R is orthogonal (:func:`~..frictionless.active_set.is_orthogonal`)
the constraints fix DOFs of y = R u, the active normals and the stick
tangentials, and the system is solved eliminated as on the frictionless
path (:func:`~..frictionless.active_set.eliminated_step`): CG on
(K̂ + S)_FF, K̂ = R K Rᵀ, whose spring S = Eᵀ diag(k_e) E (R v = Eᵀ e: e
on the node's two tangent rows) is a 2 × 2 block per slip node, inside
K̂'s pattern; its V-cycle is :meth:`~solver.linalg.amg.Multigrid.
eliminated` of the one hierarchy of K (built once for all load steps),
K's aggregates and prolongator with the fixed rows dropped and the first
coarse operator updated through the fixed and the slip rows. The
preconditioner then sees neither the constraints' Schur complement nor
the springs as a perturbation, so the CG count per system stays nearly
flat under refinement (benchmarks/README.md). A spring there is capped at
:data:`SPRING_CAP` (no constraint across the slip, which would not be a
DOF of y). Otherwise the system is solved by
:func:`~solver.linalg.amg.projected_cg` with K's own V-cycle, the springs
left to CG.

A body held by contact only (K singular, its kernel the rigid-body
modes; :class:`FloatingIterativeSpace`): the hierarchy's coarsest level
is solved by a pseudo-inverse, the first contact starts from the rigid
placement, and each Newton system is held along the modes its
constraints leave free.

Warm starts: each step starts from u_{κ−1} (the sets of the new load at
the old answer) and each Newton system from the last iterate moved onto
its constraints. Inexact Newton with Eisenstat & Walker's forcing term as
on the frictionless path (its :data:`~..frictionless.active_set.ETA_MAX`,
:data:`~..frictionless.active_set.ETA_MIN`, γ, final fraction). The stopping test
and the verification of each step are those of the factorisation path
(:meth:`~.projection.ProjectionSystem.error`,
:func:`~solver.contact.verify.verify_contact` in :mod:`.steps`)."""

import time

import numpy as np
import scipy.sparse as sp
from scipy.optimize import OptimizeResult

from ...linalg.amg import projected_cg, projected_gmres
from ...linalg.threads import single_blas_thread
from ...ncp import MESSAGES
from ..frictionless.active_set import (ETA_MAX, FINAL_FRACTION,
                                       KRYLOV_MAX, eliminated_step,
                                       forcing_term, hertz_start,
                                       is_orthogonal, record_krylov)
from ..geometry import rotate_stiffness
from ..strategies.reduction import FullSystem
from ..verify import contact_weight
from .projection import ProjectionSystem

__all__ = ["IterativeSpace", "FloatingIterativeSpace", "LaggedProjection",
           "solve_step", "SPRING_CAP", "SlipRule", "slip_loads",
           "slip_springs", "constrained_rows", "iterate_measure", "stopping",
           "implicit_radius", "bound_rows"]

#: A slip node whose spring q/(1 − q)·D c_t would exceed this multiple of
#: D c_t (≈ the diagonal of K; q → 1 at the edge of the stick set) gets
#: the spring's limit, the constraint e·Δu = 0, instead on the projected
#: path, and this spring on the eliminated one (module docstring). Either
#: shapes only the Newton path; constraining every slip node this way (a
#: cap of 1 or 10) costs 3–5× the Newton systems on the a/h 8 sphere, so
#: the cap only catches q ≈ 1.
SPRING_CAP = 1e3


class LaggedProjection(ProjectionSystem):
    """The projection formulation of a step whose Jacobian blocks are never
    assembled (the active set method does not use them; on the full system
    each would be a copy of K)."""

    lazy_blocks = True


class IterativeSpace(FullSystem):
    """The reduction of the friction driver on the iterative path: the full
    system (nothing condensed; its load, restriction and displacement are
    :class:`~..strategies.reduction.FullSystem`'s) whose load steps are
    solved by :func:`solve_step` with the ``engine``'s AMG hierarchy of
    K."""

    system_kind = LaggedProjection

    floating = None  # a body held by contact only: FloatingIterativeSpace

    def __init__(self, problem, geometry, engine):  # no factorisation
        self.problem, self.geometry, self.engine = problem, geometry, engine
        self.K = problem.K
        self.linear_solver = engine.linear_solver
        self._multigrid = None
        self._rotated = None  # (R, K̂ = R K Rᵀ or None) of the system
        self.first = True  # no step solved yet: the Hertz start applies
        self._last = None  # (f_κ, u_κ) of the last step solved
        self._increment = None  # (Δf, Δu) of the last step solved

    def jacobian(self, system):
        """None: the active set method assembles no Jacobian."""
        return None

    def newton(self, system, x0, load, tol, max_iter):
        """Solve the step set on ``system`` (:meth:`~.system.
        FrictionSystem.set_step`, its load vector ``load``) from ``x0``;
        the result of :func:`solve_step`."""
        if self._multigrid is None:  # once for all load steps
            self._multigrid = self.engine.multigrid(self.problem)
        first, self.first = self.first, False
        load = np.asarray(load, float)
        if load.ndim == 0:
            load = float(load) * system.f
        x0 = np.array(x0, float)
        x0[:system.n] = self.predictor(load, system.u_previous)
        touching = None
        if self.floating is not None and not np.any(system.u_previous):
            placed_u, touching = self.floating.place(load)  # first contact
            if placed_u is not None:
                x0[:system.n], first = placed_u, False
        if self._rotated is None or self._rotated[0] is not system.R:
            K_hat = None
            if is_orthogonal(system.R):
                K_hat = rotate_stiffness(system.K, system.R,
                                         system.geometry.free_dofs())
            self._rotated = (system.R, K_hat)
        result = solve_step(system, self._multigrid, x0, load, tol,
                            max_iter, hertz=first, K_hat=self._rotated[1],
                            floating=self.floating, touching=touching)
        u = system.u_previous + result.x[:system.n]
        if self._last is not None:
            self._increment = (load - self._last[0], u - self._last[1])
        self._last = (load, u)
        return result

    def predictor(self, load, u_previous):
        """Δu of the step's start: the last step's increment when the
        load repeats that step's load increment (steps of one stage: the
        answer moves nearly linearly), else 0. The iterates do not depend
        on it beyond the Newton path (the sets are read from the start)."""
        if self._increment is None or self._last is None \
                or not np.array_equal(u_previous, self._last[1]):
            return np.zeros_like(u_previous)
        step, du = self._increment
        change = load - self._last[0]
        size = np.linalg.norm(step)
        if size > 0 and np.linalg.norm(change - step) <= 1e-12 * size:
            return du
        return np.zeros_like(u_previous)


def solve_step(system, multigrid, x0, load, tol, max_iter, hertz=False,
               K_hat=None, floating=None, touching=None):
    """One load step of ``system`` (a :class:`~.projection.
    ProjectionSystem` on the full K, lagged or implicit bound, its step
    set) by the active set method of the module, each Newton system by
    projected CG (GMRES for the implicit bound)
    preconditioned by ``multigrid``, from x0 = [Δu; ĝ] (only Δu is used:
    g follows from u). ``hertz``: the first system may give the free
    solution, and then the next set is :func:`~..frictionless.active_set.
    hertz_start`. Returns an OptimizeResult as :func:`solver.ncp.solve_ncp`'s
    (``x`` = [Δu; ĝ], ``success``, ``status``, ``message``, ``nit``,
    ``njev`` = Newton systems, ``nfev``, ``error``, ``stopping``,
    ``history`` with ``krylov`` and ``setup`` per system) plus ``krylov``
    in total.
    ``K_hat``: K̂ = R K Rᵀ (R = ``system.R`` orthogonal) to solve each
    Newton system eliminated (module docstring), None: projected CG.
    ``floating``: a body held by contact only, its :class:`~..strategies.
    floating.RigidPlacement` (:class:`FloatingIterativeSpace`), with
    ``touching`` the first system's active set (the placement's nodes) or
    None."""
    if floating is not None and K_hat is None:
        from ...errors import SolverError

        raise SolverError(
            "backend='amg' needs an orthogonal rotation of the contact "
            "frames for a body held by contact only (a roller's normal "
            "leaves its free plane here): use a factorisation")
    with single_blas_thread():  # vectors: BLAS threads only spin
        return _iterate(system, multigrid, x0, load, tol, max_iter, hertz,
                        K_hat, floating, touching)


class SlipRule:
    """The stick and slip sets of the method from w = g − c_t Δu_t (m, k)
    and the radii b (m,) (module docstring): stick |w| < b, slip |w| ≥ b
    where b > 0, with ŵ = w/|w|; a node whose slip turned back
    (ŵ·ŵ_prev < 0) twice in a row is put in the stick set. One per load
    step: it remembers the last iterates' directions. Nodewise, so the
    ranks of a distributed run each call it on their own nodes and take
    the same decisions (:mod:`solver.mpi.krylov_friction`)."""

    def __init__(self, k):
        self.k = k
        self.hat = self.slip = self.turned = None

    def __call__(self, w, b, stuck=None):
        """(stick, slip, ŵ, |w|) of the iterate; ``stuck`` (m,) bool, if
        given, is the stick set instead, with no slip (a body held by
        contact only starts stuck on its placement's nodes)."""
        size = np.linalg.norm(w, axis=1)
        stick = size < b
        slip = ~stick & (b > 0)
        if stuck is not None:
            stick, slip = stuck.copy(), np.zeros(len(b), bool)
        hat = np.divide(w, size[:, None], out=np.zeros_like(w),
                        where=size[:, None] > 0)
        turned = np.zeros(len(b), bool)
        if self.hat is not None:  # the slip turned back (2D and 3D)
            turned = slip & self.slip & (
                np.einsum("ij,ij->i", hat, self.hat) < 0)
        self.hat, self.slip = hat, slip
        if self.turned is not None:  # twice in a row: stick
            flipping = turned & self.turned
            stick, slip = stick | flipping, slip & ~flipping
        self.turned = turned
        return stick, slip, hat, size


def slip_loads(lumped, b, hat, slip):
    """The lagged bound's loads D b ŵ on the slip nodes' tangent rows
    (mt,), node by node (module docstring)."""
    m, k = hat.shape
    force = np.zeros(m * k)
    force[slip.repeat(k)] = ((lumped * b)[slip, None] * hat[slip]).ravel()
    return force


def slip_springs(system, b, slip, hat, size, capped):
    """The springs across the slip of the 3D slip nodes (module docstring):
    (E, k_e, soft) with E (p, n) the rows e·y_t of y = R u (in ``system``'s
    row numbering), k_e = D c_t q/(1 − q) and ``soft`` k_e within
    :data:`SPRING_CAP` (the others are constraints on the projected path);
    ``capped``: k_e at most the cap's (the eliminated path, all soft)."""
    m, k = hat.shape
    mask = system.t_free.reshape(m, k).astype(float)
    across = np.column_stack([-hat[:, 1], hat[:, 0]]) * mask
    nodes = np.flatnonzero(slip & (np.linalg.norm(across, axis=1) > 0.5))
    q = np.minimum(b[nodes] / size[nodes], 1.0)
    ratio = q / np.maximum(1.0 - q, 1e-300)
    if capped:
        ratio = np.minimum(ratio, SPRING_CAP)
    # v = R_tᵀ e: the tangent rows of the node weighted by e
    rows = system.t_rows.reshape(m, k)[nodes]
    used = rows >= 0
    E = sp.csr_matrix((across[nodes][used], (np.nonzero(used)[0],
                                             rows[used])),
                      shape=(len(nodes), system.n))
    return E, system.lumped[nodes] * system.c_t * ratio, \
        ratio <= SPRING_CAP


def constrained_rows(system, active, stick):
    """The rows of y = R u the Newton system fixes: the active normals,
    then the stick nodes' free tangents."""
    m, k = system.m, system.dim - 1
    return np.concatenate([
        system.n_rows[active], system.t_rows.reshape(m, k)[stick][
            system.t_free.reshape(m, k)[stick]]])


def implicit_radius(system, lam, un):
    """The implicit bound's radii of the sets at the iterate, b = f_c
    max(λ − c(s − u_n), 0)/D (λ = −r_n, u_n the normal rows of R u;
    module docstring): the active set's measure, f_c p at a fixed point.
    Nodewise, as :class:`SlipRule`."""
    return system.friction * np.maximum(
        lam - system.stiffness * (system.geometry.gap - un), 0.0) \
        / system.lumped


def iterate_measure(system, u, r):
    """At the iterate u, r = R(K u − f_κ): g = r_t/D on the free tangents
    (eliminated exactly, module docstring), x = [Δu; g/c_t] and the
    formulation's stopping measure and scale, (g, x, error, scale)."""
    g = np.zeros(system.mt)
    free = system.t_free
    g[free] = r[system.t_rows[free]] / system.lumped_t[free]
    x = np.concatenate([u - system.u_previous, g / system.c_t])
    parts = system.residual(x)
    return g, x, system.error(*parts), system.scale(*parts)


def stopping(err, scale, tol, finite, njev, max_iter):
    """(status, detail) of :data:`solver.ncp.MESSAGES` where the iteration
    ends at this iterate (4: not ``finite``, 0: error ≤ tol·scale, 1:
    ``max_iter`` Newton systems solved), or None: go on."""
    if not finite:
        return 4, "the iterate is not finite"
    if err <= tol * scale:
        return 0, ""
    if njev >= max_iter:
        return 1, ""
    return None


class _Springs:
    """K + V diag(k) Vᵀ as an operator for :func:`projected_cg`."""

    def __init__(self, K, V, k):
        self.K, self.V, self.k = K, V, k
        self.shape = K.shape

    def __matmul__(self, x):
        out = self.K @ x
        if self.V is not None:
            out = out + self.V @ (self.k * (self.V.T @ x))
        return out


class _Coupled:
    """A + Rᵀ N R K as an operator for :func:`projected_gmres`: the
    springs' ``A`` (:class:`_Springs`) with the implicit bound's rows N
    (in rotated coordinates) applied to the rotated K u."""

    def __init__(self, A, R, N, K):
        self.A, self.R, self.N, self.K = A, R, N, K
        self.shape = K.shape

    def __matmul__(self, x):
        return self.A @ x + self.R.T @ (self.N @ (self.R @ (self.K @ x)))


def bound_rows(system, slip, hat, n):
    """N (n, n) sparse in rotated coordinates: f_c ŵ_j in the row of each
    free tangent j of a slip node and the column of its normal, so that
    the rows r_t + N r (r = R(Ku − f)) say D g·ŵ = r_t·ŵ = −f_c r_n, the
    implicit bound D b = f_c λ (module docstring)."""
    m, k = hat.shape
    rows = system.t_rows.reshape(m, k)
    use = slip[:, None] & system.t_free.reshape(m, k)
    columns = np.broadcast_to(system.n_rows[:, None], (m, k))
    return sp.csr_matrix((system.friction * hat[use], (rows[use],
                                                        columns[use])),
                         shape=(n, n))


def _iterate(system, multigrid, x0, load, tol, max_iter, hertz, K_hat,
             floating, touching):
    clock = time.perf_counter()
    n, m, k = system.n, system.m, system.dim - 1
    K, R = system.K, system.R
    t_rows, n_rows, t_free = system.t_rows, system.n_rows, system.t_free
    free_rows = t_rows[t_free]  # a roller's e_c has no row
    lumped, lumped_t, c_t = system.lumped, system.lumped_t, system.c_t
    s, c = system.geometry.gap, system.stiffness
    load = np.asarray(load, float)
    f = float(load) * system.f if load.ndim == 0 else load
    Rf = R @ f
    u_previous = system.u_previous
    C_n = R[n_rows].tocsr()
    R_t = R[free_rows].tocsr()  # the free tangential rows
    implicit = system.coulomb == "implicit"
    b, _ = system.bound(np.zeros(n), derivative=False)  # lagged: f_c p_{κ−1}
    u = u_previous + np.asarray(x0[:n], float)
    history = {key: [] for key in ("residual", "error", "merit", "alpha",
                                   "step", "active", "stick", "slip",
                                   "krylov", "forcing", "krylov_decades",
                                   "setup")}
    previous_sets, previous_error, eta = None, None, ETA_MAX
    rule = SlipRule(k)
    free_solve = False
    status, detail, njev, nfev = 1, "", 0, 0
    x = None
    while True:
        r = R @ (K @ u) - Rf
        g, x, err, scale = iterate_measure(system, u, r)
        nfev += 1
        end = stopping(err, scale, tol, np.isfinite(err)
                       and np.all(np.isfinite(u)), njev, max_iter)
        if end is not None:
            status, detail = end
            break
        lam = -r[n_rows]
        un = C_n @ u
        active = lam - c * (s - un) > 0
        if implicit:  # f_c p at the iterate, by the active set's measure
            b = implicit_radius(system, lam, un)
        if free_solve:  # the free solution was just solved: Hertz's set
            free_solve, first = False, hertz_start(un - s)
            if first is not None:
                active = first
        if floating is not None:  # the placement's nodes, then held
            if njev == 0 and touching is not None:
                active = touching
            active = floating.hold(active, lam - c * (s - un))
        slide = np.zeros(system.mt)
        slide[t_free] = R_t @ (u - u_previous)
        w = ((g - c_t * slide) * t_free).reshape(m, k)
        stuck = touching if floating is not None and njev == 0 \
            and touching is not None and implicit \
            and system.friction > 0 else None  # stuck: class doc
        stick, slip, hat, size = rule(w, b, stuck)
        sets = (active, stick, slip)
        final = previous_sets is not None and all(
            np.array_equal(a, p) for a, p in zip(sets, previous_sets))
        history["residual"].append(err)
        history["error"].append(err)
        history["merit"].append(0.5 * err ** 2)
        history["active"].append(int(active.sum()))
        history["stick"].append(int(stick.sum()))
        history["slip"].append(int(slip.sum()))
        if previous_error is not None and not final:
            eta = forcing_term(eta, err, previous_error)
        weight = contact_weight(system.load_norm, lam, lumped_t * g)
        floor = FINAL_FRACTION * tol * scale / weight
        atol = max(eta * err / weight, floor)
        if final and not (k == 2 and slip.any()):
            atol = floor  # the sets repeat: the last, linear system
        elif final:  # 3D slip directions still turn: Newton's own rate
            atol = max(forcing_term(eta, err, previous_error, False)
                       * err / weight, floor)
        free_solve = hertz and njev == 0 and not active.any() \
            and not stick.any()
        # the loads and springs of the slip nodes (module docstring)
        force = np.zeros(system.mt)
        N = None
        if implicit:  # D g·ŵ = −f_c r_n: rows N of the Newton system
            N = bound_rows(system, slip, hat, n)
            rhs = f.copy()
        else:
            force = slip_loads(lumped, b, hat, slip)
            rhs = f + R[t_rows[t_free]].T @ force[t_free]
        V, spring, W, S = None, None, None, None
        if k == 2 and slip.any():
            # no constraint across where eliminated: the cap's spring
            E, stiff, soft = slip_springs(system, b, slip, hat, size,
                                          capped=K_hat is not None)
            across_rows = (E @ R).tocsr()
            if soft.any():
                V = across_rows[soft].T.tocsr()
                spring = stiff[soft]
                rhs = rhs + V @ (spring * (V.T @ u_previous))
                if K_hat is not None:  # in y = R u: R V = Eᵀ
                    E_soft = E[soft]
                    S = (E_soft.T @ sp.diags(spring) @ E_soft).tocsr()
            if not soft.all():  # stiffer than SPRING_CAP: e·Δu_t = 0
                W = across_rows[~soft]
        constrained = constrained_rows(system, active, stick)
        C = R[constrained].tocsr()
        if W is not None:
            C = sp.vstack([C, W], format="csr")
        target = np.concatenate([s[active], (C @ u_previous)[
            int(active.sum()):]])
        row_norm = np.asarray(C.multiply(C).sum(axis=1)).ravel()
        start = u + C.T @ ((target - C @ u) / row_norm)
        unheld = None
        if floating is not None:  # modes no constraint or spring sees
            seen = C if S is None else sp.vstack([C, E_soft @ R])
            unheld = floating.unheld(seen)
        if K_hat is not None and (len(constrained) or S is not None
                                  or N is not None):
            f_hat = R @ rhs
            coupling = None
            if N is not None:
                f_hat = f_hat + N @ Rf
                coupling = (N @ K_hat).tocsr()
            krylov, u_next = eliminated_step(K_hat, f_hat, R, multigrid,
                                             constrained, start, atol, S,
                                             coupling, hold=unheld)
        elif N is not None:
            krylov = projected_gmres(
                _Coupled(_Springs(K, V, spring), R, N, K),
                rhs + R.T @ (N @ Rf), multigrid, start, C, atol=atol,
                maxiter=KRYLOV_MAX)
            u_next = krylov.x
        else:
            krylov = projected_cg(_Springs(K, V, spring), rhs, multigrid,
                                  start, C, atol=atol, maxiter=KRYLOV_MAX)
            u_next = krylov.x
        njev += 1
        history["step"].append("active set")
        history["alpha"].append(1.0)
        failure = record_krylov(history, krylov, atol, err)
        u = u_next
        previous_sets, previous_error = sets, err
        if failure:
            status, detail = 5, failure
            break
    message = MESSAGES[status] + (f": {detail}" if detail else "")
    return OptimizeResult(
        x=x, success=status == 0, status=status, message=message, nit=njev,
        njev=njev, nfev=nfev, residual=err, error=err, method="min",
        krylov=int(sum(history["krylov"])), history=history,
        stopping=dict(test="error(x) ≤ tol·scale(x)", tol=float(tol),
                      scale=float(scale), absolute=float(err),
                      relative=float(err / scale) if scale > 0 else 0.0),
        time=time.perf_counter() - clock)


class FloatingIterativeSpace(IterativeSpace):
    r"""The iterative path's friction steps of a body held by contact only
    (K singular, its kernel the rigid-body modes): the first step with
    contact starts from the rigid body put onto the obstacle by the step's
    load with its touching nodes active (:class:`~..strategies.floating.
    RigidPlacement`; with the implicit bound and friction in the step also
    stuck, as the full system's factorisation path starts, :meth:`~..
    strategies.floating_full.FloatingFullSystem.step_start`: they hold
    every mode, tangential ones included, and their forces balance the
    step's load), every active set is kept holding the modes the normals
    hold (:meth:`~..strategies.floating.RigidPlacement.hold`), and each
    Newton system keeps the amplitudes α_V = Z u of the modes V that none
    of its constraints (active normals, stick tangents) or springs sees
    at their start (:meth:`~..strategies.floating.RigidPlacement.unheld`,
    :func:`~..frictionless.active_set.eliminated_step`'s ``hold``): where
    no node has a friction bound (the lagged first step, a frictionless
    stage) those are the sliding modes, along which the step's load has
    no share (checked before the run), and the body does not slide, as on
    the factorisation path (Δα_V = 0, :meth:`~..strategies.floating.
    FloatingSystem._friction_jacobian`), so both give the same answer of
    that non-unique step; later, a Newton system whose slip nodes carry
    the tangential load as loads alone gets the direction without
    sliding, which shapes only the Newton path (the stopping test is the
    step's).
    Before each lagged step the load is checked against the previous
    step's bounds (:func:`~..strategies.floating.lagged_unheld`).

    Refused (SolverError, one line): a run with a step without friction
    (a frictionless stage of the load path, or the lagged bound's first
    step, f_c p_0 = 0) in which the contact normals hold a rigid motion
    only weakly
    (:func:`~..strategies.floating.warn_weakly_held`: a spin that only a
    round surface's facets see, ratio ≤ WEAK_RTOL of
    :mod:`solver.problem.rigid`). The eliminated K̂_FF of such a step is
    nearly singular along the motion, which only the facets' lever arms
    hold, so a CG solve to its tolerance leaves the motion's amplitude
    inexact by far more than the residual, the nodes at the contact edge
    change sides with it, and the step's error stalls above tol (the
    factorisation solves those systems to round-off)."""

    def __init__(self, problem, geometry, engine, friction,
                 coulomb="lagged"):
        from ..strategies.floating import RigidPlacement

        super().__init__(problem, geometry, engine)
        self.floating = RigidPlacement(problem, geometry, friction)
        self.weakly_held = self.floating.weakly_held
        refused = self.weakly_held
        if not refused and coulomb != "implicit":  # f_c p_0 = 0 in step 1
            from ...problem.rigid import weakly_held

            refused = weakly_held(problem, self.floating.N,
                                  self.floating.modes[geometry.free_dofs()])
            refused = [dict(motion=t, ratio=r) for t, r in refused]
        if refused:  # the class docstring's last part
            from ...errors import SolverError

            raise SolverError(
                "backend='amg' is not supported for friction on a body "
                "held by contact only whose rigid-body motion "
                f"{refused[0]['motion']} the contact normals hold only "
                f"weakly (ratio {refused[0]['ratio']:.2g}) in a step "
                "without friction (a frictionless stage, or the lagged "
                "bound's first step): its Newton systems are nearly "
                "singular along it and the step stalls above tol; hold "
                "it by a support, use coulomb='implicit' with friction "
                "in every stage, or a factorisation (backend='auto')")

    def begin_step(self, system, load, step_friction, state, lumped,
                   coulomb):
        """None, or why the lagged step's load cannot be held."""
        from ..strategies.floating import lagged_unheld

        return lagged_unheld(self.problem, self.floating.N, self.floating.T,
                             load, step_friction, state, lumped, coulomb)

    def step_start(self, system, du, u_previous, load):
        """None: :meth:`newton` places the body (before any contact)."""
        return None

    def alpha(self, x):
        """The rigid-body amplitudes Rᵀu of the displacement x."""
        return self.floating.modes.T @ np.asarray(x, float)
