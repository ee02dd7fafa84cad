r"""SuperLU backend (SciPy's ``splu``): no extra dependency, BSD licence.

PKPᵀ = LDLᵀ with SuperLU in symmetric mode, diagonal pivots only
(``diag_pivot_thresh=0``) and our ordering P, so that U = DLᵀ (X. S. Li,
*An overview of SuperLU*, ACM TOMS 31 (2005); SuperLU Users' Guide §2.7).
A is positive definite iff every pivot D_kk > 0 (Sylvester's law of
inertia, :func:`~solver.linalg.base.check_pivots`); the factorisation is
Cholesky's up to the first non-positive pivot, hence backward stable where
it matters. With the Schur set c last S = L₂₂U₂₂ (the condensed thesis
split with φ_FB is sensitive even to the round-off of U₂₂ᵀD₂₂⁻¹U₂₂). The
factors, copies in SciPy, are read once and dropped."""

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
import scipy.sparse.linalg as sla

from ..errors import ProblemError
from .base import Factor, check_pivots, not_positive_definite

__all__ = ["NAME", "EXTRA", "REQUIRES", "LICENCE", "USES_ORDER",
           "available", "factorize", "Factorization", "refuse",
           "schur_last"]

NAME, EXTRA, REQUIRES = "superlu", None, "scipy"
LICENCE = "BSD-3-Clause (SuperLU, SciPy)"
USES_ORDER = True


def available():
    return True


def order_with_last(A, last):
    """Reverse Cuthill-McKee of A without ``last``, then ``last``."""
    n = A.shape[0]
    last = np.asarray(last, np.int64).ravel()
    order = csgraph.reverse_cuthill_mckee(sp.csr_matrix(A),
                                          symmetric_mode=True)
    keep = np.ones(n, bool)
    keep[last] = False
    return np.concatenate([order[keep[order]], last])


def schur_last(A, order, schur):
    """(c, the order): the Schur set c = ``schur`` and an elimination order
    of A that ends with c (``order`` if it does, else ``order`` without c
    then c, or :func:`order_with_last`)."""
    c = np.asarray(schur, np.int64).ravel()
    if order is not None and np.array_equal(order[len(order) - len(c):], c):
        return c, order
    return c, order_with_last(A, c) if order is None else \
        np.concatenate([np.setdiff1d(order, c, True), c])


class Factorization(Factor):
    r"""PKPᵀ = LDLᵀ of a symmetric positive definite matrix (SuperLU):
    ``order`` the elimination order (e.g. :func:`~solver.linalg.dof_ordering`;
    default SuperLU's minimum degree, or reverse Cuthill-McKee with the Schur
    set ``schur`` last); ``name`` the key prefix of A for the ProblemError
    "{name}_data: {name} is not positive definite (...)"; ``check`` False
    skips reading U (a bare solver)."""

    backend = NAME

    def __init__(self, A, order=None, name="K", check=True, schur=None):
        A = sp.csc_matrix(A, dtype=np.float64)
        self.n = n = A.shape[0]
        if schur is not None:
            self.schur_dofs, order = schur_last(A, order, schur)
        self.order = order = None if order is None else np.asarray(order)
        key = f"{name}_data"
        if order is not None:
            A = A[order][:, order].tocsc()
        try:
            self.lu = sla.splu(A, permc_spec="NATURAL" if order is not None
                               else "MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                               options={"SymmetricMode": True})
        except RuntimeError:  # "Factor is exactly singular"
            raise ProblemError(f"{key}: {not_positive_definite(name, True)}"
                               ": its factorisation has an exactly zero "
                               "pivot") from None
        del A
        if not np.array_equal(self.lu.perm_r, self.lu.perm_c):
            raise ProblemError(f"{key}: {not_positive_definite(name)}: a "
                               "diagonal pivot of its LDLᵀ factorisation "
                               "is exactly zero")
        self.nnz = int(self.lu.nnz)
        if check or schur is not None:
            U = self.lu.U
            pivots = U.diagonal()
            if check:
                check_pivots(pivots, name)
            if schur is not None:  # L₂₂U₂₂, as SuperLU computed them
                m = len(self.schur_dofs)
                U22 = U[n - m:, n - m:].toarray()
                del U
                S = self.lu.L[n - m:, n - m:].toarray() @ U22
                self.S = 0.5 * (S + S.T)

    def solve(self, b):
        """A⁻¹b for b of shape (n,) or (n, k)."""
        b = np.asarray(b, dtype=np.float64)
        if self.order is None:
            return self.lu.solve(b)
        x = np.empty_like(b)
        x[self.order] = self.lu.solve(np.ascontiguousarray(b[self.order]))
        return x


def factorize(A, order=None, schur=None, name="K", check=True):
    return Factorization(A, order, name, check, schur)


def refuse(A, name, backend):
    """Raise the refusal of A after ``backend``'s Cholesky factorisation met
    a pivot ≤ 0: the LDLᵀ above counts the negative and round-off pivots
    (its inertia), so that every backend gives the same message."""
    Factorization(A, None, name, True)
    raise ProblemError(f"{name}_data: {not_positive_definite(name)}: a "
                       f"pivot of its Cholesky factorisation ({backend}) "
                       "is zero or negative")
