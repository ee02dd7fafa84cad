r"""Intel oneMKL PARDISO backend, through ctypes on the ``mkl`` wheel.

``pip install '.[mkl]'`` (Intel Simplified Software Licence) puts
``libmkl_rt.so.*`` in the environment's ``lib/`` (Linux only here); it is
loaded with ctypes and set to the LP64 interface. pypardiso does not
expose the Schur mode.

Settings (oneMKL Developer Reference, "pardiso", "pardiso iparm
Parameter", "pardiso_getdiag"): ``mtype = 2`` (real SPD; the upper
triangle in CSR with sorted columns), ``iparm[1] = 2`` (METIS nested
dissection), ``iparm[34] = 1`` (zero-based), ``iparm[55] = 1`` (pivots
readable) and, for a Schur set c, ``iparm[35] = 2`` with ``perm[c] = 1``:
phase 22 factorises all of A *and* returns the dense S on c. Phase 331
(forward only) then leaves g̃ in the c rows, and phase 333 (backward only)
with u_c in those rows gives the interior unknowns: one triangular sweep
each. A non-positive pivot stops PARDISO with error -4 (SuperLU's LDLᵀ
then names the inertia); otherwise the pivots (``pardiso_getdiag``) go
through :func:`~solver.linalg.base.check_pivots`. :class:`BorderedFactor`
(two bodies' candidates, :mod:`solver.contact.strategies.bordered`) uses
``mtype = −2`` (symmetric indefinite) on K bordered by constraint rows,
with the border as the Schur set."""

import ctypes
import glob
import os
import site
import sys
import weakref

import numpy as np
import scipy.sparse as sp

from ..errors import SolverError
from .base import Factor, check_pivots
from .superlu import refuse

__all__ = ["NAME", "EXTRA", "REQUIRES", "LICENCE", "USES_ORDER",
           "available", "factorize", "PardisoFactor", "factorize_bordered",
           "BorderedFactor"]

NAME, EXTRA, REQUIRES = "pardiso", "mkl", "mkl>=2023"
LICENCE = "Intel Simplified Software Licence (oneMKL)"
USES_ORDER = False
_LIB = []


def _library():
    """libmkl_rt from the environment (None if absent), loaded once."""
    if not _LIB:
        paths = [path for prefix in (sys.prefix, site.USER_BASE)
                 for path in sorted(glob.glob(os.path.join(
                     prefix, "lib", "libmkl_rt.so*")))]
        lib = None
        for path in paths:
            try:
                lib = ctypes.CDLL(path)
                lib.MKL_Set_Interface_Layer(0)  # MKL_INTERFACE_LP64
                lib.pardiso, lib.pardiso_getdiag  # noqa: B018 (exist?)
                break
            except (OSError, AttributeError):
                lib = None
        _LIB.append(lib)
    return _LIB[0]


def available():
    return _library() is not None


def _ptr(array):
    return array.ctypes.data_as(ctypes.c_void_p)


def _int(value):
    return ctypes.byref(ctypes.c_int32(value))


def _pardiso(lib, arrays, phase, n, b, x, nrhs=1, mtype=2):
    """One ``pardiso`` call (maxfct = mnum = 1, ``mtype``, msglvl = 0) on
    ``arrays`` = (pt, a, ia, ja, perm, iparm); returns its error code."""
    pt, a, ia, ja, perm, iparm = map(_ptr, arrays)
    error = ctypes.c_int32(0)
    lib.pardiso(pt, _int(1), _int(1), _int(mtype), _int(phase), _int(n), a, ia,
                ja, perm, _int(nrhs), iparm, _int(0), _ptr(b), _ptr(x),
                ctypes.byref(error))
    return error.value


def _upper(A):
    """The upper triangle of A in CSR, sorted, no duplicates, 32-bit
    indices: (data, indptr, indices). One pass over A's CSR arrays (no COO
    copy of A as ``scipy.sparse.triu`` makes)."""
    A = sp.csr_matrix(A, dtype=np.float64)
    if not A.has_canonical_format:
        A = A.copy()
        A.sum_duplicates()  # also sorts the indices
    n = A.shape[0]
    rows = np.repeat(np.arange(n, dtype=np.int32), np.diff(A.indptr))
    keep = A.indices >= rows
    if np.count_nonzero(keep) >= 2 ** 31:
        raise SolverError("pardiso backend: more than 2³¹ nonzeros")
    indptr = np.zeros(n + 1, np.int32)
    np.cumsum(np.bincount(rows[keep], minlength=n), out=indptr[1:])
    return (np.ascontiguousarray(A.data[keep]), indptr,
            A.indices[keep].astype(np.int32))


