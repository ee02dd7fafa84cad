r"""The candidates' condensation of a two-body (dual mortar) problem from a
factorisation of K itself, not of K̃ = T⁻ᵀKT⁻¹.

The nodewise problem in v (:mod:`solver.contact.two_body`) has K̃ =
T⁻ᵀKT⁻¹, T = I − E (E: the slave DOFs' rows P = D⁻¹M ⊗ I_d on the master
DOFs). K̃ glues the two bodies along the whole covered slave surface, so
its factor has some 1.5× the fill of K's (two independent bodies); and the
candidates' condensation needs only

.. math::
    (K̂^{-1})_{cc} = G K_r^{-1} G^T, \qquad G = (R T R^T)_{c,:}
                  = C_c − (R E)_{c,:},

with K̂ = R K̃ Rᵀ, K_r = R K Rᵀ (R the contact frames of the slave nodes,
the identity on the master), c the candidates' normal rows. G is nonzero
on J = c ∪ (the master DOFs coupled to them) only, so one factorisation of
K_r with the Schur set J gives S_J = ((K_r⁻¹)_JJ)⁻¹ (dense, |J| × |J|: the
slave candidates' normal rows and their masters' DOFs) and

.. math::
    S = \bigl(G_J S_J^{-1} G_J^T\bigr)^{-1}, \qquad
    w = K̂^{-1} f̂ = R T K^{-1} f = T_r K_r^{-1} R f, \qquad
    û = w + T_r K_r^{-1} G^T S (u_n − w_c),

the last by one back-substitution of K_r (:class:`NormalCondensation`'s
S, g̃ = S w_c and û, the same numbers to rounding). This is the Schur
complement of the interface of both bodies (Wriggers, *Computational
Contact Mechanics*, 2006, §6.2.2; FETI-like interface condensation,
Dostál, *Optimal Quadratic Programming Algorithms*, 2009): K's fill, the
mortar coupling only in the dense interface block."""

import numpy as np
import scipy.linalg as sla

from ...linalg import dof_ordering, get_backend
from ..geometry import rotate_stiffness, rotation

__all__ = ["MortarCondensation"]


class MortarCondensation:
    """:class:`~.candidates.NormalCondensation`'s interface (``R``,
    ``normal_rows``, :meth:`factorize`, :meth:`displacement`) for the
    nodewise problem ``problem`` in v of a two-body problem ``original``
    with u = (I + ``E``) v (module docstring); K of ``original`` is
    factorised by the :mod:`solver.linalg` ``backend``."""

    def __init__(self, problem, geometry, backend, original, E):
        self.problem, self.geometry, self.original = problem, geometry, \
            original
        self.module = get_backend(backend)
        n = problem.n_dofs
        self.R = rotation(n, geometry)[0]
        self.K = rotate_stiffness(original.K, self.R, geometry.free_dofs())
        self.E_r = (self.R @ E).tocsr()      # R E Rᵀ: R is I on the master
        # f = Tᵀ f̃ (f̃ = T⁻ᵀ f): the two-body load, then rotated
        f = problem.f - E.T @ problem.f
        self.f = self.R @ f
        self.normal_rows = geometry.dofs[:, -1]
        self.factorizations = 0

    def _T(self, x):
        """T_r x = x − R E Rᵀ x (x rotated, (n,) or (n, k))."""
        return x - self.E_r @ x

    def factorize(self, nodes):
        """Factorise K_r with the Schur set J = normal rows c of ``nodes``
        and their masters' DOFs. Returns (S, g̃, w_c) as
        :meth:`NormalCondensation.factorize`."""
        self.nodes = np.asarray(nodes, np.int64)
        c = self.normal_rows[self.nodes]
        coupled = self.E_r[c]
        masters = np.unique(coupled.indices)
        J = np.concatenate([c, masters])
        order = dof_ordering(self.original, last=J) \
            if self.module.USES_ORDER else None
        self.factor = self.module.factorize(
            self.K, order, J if len(J) else None, "K",
            self.factorizations == 0)
        self.factorizations += 1
        w = self.factor.solve(self.f)
        self.w = self._T(w)
        if not len(c):
            self.X = np.zeros((0, 0))
            return np.zeros((0, 0)), np.zeros(0), np.zeros(0)
        m = len(c)
        # G_Jᵀ (|J|, m): the identity on c, −(R E)_{c, masters}ᵀ below
        G_T = np.zeros((len(J), m))
        G_T[np.arange(m), np.arange(m)] = 1.0
        G_T[m:] = -coupled[:, masters].T.toarray()
        self.X = sla.cho_solve(sla.cho_factor(self.factor.S), G_T)
        H = G_T.T @ self.X                   # (K̂⁻¹)_cc
        S = np.linalg.inv(0.5 * (H + H.T))
        self.S = S = 0.5 * (S + S.T)
        w_c = self.w[c]
        return S, S @ w_c, w_c

    def displacement(self, u_n):
        """(v, normal displacement at every free contact node) from the
        candidates' normal displacements u_n: one back-substitution."""
        c = self.normal_rows[self.nodes]
        u_hat = self.w
        if len(c):
            y = self.S @ (np.asarray(u_n, float) - self.w[c])
            z = self.factor.back_substitute(None, self.X @ y)
            u_hat = self.w + self._T(z)
        return self.R.T @ u_hat, u_hat[self.normal_rows]
