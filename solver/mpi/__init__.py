r"""The contact solve on PETSc under MPI (``--engine petsc``).

``mpiexec -n N python -m solver X.npz --engine petsc [options]`` runs the
same solves as the serial engine with PETSc (petsc4py, mpi4py) doing the
linear algebra on N ranks; docs/mpi.md explains the design. Rank 0 runs
the project's own code (geometry, Newton, verification, output) and
broadcasts each collective step as a command (:mod:`~solver.mpi.service`);
rows are partitioned by nodes (:mod:`~solver.mpi.layout`); the engine is
one more backend of the serial drivers (:class:`~solver.mpi.engine.
PetscEngine`): a distributed MUMPS factorisation in its Schur mode per
condensation (:mod:`~solver.mpi.condensation`, :mod:`~solver.mpi.schur`),
or KSP on the full system's Newton systems (:mod:`~solver.mpi.full`);
:mod:`~solver.mpi.snesvi` is PETSc's own SNESVI, a cross-check. Nothing
here is imported unless the petsc engine is asked for, and importing this
package needs neither petsc4py nor MPI."""

__all__ = ["available", "missing", "EXTRA"]

#: The pip extra that installs the engine's Python packages.
EXTRA = "petsc"


def missing():
    """None if petsc4py and mpi4py import, else a one-line reason."""
    import importlib.util

    for name in ("mpi4py", "petsc4py"):
        if importlib.util.find_spec(name) is None:
            return (f"{name} is not installed: the petsc engine needs "
                    f"pip install 'contact-ssn[{EXTRA}]' against a PETSc "
                    "with MUMPS (docs/mpi.md)")
    return None


def available():
    """Whether the petsc engine can run here."""
    return missing() is None
