r"""The projection formulation of a load step (beyond the thesis):
unknowns x = [Δu; ĝ] (ĝ = g_t/c_t) and the row g − P(w), w = g − c_t ZRΔu,
P the projection onto the disc |·| ≤ b = f_c p of R^{d−1} (Alart &
Curnier, CMAME 92 (1991) 353; Hüeber, Stadler & Wohlmuth, SIAM J. Sci.
Comput. 30 (2008) 572), in place of the thesis's split (:mod:`.driver`).

P(w) = w·min(1, b/|w|); at a stick node (|w| < b) ∂P/∂w = I, at a slip
node ∂P/∂w = (b/|w|)(I − ŵŵᵀ) and ∂P/∂b = ŵ; in 2D the clip onto
[−b, b]. At a roller (:mod:`solver.contact.geometry`) the row along e_c
is a support reaction, not friction: w_c ≡ 0, the e_c column of ∂P/∂w
drops and the row of g_c is g_c itself, so the Coulomb set is the disc
cut to the free tangents (exact for loads symmetric about the plane)."""

import numpy as np
import scipy.linalg as sla_dense
import scipy.sparse as sp

from ...linalg.dense import factorize
from .newton import ReducedJacobian
from .system import FrictionSystem
from ..verify import contact_weight

__all__ = ["ProjectionSystem", "project_disc", "disc_derivative",
           "block_diagonal"]


def project_disc(w, b, k):
    """P(w) onto the disc (ball) |·| ≤ b of R^k, per node: w flat (m·k,)
    node by node, b (m,); w·min(1, b/|w|)."""
    w = np.reshape(w, (len(b), k))
    size = np.linalg.norm(w, axis=1)
    ratio = np.minimum(1.0, np.divide(b, size, out=np.ones_like(size),
                                      where=size > b))
    return (w * ratio[:, None]).ravel()


def disc_derivative(w, b, t_free=None):
    """∂P/∂w of the projection at w (m, k) for the radii b (m,): (P,
    stick, ratio, slip_hat), the (m, k, k) blocks ∂P/∂w (the e_c columns
    dropped where ``t_free`` is False), the mask |w| < b, b/|w| (1 at stick
    nodes) and ŵ at slip nodes (0 at stick nodes), which is ∂P/∂b."""
    m, k = w.shape
    size = np.linalg.norm(w, axis=1)
    stick = size < b
    ratio = np.where(stick, 1.0, np.divide(
        b, size, out=np.zeros(m), where=size > 0))
    hat = np.divide(w, size[:, None], out=np.zeros_like(w),
                    where=size[:, None] > 0)
    slip_hat = np.where(stick[:, None], 0.0, hat)
    P = ratio[:, None, None] * (np.eye(k) - slip_hat[:, :, None]
                                * slip_hat[:, None, :])
    if t_free is not None:
        P *= np.asarray(t_free, float).reshape(m, 1, k)
    return P, stick, ratio, slip_hat


def block_diagonal(P):
    """Sparse block diagonal of the (m, k, k) blocks P."""
    m, k, _ = P.shape
    rows = np.repeat(np.arange(m * k).reshape(m, k), k, axis=1).ravel()
    cols = np.tile(np.arange(m * k).reshape(m, k), (1, k)).ravel()
    return sp.csr_matrix((P.ravel(), (rows, cols)), shape=(m * k, m * k))


