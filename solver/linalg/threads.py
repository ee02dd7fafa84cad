"""One BLAS thread for the dense algebra of the size of Γc.

The Newton iterations on the condensed systems factorise dense matrices of
at most the size of S, where OpenBLAS's threads cost more than they save
(spinning threads waiting for a core). :func:`single_blas_thread` sets the
bundled OpenBLAS of NumPy and SciPy to one thread inside a ``with`` block
and restores the previous count after it; the sparse factorisations of K
keep their threads. Without such a library it does nothing."""

import contextlib
import ctypes
import glob
import os

__all__ = ["single_blas_thread", "blas_threads_for", "THREADED_ORDER"]

_LIBRARIES = None  # [(get, set)] of the loaded OpenBLAS libraries
_OUTER = []  # the thread counts before each open single_blas_thread block

#: A dense factorisation of at least this order gets the process's BLAS
#: threads back (:func:`blas_threads_for`): 3D friction on candidates
#: factorises orders of 3·10³, where threads pay (2·10¹⁰ flops per LU).
THREADED_ORDER = 2000


def _libraries():
    """(get_num_threads, set_num_threads) of NumPy's and SciPy's bundled
    OpenBLAS, found once."""
    global _LIBRARIES
    if _LIBRARIES is not None:
        return _LIBRARIES
    found = []
    for package in ("numpy", "scipy"):
        try:
            module = __import__(package)
            root = os.path.dirname(os.path.dirname(module.__file__))
            paths = glob.glob(os.path.join(root, f"{package}.libs",
                                           "lib*openblas*.so*"))
        except Exception:  # noqa: BLE001 - no wheel layout: nothing to set
            paths = []
        for path in paths:
            try:
                lib = ctypes.CDLL(path)
            except OSError:
                continue
            for suffix in ("64_", ""):
                get = getattr(lib, f"scipy_openblas_get_num_threads{suffix}",
                              None)
                set_ = getattr(lib, f"scipy_openblas_set_num_threads{suffix}",
                               None)
                if get is not None and set_ is not None:
                    get.restype, set_.argtypes = ctypes.c_int, [ctypes.c_int]
                    found.append((get, set_))
                    break
    _LIBRARIES = found
    return found


@contextlib.contextmanager
def single_blas_thread():
    """Run the block with one OpenBLAS thread (NumPy's and SciPy's)."""
    libraries = _libraries()
    before = [get() for get, _ in libraries]
    _OUTER.append(before)
    try:
        for (_, set_), count in zip(libraries, before):
            if count != 1:
                set_(1)
        yield
    finally:
        _OUTER.pop()
        for (_, set_), count in zip(libraries, before):
            if count != 1:
                set_(count)


@contextlib.contextmanager
def blas_threads_for(order):
    """Inside :func:`single_blas_thread`: the thread counts from before the
    outermost block for one dense factorisation of order ≥
    :data:`THREADED_ORDER`; otherwise nothing changes."""
    libraries = _libraries()
    if order < THREADED_ORDER or not _OUTER:
        yield
        return
    try:
        for (_, set_), count in zip(libraries, _OUTER[0]):
            if count != 1:
                set_(count)
        yield
    finally:
        for (_, set_), count in zip(libraries, _OUTER[0]):
            if count != 1:
                set_(1)
