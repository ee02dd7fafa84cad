"""The trailing block of a CHOLMOD supernodal factor, read in place.

kvxopt wraps a ``cholmod_factor`` in a PyCapsule and hands out L only by
converting the factor into a sparse matrix (``getfactor``, which empties
the factor). This module reads the struct through ctypes instead, without
copying it: the layout of ``cholmod_factor`` (``cholmod.h``: n, minor,
Perm, ColCount, IPerm, nzmax, p, i, x, z, nz, next, prev, nsuper, ssize,
xsize, maxcsize, maxesize, super, pi, px, s, then eight ints) has been the
same since CHOLMOD 1.x. Supernode k holds columns super[k]..super[k+1]−1,
its row indices are s[pi[k]:pi[k+1]] and its values the column-major
dense block x[px[k]:px[k+1]] (CHOLMOD User Guide, "cholmod_factor";
Chen, Davis, Hager, Rajamanickam, ACM TOMS 35, 2008). Every field read is
checked against what we asked for, and the caller checks the diagonal;
on any mismatch it returns None and the caller computes S another way.
"""

import ctypes

import numpy as np

__all__ = ["trailing_block"]

_size, _ptr, _int = ctypes.c_size_t, ctypes.c_void_p, ctypes.c_int


class _Factor(ctypes.Structure):
    _fields_ = ([(name, _size) for name in ("n", "minor")]
                + [(name, _ptr) for name in ("Perm", "ColCount", "IPerm")]
                + [("nzmax", _size)]
                + [(name, _ptr) for name in ("p", "i", "x", "z", "nz",
                                             "next", "prev")]
                + [(name, _size) for name in ("nsuper", "ssize", "xsize",
                                              "maxcsize", "maxesize")]
                + [(name, _ptr) for name in ("super", "pi", "px", "s")]
                + [(name, _int) for name in (
                    "ordering", "is_ll", "is_super", "is_monotonic",
                    "itype", "xtype", "dtype", "useGPU")])


def _array(address, ctype, size):
    return np.ctypeslib.as_array(ctypes.cast(address, ctypes.POINTER(ctype)),
                                 (size,))


def trailing_block(F, order, m):
    """L₂₂ (dense m×m, lower) of the factor F = PAPᵀ = LLᵀ with P =
    ``order``, or None if F is not the supernodal real LLᵀ factor of that
    order (then nothing is read beyond the header)."""
    api = ctypes.pythonapi
    api.PyCapsule_GetName.restype = ctypes.c_char_p
    api.PyCapsule_GetName.argtypes = [ctypes.py_object]
    api.PyCapsule_GetPointer.restype = ctypes.c_void_p
    api.PyCapsule_GetPointer.argtypes = [ctypes.py_object, ctypes.c_char_p]
    name = api.PyCapsule_GetName(F)
    if not name or not name.startswith(b"CHOLMOD") or order is None:
        return None
    f = _Factor.from_address(api.PyCapsule_GetPointer(F, name))
    n = len(order)
    if (f.n, f.minor, f.is_ll, f.is_super, f.xtype, f.dtype) != \
            (n, n, 1, 1, 1, 0) or f.itype not in (0, 2) or not f.nsuper:
        return None
    index = ctypes.c_int64 if f.itype == 2 else ctypes.c_int32
    if not np.array_equal(_array(f.Perm, index, n), order):
        return None
    ns = f.nsuper
    first = _array(f.super, index, ns + 1)
    pi, px = _array(f.pi, index, ns + 1), _array(f.px, index, ns + 1)
    s, x = _array(f.s, index, f.ssize), _array(f.x, ctypes.c_double, f.xsize)
    L22, start = np.zeros((m, m)), n - m
    for k in range(int(np.searchsorted(first, start, "right")) - 1, ns):
        ncols, rows = first[k + 1] - first[k], s[pi[k]:pi[k + 1]]
        block = x[px[k]:px[k] + len(rows) * ncols].reshape(ncols, len(rows))
        cols = np.arange(max(first[k], start), first[k + 1])
        L22[:, cols - start] = 0.0
        sub = block[cols - first[k]].T  # (rows, cols)
        keep = rows >= start
        L22[np.ix_(rows[keep] - start, cols - start)] = sub[keep]
    return np.tril(L22)
