r"""MUMPS's own Schur mode through ``libpetsc`` (ctypes; no build step).

petsc4py 3.18 binds neither ``MatFactorSetSchurIS`` nor
``MatFactorCreateSchurComplement``; both are plain C functions of the
shared ``libpetsc`` that petsc4py loaded, called here with ctypes on the
petsc4py objects' ``handle`` pointers (PETSc 3.18's ``petscmat.h``).
With a Schur set c, MUMPS returns S = K_cc − K_ci K_ii⁻¹ K_ic (thesis
(63)-(66)) from the *factorisation itself*, no solves (Users' Guide 5.5,
ICNTL(19)); PETSc accepts it on several ranks when the whole set is given
on rank 0 (centralised on the host, ICNTL(19) = 1)."""

import ctypes

import numpy as np

from .service import command

__all__ = ["set_schur_is", "schur_complement", "interior_solves", "interior",
           "mumps_memory"]

_LIB = []


def petsc_library():
    """libpetsc as petsc4py loaded it (the same shared object)."""
    if not _LIB:
        import petsc4py

        path = petsc4py.get_config()["PETSC_DIR"] + "/lib/libpetsc_real.so"
        lib = ctypes.CDLL(path, mode=ctypes.RTLD_GLOBAL)
        for name in ("MatFactorSetSchurIS", "MatFactorCreateSchurComplement",
                     "MatDenseGetArrayRead", "MatDenseRestoreArrayRead",
                     "MatGetSize", "MatDestroy", "MatMumpsSetIcntl",
                     "MatMumpsGetInfo", "MatMumpsGetInfog"):
            getattr(lib, name).restype = ctypes.c_int
        _LIB.append(lib)
    return _LIB[0]


def _check(code, name):
    if code:
        raise RuntimeError(f"PETSc's {name} failed with error code {code}")


def set_schur_is(F, rows, comm):
    """Declare the Schur set of the (not yet factorised) MUMPS factor
    ``F`` (petsc4py Mat): global ``rows`` on rank 0, none elsewhere."""
    from petsc4py import PETSc

    mine = np.asarray(rows, PETSc.IntType) if comm.getRank() == 0 else \
        np.zeros(0, PETSc.IntType)
    iset = PETSc.IS().createGeneral(mine, comm=comm)
    _check(petsc_library().MatFactorSetSchurIS(ctypes.c_void_p(F.handle),
                                      ctypes.c_void_p(iset.handle)),
           "MatFactorSetSchurIS")
    iset.destroy()


def schur_complement(F):
    """S (m, m) from the factorised ``F`` on rank 0 (a copy; MUMPS keeps
    its own, which PETSc factorises for later solves)."""
    from petsc4py import PETSc

    lib = petsc_library()
    S = ctypes.c_void_p()
    status = ctypes.c_int()
    _check(lib.MatFactorCreateSchurComplement(
        ctypes.c_void_p(F.handle), ctypes.byref(S), ctypes.byref(status)),
        "MatFactorCreateSchurComplement")
    try:
        rows = np.ctypeslib.as_ctypes(np.zeros(1, PETSc.IntType))
        cols = np.ctypeslib.as_ctypes(np.zeros(1, PETSc.IntType))
        _check(lib.MatGetSize(S, rows, cols), "MatGetSize")
        m, n = int(rows[0]), int(cols[0])
        data = ctypes.POINTER(ctypes.c_double)()
        _check(lib.MatDenseGetArrayRead(S, ctypes.byref(data)),
               "MatDenseGetArrayRead")
        out = np.ctypeslib.as_array(data, shape=(n, m)).T.copy() \
            if m * n else np.zeros((m, n))  # column-major, lda = m
        _check(lib.MatDenseRestoreArrayRead(S, ctypes.byref(data)),
               "MatDenseRestoreArrayRead")
    finally:
        lib.MatDestroy(ctypes.byref(S))
    return out


def interior_solves(F):
    """From now on ``MatSolve`` with ``F`` solves K_ii x_i = b_i only
    (ICNTL(26) = 0; PETSc 3.18's full solve through S, ICNTL(26) = −1, is
    sequential only: "Parallel Schur complements not yet supported")."""
    from petsc4py import PETSc

    c_int = ctypes.c_int64 if PETSc.IntType().itemsize == 8 else \
        ctypes.c_int32
    _check(petsc_library().MatMumpsSetIcntl(ctypes.c_void_p(F.handle), c_int(26),
                                   c_int(0)),
           "MatMumpsSetIcntl")


#: MUMPS's memory statistics (MB; Users' Guide 5.5, section 6): this
#: process's INFO and the INFOG maxima / sums over the processes.
MEMORY_INFO = dict(estimate=15, allocated=16, used=22)
MEMORY_INFOG = dict(estimate_max=16, estimate_sum=17, used_max=21,
                    used_sum=22)


def petsc_int_type():
    from petsc4py import PETSc

    return ctypes.c_int64 if PETSc.IntType().itemsize == 8 else \
        ctypes.c_int32


