r"""The Newton system of a condensed 3D friction step with the tractions
eliminated (projection onto the Coulomb disc, :mod:`.projection`).

On the system condensed onto Γc or onto candidate nodes (S dense n×n,
n = 3m) the unknowns x = [Δu; ĝ] (ĝ = g_t/c_t, 2m) have the rows

.. math::
    (RS)_t\,dΔu − D_t c_t\,dĝ = −F_1, \qquad
    P_u\,dΔu + c_t (I − P_w)\,dĝ = −F_2, \qquad
    N\,dΔu = −F_3,

P_w the per-node blocks ∂P/∂w (stick: I; slip: |b|/|w| (I − ŵŵᵀ)),
P_u = c_t P_w R_t − ŵ ∂b/∂Δu (implicit bound, slip nodes) and N the NCP
rows of the normal pairs (Hüeber, Stadler & Wohlmuth 2008; Alart &
Curnier 1991). The first row gives dĝ = D_t⁻¹c_t⁻¹((RS)_t dΔu + F_1) (a
slip node with |b|/|w| ≤ 1/2 takes dĝ from its own row instead, exact
for b = 0), and what is left is one dense n×n system,

.. math::
    \begin{bmatrix} P_u + (I − P_w) D_t^{-1} (RS)_t \\ N \end{bmatrix}
    dΔu = \begin{bmatrix} −F_2 − (I − P_w) D_t^{-1} F_1 \\ −F_3
    \end{bmatrix},

n³/3 flops instead of (5n/3)³/3 for the whole J, singular exactly when J
is. :class:`DiscSystem` returns the projection rows as nodal forces
D(g − P(w)): the same direction, but the line searches then weigh every
row in force units, as the stopping measure does (benchmarks/README.md,
"3D friction: the projection rows in force units"). A roller's e_c row is
c_t dĝ_c = −F_2,c and ∂P/∂w loses its column: the matrix stays square.

That n×n system is not factorised as it stands (:data:`REDUCED`). In
the rotated displacement v = RΔu (T = R S Rᵀ) and, per node, the
eigenbasis Q_i of the symmetric P_w block (slip: ŵ, ŵ⊥
with eigenvalues 0 and |b|/|w|; stick: I with 1, 1), every row of the
system is one scalar equation

.. math:: α_j\,(T'y)_j + β_j\,y_j = h'_j, \qquad y = Gᵀv, \quad
          T' = GᵀTG,

G = blockdiag(Q_i) (identity on the normal components): α = (1 − π)/D,
β = c_t π on the tangential rows (π the eigenvalue), α = −w_a, β = −c w_b
on the normal pairs. Where α_j = 0 the row fixes y_j, where β_j = 0 it
fixes the force q_j = (T'y)_j, and what is left is the exact block
elimination of the primal–dual active set method (Hüeber, Stadler &
Wohlmuth 2008), the 3D form of :mod:`.newton`'s: the primal system
(T'_FF + diag(β/α)) y_F = h_F/α_F − T'_FK y_K on F = {α ≠ 0} (slip
tangents and active normals), or the dual one in the forces q = T'y,
(C'_UU + diag(α/β)) q_U = h_U/β_U − C'_UQ q_Q on U = {β ≠ 0} (stick
tangents, the ŵ⊥ rows of slip nodes and inactive normals), C' = T'⁻¹ the
flexibility (made once per run when first needed); whichever is smaller.
Both are symmetric and, with α/β ≥ 0 (φ_min, φ_FB (30)), positive
definite: a Cholesky of order ≈ n/2 instead of an LU of order n, the
same direction to round-off (tests/test_friction_disc_reduced.py). The
implicit bound adds κ_j (T'y)_{n_i} to the ŵ row of a sliding node in
contact (κ = f_c a_i/D_i along ŵ, a_i = [λ_i > 0], from −ŵ ∂b/∂Δu), a
force row still: the primal system takes the T' row of n_i into that row
(then unsymmetric, LU); the dual one is not used then (through C the
coupling would carry C's round-off times f_c,
:data:`~.newton.DUAL_MAX_FRICTION`).

The projection's parameter c_t (:data:`NODAL_CT`). The solution of
g = P(g − c_t ZRΔu) does not depend on c_t > 0, the Newton iterates do
(Alart & Curnier 1991's r; Christensen, Klarbring, Pang & Strömberg,
IJNME 42 (1998) 145-173; Hüeber, Stadler & Wohlmuth 2008's c): |w| =
|g − c_t Δu_t| against b is a return mapping, the trial traction of a
node held where the iterate has it slide by Δu_t, and decides which
nodes a Newton step treats as stuck. A node held against a slip δ
carries a force between δ/C_ii (the rest of Γc free: the local
flexibility, the Delassus diagonal of nonsmooth contact dynamics, Jourdan,
Alart & Jean, CMAME 155 (1998) 31-47) and T_ii δ (the rest held), both
bounds of the Schur complements of T (C = T⁻¹); in traction units, per
node i (its free tangents j averaged, so that c_t commutes with the
per-node blocks ∂P/∂w)

.. math:: c_{t,i} = \operatorname{mean}_j \sqrt{T_{jj}/C_{jj}}\,/\,D_j,

the geometric mean of the two bounds, the one mean that is the same read
from the primal side (stiffness T) or the dual side (flexibility C). It
has no constant fitted to a mesh and follows the mesh's grading node by
node. The scalar k̄/D̄ of :class:`~.system.FrictionSystem` (the mean of
K's diagonal, which bounds T's from above, over the mean area) took 6
Jacobians in load steps of a mesh graded toward the contact where this
c_t takes 5 (benchmarks/README.md, "3D friction: c_t per node from
the condensed stiffness"). Where T is only semidefinite (no C) the
scalar stays."""

