"""The system of one load step of Coulomb friction (thesis (110)/(111),
and the projection formulation): residual and Jacobian for
:func:`solver.ncp.solve_ncp`. The formulations, the bound f_c p and the
references are described in :mod:`solver.contact.friction.driver`, whose driver
builds one :class:`FrictionSystem` per run and moves it from step to step.
"""

import numpy as np
import scipy.linalg as sla_dense
import scipy.sparse as sp

from ...errors import SolverError
from ...linalg.threads import single_blas_thread
from ...ncp import stable_norm
from ...linalg.dense import factorize
from .newton import ReducedJacobian
from .projection import block_diagonal, disc_derivative, project_disc
from ..geometry import contact_stiffness, rotation
from ..verify import force_scale

__all__ = ["FORMULATIONS", "COULOMB", "FrictionSystem", "check_geometry"]

FORMULATIONS = ("thesis", "projection")
COULOMB = ("lagged", "implicit")


def check_geometry(geometry, formulation):
    """SolverError (one line) for what friction does not take: the
    thesis's split formulation (110)/(111) outside 2D (its Δu_t = Δu_t⁺ −
    Δu_t⁻ splits a scalar tangential slip, which a tangent plane does not
    have: the projection onto the Coulomb disc replaces it), and with
    roller nodes (the split has no row to drop for a roller's constrained
    tangent; the projection form takes rollers, :class:`FrictionSystem`)."""
    if formulation == "thesis" and geometry.dim != 2:
        raise SolverError("the thesis's split formulation (Δu_t⁺, Δu_t⁻) is "
                          "2D-only; use --formulation projection "
                          "(formulation=\"projection\") in 3D")
    if formulation == "thesis" and geometry.has_rollers:
        raise SolverError("the thesis's split formulation does not take "
                          "roller nodes (contact nodes with a Dirichlet "
                          "component); use --formulation projection "
                          "(formulation=\"projection\") or rollers=False")


