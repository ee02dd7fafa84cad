r"""Is K positive definite? MUMPS's answer after its factorisation.

The serial backends refuse a singular or indefinite K from the pivots of
their LDLᵀ (:func:`solver.linalg.base.check_pivots`). MUMPS factorises
the padded K̂ as a general symmetric matrix (SYM = 2, docs/mpi.md) and
does not stop at such pivots, so the same test is asked of it (Users'
Guide 5.5, sections 5.1.2, 6.1-6.2 and 8): null pivots below
PIVOT_RTOL‖K̂‖ (ICNTL(24) = 1, CNTL(3), INFOG(28)), negative pivots
(INFOG(12)) and errors (INFOG(1) < 0). Under a Schur set these count the
eliminated unknowns only; the dense Cholesky of S on rank 0 fails for the
rest."""

import ctypes

from ..errors import ProblemError
from ..linalg.base import PIVOT_RTOL, not_positive_definite

__all__ = ["watch_pivots", "check_factorization", "mumps_infog",
           "schur_cholesky", "set_up_checked", "refusal"]

#: INFOG(1) values that mean MUMPS ran short of memory.
MEMORY_ERRORS = (-8, -9, -13, -19, -20)


def _lib_and_int():
    from .schur import petsc_int_type, petsc_library

    return petsc_library(), petsc_int_type()


def watch_pivots(F):
    """Ask the (not yet factorised) MUMPS factor ``F`` to count pivots
    below PIVOT_RTOL‖K̂‖ (ICNTL(24) = 1, CNTL(3))."""
    lib, c_int = _lib_and_int()
    lib.MatMumpsSetCntl.restype = ctypes.c_int
    code = lib.MatMumpsSetIcntl(ctypes.c_void_p(F.handle), c_int(24),
                                c_int(1))
    code = code or lib.MatMumpsSetCntl(ctypes.c_void_p(F.handle), c_int(3),
                                       ctypes.c_double(PIVOT_RTOL))
    if code:
        raise RuntimeError(f"PETSc's MatMumpsSetIcntl/Cntl failed ({code})")


def refusal(detail, singular=True):
    """The serial engine's ProblemError for K (``K_data: K is not positive
    definite ...``, :func:`solver.linalg.base.not_positive_definite`)."""
    return ProblemError(f"K_data: {not_positive_definite('K', singular)}: "
                        f"{detail}")


def set_up_checked(ksp, prepare=None):
    """Set up the MUMPS KSP ``ksp`` with the pivot counts on
    (:func:`watch_pivots`), ``prepare(F)`` before the factorisation if
    given, and :func:`check_factorization` after; returns the factor."""
    pc = ksp.getPC()
    pc.setFactorSetUpSolverType()
    watch_pivots(pc.getFactorMatrix())
    if prepare is not None:
        prepare(pc.getFactorMatrix())
    ksp.setUp()
    check_factorization(pc.getFactorMatrix())
    return pc.getFactorMatrix()


def mumps_infog(F, *indices):
    """INFOG(i) of the MUMPS factor ``F`` for each index (global values,
    the same on every rank)."""
    lib, c_int = _lib_and_int()
    out = []
    for index in indices:
        value = c_int()
        if lib.MatMumpsGetInfog(ctypes.c_void_p(F.handle), c_int(index),
                                ctypes.byref(value)):
            raise RuntimeError("PETSc's MatMumpsGetInfog failed")
        out.append(int(value.value))
    return out


def check_factorization(F):
    """Raise :class:`~solver.errors.ProblemError` (bad input: the CLI's
    exit 2) if MUMPS found K singular or indefinite, RuntimeError if it
    failed otherwise (with its INFOG(1), INFOG(2))."""
    error, detail, negative, null = mumps_infog(F, 1, 2, 12, 28)
    if error == -10 or (error >= 0 and null > 0):
        count = f"{null} pivot(s)" if null > 0 else "a pivot"
        raise refusal(f"{count} of MUMPS's LDLᵀ factorisation below "
                      f"{PIVOT_RTOL:g} of ‖K‖")
    if error >= 0 and negative > 0:
        raise refusal(f"it has {negative} negative eigenvalue(s) (the "
                      "inertia of MUMPS's LDLᵀ factorisation)", False)
    if error in MEMORY_ERRORS:
        raise RuntimeError(
            f"MUMPS ran out of memory (INFOG(1) = {error}, INFOG(2) = "
            f"{detail}): run on more ranks or machines")
    if error < 0:
        raise RuntimeError(f"MUMPS failed: INFOG(1) = {error}, INFOG(2) = "
                           f"{detail} (MUMPS Users' Guide, section 8)")


def schur_cholesky(S, scale):
    """The Cholesky factor (``cho_factor``) of MUMPS's Schur complement S,
    whose pivots are the last of K's LDLᵀ: ProblemError if one is ≤
    PIVOT_RTOL ``scale`` (K's largest diagonal entry) or negative."""
    import numpy as np
    import scipy.linalg as la

    try:
        cho = la.cho_factor(0.5 * (S + S.T))
    except (la.LinAlgError, ValueError):
        raise refusal("its Schur complement on the contact normal rows is "
                      "not (MUMPS's S, dense Cholesky)", False) from None
    pivots = np.diag(cho[0]) ** 2
    small = int(np.count_nonzero(pivots <= PIVOT_RTOL * scale))
    if small:
        raise refusal(f"{small} pivot(s) of its Schur complement on the "
                      "contact normal rows at round-off level "
                      f"({pivots.min() / scale:.2g} of K's largest diagonal "
                      "entry)")
    return cho
