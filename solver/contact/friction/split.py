r"""The thesis's split formulation (110)/(111) of a load step: unknowns
x = [Δu; ĝ; Δu_t⁺; Δu_t⁻] (ĝ = g_t/c_t), the slip split by (106) and two
complementarity pairs (98), (101) for the Coulomb bound (the rows in
:mod:`solver.contact.friction.driver`). 2D only, no rollers."""

import numpy as np
import scipy.sparse as sp

from ...errors import SolverError
from ...ncp import stable_norm
from .system import FrictionSystem

__all__ = ["SplitSystem", "check_geometry"]


def check_geometry(geometry):
    """SolverError (one line) for what the split does not take: a
    geometry outside 2D (Δu_t = Δu_t⁺ − Δu_t⁻ splits a scalar slip) and
    roller nodes (no row to drop for a constrained tangent)."""
    if geometry.dim != 2:
        raise SolverError("the thesis's split formulation (Δu_t⁺, Δu_t⁻) is "
                          "2D-only; use --formulation projection "
                          "(formulation=\"projection\") in 3D")
    if geometry.has_rollers:
        raise SolverError("the thesis's split formulation does not take "
                          "roller nodes (contact nodes with a Dirichlet "
                          "component); use --formulation projection "
                          "(formulation=\"projection\") or rollers=False")


class SplitSystem(FrictionSystem):
    """The thesis's split (110)/(111) of one load step
    (:class:`~.system.FrictionSystem`'s parameters)."""

    formulation = "thesis"

    def __init__(self, K, f, geometry, *args, **kwargs):
        check_geometry(geometry)
        super().__init__(K, f, geometry, *args, **kwargs)
        n, m = self.n, self.m
        RK, R, other, a, b = (self.RK, self.R, self.x_rows, self.t_rows,
                              self.n_rows)
        I, Z0 = sp.identity(m, format="csr"), sp.csr_matrix((m, m))
        self._I, self._Z0 = I, Z0
        Zn = sp.csr_matrix((m, n))
        self._JE = sp.bmat([
            [RK[other], None, None, None],
            [RK[a], -sp.diags(self.lumped), None, None],
            [R[a], None, -I, I]], format="csr")
        self._JA = sp.bmat([[-RK[b], Z0, Z0, Z0], [Zn, Z0, Z0, I],
                            [Zn, Z0, I, Z0]], format="csr")
        self._JB_normal = sp.hstack([-self.gap_scale * R[b], Z0, Z0, Z0],
                                    format="csr")

    @property
    def n_unknowns(self):
        return self.n + 3 * self.m

    def _split(self, x):
        """(Δu, g_t, Δu_t⁺, Δu_t⁻) from the unknown vector x."""
        n, m = self.n, self.m
        return x[:n], self.traction(x), x[n + m:n + 2 * m], x[n + 2 * m:]

    def residual(self, x):
        """(E, A, B): E the equilibrium rows X, Z and the split (106),
        A = [λ; Δu_t⁻; Δu_t⁺] ⊥ B = [c(s − YRu); f_c p − g_t; f_c p + g_t]."""
        du, g, dp, dm = self._split(x)
        _, rx, tangential, lam, gap, b = self._shared_rows(du, g)
        split = (self.R @ du)[self.t_rows] - dp + dm
        return (np.concatenate([rx, tangential, split]),
                np.concatenate([lam, dm, dp]),
                np.concatenate([gap, b - g, b + g]))

    def _jacobian(self, x):
        du = x[:self.n]
        _, db = self.bound(self._force(du))
        m, n = self.m, self.n
        zero = sp.csr_matrix((m, n)) if db is None else db
        JB = sp.vstack([self._JB_normal,
                        sp.hstack([zero, -self._I, self._Z0, self._Z0]),
                        sp.hstack([zero, self._I, self._Z0, self._Z0])],
                       format="csr")
        return self._JE, self._JA, JB

    def error(self, E, A, B, weighted=True):
        """Stopping measure in force units (cf. FrictionlessSystem.error):
        the split rows (lengths) times k̄, the bound's pairs as nodal
        forces min(k̄ Δu_t±, D(f_c p ∓ g_t)); one scale for all rows, as
        the thesis poses its split (``weighted`` is accepted and
        ignored)."""
        k, c = self.stiffness, self.gap_scale
        m, nx = self.m, len(self.x_rows)
        E = np.concatenate([E[:nx + m], k * E[nx + m:]])
        pairs = np.concatenate([
            np.minimum(A[:m], k / c * B[:m]),
            np.minimum(k * A[m:2 * m], self.lumped * B[m:2 * m]),
            np.minimum(k * A[2 * m:], self.lumped * B[2 * m:])])
        return float(np.hypot(stable_norm(E), stable_norm(pairs)))

    def initial_guess(self, g_previous, du=None):
        """:meth:`FrictionSystem.initial_guess`; with a predictor ``du``
        the split starts consistent, Δu_t± = max(±ZRΔu, 0)."""
        x = super().initial_guess(g_previous, du)
        if du is not None:
            n, m = self.n, self.m
            dut = (self.R @ du)[self.t_rows]
            x[n + m:n + 2 * m] = np.maximum(dut, 0)
            x[n + 2 * m:] = np.maximum(-dut, 0)
        return x
