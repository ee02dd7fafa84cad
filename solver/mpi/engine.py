"""Entry points of the engine: the shared service, :func:`spmd` for API
users and :func:`main` for ``python -m solver ... --engine petsc``."""

import sys

__all__ = ["service", "spmd", "main", "engine_summary", "restore_malloc"]

_SERVICE = []


def service():
    """The process's :class:`~solver.mpi.service.Service` (made once, after
    petsc4py is initialised with the MUMPS options)."""
    if not _SERVICE:
        import os

        from mpi4py import MPI

        # MUMPS's BLAS (OpenBLAS through Debian's libblas.so.3, docs/mpi.md)
        # reads this once, when libpetsc loads: one share of the cores per
        # rank, so that N ranks do not start N × cores threads.
        os.environ.setdefault("OPENBLAS_NUM_THREADS", str(max(
            1, (os.cpu_count() or 1) // MPI.COMM_WORLD.Get_size())))
        import petsc4py

        petsc4py.init(sys.argv[:1])  # PETSc reads $PETSC_OPTIONS
        from petsc4py import PETSc

        restore_malloc()
        from . import factor, full, schur, snesvi  # noqa: F401 - commands
        from .service import Service

        PETSc.Options().setValue("k_mat_mumps_icntl_14", 50)  # workspace +%
        _SERVICE.append(Service(PETSc.COMM_WORLD.tompi4py()))
    return _SERVICE[0]


#: glibc's ``mallopt`` parameters (malloc.h) and the engine's settings:
#: mmap allowed again (glibc's default count), blocks of 32 MB and more
#: mmapped, and the heap trimmed when 32 MB lie free at its top. glibc's
#: own 128 kB thresholds (which a ``mallopt`` call also stops adapting)
#: gave the same peak memory but unmapped and faulted in every n-vector:
#: 460k against 300k page faults and ≈ 0.6 s more system time per rank
#: at 4.8·10⁵ DOFs (benchmarks/README.md, "Fourth quiet re-measurement").
M_TRIM_THRESHOLD, M_MMAP_THRESHOLD, M_MMAP_MAX = -1, -3, -4
SETTINGS = {M_TRIM_THRESHOLD: 32 << 20, M_MMAP_THRESHOLD: 32 << 20,
            M_MMAP_MAX: 65536}


def restore_malloc():
    """Give freed memory back to the system again. Debian's
    ``libsuperlu_dist.so.8``, which ``libpetsc`` links, calls
    ``mallopt(M_MMAP_MAX, 0)`` and ``mallopt(M_TRIM_THRESHOLD, -1)`` in its
    load-time constructors: from then on glibc never unmaps or trims, and
    every array the process ever freed (reading the problem, rotating and
    padding K, the scatter's buffers) stays in its resident memory under
    MUMPS's factor (MEM20C, benchmarks/README.md). Sets :data:`SETTINGS`;
    returns whether it could (False off glibc)."""
    import ctypes
    import ctypes.util

    try:
        mallopt = ctypes.CDLL(ctypes.util.find_library("c")).mallopt
    except (OSError, AttributeError, TypeError):
        return False
    return all(mallopt(param, value) == 1 for param, value in
               SETTINGS.items())


def spmd(main, *args, **kwargs):
    """Call on every rank: rank 0 runs ``main(*args, **kwargs)`` and
    returns its value (the solve functions of :mod:`solver.mpi` inside it
    use all ranks); the other ranks serve its commands and return None.
    The workers are released also when ``main`` raises."""
    svc = service()
    if not svc.root:
        svc.serve()
        return None
    try:
        return main(*args, **kwargs)
    finally:
        svc.stop(0)


def engine_summary(svc, layout, extra):
    """The ``engine`` entry of summary.json: ranks, per-rank rows, nonzeros,
    contact nodes and candidates owned, peak memory and command times."""
    import numpy as np

    per_rank = svc.call("stats")
    for name, rows in extra.pop("owned", {}).items():
        owners = np.bincount(layout.owner(np.asarray(rows, np.int64)),
                             minlength=svc.size) if len(rows) else \
            np.zeros(svc.size, np.int64)
        for stats, count in zip(per_rank, owners):
            stats[name] = int(count)
    return dict(name="petsc", ranks=svc.size, per_rank=per_rank, **extra)


def main(args):
    """``python -m solver ... --engine petsc`` on every rank: rank 0 runs
    the serial command line (:func:`solver.cli.run.run`, whose jobs call the
    petsc solvers), the others serve it; every rank returns rank 0's exit
    code."""
    svc = service()
    if not svc.root:
        return svc.serve()
    from ..cli.run import run

    code = 1
    try:
        code = run(args)
    finally:
        svc.stop(code)
    return code

