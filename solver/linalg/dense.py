"""Dense factorisations of the Newton systems on a contact zone.

The condensed Newton systems (:mod:`solver.contact.frictionless.newton`,
:mod:`solver.contact.friction.newton`) are dense, of the size of the
contact zone: LAPACK's Cholesky where the matrix is symmetric positive
definite (the primal-dual active set structure makes it so for φ_min and
φ_FB with the lagged bound), else its LU."""

import warnings

import numpy as np
import scipy.linalg as sla
from scipy.linalg import blas

__all__ = ["factorize", "symmetric_from_upper", "SYMMETRIZE_BLOCK",
           "DenseSchur"]


def factorize(A, symmetric):
    """Cholesky of A if ``symmetric`` and it is positive definite, else LU;
    None if A is (numerically) singular. Returns a solve callable."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sla.LinAlgWarning)
        if symmetric:
            try:
                factor = sla.cho_factor(A, check_finite=False)
                return lambda b: sla.cho_solve(factor, b,
                                               check_finite=False)
            except np.linalg.LinAlgError:
                pass
        lu, piv = sla.lu_factor(A, check_finite=False)
        if not np.all(np.diagonal(lu)):
            return None
        return lambda b: sla.lu_solve((lu, piv), b, check_finite=False)


#: Columns per block of :func:`symmetric_from_upper`'s copy.
SYMMETRIZE_BLOCK = 512


def symmetric_from_upper(a):
    """The symmetric matrix whose upper triangle ``a`` holds (LAPACK's
    potri and syrk write only that one), made in place: each block of
    columns takes its lower part from the transposed block of rows, so
    no n×n temporaries are made (benchmarks/README.md, "3D friction: one
    factorisation of K")."""
    n = len(a)
    for j in range(0, n, SYMMETRIZE_BLOCK):
        e = min(j + SYMMETRIZE_BLOCK, n)
        a[e:, j:e] = a[j:e, e:].T
        block = a[j:e, j:e]
        lower = np.tril_indices(e - j, -1)
        block[lower] = block.T[lower]
    if a.flags.f_contiguous and not a.flags.c_contiguous:
        return a.T  # the same matrix, in C order as NumPy's products give
    return a


class DenseSchur:
    r"""The Schur complement of a dense SPD matrix A on the rows ``keep``,
    the rows ``drop`` eliminated: A_dd = L Lᵀ, W = L⁻¹A_dk and

    .. math:: S = A_{kk} − A_{kd} A_{dd}^{-1} A_{dk} = A_{kk} − WᵀW

    (potrf, trsm, syrk: |d|³/3 + |d|²|k| + |d||k|² flops, on the BLAS
    threads); :meth:`response` is the dropped rows' answer to the kept
    ones with no load on the dropped, A_dd⁻¹A_dk x = L⁻ᵀ(W x)."""

    def __init__(self, A, keep, drop):
        self.L = sla.cholesky(A[np.ix_(drop, drop)], lower=True,
                              check_finite=False)
        self.W = sla.solve_triangular(self.L, A[np.ix_(drop, keep)],
                                      lower=True, check_finite=False)
        self.S = symmetric_from_upper(blas.dsyrk(
            -1.0, self.W, beta=1.0, c=A[np.ix_(keep, keep)], trans=1))

    def response(self, x):
        """A_dd⁻¹A_dk x for x (|k|,) or (|k|, m)."""
        return sla.solve_triangular(self.L, self.W @ x, lower=True,
                                    trans=1, check_finite=False)