import warnings

import numpy as np
import scipy.linalg as sla
from scipy.linalg import lapack
import scipy.sparse as sp

from ...linalg.dense import symmetric_from_upper
from ...linalg.threads import blas_threads_for
from .projection import ProjectionSystem, block_diagonal, disc_derivative

__all__ = ["DiscSystem", "DiscJacobian", "REDUCED", "FORM", "NODAL_CT",
           "nodal_parameter"]

#: Solve the Newton systems reduced to the primal or dual unknowns
#: (module docstring); False: the LU of the whole n×n system (the
#: reference of the tests).
REDUCED = True

#: Which reduced system: "smaller" (the primal or the dual, whichever is),
#: or always "primal" or "dual" (tests).
FORM = "smaller"

#: c_t per contact node from the condensed stiffness, √(T_jj/C_jj)/D_j
#: (module docstring); False: the scalar k̄/D̄ of
#: :class:`~.system.FrictionSystem` (the path before, the tests'
#: reference).
NODAL_CT = True


def nodal_parameter(T_diagonal, C_diagonal, lumped_t, t_free, k, default):
    """c_t of every tangential unknown (node by node, ``k`` per node):
    the mean over a node's free tangents of √(T_jj/C_jj)/D_j (module
    docstring), ``default`` at a node without a free tangent."""
    value = np.sqrt(T_diagonal / C_diagonal) / lumped_t
    free = np.reshape(t_free, (-1, k))
    count = free.sum(axis=1)
    total = np.where(free, np.reshape(value, (-1, k)), 0.0).sum(axis=1)
    node = np.where(count > 0, total / np.maximum(count, 1), default)
    return np.repeat(node, k)


