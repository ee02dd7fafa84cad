r"""CHOLMOD backend (SuiteSparse) through kvxopt's ``cholmod`` module.

``pip install '.[cholmod]'`` installs kvxopt (GPL-3.0, a maintained fork
of CVXOPT). Y. Chen, T. A. Davis, W. W. Hager, S. Rajamanickam, *Algorithm
887: CHOLMOD, supernodal sparse Cholesky factorization and
update/downdate*, ACM TOMS 35 (2008); CHOLMOD User Guide.

PAPᵀ = LLᵀ, supernodal, in our order P (``nmethods = 1``, ``postorder =
False``: the Schur set c stays last). A non-positive pivot stops
``numeric`` (then SuperLU's LDLᵀ names the inertia,
:func:`~solver.linalg.superlu.refuse`); otherwise the pivots diag(L)² go
through :func:`~solver.linalg.base.check_pivots`. S = L₂₂L₂₂ᵀ with L₂₂
the trailing block of L, read in place from the factor
(:mod:`~solver.linalg.cholmod_struct`) and checked against L's diagonal;
should that read fail, L₂₂⁻¹ is computed by forward substitution
(``sys = 4``) on the unit vectors of c in blocks of at most m²/n columns
and inverted, much slower."""

import numpy as np
import scipy.linalg as dense
import scipy.sparse as sp

from .base import Factor, check_pivots
from .cholmod_struct import solve_columns, trailing_block
from .superlu import refuse, schur_last

__all__ = ["NAME", "EXTRA", "REQUIRES", "LICENCE", "USES_ORDER",
           "available", "factorize", "CholmodFactor"]

NAME, EXTRA, REQUIRES = "cholmod", "cholmod", "kvxopt>=1.3"
LICENCE = "GPL-3.0 (kvxopt; CHOLMOD's supernodal module is GPL-2.0+)"
USES_ORDER = True


def available():
    try:
        import kvxopt.cholmod  # noqa: F401
    except ImportError:
        return False
    return True


class CholmodFactor(Factor):
    """Supernodal LLᵀ of an SPD matrix by CHOLMOD (see the module)."""

    backend = NAME

    def __init__(self, A, order=None, schur=None, name="K", check=True):
        from kvxopt import cholmod, matrix, spmatrix

        self._cholmod, self._matrix = cholmod, matrix
        L = sp.tril(sp.csr_matrix(A, dtype=np.float64), format="coo")
        self.n = n = L.shape[0]
        if schur is not None:
            self.schur_dofs, order = schur_last(A, order, schur)
        self._order = None if order is None else np.asarray(order)
        lower = spmatrix(matrix(L.data), matrix(L.row.astype(np.int64)),
                         matrix(L.col.astype(np.int64)), (n, n))
        del L
        saved = dict(cholmod.options)
        cholmod.options.update(supernodal=2, postorder=False,
                               nmethods=1 if order is not None else 0)
        try:
            p = {} if order is None else dict(
                p=matrix(np.asarray(order, np.int64)))
            self._F = cholmod.symbolic(lower, uplo="L", **p)
            cholmod.numeric(lower, self._F)
            self._diagonal = np.array(cholmod.diag(self._F)).ravel()
            pivots = self._diagonal ** 2
        except (ArithmeticError, ValueError):  # stopped at a pivot ≤ 0
            pivots = None
        finally:
            cholmod.options.clear()
            cholmod.options.update(saved)
        del lower
        if pivots is None:
            refuse(A, name, "CHOLMOD")
        if check:
            check_pivots(pivots, name)
        if schur is not None:
            self.S = self._schur(len(self.schur_dofs))

    def _schur(self, m):
        """S = L₂₂L₂₂ᵀ, L₂₂ read in place (:mod:`.cholmod_struct`) and
        checked against the diagonal of L from ``cholmod.diag`` (bit for
        bit: the same numbers; no extra solve), else from L₂₂⁻¹ by forward
        sweeps."""
        L22 = trailing_block(self._F, self._order, m)
        if L22 is not None and np.array_equal(np.diagonal(L22),
                                              self._diagonal[self.n - m:]):
            self._L22 = L22
            S = L22 @ L22.T
            return 0.5 * (S + S.T)
        n = self.n
        inverse = np.zeros((m, m))
        block = max(1, min(m, m * m // max(n, 1)))
        for start in range(0, m, block):
            k = min(block, m - start)
            B = np.zeros((n, k), order="F")
            B[n - m + start + np.arange(k), np.arange(k)] = 1.0
            X = self._matrix(B)
            self._cholmod.solve(self._F, X, sys=4)
            inverse[:, start:start + k] = np.array(X)[n - m:]
        L22 = dense.solve_triangular(inverse, np.eye(m), lower=True)
        S = L22 @ L22.T
        return 0.5 * (S + S.T)

    _L22 = None  # L₂₂ when read in place (the Schur mode)

    def back_substitute(self, b, u_c):
        r"""u with u_c on c and A_ii u_i = −A_ic u_c (b = 0; else
        :meth:`Factor.back_substitute`) by the backward sweep alone: Pᵀ S u_c
        lives on c, the last rows of the order, so L y = P Pᵀ S u_c gives y =
        [0; L₂₂ᵀ u_c] and u = Pᵀ L⁻ᵀ y (``sys = 5``), all columns in one call
        (:func:`~.cholmod_struct.solve_columns`)."""
        if self._L22 is None or (b is not None and np.any(b)):
            return super().back_substitute(b, u_c)
        u_c = np.asarray(u_c, float)
        n, m = self.n, len(self._L22)
        y = np.zeros((n,) + u_c.shape[1:])
        y[n - m:] = self._L22.T @ u_c
        x = solve_columns(self._F, 5, y.reshape(n, -1))  # all columns
        if x is None:  # kvxopt's solve, column by column
            X = self._matrix(y.reshape(n, -1))
            self._cholmod.solve(self._F, X, sys=5)
            x = np.array(X)
        u = np.empty_like(y)
        u[self._order] = x.reshape(y.shape)
        return u

    def solve(self, b):
        """A⁻¹b (``cholmod_solve``, sys = 0) for b of shape (n,) or (n, k)."""
        b = np.asarray(b, dtype=np.float64)
        X = self._matrix(b.reshape(self.n, -1))
        self._cholmod.solve(self._F, X, sys=0)
        return np.array(X).reshape(b.shape)


def factorize(A, order=None, schur=None, name="K", check=True):
    return CholmodFactor(A, order, schur, name, check)
