r"""Counted evaluations of Φ(x) = [E(x); φ(A(x), B(x))] and of an element
of its B-subdifferential ∂_B Φ (thesis (15), (17)-(18) for φ_min, (29)-(31)
for φ_FB): the counts njev, nfev of Table 1 come from this wrapper, not
from each method's bookkeeping (as scipy.optimize's wrappers)."""

import numpy as np
import scipy.sparse as sp

from .functions import derivative_weights, phi

__all__ = ["Counted", "_default_z"]


class Counted:
    """Wraps ``fun`` and ``jac`` to count evaluations (Table 1's metrics)."""

    def __init__(self, fun, jac, kind):
        self.fun, self.jac, self.kind = fun, jac, kind
        self.nfev = self.njev = 0

    def residual(self, x):
        """Φ(x) and the pieces (E, A, B)."""
        self.nfev += 1
        E, A, B = (np.asarray(v, dtype=float) for v in self.fun(x))
        return np.concatenate([E, phi(A, B, self.kind)]), (E, A, B)

    def jacobian(self, x, parts, z=None, ties=0.0):
        """J ∈ ∂_B Φ(x) and the number of predicted contacts; with ``ties`` > 0
        (φ_min) rows with |A_i − B_i| ≤ ties take ∇A_i, the element of ∂_B
        φ_min at an exact tie (:data:`solver.ncp.newton.TIE_RTOL`)."""
        self.njev += 1
        jac = self.jac(x)
        structured = hasattr(jac, "combine")
        JE, JA, JB = (None, None, None) if structured else jac
        E, A, B = parts
        za = zb = None
        if self.kind == "fb":
            gamma = (A == 0.0) & (B == 0.0)
            if gamma.any():
                if structured:  # read only here (rule (31))
                    JA, JB = jac.JA, jac.JB
                direction = z(gamma) if z is not None else _default_z(
                    JA, gamma)
                za, zb = JA @ direction, JB @ direction
        wa, wb, _ = derivative_weights(A, B, self.kind, za, zb)
        if ties > 0 and self.kind == "min":
            near = np.abs(A - B) <= ties
            wa, wb = np.where(near, 1.0, wa), np.where(near, 0.0, wb)
        if structured:
            return jac.combine(wa, wb), int(np.count_nonzero(A > B))
        if all(isinstance(block, np.ndarray) for block in (JE, JA, JB)):
            rows = wa[:, None] * JA + wb[:, None] * JB  # dense blocks
            return np.vstack([JE, rows]), int(np.count_nonzero(A > B))
        rows = sp.diags(wa) @ sp.csr_matrix(JA) + sp.diags(wb) @ \
            sp.csr_matrix(JB)
        J = sp.vstack([sp.csr_matrix(JE), rows], format="csc")
        return J, int(np.count_nonzero(A > B))


def _default_z(JA, gamma):
    """DFK's z with z_i = 1 on γ, read in the variables of A: DFK (1996)
    pose x ≥ 0, so ∇A_i = e_i; here z = Σ_{i∈γ} ∇A_i / ‖∇A_i‖², with
    ∇A_iᵀz = 1 when the rows of γ are orthogonal (distinct contact nodes)."""
    JA = sp.csr_matrix(JA)[np.flatnonzero(gamma)]
    norms2 = np.asarray(JA.multiply(JA).sum(axis=1)).ravel()
    norms2[norms2 == 0.0] = 1.0
    return np.asarray(JA.T @ (1.0 / norms2)).ravel()
