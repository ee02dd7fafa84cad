"""The trailing block of a CHOLMOD supernodal factor, read in place.

kvxopt hands out L only by converting (and emptying) the factor; this
module reads the ``cholmod_factor`` struct through ctypes instead
(``cholmod.h``, the same layout since CHOLMOD 1.x): supernode k holds
columns super[k]..super[k+1]−1, its row indices s[pi[k]:pi[k+1]] and
its values the column-major block x[px[k]:px[k+1]] (CHOLMOD User Guide).
Every field read is checked; on a mismatch None is returned and the caller
computes S another way."""

import ctypes
import glob
import os
import threading

import numpy as np

__all__ = ["trailing_block", "solve_columns", "supernodal_size"]

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


def _factor(F):
    """(the ``cholmod_factor`` struct, its address) of kvxopt's capsule F,
    or (None, None) if F is not a CHOLMOD capsule."""
    api = ctypes.pythonapi
    api.PyCapsule_GetName.restype = ctypes.c_char_p
    api.PyCapsule_GetName.argtypes = [ctypes.py_object]
    api.PyCapsule_GetPointer.restype = ctypes.c_void_p
    api.PyCapsule_GetPointer.argtypes = [ctypes.py_object, ctypes.c_char_p]
    name = api.PyCapsule_GetName(F)
    if not name or not name.startswith(b"CHOLMOD"):
        return None, None
    pointer = api.PyCapsule_GetPointer(F, name)
    return _Factor.from_address(pointer), pointer


def supernodal_size(F):
    """The number of values of the supernodal factor F (``xsize``; known
    after ``cholmod.symbolic``), or None if F is not a supernodal CHOLMOD
    factor."""
    struct, _ = _factor(F)
    if struct is None or not struct.is_super:
        return None
    return int(struct.xsize)


def trailing_block(F, order, m):
    """L₂₂ (dense m×m, lower) of the factor F = PAPᵀ = LLᵀ with P =
    ``order``, or None if F is not the supernodal real LLᵀ factor of that
    order (then nothing is read beyond the header)."""
    f, _ = _factor(F)
    if f is None or order is None:
        return None
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


class _Dense(ctypes.Structure):
    """``cholmod_dense`` (``cholmod.h``): nrow, ncol, nzmax, d, x, z,
    xtype, dtype."""
    _fields_ = ([(name, _size) for name in ("nrow", "ncol", "nzmax", "d")]
                + [("x", _ptr), ("z", _ptr), ("xtype", _int),
                   ("dtype", _int)])


_LIBRARY = {}  # "lib" -> CDLL, "common" -> buffer, "lock"; {} until tried
_LOCK = threading.Lock()


def _cholmod_library():
    """kvxopt's bundled libcholmod with a started ``cholmod_common`` (one
    per process, for the 64-bit-index routines kvxopt's factors use), or
    None."""
    if not _LIBRARY:
        _LIBRARY["lib"] = None
        try:
            import kvxopt

            root = os.path.dirname(os.path.dirname(kvxopt.__file__))
            path = glob.glob(os.path.join(root, "kvxopt.libs",
                                          "libcholmod*.so*"))[0]
            lib = ctypes.CDLL(path)
            common = ctypes.create_string_buffer(1 << 20)  # ≫ its size
            if lib.cholmod_l_start(common) != 1:
                return None
            lib.cholmod_l_solve.restype = ctypes.POINTER(_Dense)
            lib.cholmod_l_solve.argtypes = [_int, _ptr, ctypes.POINTER(
                _Dense), _ptr]
            lib.cholmod_l_free_dense.argtypes = [ctypes.POINTER(
                ctypes.POINTER(_Dense)), _ptr]
            _LIBRARY.update(lib=lib, common=common)
        except (ImportError, IndexError, OSError, AttributeError):
            return None
    return _LIBRARY["lib"]


def solve_columns(F, sys, B):
    """``cholmod_l_solve(sys, L, B)`` for the dense (n, k) array B in one
    call (CHOLMOD's supernodal sweeps as BLAS-3), or None if that is not
    possible (then use kvxopt's ``cholmod.solve``, which calls it once per
    column)."""
    f, pointer = _factor(F)
    if f is None:
        return None
    B = np.asfortranarray(B, dtype=np.float64)
    n, k = B.shape
    lib = _cholmod_library()
    if lib is None or f.itype != 2 or f.xtype != 1 or f.dtype != 0 \
            or f.n != n or not k:
        return None
    dense = _Dense(n, k, n * k, n, B.ctypes.data, None, 1, 0)
    with _LOCK:  # one cholmod_common; ctypes releases the GIL
        X = lib.cholmod_l_solve(sys, pointer, ctypes.byref(dense),
                                _LIBRARY["common"])
        if not X:
            return None
        try:
            x = X.contents
            if (x.nrow, x.ncol, x.d, x.xtype, x.dtype) != (n, k, n, 1, 0):
                return None
            out = np.ctypeslib.as_array(ctypes.cast(
                x.x, ctypes.POINTER(ctypes.c_double)), (k, n)).T.copy()
        finally:
            lib.cholmod_l_free_dense(ctypes.byref(X), _LIBRARY["common"])
    return out