class PardisoFactor(Factor):
    """LLᵀ of an SPD matrix by MKL PARDISO (see the module docstring)."""

    backend = NAME

    def __init__(self, A, schur=None, name="K", check=True):
        lib = self._lib = _library()
        data, indptr, indices = _upper(A)
        self.n = n = A.shape[0]
        iparm = np.zeros(64, np.int32)
        iparm[[0, 1, 34, 55]] = 1, 2, 1, 1  # ours, METIS, 0-based, getdiag
        iparm[17] = -1  # report the factor's nonzeros there
        perm, m = np.zeros(n, np.int32), 1
        self._whole = whole = False  # every DOF in c: S = A, no interior
        if schur is not None:
            self.schur_dofs = c = np.asarray(schur, np.int64).ravel()
            m = len(c)
            self._whole = whole = m == n
            perm[c] = 0 if whole else 1
            # S, and the factors of all of A; PARDISO's Schur mode is not
            # asked for an empty interior (a crash was seen there)
            iparm[35] = 2 if m and not whole else 0
        S = np.zeros((m, m))
        self._arrays = (np.zeros(64, np.int64), data, indptr, indices, perm,
                        iparm)
        weakref.finalize(self, _pardiso, lib, self._arrays, -1, n,
                         np.zeros(1), np.zeros(1))  # phase −1: free memory
        for phase in (11, 22):
            error = _pardiso(lib, self._arrays, phase, n, np.zeros(1), S)
            if error == -4:  # zero pivot
                refuse(A, name, "PARDISO error -4")
            if error:
                raise SolverError(f"PARDISO phase {phase} failed with error "
                                  f"{error} (oneMKL reference, 'pardiso')")
        self.nnz = int(iparm[17])
        if check:
            pivots, diagonal = np.zeros(n), np.zeros(n)
            error = ctypes.c_int32(0)
            lib.pardiso_getdiag(_ptr(self._arrays[0]), _ptr(pivots),
                                _ptr(diagonal),
                                _int(1), ctypes.byref(error))
            check_pivots(pivots, name)
        if whole:
            self.S = sp.csr_matrix(A, dtype=np.float64)[c][:, c].toarray()
        elif schur is not None:
            rank = np.argsort(np.argsort(c))  # S's rows: c sorted
            S = S[np.ix_(rank, rank)]
            self.S = 0.5 * (S + S.T)

    def _sweep(self, phase, b):
        """One solve phase on b (n,) or (n, k); columns in Fortran order."""
        b = np.asfortranarray(b, dtype=np.float64)
        x = np.zeros_like(b, order="F")
        nrhs = 1 if b.ndim == 1 else b.shape[1]
        error = _pardiso(self._lib, self._arrays, phase, self.n, b, x, nrhs)
        if error:
            raise SolverError(f"PARDISO phase {phase} failed with error "
                              f"{error}")
        return x

    def solve(self, b):
        """A⁻¹b (phase 33) for b of shape (n,) or (n, k)."""
        return self._sweep(33, b)

    def condensed_rhs(self, b):
        """g̃ from the forward substitution alone (phase 331)."""
        if self._whole:
            return np.asarray(b, float)[self.schur_dofs]
        return self._sweep(331, b)[self.schur_dofs]

    def back_substitute(self, b, u_c):
        """Forward (331) on b, u_c into the c rows, backward (333)."""
        u_c = np.asarray(u_c, float)
        if self._whole:
            u = np.zeros((self.n,) + u_c.shape[1:])
            u[self.schur_dofs] = u_c
            return u
        y = np.zeros((self.n,) + u_c.shape[1:], order="F") if b is None \
            else self._sweep(331, b)
        y[self.schur_dofs] = u_c
        return self._sweep(333, y)


def factorize(A, order=None, schur=None, name="K", check=True):
    return PardisoFactor(A, schur, name, check)