def mumps_memory(F):
    """MUMPS's memory of the factorised ``F`` in MB: INFO(15) (estimated
    in analysis, in-core), INFO(16) (allocated by the factorisation), INFO(22)
    (effectively used), and INFOG(16)/(17), INFOG(21)/(22) (max / sum over
    the processes of INFO(15) and INFO(22))."""
    lib, c_int = petsc_library(), petsc_int_type()
    out = {}
    for table, fields in (("MatMumpsGetInfo", MEMORY_INFO),
                          ("MatMumpsGetInfog", MEMORY_INFOG)):
        for name, index in fields.items():
            value = c_int()
            _check(getattr(lib, table)(ctypes.c_void_p(F.handle),
                                       c_int(index), ctypes.byref(value)),
                   table)
            out[name] = int(value.value)
    return out


def interior(service, obj, rhs, rows, values):
    """x with x_c = ``values`` (on every rank) and K_ii x_i = rhs_i −
    K_ic x_c: one interior solve (``rhs`` a PETSc vector, overwritten)."""
    from .service import EngineError

    a, b = obj["A"].getOwnershipRange()
    mine = np.flatnonzero((rows >= a) & (rows < b))
    e = obj["x"]
    e.set(0.0)
    e.getArray()[rows[mine] - a] = values[mine]
    t = rhs.duplicate()
    obj["A"].mult(e, t)
    rhs.axpy(-1.0, t)  # rhs − K e(x_c); its c rows are ignored
    t.destroy()
    obj["ksp"].solve(rhs, obj["x"])
    if obj["ksp"].getConvergedReason() < 0:  # checked factor: not expected
        raise EngineError(f"MUMPS's solve failed (KSP reason "
                          f"{obj['ksp'].getConvergedReason()})")
    obj["x"].getArray()[rows[mine] - a] = values[mine]
    return obj["x"]


def _reduced_rhs(service, obj, rows, b_pad):
    """g̃ = b_c − K_ci K_ii⁻¹ b_i on rank 0 (None elsewhere): one interior
    solve (y_i = K_ii⁻¹b_i, y_c = 0) and (K y)_c gathered."""
    from .layout import scatter_vector

    scatter_vector(service, b_pad, obj["b"])
    y = interior(service, obj, obj["b"].copy(), rows, np.zeros(len(rows)))
    t = obj["b"].duplicate()
    obj["A"].mult(y, t)  # (K y)_c = K_ci y_i
    a, b = obj["A"].getOwnershipRange()
    mine = np.flatnonzero((rows >= a) & (rows < b))
    parts = service.comm.gather((mine, t.getArray()[rows[mine] - a]),
                                root=0)
    t.destroy()
    if not service.root:
        return None
    r = b_pad[rows].copy()
    for idx, vals in parts:
        r[idx] -= vals
    return r


@command("condensed_rhs")
def _condensed_rhs(service, payload, local):
    """g̃ = b_c − K_ci K_ii⁻¹ b_i (thesis (66)'s condensed load) on rank 0:
    ``local`` = padded b on rank 0; one interior solve."""
    obj, rows = service.objects[payload["key"]], payload["rows"]
    return _reduced_rhs(service, obj, rows, local if service.root else None)


@command("schur_solve")
def _schur_solve(service, payload, local):
    """K⁻¹b by block elimination on the Schur-mode factor (module
    :mod:`~solver.mpi.factor`): ``local`` = (padded b, Cholesky of S) on
    rank 0; the result gathered on rank 0."""
    import scipy.linalg as la

    from .layout import gather_vector, scatter_vector
    from .service import EngineError

    obj, rows = service.objects[payload["key"]], payload["rows"]
    b_pad, cho = local if service.root else (None, None)
    r = _reduced_rhs(service, obj, rows, b_pad)
    x_c = None
    if service.root:
        x_c = la.cho_solve(cho, r)
        if not np.isfinite(x_c).all():
            raise EngineError("the Schur complement is singular")
    x_c = service.comm.bcast(x_c, root=0)
    scatter_vector(service, b_pad, obj["b"])
    return gather_vector(service, interior(service, obj, obj["b"], rows,
                                            x_c))


@command("interior_solve")
def _interior_solve(service, payload, local):
    """u with u_c given and K_ii u_i = b_i − K_ic u_c (b = 0 unless
    ``payload["rhs"]``): ``local`` = (padded b or None, u_c) on rank 0."""
    from .layout import gather_vector, scatter_vector

    obj, rows = service.objects[payload["key"]], payload["rows"]
    b_pad, u_c = local if service.root else (None, None)
    u_c = service.comm.bcast(u_c, root=0)
    rhs = obj["b"]
    if payload["rhs"]:
        scatter_vector(service, b_pad, rhs)
    else:
        rhs.set(0.0)
    return gather_vector(service, interior(service, obj, rhs, rows, u_c))
