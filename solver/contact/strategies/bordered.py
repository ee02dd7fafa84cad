r"""Two bodies' frictionless candidates condensed from K's own factor.

The nodewise problem of the dual mortar (:mod:`solver.contact.two_body`)
is in v = Tu, T = I − E, with K̃ = T⁻ᵀKT⁻¹. :class:`~.candidates.
NormalCondensation` factorises K̂ = RK̃Rᵀ with the candidates' normal rows
as the Schur set; but K̃ glues the two bodies along the slave surface
(E couples each slave node to the master nodes under its support, EᵀKE
the master nodes under neighbouring slave nodes), and its factor has
about 1.5 times the fill of K's (benchmarks/README.md, issue 32).

The same condensed quantities come from K itself. With B the candidates'
normal rows of RT (m × n: b_j·u = n_j·(u_j − Σ_k P_jk u_k), the normal
relative displacement), K̂⁻¹ = RTK⁻¹TᵀRᵀ gives

.. math::
    S^{-1} = B K^{-1} B^T, \qquad w = R T K^{-1} f, \qquad
    \hat u = R T K^{-1} (f + B^T S (u_n - w_c)),

and B K⁻¹ Bᵀ is the Schur complement (negated) of the bordered matrix
[[K, Bᵀ], [B, 0]] on its m border rows: one symmetric indefinite LDLᵀ in
which the border is eliminated last, so the interior factor is K's
(:class:`solver.linalg.pardiso.BorderedFactor`). The multipliers of the
border are what the dual mortar's saddle point would have (Wohlmuth,
SIAM J. Numer. Anal. 38 (2000) 989; the condensed form of Popp et al.,
IJNME 83 (2010) 1428, section 4), and only the candidates carry one. The
results are those of :class:`~.candidates.NormalCondensation` to
rounding (S, g̃, u), with the same interface; used for a two-body problem
on a backend with ``factorize_bordered`` (PARDISO)."""

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from ...linalg import get_backend
from ..geometry import rotation

__all__ = ["BorderedCondensation", "supports"]


def supports(problem, backend):
    """Whether ``problem`` (a nodewise problem in v with its
    ``change_of_variables``) can be condensed by ``backend`` this way."""
    return getattr(problem, "change_of_variables", None) is not None and \
        hasattr(get_backend(backend), "factorize_bordered")


class BorderedCondensation:
    """:class:`~.candidates.NormalCondensation`'s interface (``R``,
    ``normal_rows``, ``factorizations``, :meth:`factorize`,
    :meth:`displacement`) from K's bordered factor (module docstring)."""

    def __init__(self, problem, geometry, backend):
        self.problem, self.geometry = problem, geometry
        self.module = get_backend(backend)
        K, f, E = problem.change_of_variables
        n = problem.n_dofs
        self.K, self.f = K, f
        self.T = (sp.identity(n, format="csr") - E).tocsr()
        self.R = rotation(n, geometry)[0]
        self.normal_rows = geometry.dofs[:, -1]
        self.B = (self.R[self.normal_rows] @ self.T).tocsr()
        self.factorizations = 0

    def factorize(self, nodes):
        """(S, g̃, w_c) for the candidates ``nodes`` (positions in the
        geometry): S = (B_c K⁻¹ B_cᵀ)⁻¹, w_c = B_c K⁻¹ f, g̃ = S w_c."""
        self.nodes = np.asarray(nodes, np.int64)
        B = self.B[self.nodes]
        self.factor = self.module.factorize_bordered(self.K, B, "K")
        self.factorizations += 1
        self.u0 = self.factor.solve(self.f)          # K⁻¹ f
        w_c = B @ self.u0
        if not len(self.nodes):
            self.S = np.zeros((0, 0))
        else:
            C = sla.cho_factor(self.factor.C)
            S = sla.cho_solve(C, np.eye(len(self.nodes)))
            self.S = 0.5 * (S + S.T)
        return self.S, self.S @ w_c, w_c

    def displacement(self, u_n):
        """(v, normal displacement at every free contact node) from the
        candidates' normal displacements u_n: u = K⁻¹(f + B_cᵀ y), y =
        S(u_n − w_c), one back-substitution, and v = Tu."""
        u = self.u0
        if len(self.nodes):
            y = self.S @ (np.asarray(u_n, float) - self.B[self.nodes]
                          @ self.u0)
            u = self.factor.solve(self.f, -y)
        v = self.T @ u
        return v, self.B @ u