class DiscSystem(ProjectionSystem):
    """:class:`~.projection.ProjectionSystem` on a dense condensed S (3D)
    whose :meth:`jacobian` is a :class:`DiscJacobian`."""

    lazy_blocks = True  # RK stays sparse here (R S is kept apart)

    def __init__(self, K, *args, **kwargs):
        super().__init__(K, *args, **kwargs)
        self.dense = self.dense_schur and self.dim == 3
        if self.dense:  # R sparse (per-node frames): R S and R's rows dense
            t = np.where(self.t_free, self.t_rows, 0)
            self.RS = np.asarray(self.R @ np.asarray(K, float))
            self.RS_t, self.RS_n = self.RS[t], self.RS[self.n_rows]
            # a roller's constrained tangent e_c: no equilibrium row, and
            # it moves no DOF (u_c = 0): its rows of (RS)_t and R_t are 0
            self.R_t = sp.diags(self.t_free.astype(float)) @ self.R[t]
            self.RS_t[~self.t_free] = 0.0
            self.R_n = self.R[self.n_rows].toarray()
            self._factor = None  # (kind, matrix, solve) of the last one
            self._flexibility = None  # T⁻¹, made when first needed
            self._rotated = None  # T = R S Rᵀ, made when first needed
            if NODAL_CT and self.m:
                self.c_t = self._nodal_ct()

    def _nodal_ct(self):
        """c_t per node (:func:`nodal_parameter`), or the scalar where T
        is not positive definite (no flexibility C)."""
        try:
            C = self.flexibility()
        except np.linalg.LinAlgError:
            return self.c_t
        rows = np.where(self.t_free, self.t_rows, 0)  # e_c: not read
        return nodal_parameter(np.diagonal(self.T)[rows],
                               np.diagonal(C)[rows], self.lumped_t,
                               self.t_free, self.dim - 1, self.c_t)

    @property
    def shares_flexibility(self):
        """Whether the step's start (:mod:`.start`) takes C[:, n] from
        :meth:`flexibility`, which the dual systems use anyway, instead of
        factorising S once more."""
        return self.dense and REDUCED

    @property
    def T(self):
        """T = R S Rᵀ, the condensed stiffness in the rotated components
        (dense n×n, made once)."""
        if self._rotated is None:
            self._rotated = np.ascontiguousarray((self.R @ self.RS.T).T)
        return self._rotated

    def flexibility(self):
        """C = T⁻¹ = R S⁻¹ Rᵀ (dense n×n, made once): LAPACK's potrf and
        potri, n³ flops (a solve with the n columns of I takes 2n³)."""
        if self._flexibility is False:  # tried: T is not SPD
            raise np.linalg.LinAlgError("T is not positive definite")
        if self._flexibility is None:
            T = self.T
            with blas_threads_for(len(T)):
                factor, info = lapack.dpotrf(T, lower=False, clean=False)
                if info == 0:
                    inverse, info = lapack.dpotri(factor, lower=False)
            if info != 0:
                self._flexibility = False
                raise np.linalg.LinAlgError("T is not positive definite")
            self._flexibility = symmetric_from_upper(inverse)
        return self._flexibility

    def _force(self, du):
        """r = R(Ku − f_κ), by BLAS on the dense R S."""
        if not self.dense:
            return super()._force(du)
        return self._r_previous + self.RS @ du - self._Rf_step

    def bound(self, r, derivative=True):
        """f_c p and its derivative rows, dense (m × n) on the dense
        R S."""
        if not self.dense or self.coulomb == "lagged" or not derivative:
            return super().bound(r, derivative)
        active = (-r[self.n_rows] > 0.0) / self.lumped
        return self.friction * self.pressure(r), \
            -self.friction * active[:, None] * self.RS_n

    def residual(self, x):
        """(E, A, B) of :meth:`ProjectionSystem.residual` with the
        projection rows in nodal force units, D(g − P(w)) (module
        docstring: the merit ‖Φ‖ of the line searches)."""
        E, A, B = super().residual(x)
        if self.dense:
            E[len(E) - self.mt:] *= self.lumped_t
        return E, A, B

    def error(self, E, A, B, weighted=True):
        """:meth:`ProjectionSystem.error` (which weighs the projection rows
        by D itself) of the residual of :meth:`residual`."""
        if self.dense:
            E = E.copy()
            E[len(E) - self.mt:] /= self.lumped_t
        return super().error(E, A, B, weighted)

    def jacobian(self, x):
        if not self.dense:
            return super().jacobian(x)
        return DiscJacobian(self, x)


