r"""The frictionless system (67) of thesis §3.2 as residual and Jacobian
for :func:`solver.ncp.solve_ncp`.

Unknown: the reduced displacement vector u (Ñ entries). At each contact
node the rotation **R** maps the nodal vector to (tangential, normal)
components (58)-(60) (:func:`~solver.contact.geometry.rotation`); **X**
keeps every row except the normal rows of contact nodes and **Y** keeps
only those (66). The system (67) is the mixed NCP

.. math::
    X(RKu − Rf) = 0, \quad
    A(u) = −Y(RKu − Rf) \ge 0,\ B(u) = c(s − YRu) \ge 0,\ A^T B = 0,

A the normal contact force λ, B the remaining gap scaled by c > 0 (the
same solution, another Newton path; c = 1 is the thesis). The thesis's
(69) is the same with φ_min and signs flipped; its "−Y(RKu + Rf)" is a typo
for −Y(RKu − Rf). On the full K or on a dense Schur complement (then its
Newton systems are solved on the free components, :mod:`.newton`); the
same in 2D and 3D."""

import numpy as np
import scipy.sparse as sp

from ...ncp import stable_norm
from .newton import CondensedJacobian
from ..geometry import contact_stiffness, rotation
from ..verify import contact_weight, force_scale

__all__ = ["FrictionlessSystem"]


class FrictionlessSystem:
    """Residual and Jacobian of (67) for :func:`solver.ncp.solve_ncp` on
    the reduced stiffness K (Ñ, Ñ) (sparse, or a dense S), the load f and
    the ``geometry``; ``gap_scale`` is c. ``stiffness`` k̄ of :meth:`error`
    and ``load_norm`` ‖f‖₂ of :meth:`scale` default to those of K and f; a
    condensed system or a coarse level passes the problem's."""

    def __init__(self, K, f, geometry, gap_scale=1.0, stiffness=None,
                 load_norm=None):
        n = K.shape[0]
        # A dense K (a Schur complement S) stays dense: its Jacobian blocks
        # are dense arrays, which :func:`solver.ncp.solve_ncp` combines and
        # factorises with LAPACK, no sparse assembly (the same values).
        dense = isinstance(K, np.ndarray)
        self.K = K if dense else sp.csr_matrix(K)
        self.f, self.geometry = f, geometry
        self.gap_scale = float(gap_scale)
        self.R, _, _, b = rotation(n, geometry)
        keep = np.ones(n, dtype=bool)
        keep[b] = False
        self.x_rows, self.y_rows = np.flatnonzero(keep), b  # X and Y (66)
        RK = self.R @ self.K if dense else (self.R @ self.K).tocsr()
        self.Rf = self.R @ f
        self._JE = RK[self.x_rows]
        self._JA = -RK[self.y_rows]
        RY = self.R[self.y_rows]
        self._JB = -self.gap_scale * (RY.toarray() if dense else RY)
        self._reduced = None
        if dense and _orthogonal(self.R):  # Newton on the free components
            self._reduced = CondensedJacobian(
                self.K, self.R, self.x_rows, self.y_rows, self._JA,
                self._JB, self.gap_scale)
        self.stiffness = contact_stiffness(self.K, geometry) \
            if stiffness is None else float(stiffness)
        self.load_norm = stable_norm(f) if load_norm is None \
            else float(load_norm)

    def residual(self, u):
        """(E, A, B) = (X(RKu − Rf), −Y(RKu − Rf), c(s − YRu)), thesis (67)."""
        r = self.R @ (self.K @ u) - self.Rf
        gap = self.geometry.gap - (self.R @ u)[self.y_rows]
        return r[self.x_rows], -r[self.y_rows], self.gap_scale * gap

    def jacobian(self, u):
        """(JE, JA, JB) = (XRK, −YRK, −cYR), constant (the system is
        linear); on a dense K a :class:`~.newton.CondensedJacobian`, whose
        Newton systems are solved on the free components only."""
        if self._reduced is not None:
            return self._reduced
        return self._JE, self._JA, self._JB

    def error(self, E, A, B, weighted=True):
        """Stopping measure in force units, whatever c and the NCP function:
        ‖[E; w·min(A, k̄ B / c)]‖₂ with k̄ the mean stiffness diag(K) at
        the normal DOFs, so that a gap error δ counts as the force k̄δ, and
        w = F/F_c, so that the contact rows are measured against the
        contact forces (:func:`~solver.contact.verify.contact_weight`;
        w = 1 if not ``weighted``)."""
        w = contact_weight(self.load_norm, A) if weighted else 1.0
        return float(np.hypot(stable_norm(E), w * stable_norm(np.minimum(
                A, self.stiffness / self.gap_scale * B))))

    def scale(self, E, A, B):
        """The force scale F = max(‖f‖₂, ‖λ⁺‖₂) of the stopping test
        error ≤ tol·F (A = λ; :mod:`solver.contact.verify`)."""
        return force_scale(self.load_norm, A)

    def contact_force(self, u):
        """λ = −Y(RKu − Rf): normal contact force at the free contact nodes."""
        return -(self.R @ (self.K @ u) - self.Rf)[self.y_rows]

    def normal_displacement(self, u):
        """u_n = YRu at the free contact nodes."""
        return (self.R @ u)[self.y_rows]


def _orthogonal(R):
    """Whether the sparse square R has RᵀR = I (to round-off), tested on
    two fixed random vectors x: ‖RᵀRx − x‖ ≤ 1e-12‖x‖ (RᵀR − I ≠ 0 maps
    such x to a non-zero vector with probability 1)."""
    n = R.shape[0]
    if R.shape[1] != n:
        return False
    x = np.random.default_rng(17).standard_normal((n, 2))
    return bool(np.abs(R.T @ (R @ x) - x).max(initial=0.0) <= 1e-12 *
                np.abs(x).max(initial=1.0))
