"""Generic checks of the ``.npz`` arrays: dtype, shape, range, CSR matrices.

Every failure raises :class:`~solver.errors.ProblemError` whose message
starts with the offending key."""

import numpy as np
import scipy.sparse as sp

from ..errors import ProblemError
from .format import LOAD_LIMIT, SYMMETRY_RTOL

__all__ = ["fail", "check_array", "check_range", "csr", "check_norm",
           "check_load", "load_limit", "check_positive_definite"]


def fail(key, message):
    raise ProblemError(f"{key}: {message}")


def check_array(arrays, key, kind, ndim, shape=None):
    """Generic checks of one key: dtype class, ndim, shape, finiteness."""
    a = arrays[key]
    if a.dtype == object:
        fail(key, "contains Python objects (refused)")
    if kind == "str":
        if a.dtype.kind != "U" or a.ndim != 0:
            fail(key, f"expected a text scalar, got dtype {a.dtype} with "
                      f"shape {a.shape}")
        order = a.dtype.byteorder if a.dtype.byteorder in "<>" else "="
        codes = np.frombuffer(a.tobytes(),
                              dtype=np.dtype("u4").newbyteorder(order))
        surrogate = (codes >= 0xD800) & (codes <= 0xDFFF)
        if ((codes > 0x10FFFF) | surrogate).any():
            # NumPy would make a Python str that breaks later (SystemError)
            fail(key, "not valid text: invalid code points (damaged file?)")
        return str(a)
    if kind == "int" and a.dtype.kind not in "iu":
        fail(key, f"expected integers, got dtype {a.dtype}")
    if kind == "float" and a.dtype.kind not in "fiu":
        fail(key, f"expected real numbers, got dtype {a.dtype}")
    if a.ndim != ndim:
        fail(key, f"expected {ndim} dimension(s), got shape {a.shape}")
    if shape is not None:
        for axis, (want, got) in enumerate(zip(shape, a.shape)):
            if want is not None and want != got:
                fail(key, f"expected shape {_shape_text(shape)}, got "
                          f"{a.shape}")
    if kind == "float":
        a = a.astype(np.float64)
        bad = ~np.isfinite(a)
        if bad.any():
            fail(key, f"{int(bad.sum())} entries are NaN or infinite "
                      f"(first at index {np.argwhere(bad)[0].tolist()})")
    else:
        a = a.astype(np.int64)
    return a


def _shape_text(shape):
    return "(" + ", ".join("?" if s is None else str(s) for s in shape) + ")"


def check_range(key, a, low, high):
    if a.size and (a.min() < low or a.max() >= high):
        bad = a[(a < low) | (a >= high)][0]
        fail(key, f"index {int(bad)} out of range [{low}, {high})")


def csr(arrays, name, n=None):
    """Validate and build the CSR matrix stored under ``name_*``."""
    shape = check_array(arrays, f"{name}_shape", "int", 1, (2,))
    rows, cols = (int(v) for v in shape)
    if rows != cols or rows < 1:
        fail(f"{name}_shape", f"expected a square non-empty matrix, got "
                              f"{(rows, cols)}")
    if n is not None and rows != n:
        fail(f"{name}_shape", f"expected ({n}, {n}), got {(rows, cols)}")
    # The row pointer first: its last entry bounds what a reader
    # (solver.problem.load.Archive) accepts for the data and indices.
    indptr = check_array(arrays, f"{name}_indptr", "int", 1, (rows + 1,))
    data = check_array(arrays, f"{name}_data", "float", 1)
    indices = check_array(arrays, f"{name}_indices", "int", 1,
                          (len(data),))
    if indptr[0] != 0 or indptr[-1] != len(data) \
            or (np.diff(indptr) < 0).any():
        fail(f"{name}_indptr", f"not a valid CSR row pointer (must rise "
                               f"from 0 to nnz = {len(data)})")
    check_range(f"{name}_indices", indices, 0, cols)
    A = sp.csr_matrix((data, indices, indptr), shape=(rows, cols))
    A.sum_duplicates()
    scale = abs(A).max() if A.nnz else 0.0
    if scale == 0.0:
        fail(f"{name}_data", "the matrix is zero")
    check_norm(f"{name}_data", A.data, scale)
    asym = abs(A - A.T).max()
    if asym > SYMMETRY_RTOL * scale:
        fail(f"{name}_data", f"the matrix is not symmetric (max |A - Aᵀ| = "
                             f"{asym:.3g}, max |A| = {scale:.3g})")
    diagonal = A.diagonal()
    if (diagonal <= 0).any():
        i = int(np.argmax(diagonal <= 0))
        fail(f"{name}_data", f"diagonal entry {i} is {diagonal[i]:.3g}: the "
                             "matrix is not positive definite")
    return A


def check_norm(key, values, scale=None):
    """The Euclidean norm and the sum of ``values`` must be finite: larger
    values overflow double precision in the solver (and in ``--info``)."""
    values = np.asarray(values, dtype=float).ravel()
    if scale is None:
        scale = np.abs(values).max(initial=0.0)
    if scale > 0 and not (np.isfinite(scale * np.linalg.norm(values / scale))
                          and np.isfinite(np.abs(values).sum())):
        fail(key, f"values up to {scale:.3g} overflow double precision "
                  "(rescale the units)")


def _norms(rows):
    """Euclidean norms of the rows of a 2D array, without overflow."""
    top = np.abs(rows).max(axis=1, initial=0.0)
    safe = np.where(top > 0, top, 1.0)
    return top * np.linalg.norm(rows / safe[:, None], axis=1)


def load_limit(K):
    """The largest ‖f‖₂ accepted with the stiffness ``K``:
    :data:`~solver.problem.format.LOAD_LIMIT` / max(k, 1/k), k = max|K_ij|
    (why: :data:`~solver.problem.format.LOAD_LIMIT`)."""
    k = float(np.abs(K.data).max(initial=0.0))
    with np.errstate(divide="ignore", over="ignore"):
        return LOAD_LIMIT / max(k, 1.0 / k), k


def check_load(key, loads, K):
    """Every load in ``loads`` (a vector, or one stage per row) within
    :func:`load_limit` of ``K``; the message names the stage, the norm, the
    largest entry and its DOF, and the limit."""
    loads = np.asarray(loads, dtype=float)
    rows = loads.reshape(-1, loads.shape[-1]) if loads.size else \
        np.zeros((1, 0))
    norms = _norms(rows)
    limit, k = load_limit(K)
    stage = int(np.argmax(norms))
    if not norms[stage] > limit:
        return
    row = rows[stage]
    dof = int(np.argmax(np.abs(row)))
    where = f"stage {stage} has " if loads.ndim == 2 else ""
    fail(key, f"{where}‖f‖₂ = {norms[stage]:.3g} (largest entry "
              f"{row[dof]:.3g} at DOF {dof}), above {limit:.3g}, the "
              f"largest load this K allows (‖f‖₂·max(k, 1/k) <= "
              f"{LOAD_LIMIT:g} with k = max|K_ij| = {k:.3g}, so that the "
              "squares of forces, K times forces and displacements fit in "
              "double precision; rescale the units)")


def check_positive_definite(A, name="K", order=None, backend="auto"):
    r"""Raise :class:`ProblemError` unless the symmetric A is positive
    definite (no LDLᵀ pivot below :data:`~solver.linalg.PIVOT_RTOL` of the
    largest), by one sparse factorisation by ``backend`` (default the first
    installed) in the elimination ``order`` if given; ``name`` is the key
    prefix for the message."""
    from ..linalg import factorize
    factorize(A, order, name=name, backend=backend)