class DiscJacobian:
    """The structured Jacobian of :func:`solver.ncp.solve_ncp` (``JA``,
    ``JB``, :meth:`combine`) at the iterate x of a :class:`DiscSystem`;
    ``P`` holds the per-node blocks ∂P/∂w, a roller's e_c columns dropped
    (module docstring)."""

    def __init__(self, system, x):
        s = self.system = system
        self.x = x
        m, k = s.m, s.dim - 1
        du, g = x[:s.n], s.traction(x)
        r = s._force(du)
        b, self.db = s.bound(r)
        #: f_c a_i/D_i of the implicit bound (∂b/∂Δu = −slope·(RS)_n), or
        #: None (lagged)
        self.slope = None if self.db is None else \
            s.friction * (-r[s.n_rows] > 0.0) / s.lumped
        self.ct = np.broadcast_to(s.c_t, (s.mt,))
        self.P, self.stick, self.ratio, self.slip_hat = disc_derivative(
            s._slide(g, du).reshape(m, k), b,
            s.t_free if s.rollers else None)
        self.blocks = block_diagonal(self.P)
        self._Pu = None
        # Slip nodes with |b|/|w| ≤ 1/2 take dĝ from their projection row,
        # (I − P_w)⁻¹ = (I − ŵŵᵀ)/(1 − ratio) + ŵŵᵀ: exact where b = 0
        # (ĝ stays 0 at f_c = 0 or out of contact, not round-off of S).
        slip_hat, ratio = self.slip_hat, self.ratio
        self.own = ~self.stick & (ratio <= 0.5)
        outer = slip_hat[self.own, :, None] * slip_hat[self.own, None, :]
        self.inverse = (np.eye(k) - outer) / (1 - ratio[self.own, None,
                                                        None]) + outer
        if s.rollers:  # a roller's I − P_w (e_c columns dropped) directly
            rolling = ~s.t_free.reshape(m, k).all(axis=1)[self.own]
            self.inverse[rolling] = np.linalg.inv(
                np.eye(k) - self.P[self.own][rolling])

    @property
    def JA(self):
        """The normal pairs' −YRK (sparse; φ_FB's rule (31) only)."""
        return self.system._JA

    @property
    def JB(self):
        """The normal pairs' −cYR (sparse; φ_FB's rule (31) only)."""
        return self.system._JB

    @property
    def Pu(self):
        """P_u = c_t P_w R_t − ŵ ∂b/∂Δu, dense (n_t × n): only the LU of
        the whole system forms it."""
        if self._Pu is None:
            s, k = self.system, self.system.dim - 1
            Pu = (self.blocks @ s.R_t).toarray()  # R_t sparse
            Pu *= self.ct[:, None]
            if self.db is not None:  # −ŵ ∂b/∂Δu at slip nodes
                Pu -= self.slip_hat.reshape(-1, 1) * np.repeat(np.asarray(
                    self.db.todense() if sp.issparse(self.db)
                    else self.db), k, axis=0)
            self._Pu = Pu
        return self._Pu

    def pu_times(self, du):
        """P_u dΔu, from the sparse blocks (no dense P_u)."""
        s = self.system
        out = self.ct * (self.blocks @ (s.R_t @ du))
        if self.db is not None:
            out -= self.slip_hat.ravel() * np.repeat(self.db @ du,
                                                     s.dim - 1)
        return out

    def pu_rtimes(self, F):
        """Fᵀ P_u, from the sparse blocks."""
        s = self.system
        out = s.R_t.T @ (self.blocks.T @ (self.ct * F))
        if self.db is not None:
            k = s.dim - 1
            out -= (F * self.slip_hat.ravel()).reshape(-1, k).sum(1) \
                @ self.db
        return out

    def frames(self):
        """(Q, π): per node the eigenbasis Q_i (m, k, k) of its block P_w
        (columns ŵ, ŵ⊥ at a slip node with ŵ ≠ 0; I else, where P_w is
        diagonal: stick, w = 0, a roller) and the eigenvalues π (m, k)."""
        P, hat = self.P, self.slip_hat
        m, k = hat.shape
        Q = np.broadcast_to(np.eye(k), (m, k, k)).copy()
        pi = np.diagonal(P, axis1=1, axis2=2).copy()
        turn = (hat != 0.0).any(axis=1)
        if self.system.rollers:
            turn &= self.system.t_free.reshape(m, k).all(axis=1)
        if turn.any():  # k = 2: Q = [ŵ, ŵ⊥], π = (0, |b|/|w|)
            h = hat[turn]
            Q[turn] = np.stack([h, np.stack([-h[:, 1], h[:, 0]], 1)], 2)
            pi[turn] = np.stack([np.zeros(len(h)), self.ratio[turn]], 1)
        return Q, pi

    def _blocks(self, X, transpose=False):
        """blockdiag(P_w) X (or P_wᵀ X) for X with 2m rows."""
        m, k = self.P.shape[:2]
        P = np.swapaxes(self.P, 1, 2) if transpose else self.P
        shape = X.shape
        return np.einsum("ikl,il...->ik...", P,
                         X.reshape((m, k) + shape[1:])).reshape(shape)

    def combine(self, wa, wb):
        return _DiscCombined(self, np.asarray(wa, float),
                             np.asarray(wb, float))


