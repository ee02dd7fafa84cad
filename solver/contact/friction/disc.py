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
c_t dĝ_c = −F_2,c and ∂P/∂w loses its column: the matrix stays square."""

import warnings

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from ...linalg.threads import blas_threads_for
from .projection import ProjectionSystem, block_diagonal, disc_derivative

__all__ = ["DiscSystem", "DiscJacobian"]


class DiscSystem(ProjectionSystem):
    """:class:`~.projection.ProjectionSystem` on a dense condensed S (3D)
    whose :meth:`jacobian` is a :class:`DiscJacobian`."""

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
        m, k = s.m, s.dim - 1
        du, g = x[:s.n], s.traction(x)
        r = s._force(du)
        b, db = s.bound(r)
        ct = self.ct = np.broadcast_to(s.c_t, (s.mt,))
        self.P, stick, ratio, slip_hat = disc_derivative(
            s._slide(g, du).reshape(m, k), b,
            s.t_free if s.rollers else None)
        Pu = (block_diagonal(self.P) @ s.R_t).toarray()  # R_t sparse
        Pu *= ct[:, None]
        if db is not None:  # −ŵ ∂b/∂Δu at slip nodes
            Pu -= slip_hat.reshape(-1, 1) * np.repeat(np.asarray(
                db.todense() if sp.issparse(db) else db), k, axis=0)
        self.Pu = Pu
        # Slip nodes with |b|/|w| ≤ 1/2 take dĝ from their projection row,
        # (I − P_w)⁻¹ = (I − ŵŵᵀ)/(1 − ratio) + ŵŵᵀ: exact where b = 0
        # (ĝ stays 0 at f_c = 0 or out of contact, not round-off of S).
        self.own = ~stick & (ratio <= 0.5)
        outer = slip_hat[self.own, :, None] * slip_hat[self.own, None, :]
        self.inverse = (np.eye(k) - outer) / (1 - ratio[self.own, None,
                                                        None]) + outer
        if s.rollers:  # a roller's I − P_w (e_c columns dropped) directly
            rolling = ~s.t_free.reshape(m, k).all(axis=1)[self.own]
            self.inverse[rolling] = np.linalg.inv(
                np.eye(k) - self.P[self.own][rolling])
        self.JA, self.JB = s._JA, s._JB

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
        self.N = -(wa[:, None] * s.RS_n) - s.gap_scale * (wb[:, None]
                                                          * s.R_n)
        self.Dc = s.lumped_t * jac.ct

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
        top = jac.Pu + self._free(s.RS_t / D[:, None])
        h = -F2 - self._free(F1 / D)
        free = s.t_free  # a roller's e_c row gives dĝ_c = −F_2,c/c_t
        if s.rollers:
            top, h = top[free], h[free]
        M = np.vstack([top, self.N])
        h = np.concatenate([h, -F3])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", sla.LinAlgWarning)
            with blas_threads_for(len(M)):  # a/h 32: order ≈ 3·10³
                lu, piv = sla.lu_factor(M, check_finite=False)
            if not np.all(np.diagonal(lu)):
                return None
            du = sla.lu_solve((lu, piv), h, check_finite=False)
        dg = (s.RS_t @ du + F1) / self.Dc
        if s.rollers:
            dg[~free] = -F2[~free] / jac.ct[~free]
        own = jac.own  # slip nodes far from the disc's edge: their own rows
        if own.any():
            m, k = jac.P.shape[:2]
            rhs = -((F2 + jac.Pu @ du) / jac.ct).reshape(m, k)[own]
            dg.reshape(m, k)[own] = np.einsum("ikl,il->ik", jac.inverse,
                                              rhs)
        d = np.concatenate([du, dg])
        return d if np.all(np.isfinite(d)) else None

    def rmatvec(self, F):
        """JᵀF in the unknowns x = [Δu; ĝ] (∇ψ of φ_FB, (28))."""
        jac, s = self.jac, self.jac.system
        F1, F2, F3 = self._rows(F)
        F2 = F2 * s.lumped_t  # (diag(D) J_2)ᵀ F_2
        gu = F1 @ s.RS_t + F2 @ jac.Pu + F3 @ self.N
        gg = -self.Dc * F1 + jac.ct * (F2 - jac._blocks(F2, transpose=True))
        return np.concatenate([gu, gg])
