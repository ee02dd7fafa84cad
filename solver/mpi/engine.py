"""The PETSc engine (:class:`PetscEngine`: the linear algebra of the serial
drivers on the ranks of ``mpiexec``), the shared service, and
:func:`spmd`, which every rank calls (rank 0 runs the solve, the others
serve it; the command line does the same in :func:`solver.cli.main`)."""

import sys

from ..errors import SolverError

__all__ = ["PetscEngine", "KSPS", "service", "spmd", "engine_summary",
           "check_problem", "restore_malloc"]

#: Solvers of the full system's Newton systems (``ksp=``).
KSPS = ("mumps", "gamg", "hypre")

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
        from . import (distributed, factor, full,  # noqa: F401
                       krylov_friction, partitioned_friction,
                       partitioned_full, schur, snesvi)
        from .service import Service

        PETSc.Options().setValue("k_mat_mumps_icntl_14", 50)  # workspace +%
        _SERVICE.append(Service(PETSc.COMM_WORLD.tompi4py()))
        Service.current = _SERVICE[0]
    return _SERVICE[0]


#: glibc's ``mallopt`` parameters and the engine's settings: mmap allowed,
#: blocks of 32 MB and more mmapped, the heap trimmed when 32 MB lie free
#: at its top (docs/mpi.md, "Memory per rank").
M_TRIM_THRESHOLD, M_MMAP_THRESHOLD, M_MMAP_MAX = -1, -3, -4
SETTINGS = {M_TRIM_THRESHOLD: 32 << 20, M_MMAP_THRESHOLD: 32 << 20,
            M_MMAP_MAX: 65536}


def restore_malloc():
    """Give freed memory back to the system again: Debian's
    ``libsuperlu_dist.so.8``, which ``libpetsc`` links, switches glibc's
    unmapping and trimming off when it loads, and every array the process
    ever freed stays resident under MUMPS's factor. Sets :data:`SETTINGS`;
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


def check_problem(problem):
    """SolverError unless the engine can partition ``problem``: a mesh, or
    two bodies' nodewise problem in the numbering of their mesh
    (:func:`~solver.mpi.layout.mesh_of`)."""
    from .layout import mesh_of

    if mesh_of(problem) is None:
        raise SolverError("the petsc engine partitions a mesh by nodes: a "
                          "discrete problem (no mesh) runs on the serial "
                          "engine")


class PetscEngine:
    """The engine (:mod:`solver.contact.engine`) on the ranks of
    ``mpiexec`` (module docstring of :mod:`solver.mpi`); make it on rank 0
    inside :func:`spmd`. ``ksp``: "mumps" or "gamg" for the full system;
    ``schur_block``: None (MUMPS's Schur mode) or k (:mod:`.factor`)."""

    name = "petsc"

    def __init__(self, ksp="mumps", schur_block=None):
        if ksp not in KSPS:
            raise SolverError(f"ksp must be one of {KSPS}, got {ksp!r}")
        self.ksp, self.schur_block = ksp, schur_block
        self.linear_solver = "petsc-mumps"
        self.svc = service()
        self.layout, self.problem = None, None
        self.made, self.full = [], False

    def _layout(self, problem):
        """The partition of ``problem``'s nodes, sent to every rank once."""
        from .layout import Layout

        check_problem(problem)
        if self.problem is not problem:
            self.svc.mark("start")
            self.layout, self.problem = Layout(problem, self.svc.size), \
                problem
            self.svc.call("layout", self.layout.ranges())
        return self.layout

    def condensation(self, problem, dofs):
        """K condensed onto ``dofs`` (:class:`~solver.mpi.condensation.
        PetscCondensation`)."""
        from .condensation import PetscCondensation

        made = PetscCondensation(self.svc, self._layout(problem), problem,
                                 dofs)
        self.made.append(("dofs", made))
        return made

    def held_condensation(self, problem, dofs):
        """(F, K_F condensed onto ``dofs``) of a body held by contact only
        (:class:`solver.contact.strategies.floating.FloatingSystem`): K
        with the r DOFs F held (:func:`solver.linalg.kernel.
        held_stiffness`) is built on rank 0 only while it is padded and
        scattered, then factorised by MUMPS with its Schur set, whose
        pivot check refuses a K with a kernel beyond the rigid modes."""
        from ..linalg.kernel import held_stiffness
        from .condensation import PetscCondensation

        fixed = problem.fixed_dofs()
        made = PetscCondensation(
            self.svc, self._layout(problem), problem, dofs,
            stiffness=lambda: held_stiffness(problem.K, fixed))
        self.made.append(("dofs", made))
        return fixed, made

    def normal_condensation(self, problem, geometry):
        """K̂ condensed onto candidate normal DOFs (:class:`~solver.mpi.
        condensation.PetscNormalCondensation`)."""
        from .condensation import PetscNormalCondensation

        made = PetscNormalCondensation(self.svc, self._layout(problem),
                                       problem, geometry, self.schur_block)
        self.made.append(("normal", made))
        return made

    def full_jacobian(self, system, problem, geometry):
        """The full system's Jacobian, its Newton systems solved by KSP on
        all ranks (:func:`~solver.mpi.full.full_jacobian`)."""
        from .full import full_jacobian

        self.full = True
        return full_jacobian(self.svc, self._layout(problem), problem,
                             geometry, system, self.ksp)

    def full_linear_solver(self):
        """What solves the full system's Newton steps."""
        return f"petsc-{self.ksp}"

    def summary(self):
        """The ``engine`` entry of a result: ranks, per-rank rows,
        nonzeros, contact DOFs or candidates owned, peak memory and
        command times (:func:`engine_summary`)."""
        import numpy as np

        extra, owned = {}, {}
        if self.full:
            from .full import ksp_statistics

            extra.update(system="full", ksp=self.ksp,
                         **ksp_statistics(self.svc, self.ksp))
        else:
            extra.update(system="condensed", ksp="mumps")
        for kind, made in self.made:
            if kind == "normal":
                rows = self.layout.red_to_pad[made.normal_rows]
                owned["contact_nodes_owned"] = rows
                if made.nodes is not None:
                    owned["candidates_owned"] = rows[
                        made.nodes]
                extra.update(schur="mumps" if self.schur_block is None
                             else "solves", schur_block=self.schur_block,
                             factorizations=made.factor.factorizations
                             if made.factor is not None else 0)
            else:
                owned["contact_dofs_owned"] = self.layout.red_to_pad[
                    made.dofs]
                extra.update(schur="mumps", solves=made.n_solves)
        extra["owned"] = {k: np.asarray(v) for k, v in owned.items()}
        return engine_summary(self.svc, self.layout, extra)