class BorderedFactor:
    r"""B K⁻¹ Bᵀ and solves with K from one factorisation of the bordered
    matrix

    .. math::
        A = \begin{pmatrix} K & B^T \\ B & 0 \end{pmatrix},

    K SPD (n × n), B sparse (m × n), by PARDISO's symmetric indefinite
    LDLᵀ (``mtype = −2``, Bunch–Kaufman pivots) with the m border rows as
    the Schur set (``iparm[35] = 2``): the border is eliminated last, so
    the interior factor is K's own (its fill, not that of a matrix in which
    B's rows have been folded into K), and the Schur complement of A on
    the border is −B K⁻¹ Bᵀ. ``C`` = B K⁻¹ Bᵀ (m × m, dense, SPD for B of
    full row rank). :meth:`solve` (b, μ) = K⁻¹(b − Bᵀμ): the forward and
    diagonal sweeps on (b, 0), μ put into the border rows, the backward
    sweep (the block LDLᵀ's back substitution). K's inertia is checked:
    no perturbed pivot and n positive pivots in the interior, otherwise
    the one-line refusal of a K that is not positive definite."""

    backend = NAME

    def __init__(self, K, B, name="K"):
        lib = self._lib = _library()
        n, m = K.shape[0], B.shape[0]
        self.n, self.m = n, m
        data, indptr, indices = _bordered_upper(K, B)
        iparm = np.zeros(64, np.int32)
        iparm[[0, 1, 9, 34]] = 1, 2, 8, 1  # ours, METIS, eps 1e-8, 0-based
        iparm[17] = -1
        perm = np.zeros(n + m, np.int32)
        perm[n:] = 1
        iparm[35] = 2
        S = np.zeros((m, m))
        self._arrays = (np.zeros(64, np.int64), data, indptr, indices, perm,
                        iparm)
        weakref.finalize(self, _pardiso, lib, self._arrays, -1, n + m,
                         np.zeros(1), np.zeros(1), 1, -2)
        for phase in (11, 22):
            error = _pardiso(lib, self._arrays, phase, n + m, np.zeros(1), S,
                             1, -2)
            if error == -4:
                refuse(K, name, "PARDISO error -4")
            if error:
                raise SolverError(f"PARDISO phase {phase} failed with error "
                                  f"{error} (oneMKL reference, 'pardiso')")
        self.nnz = int(iparm[17])
        if iparm[13] or iparm[21] != n:  # perturbed pivots, inertia
            refuse(K, name, f"PARDISO LDLᵀ: {int(iparm[21])} positive "
                   f"pivots of {n}, {int(iparm[13])} perturbed")
        C = -S
        self.C = 0.5 * (C + C.T)

    def solve(self, b, mu=None):
        """K⁻¹(b − Bᵀμ) for b (n,) and μ (m,) (default 0)."""
        n, m = self.n, self.m
        x = np.zeros(n + m)
        x[:n] = b
        for phase in (331, 332):
            y = np.zeros_like(x)
            error = _pardiso(self._lib, self._arrays, phase, n + m, x, y, 1,
                             -2)
            if error:
                raise SolverError(f"PARDISO phase {phase} failed with error "
                                  f"{error}")
            x = y
        x[n:] = 0.0 if mu is None else mu
        y = np.zeros_like(x)
        error = _pardiso(self._lib, self._arrays, 333, n + m, x, y, 1, -2)
        if error:
            raise SolverError(f"PARDISO phase 333 failed with error {error}")
        return y[:n]


def _bordered_upper(K, B):
    """The upper triangle of [[K, Bᵀ], [B, 0]] in CSR (sorted, 32-bit, the
    border's zero diagonal stored): row i < n is K's upper row i followed
    by row i of Bᵀ (columns n + j, all beyond K's), row n + j its diagonal
    alone; in one scatter, without assembling the whole matrix."""
    n, m = K.shape[0], B.shape[0]
    k_data, k_ptr, k_ind = _upper(K)
    Bt = sp.csr_matrix(sp.csr_matrix(B, dtype=np.float64).T)
    Bt.sum_duplicates()  # also sorts
    k_count, b_count = np.diff(k_ptr), np.diff(Bt.indptr)
    indptr = np.zeros(n + m + 1, np.int64)
    np.cumsum(np.concatenate([k_count + b_count, np.ones(m, np.int64)]),
              out=indptr[1:])
    if indptr[-1] >= 2 ** 31:
        raise SolverError("pardiso backend: more than 2³¹ nonzeros")
    data = np.zeros(indptr[-1])
    indices = np.empty(indptr[-1], np.int32)
    start = indptr[:n]
    at = np.repeat(start - k_ptr[:-1], k_count) + np.arange(len(k_data))
    data[at], indices[at] = k_data, k_ind
    at = np.repeat(start + k_count - Bt.indptr[:-1], b_count) \
        + np.arange(Bt.nnz)
    data[at], indices[at] = Bt.data, n + Bt.indices
    indices[indptr[n:-1]] = np.arange(n, n + m)
    return data, indptr.astype(np.int32), indices


def factorize_bordered(K, B, name="K"):
    """:class:`BorderedFactor` of K bordered by B."""
    return BorderedFactor(K, B, name)