class FrictionSystem:
    """Residual and Jacobian of one load step, for :func:`solve_ncp`.

    Parameters
    ----------
    K, f : reduced stiffness and full load.
    geometry : ContactGeometry
        Gaps and normals at the free contact nodes and the rollers (the
        projection form only: a roller's g_t is 0 along its constrained
        tangents e_c and that tangential equilibrium row is left out, so
        that its Coulomb set is the disc cut to the free tangents,
        :mod:`solver.contact.friction.driver`).
    lumped : (Nca,) array
        D_ii = Σ_j M_ij at the free contact nodes.
    friction : float
        f_c ≥ 0.
    formulation : {"thesis", "projection"}
    coulomb : {"lagged", "implicit"}
    gap_scale : float
        c in the normal pair's B = c(s − YRu) (1 = thesis).
    stiffness : float, optional
        k̄ of the stopping measure and of c_t (default: mean of diag K at
        the contact DOFs; a condensed system passes that of the full K).
    """

    def __init__(self, K, f, geometry, lumped, friction,
                 formulation="thesis", coulomb="lagged", gap_scale=1.0,
                 stiffness=None):
        if formulation not in FORMULATIONS:
            raise SolverError(f"formulation must be one of {FORMULATIONS}, "
                              f"got {formulation!r}")
        if coulomb not in COULOMB:
            raise SolverError(f"coulomb must be one of {COULOMB}, got "
                              f"{coulomb!r}")
        check_geometry(geometry, formulation)
        self.dim = int(geometry.dim)
        n = K.shape[0]
        self.n, self.m = n, len(geometry.dofs)
        self.K, self.f = sp.csr_matrix(K), np.asarray(f, float)
        self.geometry, self.lumped = geometry, np.asarray(lumped, float)
        self.friction, self.formulation = float(friction), formulation
        self.coulomb, self.gap_scale = coulomb, float(gap_scale)
        self.R, other, a, b = rotation(n, geometry)
        self.RT = self.R.T  # once: SciPy makes a new transpose per ``.T``
        self.x_rows, self.t_rows, self.n_rows = other, a, b  # X, Z, Y
        #: condensed onto Γc: K is the dense S, no other rows
        self.dense_schur = isinstance(K, np.ndarray) and not len(other)
        #: tangential unknowns: m(d − 1), node by node (the tangent basis)
        self.mt = len(a)
        #: the tangential unknowns with an equilibrium row: False at a
        #: roller's constrained tangent e_c (``dofs`` −1), whose g is 0
        self.t_free = a >= 0
        self.rollers = not bool(self.t_free.all())
        self.lumped_t = np.repeat(self.lumped, self.dim - 1)
        self.RK = (self.R @ self.K).tocsr()
        self.Rf = self.R @ self.f
        self.stiffness = contact_stiffness(self.K, geometry) \
            if stiffness is None else float(stiffness)
        # c_t of the projection: stiffness per unit contact length.
        self.c_t = self.stiffness / float(self.lumped.mean()) \
            if self.m else 1.0
        m, mt = self.m, self.mt
        I, Z0 = sp.identity(m, format="csr"), sp.csr_matrix((m, m))
        self._I, self._Z0 = I, Z0
        RK, R = self.RK, self.R
        if formulation == "thesis":
            Zn = sp.csr_matrix((m, n))
            self._JE = sp.bmat([
                [RK[other], None, None, None],
                [RK[a], -sp.diags(self.lumped), None, None],
                [R[a], None, -I, I]], format="csr")
            self._JA = sp.bmat([[-RK[b], Z0, Z0, Z0], [Zn, Z0, Z0, I],
                                [Zn, Z0, I, Z0]], format="csr")
            self._JB_normal = sp.hstack([-self.gap_scale * R[b], Z0, Z0,
                                         Z0], format="csr")
        else:
            Zt = sp.csr_matrix((m, mt))
            Dt, free = sp.diags(self.lumped_t, format="csr"), a
            #: ZR with a roller's e_c rows 0 (it moves no tangential DOF)
            self._Rt = R[a]
            if self.rollers:
                free = a[self.t_free]
                Dt = Dt[self.t_free]
                self._Rt = sp.diags(self.t_free.astype(float)) @ R[
                    np.where(self.t_free, a, 0)]
            self._JE_fixed = sp.bmat([
                [RK[other], sp.csr_matrix((len(other), mt))],
                [RK[free], -Dt]], format="csr")
            self._JA = sp.hstack([-RK[b], Zt], format="csr")
            self._JB = sp.hstack([-self.gap_scale * R[b], Zt], format="csr")
        self.load_norm = stable_norm(self.f)
        # Condensed (dense S, no other rows) projection form: Newton
        # systems on the free components only (:mod:`.newton`;
        # 2D only: in 3D the generic path with the full Jacobian).
        self.reduced = (self.reduced_newton and formulation == "projection"
                        and self.dim == 2 and not self.rollers
                        and isinstance(K, np.ndarray) and not len(other))
        if self.reduced:
            RS = R @ np.asarray(K, float)
            self.T = np.ascontiguousarray((R @ RS.T).T)  # R S Rᵀ
            self.RK = RS  # dense: residuals by BLAS, not CSR of a dense S
            self._factor = None  # (kind, matrix, solve) of the last one
            self._flexibility = None  # T⁻¹, made when first needed
        self.set_step(np.zeros(n), 1.0, np.zeros(m))

    #: Solve the condensed projection form's Newton systems reduced to the
    #: free components (:mod:`.newton`); False: the full J (the
    #: reference of the tests).
    reduced_newton = True

    @property
    def n_unknowns(self):
        return self.n + (3 * self.m if self.formulation == "thesis"
                         else self.mt)

    def set_step(self, u_previous, load, p_previous, friction=None,
                 load_norm=None):
        """Fix u_{κ−1}, the step's load, the lagged pressure p_{κ−1} and
        (optionally) the step's friction coefficient and the ‖f‖₂ of the
        stopping test's force scale (:meth:`scale`; a condensed system is
        given that of the problem's load).

        ``load`` is the load vector f_κ of the step, or a number κ/κc
        meaning κ/κc · f.
        """
        if load_norm is not None:
            self.load_norm = float(load_norm)
        self.u_previous = np.asarray(u_previous, float)
        load = np.asarray(load, float)
        self._Rf_step = (float(load) * self.Rf if load.ndim == 0
                         else self.R @ load)
        self.p_previous = np.asarray(p_previous, float)
        if friction is not None:
            self.friction = float(friction)
        self._r_previous = self.RK @ self.u_previous
        self._last_force = None  # (Δu, r) of the last :meth:`_force`

    def _split(self, x):
        """(Δu, g_t, Δu_t⁺, Δu_t⁻) from the unknown vector x.

        x holds the traction as ĝ = g_t / c_t, a length like every other
        unknown: the descent test (26) of the FB method, ∇ψᵀd ≤ −ρ‖d‖ᵖ,
        compares norms of d and is meaningless when d mixes displacements
        (~1e-3) with tractions (~1e2); unscaled, it rejects good Newton
        directions and the method stalls on gradient steps.
        """
        n, m = self.n, self.mt
        return (x[:n], self.c_t * x[n:n + m], x[n + m:n + 2 * m],
                x[n + 2 * m:])

    def traction(self, x):
        """g_t from the unknown vector x ((m,), or m(d − 1) node by node
        in the tangent basis)."""
        return self.c_t * x[self.n:self.n + self.mt]

    def _force(self, du):
        """r = R(Ku − f_κ) with u = u_{κ−1} + Δu. The last one is kept:
        the Jacobian at the iterate whose residual was just evaluated, and
        the step's check, reuse it (one product with the dense RS fewer per
        Newton iteration on the condensed system)."""
        last = self._last_force
        if last is not None and np.array_equal(last[0], du):
            return last[1]
        r = self._r_previous + self.RK @ du - self._Rf_step
        self._last_force = (np.array(du, float), r)
        return r

    def pressure(self, r):
        """Lumped contact pressure of the current iterate, ≥ 0."""
        return np.maximum(-r[self.n_rows], 0.0) / self.lumped

    def bound(self, r, derivative=True):
        """f_c p and its derivative rows (None if lagged or not
        ``derivative``)."""
        if self.coulomb == "lagged":
            return self.friction * self.p_previous, None
        if not derivative:
            return self.friction * self.pressure(r), None
        active = (-r[self.n_rows] > 0.0) / self.lumped
        d = -self.friction * (sp.diags(active) @ self.RK[self.n_rows])
        return self.friction * self.pressure(r), d

    def residual(self, x):
        du, g, dp, dm = self._split(x)
        r = self._force(du)
        u = self.u_previous + du
        lam = -r[self.n_rows]
        gap = self.gap_scale * (self.geometry.gap - (self.R @ u)[self.n_rows])
        b, _ = self.bound(r, derivative=False)
        tangential = r[self.t_rows] - self.lumped_t * g
        if self.rollers:  # no equilibrium row along a roller's e_c
            tangential = tangential[self.t_free]
        if self.formulation == "thesis":
            split = (self.R @ du)[self.t_rows] - dp + dm
            E = np.concatenate([r[self.x_rows], tangential, split])
            A = np.concatenate([lam, dm, dp])
            B = np.concatenate([gap, b - g, b + g])
        elif self.dim == 2:
            w = self._slide(g, du)
            E = np.concatenate([r[self.x_rows], tangential,
                                g - np.clip(w, -b, b)])
            A, B = lam, gap
        else:
            w = self._slide(g, du)
            E = np.concatenate([r[self.x_rows], tangential,
                                g - project_disc(w, b, self.dim - 1)])
            A, B = lam, gap
        return E, A, B

    def _slide(self, g, du):
        """w = g − c_t ZRΔu of the projection, 0 along a roller's e_c: the
        Coulomb set there is the disc cut to the free tangents (an
        interval when one is free), and g − P(w) = 0 makes g_c = 0."""
        w = g - self.c_t * (self.R @ du)[self.t_rows]
        return np.where(self.t_free, w, 0.0) if self.rollers else w

    def tangential(self, v):
        """The tangential components v[Z] of a rotated vector v = R·(…),
        node by node; 0 along a roller's e_c (u_c = 0 is prescribed)."""
        out = v[self.t_rows]
        return np.where(self.t_free, out, 0.0) if self.rollers else out

    def jacobian(self, x):
        """(JE, JA, JB) with respect to x (ĝ columns scaled by c_t), or,
        on the condensed projection form, the same Jacobian as a
        :class:`~.newton.ReducedJacobian`."""
        if self.reduced:
            du, g = x[:self.n], self.traction(x)
            r = self._force(du)
            b, _ = self.bound(r, derivative=False)
            w = g - self.c_t * (self.R @ du)[self.t_rows]
            stick = np.abs(w) < b
            active = None if self.coulomb == "lagged" else \
                (-r[self.n_rows] > 0.0).astype(float)
            return ReducedJacobian(self, x, stick, ~stick & (w >= 0),
                                   active)
        scale = np.ones(self.n_unknowns)
        scale[self.n:self.n + self.mt] = self.c_t
        S = sp.diags(scale)
        return tuple((J @ S).tocsr() for J in self._jacobian(x))

    def _jacobian(self, x):
        du, g, dp, dm = self._split(x)
        r = self._force(du)
        b, db = self.bound(r)
        if self.formulation == "thesis":
            if db is None:
                JB = sp.vstack([self._JB_normal,
                                sp.hstack([sp.csr_matrix((self.m, self.n)),
                                           -self._I, self._Z0, self._Z0]),
                                sp.hstack([sp.csr_matrix((self.m, self.n)),
                                           self._I, self._Z0, self._Z0])],
                               format="csr")
            else:
                JB = sp.vstack([self._JB_normal,
                                sp.hstack([db, -self._I, self._Z0,
                                           self._Z0]),
                                sp.hstack([db, self._I, self._Z0,
                                           self._Z0])], format="csr")
            return self._JE, self._JA, JB
        if self.dim != 2 or self.rollers:
            return self._disc_jacobian(du, g, b, db)
        # projection row: g − clip(w, −b, b), w = g − c_t ZRΔu
        w = g - self.c_t * (self.R @ du)[self.t_rows]
        stick = np.abs(w) < b
        upper = ~stick & (w >= 0)
        stick_rows = sp.diags(stick.astype(float)) @ (
            self.c_t * self._Rt)
        slip_g = sp.diags((~stick).astype(float))
        rows_du = stick_rows
        if db is not None:
            sign = np.where(upper, -1.0, 1.0) * (~stick)
            rows_du = rows_du + sp.diags(sign) @ db
        J3 = sp.hstack([rows_du, slip_g], format="csr")
        return sp.vstack([self._JE_fixed, J3], format="csr"), self._JA, \
            self._JB

    def _disc_jacobian(self, du, g, b, db):
        r"""(JE, JA, JB) of the projection onto the disc (any d): the row
        g − P(w), w = g − c_t ZRΔu, P(w) = w·min(1, b/|w|); stick (|w| < b):
        ∂P/∂w = I; slip: ∂P/∂w = b/|w| (I − ŵŵᵀ), ∂P/∂b = ŵ (Alart &
        Curnier 1991; Hüeber, Stadler & Wohlmuth 2008). In 2D this is the
        clip's Jacobian (I − ŵŵᵀ = 0, ŵ = ±1). At a roller w_c ≡ 0
        (:meth:`_slide`): the e_c column of ∂P/∂w drops, the row of g_c is
        g_c itself (:func:`~.projection.disc_derivative`)."""
        k, m = self.dim - 1, self.m
        P, stick, _, slip_hat = disc_derivative(
            self._slide(g, du).reshape(m, k), b,
            self.t_free if self.rollers else None)
        blocks = block_diagonal(P)
        rows_du = blocks @ (self.c_t * self._Rt)
        if db is not None:  # −∂P/∂b db = −ŵ db at slip nodes
            rows_du = rows_du - sp.diags(slip_hat.ravel()) @ sp.csr_matrix(
                db[np.repeat(np.arange(m), k)])
        J3 = sp.hstack([rows_du, sp.identity(m * k) - blocks],
                       format="csr")
        return sp.vstack([self._JE_fixed, J3], format="csr"), self._JA, \
            self._JB

    def _reduced_solve(self, A, h, symmetric, kind):
        """A⁻¹h for the reduced Newton matrix A of ``kind`` ("primal" or
        "dual", :mod:`.newton`; None if singular); the
        factorisation is reused while A is unchanged."""
        cached = self._factor
        if cached is None or cached[0] != kind \
                or cached[1].shape != A.shape \
                or not np.array_equal(cached[1], A):
            cached = self._factor = (kind, A, factorize(A, symmetric))
        return None if cached[2] is None else cached[2](h)

    def flexibility(self):
        """C = T⁻¹ = R S⁻¹ Rᵀ (dense 2m×2m, computed once)."""
        if self._flexibility is None:
            factor = sla_dense.cho_factor(self.T, check_finite=False)
            self._flexibility = sla_dense.cho_solve(
                factor, np.eye(len(self.T)), check_finite=False)
        return self._flexibility

    def error(self, E, A, B):
        """Stopping measure in force units (cf. FrictionlessSystem.error)."""
        k, c = self.stiffness, self.gap_scale
        m, nx = self.m, len(self.x_rows)
        if self.formulation == "thesis":
            E = np.concatenate([E[:nx + m], k * E[nx + m:]])
            pairs = np.concatenate([
                np.minimum(A[:m], k / c * B[:m]),
                np.minimum(k * A[m:2 * m], self.lumped * B[m:2 * m]),
                np.minimum(k * A[2 * m:], self.lumped * B[2 * m:])])
        else:
            mt = int(self.t_free.sum())  # the tangential equilibrium rows
            E = np.concatenate([E[:nx + mt], self.lumped_t * E[nx + mt:]])
            pairs = np.minimum(A, k / c * B)
        return float(np.hypot(stable_norm(E), stable_norm(pairs)))

    def scale(self, E, A, B):
        """Force scale F = max(‖f‖₂, ‖λ⁺‖₂) of the stopping test error ≤
        tol·F (A[:m] = λ in both formulations; :mod:`solver.contact.verify`)."""
        return force_scale(self.load_norm, A[:self.m])

    def initial_guess(self, g_previous, du=None):
        """Each step starts from the previous solution: the same g_t and
        Δu = 0, or, given the step's predictor ``du`` (a condensed system:
        Γc moving as the unconstrained body), that predictor with its
        normal contact forces corrected (:meth:`contact_corrected`). The
        thesis's split then starts consistent, Δu_t± = max(±ZRΔu, 0).
        Call :meth:`set_step` first: the correction needs the step's
        load."""
        x = np.zeros(self.n_unknowns)
        x[self.n:self.n + self.mt] = np.ravel(g_previous) / self.c_t
        if du is not None:
            du = self.contact_corrected(du)
            x[:self.n] = du
            if self.formulation == "thesis":
                dut = (self.R @ du)[self.t_rows]
                x[self.n + self.m:self.n + 2 * self.m] = np.maximum(dut, 0)
                x[self.n + 2 * self.m:] = np.maximum(-dut, 0)
        return x

    #: Passes of the primal-dual active set iteration of
    #: :meth:`contact_corrected`; without convergence the predictor is
    #: returned as it is (a start only).
    start_passes = 50

    def contact_corrected(self, du):
        r"""The predictor Δu of a condensed step with its normal contact
        forces corrected: the normal contact problem of the step with the
        friction tractions held at the previous step's, i.e. the increment
        e = −C_{:,n} z (C = T⁻¹ = R S⁻¹ Rᵀ, the flexibility; z the change of
        the normal forces) with

        .. math::  λ + z \ge 0, \quad s − u_n + C_{nn} z \ge 0, \quad
                   (λ + z)^T (s − u_n + C_{nn} z) = 0,

        where λ and s − u_n are those of the predictor.

        Why: the predictor moves Γc as the unconstrained body, so it keeps
        the previous contact forces and pushes the nodes in contact into
        the obstacle by the step's whole free motion, far from the
        complementarity set. There φ_FB is curved and its Newton step
        removes only part of the penetration per iteration (φ_min's, which
        is piecewise linear, lands on the set in one). Started on the set,
        λ ≥ 0 ⊥ s − u_n ≥ 0, both methods meet φ_FB's curvature only where
        the step changes the contact set; the tangential forces keep their
        balance with g_t of the previous step (the correction adds normal
        forces only).

        The linear complementarity problem (symmetric positive definite
        C_nn, m × m) is solved by the primal-dual active set method
        (Hintermüller, Ito & Kunisch, SIAM J. Optim. 13 (2002) 865-888),
        started from the penetrating nodes: each pass one solve of the
        size of the contact set. Only on a condensed system (dense S) and
        for the projection formulation: the full system starts from
        Δu = 0 as in the thesis, and the thesis's split, degenerate where
        p = 0, keeps the predictor (its condensed Newton path is sensitive
        to the start)."""
        du = np.asarray(du, float)
        if not self.m or self.formulation != "projection" \
                or not self.dense_schur:
            return du
        nr = self.n_rows
        lam = -self._force(du)[nr]
        gap = self.geometry.gap - (self.R @ (self.u_previous + du))[nr]
        if not (gap < 0.0).any() and not (lam > 0.0).any():
            return du  # nothing touches: the predictor is the step's answer
        with single_blas_thread():  # Γc's size, as solve_ncp's algebra
            return self._corrected(du, lam, gap)

    def _corrected(self, du, lam, gap):
        """:meth:`contact_corrected` once something touches."""
        nr = self.n_rows
        C_n, M = self._normal_flexibility()
        q = gap - M @ lam
        rho = 1.0 / np.diagonal(M)
        active = gap < 0.0
        for _ in range(self.start_passes):
            y = np.zeros(self.m)
            if active.any():
                y[active] = sla_dense.solve(M[np.ix_(active, active)],
                                            -q[active], assume_a="pos",
                                            check_finite=False)
            following = y - rho * (q + M @ y) > 0.0
            if np.array_equal(following, active):
                break
            active = following
        else:
            return du
        return du - self.RT @ (C_n @ (y - lam))

    def _normal_flexibility(self):
        """(C[:, n], C[n, n]) of the flexibility C = R S⁻¹ Rᵀ, in rotated
        components (made once per system)."""
        cached = getattr(self, "_normal_columns", None)
        if cached is None:
            if self.reduced:
                C_n = self.flexibility()[:, self.n_rows]
            else:
                factor = sla_dense.cho_factor(self.K.toarray(),
                                              overwrite_a=True,
                                              check_finite=False)
                C_n = self.R @ sla_dense.cho_solve(
                    factor, self.R[self.n_rows].T.toarray(),
                    check_finite=False)
            C_n = np.ascontiguousarray(C_n)
            cached = self._normal_columns = (C_n, C_n[self.n_rows])
        return cached