class ProjectionSystem(FrictionSystem):
    """The projection formulation of one load step
    (:class:`~.system.FrictionSystem`'s parameters). Condensed (dense S,
    no other rows) in 2D without rollers, its Newton systems are solved on
    the free components (:class:`~.newton.ReducedJacobian`)."""

    formulation = "projection"
    #: Solve the condensed Newton systems reduced to the free components
    #: (:mod:`.newton`); False: the full J (the reference of the tests).
    reduced_newton = True

    #: Assemble the sparse Jacobian blocks of RK when first used, not in
    #: the constructor (:class:`~.disc.DiscSystem`: on a dense S they copy
    #: S into CSR, and φ_min's reduced systems never read them).
    lazy_blocks = False

    def __init__(self, K, *args, **kwargs):
        super().__init__(K, *args, **kwargs)
        R, a = self.R, self.t_rows
        #: ZR with a roller's e_c rows 0 (it moves no tangential DOF)
        self._Rt = R[a]
        if self.rollers:
            self._Rt = sp.diags(self.t_free.astype(float)) @ R[
                np.where(self.t_free, a, 0)]
        self._blocks = None if self.lazy_blocks else self._sparse_blocks()
        self.reduced = (self.reduced_newton and self.dim == 2
                        and not self.rollers and self.dense_schur)
        if self.reduced:
            RS = R @ np.asarray(K, float)
            self.T = np.ascontiguousarray((R @ RS.T).T)  # R S Rᵀ
            self.RK = RS  # dense: residuals by BLAS, not CSR of a dense S
            self._factor = None  # (kind, matrix, solve) of the last one
            self._flexibility = None  # T⁻¹, made when first needed

    def _sparse_blocks(self):
        """(JE's fixed rows, JA, JB) in CSR: the X and tangential
        equilibrium rows [RK, −D] and the normal pairs' −YRK, −cYR."""
        RK, R, other, a = self.RK, self.R, self.x_rows, self.t_rows
        m, mt = self.m, self.mt
        Zt = sp.csr_matrix((m, mt))
        Dt, free = sp.diags(self.lumped_t, format="csr"), a
        if self.rollers:
            free = a[self.t_free]
            Dt = Dt[self.t_free]
        return (sp.bmat([[RK[other], sp.csr_matrix((len(other), mt))],
                         [RK[free], -Dt]], format="csr"),
                sp.hstack([-RK[self.n_rows], Zt], format="csr"),
                sp.hstack([-self.gap_scale * R[self.n_rows], Zt],
                          format="csr"))

    def _block(self, i):
        if self._blocks is None:
            self._blocks = self._sparse_blocks()
        return self._blocks[i]

    @property
    def _JE_fixed(self):
        return self._block(0)

    @property
    def _JA(self):
        return self._block(1)

    @property
    def _JB(self):
        return self._block(2)

    @property
    def n_unknowns(self):
        return self.n + self.mt

    def residual(self, x):
        """(E, A, B): E the equilibrium rows X, Z (none along a roller's
        e_c) and g − P(w), A = λ ⊥ B = c(s − YRu)."""
        du, g = x[:self.n], self.traction(x)
        _, rx, tangential, lam, gap, b = self._shared_rows(du, g)
        w = self._slide(g, du)
        P = np.clip(w, -b, b) if self.dim == 2 else \
            project_disc(w, b, self.dim - 1)
        return np.concatenate([rx, tangential, g - P]), lam, gap

    def _slide(self, g, du):
        """w = g − c_t ZRΔu, 0 along a roller's e_c (g − P(w) = 0 then
        makes g_c = 0)."""
        w = g - self.c_t * (self.R @ du)[self.t_rows]
        return np.where(self.t_free, w, 0.0) if self.rollers else w

    def jacobian(self, x):
        """:meth:`FrictionSystem.jacobian`, or on the condensed 2D system
        the same Jacobian as a :class:`~.newton.ReducedJacobian`."""
        if not self.reduced:
            return super().jacobian(x)
        du, g = x[:self.n], self.traction(x)
        r = self._force(du)
        b, _ = self.bound(r, derivative=False)
        w = g - self.c_t * (self.R @ du)[self.t_rows]
        stick = np.abs(w) < b
        active = None if self.coulomb == "lagged" else \
            (-r[self.n_rows] > 0.0).astype(float)
        return ReducedJacobian(self, x, stick, ~stick & (w >= 0), active)

    def _jacobian(self, x):
        """(JE, JA, JB) of the projection onto the disc (any d; in 2D the
        clip's), module docstring: ∂P/∂w, ∂P/∂b = ŵ; at a roller the e_c
        column drops."""
        du, g = x[:self.n], self.traction(x)
        b, db = self.bound(self._force(du))
        k, m = self.dim - 1, self.m
        P, stick, _, slip_hat = disc_derivative(
            self._slide(g, du).reshape(m, k), b,
            self.t_free if self.rollers else None)
        blocks = block_diagonal(P)
        # c_t a scalar or one value per tangential unknown (DiscSystem's)
        rows_du = blocks @ (sp.diags(np.broadcast_to(self.c_t, (self.mt,)))
                            @ self._Rt)
        if db is not None:  # −∂P/∂b db = −ŵ db at slip nodes
            rows_du = rows_du - sp.diags(slip_hat.ravel()) @ sp.csr_matrix(
                db[np.repeat(np.arange(m), k)])
        J3 = sp.hstack([rows_du, sp.identity(m * k) - blocks],
                       format="csr")
        return sp.vstack([self._JE_fixed, J3], format="csr"), self._JA, \
            self._JB

    def error(self, E, A, B, weighted=True):
        """Stopping measure in force units (cf. FrictionlessSystem.error):
        the projection rows (tractions) as nodal forces D(g − P(w)), they
        and the normal pairs weighted by w = F/F_c, so that the Coulomb
        law is measured against the contact forces
        (:func:`~solver.contact.verify.contact_weight`; w = 1 if not
        ``weighted``)."""
        k, c = self.stiffness, self.gap_scale
        w = contact_weight(self.load_norm,
                           self.gathered(np.maximum(A, 0.0)),
                           self.gathered(self.last_friction_force)) \
            if weighted else 1.0
        head = len(self.x_rows) + int(self.t_free.sum())  # equilibrium rows
        E = np.concatenate([E[:head], w * self.lumped_t * E[head:]])
        pairs = np.minimum(A, k / c * B)
        return float(np.hypot(self.norm(E), w * self.norm(pairs)))

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
