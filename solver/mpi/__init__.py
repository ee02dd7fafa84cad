r"""The contact solve on PETSc under MPI (``--engine petsc``).

``mpiexec -n N python -m solver X.npz --engine petsc [options]`` runs the
same solves as the serial engine with PETSc (petsc4py, mpi4py) doing the
linear algebra on N ranks. Nothing here is imported unless the petsc engine
is asked for, and importing this package needs neither petsc4py nor MPI.

Design (docs/mpi.md has the reasons and the measurements):

* **Rank 0 drives, every rank computes.** Rank 0 reads the ``.npz``, runs
  the project's own code (geometry, the φ_min / φ_FB Newton of
  :mod:`solver.ncp`, verification, output); each collective linear-algebra
  step (scatter K, factorise, solve, Schur complement) is a command that
  rank 0 broadcasts and all ranks execute together
  (:class:`~solver.mpi.service.Service`). K itself fits one machine far
  beyond the size at which its factorisation does not.
* **Layout** (:mod:`~solver.mpi.layout`): rows partitioned by nodes, block
  size = dimension: every node of the mesh keeps its ``dim`` rows (a
  Dirichlet DOF becomes an identity row), so a node's DOFs, and a contact
  node's normal row, live on one rank.
* **The engine is a backend** (:class:`~solver.mpi.engine.PetscEngine`):
  the serial drivers of :mod:`solver.contact` run unchanged and ask it for
  their linear algebra — one distributed MUMPS factorisation of K (or of
  the rotated K̂ = RKRᵀ) in MUMPS's own Schur mode per condensation
  (:mod:`~solver.mpi.condensation`, :mod:`~solver.mpi.schur`, ctypes on
  libpetsc), or, on the full system, every Newton system solved by KSP
  (MUMPS or CG + GAMG, :mod:`~solver.mpi.full`). :func:`solver.solve`
  with ``engine="petsc"`` chooses it. :mod:`~solver.mpi.snesvi` is
  PETSc's own SNESVI, a cross-check.
"""

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