class _DiscCombined:
    """J = [JE; diag(w_a)JA + diag(w_b)JB] of a :class:`DiscJacobian`."""

    def __init__(self, jac, wa, wb):
        self.jac, s = jac, jac.system
        self.wa, self.wb = wa, wb
        self.Dc = s.lumped_t * jac.ct

    @property
    def N(self):
        """The normal pairs' rows −w_a (RS)_n − c w_b R_n (dense m × n)."""
        s = self.jac.system
        return -(self.wa[:, None] * s.RS_n) - s.gap_scale * (
            self.wb[:, None] * s.R_n)

    def _free(self, X):
        """(I − P_w) X."""
        return X - self.jac._blocks(X)

    def _rows(self, F):
        """(F_1, F_2, F_3) of F = [E; Φ]: F_1 the tangential equilibrium
        rows, 0 at a roller's e_c (it has none), F_2 the projection rows,
        F_3 the normal pairs."""
        s = self.jac.system
        nf, mt = len(F) - s.mt - s.m, s.mt
        F1 = F[:nf]
        if s.rollers:
            F1 = np.zeros(mt)
            F1[s.t_free] = F[:nf]
        return F1, F[nf:nf + mt], F[nf + mt:]

    def direction(self, F):
        """d with J d = −F, or None if J is (numerically) singular."""
        jac, s = self.jac, self.jac.system
        F1, F2, F3 = self._rows(F)
        D = s.lumped_t
        F2 = F2 / D  # rows D(g − P(w)) (DiscSystem.residual): J's rows /D
        h = -F2 - self._free(F1 / D)
        free = s.t_free  # a roller's e_c row gives dĝ_c = −F_2,c/c_t
        if REDUCED:
            du = self._reduced(h, -F3)
        else:
            du = self._whole(h, -F3)
        if du is None:
            return None
        dg = (s.RS_t @ du + F1) / self.Dc
        if s.rollers:
            dg[~free] = -F2[~free] / jac.ct[~free]
        own = jac.own  # slip nodes far from the disc's edge: their own rows
        if own.any():
            m, k = jac.P.shape[:2]
            rhs = -((F2 + jac.pu_times(du)) / jac.ct).reshape(m, k)[own]
            dg.reshape(m, k)[own] = np.einsum("ikl,il->ik", jac.inverse,
                                              rhs)
        d = np.concatenate([du, dg])
        return d if np.all(np.isfinite(d)) else None

    def _whole(self, h_t, h_n):
        """dΔu from the LU of the whole n×n system (module docstring)."""
        jac, s = self.jac, self.jac.system
        D = s.lumped_t
        top = jac.Pu + self._free(s.RS_t / D[:, None])
        if s.rollers:
            top, h_t = top[s.t_free], h_t[s.t_free]
        M = np.vstack([top, self.N])
        h = np.concatenate([h_t, h_n])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", sla.LinAlgWarning)
            with blas_threads_for(len(M)):  # a/h 32: order ≈ 3·10³
                lu, piv = sla.lu_factor(M, check_finite=False)
            if not np.all(np.diagonal(lu)):
                return None
            return sla.lu_solve((lu, piv), h, check_finite=False)

    def _reduced(self, h_t, h_n):
        """dΔu from the primal or the dual system (module docstring),
        whichever is smaller; None if singular."""
        jac, s = self.jac, self.jac.system
        n, m, k = s.n, s.m, s.dim - 1
        Q, pi = jac.frames()
        # every row α_j (T'y)_j + β_j y_j = h'_j, at its position in v
        at = s.t_rows.reshape(m, k)
        valid = s.t_free.reshape(m, k)
        alpha, beta, h = np.zeros(n), np.zeros(n), np.zeros(n)
        alpha[at[valid]] = ((1.0 - pi) / s.lumped[:, None])[valid]
        beta[at[valid]] = (jac.ct.reshape(m, k) * pi)[valid]
        h[at[valid]] = np.einsum("ilk,il->ik", Q, h_t.reshape(m, k))[valid]
        alpha[s.n_rows] = -self.wa
        beta[s.n_rows] = -s.gap_scale * self.wb
        h[s.n_rows] = h_n
        # v = G y: each y_j enters v at one or two positions, v[r] += g y_j
        r1, r2 = np.arange(n), np.arange(n)
        g1, g2 = np.ones(n), np.zeros(n)
        turned = (Q != np.eye(k)).any(axis=(1, 2))
        pairs = at[turned]  # such nodes have both tangents (no roller)
        for c in range(k):
            r1[pairs[:, c]], r2[pairs[:, c]] = pairs[:, 0], pairs[:, 1]
            g1[pairs[:, c]], g2[pairs[:, c]] = Q[turned, 0, c], \
                Q[turned, 1, c]
        primal = alpha != 0.0
        dual = beta != 0.0
        if not (primal | dual).all():
            return None  # a zero row: J singular
        coupled = np.zeros(0, int)
        if jac.slope is not None:  # implicit bound: + κ_j (T'y)_{n_i}
            kappa, partner = np.zeros(n), np.zeros(n, int)
            lift = np.einsum("ilk,il->ik", Q, jac.slip_hat) \
                * jac.slope[:, None]
            kappa[at[valid]] = lift[valid]
            partner[at[valid]] = np.repeat(s.n_rows[:, None], k,
                                           axis=1)[valid]
            coupled = np.flatnonzero(kappa)
            if not primal[coupled].all():  # not one force row: the LU
                return self._whole(h_t, h_n)
        use_dual = not coupled.size and (
            FORM == "dual" or FORM == "smaller"
            and np.count_nonzero(dual) < np.count_nonzero(primal))
        if use_dual:
            try:
                matrix = s.flexibility()
            except np.linalg.LinAlgError:  # S only semidefinite: no C
                use_dual = False
        if use_dual:  # forces q = T'y; q_j = h_j/α_j where β_j = 0
            U, a, b = np.flatnonzero(dual), beta, alpha
            kind = "dual"
        else:  # y_j = h_j/β_j where α_j = 0
            U, a, b = np.flatnonzero(primal), alpha, beta
            kind, matrix = "primal", s.T
        fixed = np.ones(n, bool)
        fixed[U] = False
        z = np.zeros(n)
        z[fixed] = h[fixed] / b[fixed]

        def spread(y):  # G y
            return np.bincount(r1, g1 * y, n) + np.bincount(r2, g2 * y, n)

        def gather(v, rows):  # (Gᵀ v)[rows]
            return g1[rows] * v[r1[rows]] + g2[rows] * v[r2[rows]]

        # Gᵀ matrix G on U × U, by gathers (G has ≤ 2 entries per column:
        # no product with the whole matrix); the second entries only on
        # the turned components t
        i1, i2, w1, w2 = r1[U], r2[U], g1[U], g2[U]
        A = matrix[np.ix_(i1, i1)]
        scaled = np.flatnonzero(w1 != 1.0)  # turned components only
        A[scaled] *= w1[scaled, None]
        A[:, scaled] *= w1[scaled]
        t = np.flatnonzero(w2)
        if t.size:
            A[:, t] += matrix[np.ix_(i1, i2[t])] * (w1[:, None] * w2[t])
            A[t, :] += matrix[np.ix_(i2[t], i1)] * (w2[t, None] * w1)
            A[np.ix_(t, t)] += matrix[np.ix_(i2[t], i2[t])] * (
                w2[t, None] * w2[t])
        shift = b[U] / a[U]
        A[np.arange(len(U)), np.arange(len(U))] += shift
        known = matrix @ spread(z)
        rhs = h[U] / a[U] - gather(known, U)
        symmetric = bool((shift >= 0).all())
        if coupled.size:  # the slip rows' κ/α (T'y)_n: rows of T, unsymmetric
            where = np.searchsorted(U, coupled)
            weight = kappa[coupled] / alpha[coupled]
            normal = partner[coupled]
            A[where] += weight[:, None] * (matrix[np.ix_(normal, i1)] * w1
                                           + matrix[np.ix_(normal, i2)] * w2)
            rhs[where] -= weight * known[normal]
            symmetric = False
        with blas_threads_for(len(A)):
            solved = s._reduced_solve(A, rhs, symmetric, kind)
        if solved is None:
            return None
        z[U] = solved
        v = spread(z)
        if use_dual:  # z = q in the frames: v = C G q
            v = matrix @ v
        return s.RT @ v

    def rmatvec(self, F):
        """JᵀF in the unknowns x = [Δu; ĝ] (∇ψ of φ_FB, (28))."""
        jac, s = self.jac, self.jac.system
        F1, F2, F3 = self._rows(F)
        F2 = F2 * s.lumped_t  # (diag(D) J_2)ᵀ F_2
        gu = F1 @ s.RS_t + jac.pu_rtimes(F2) \
            - (self.wa * F3) @ s.RS_n \
            - s.gap_scale * ((self.wb * F3) @ s.R_n)
        gg = -self.Dc * F1 + jac.ct * (F2 - jac._blocks(F2, transpose=True))
        return np.concatenate([gu, gg])
