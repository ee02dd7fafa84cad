r"""The contact solve on PETSc under MPI (``--engine petsc``; the design
in docs/mpi.md).

``mpiexec -n N python -m solver X.npz --engine petsc [options]`` runs the
serial engine's solves with PETSc (petsc4py, mpi4py) doing the linear
algebra on N ranks. Rank 0 runs the project's own code and broadcasts
each collective step as a command (:mod:`.service`); rows are partitioned
by nodes (:mod:`.layout`); :class:`~.engine.PetscEngine` is one more
engine of the serial drivers: a distributed MUMPS factorisation in its
Schur mode per condensation (:mod:`.condensation`, :mod:`.schur`), or KSP
on the full system's Newton systems (:mod:`.full`); :mod:`.snesvi` is
PETSc's SNESVI, a cross-check. Importing this package needs neither
petsc4py nor MPI."""

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
