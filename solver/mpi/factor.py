r"""One distributed MUMPS factorisation, its Schur complement and solves.

:class:`PetscFactor` is a :class:`solver.linalg.base.Factor` (the serial
backends' interface: ``solve``, ``S``, ``back_substitute``) whose work runs
on every rank: K (reduced numbering, rank 0) is padded and scattered
(:mod:`~solver.mpi.layout`) and factorised once by MUMPS (``PCCHOLESKY``,
``mat_solver_type mumps``; LDLᵀ of the SPD K, half LU's work); MUMPS
controls go through the options database (``-mat_mumps_icntl_*``: petsc4py
3.18 binds no ``MatMumpsSetIcntl``).

The Schur complement on the DOFs c (m of them) comes from the same factor:
(K⁻¹)_cc = S⁻¹ (block inverse), so S = ((K⁻¹)_cc)⁻¹, and the columns
K⁻¹e_c are computed ``block`` at a time by one many-right-hand-side solve
(``MatMatSolve`` of the factor, what ``KSPMatSolve`` calls; petsc4py 3.18
binds the former only), of which only the rows c are kept. The right-hand
sides e_c go to MUMPS as a *sparse* block (the transpose of a k×n AIJ
matrix: ICNTL(20), the forward solve pruned to the paths of c), measured
on the 1.2·10⁵-DOF block with 64 columns: 0.77 s CPU against 1.86 s as a
dense block and 3.8 s as 64 single solves (``block=1``, the plain
column-by-column solve; benchmarks/README.md has the large sizes). The
dense n×block slab is transient and far smaller than the factors. The
factor does not depend on c: a larger candidate set costs solves, not a
refactorisation (the serial backends refactorise). MUMPS's own Schur mode
(``MatFactorSetSchurIS``) has no petsc4py 3.18 binding.
"""

import numpy as np

from ..linalg.base import Factor
from .layout import gather_vector, scatter_matrix, scatter_vector
from .service import EngineError, command

__all__ = ["PetscFactor", "SCHUR_BLOCK"]

#: Right-hand sides per KSPMatSolve of the Schur complement.
SCHUR_BLOCK = 64


class PetscFactor(Factor):
    """Rank 0's handle of a distributed factorisation of the reduced SPD
    ``A`` (scipy sparse) with the Schur complement on ``schur`` (reduced
    DOFs, optional). ``key`` names it in the service's objects."""

    backend = "petsc-mumps"

    def __init__(self, service, layout, A, schur=None, key="K",
                 block=SCHUR_BLOCK):
        self.service, self.layout, self.key = service, layout, key
        self.n = A.shape[0]
        service.call("factor", dict(key=key, bsize=layout.dim),
                     layout.matrix(A))
        self.schur(schur, block)

    def schur(self, dofs, block=SCHUR_BLOCK):
        """(Re)compute S on the reduced DOFs ``dofs`` (no refactorisation)."""
        self.schur_dofs = None if dofs is None else \
            np.asarray(dofs, np.int64)
        if dofs is None or not len(dofs):
            self.S = None if dofs is None else np.zeros((0, 0))
            return self.S
        rows = self.layout.red_to_pad[self.schur_dofs]
        G = self.service.call("inverse_block", dict(key=self.key, rows=rows,
                                                    block=int(block)))
        S = np.linalg.inv(0.5 * (G + G.T))
        self.S = 0.5 * (S + S.T)
        return self.S

    def solve(self, b):
        """K⁻¹b, b of shape (n,) or (n, k) (k solves)."""
        b = np.asarray(b, float)
        if b.ndim == 2:
            return np.column_stack([self.solve(col) for col in b.T])
        x = self.service.call("solve", dict(key=self.key),
                              self.layout.pad(b))
        return self.layout.unpad(x)


@command("factor")
def _factor(service, payload, local):
    from petsc4py import PETSc

    A = scatter_matrix(service, local, payload["bsize"])
    ksp = PETSc.KSP().create(comm=A.getComm())
    ksp.setOperators(A)
    ksp.setType("preonly")
    pc = ksp.getPC()
    pc.setType("cholesky")
    pc.setFactorSolverType("mumps")
    ksp.setOptionsPrefix(f"{payload['key'].lower()}_")
    ksp.setFromOptions()
    ksp.setUp()
    x, b = A.createVecs()
    service.objects[payload["key"]] = dict(A=A, ksp=ksp, x=x, b=b)


@command("solve")
def _solve(service, payload, local):
    obj = service.objects[payload["key"]]
    scatter_vector(service, local, obj["b"])
    obj["ksp"].solve(obj["b"], obj["x"])
    if obj["ksp"].getConvergedReason() < 0:  # the factorisation failed
        raise EngineError("MUMPS could not factorise K (singular: is the "
                          "body supported?)")
    return gather_vector(service, obj["x"])


@command("inverse_block")
def _inverse_block(service, payload, local):
    """(K⁻¹)_cc on rank 0, ``block`` columns per KSPMatSolve."""
    from petsc4py import PETSc

    obj = service.objects[payload["key"]]
    rows, k = payload["rows"], payload["block"]
    a, b = obj["A"].getOwnershipRange()
    mine = np.flatnonzero((rows >= a) & (rows < b))
    out = np.zeros((len(mine), len(rows)))
    for start in range(0, len(rows), k):
        cols = np.arange(start, min(start + k, len(rows)))
        if k == 1:
            obj["b"].set(0.0)
            if a <= rows[start] < b:
                obj["b"].setValue(rows[start], 1.0)
            obj["b"].assemble()
            obj["ksp"].solve(obj["b"], obj["x"])
            out[:, start] = obj["x"].getArray()[rows[mine] - a]
            continue
        comm = obj["A"].getComm()
        X = PETSc.Mat().createDense(((b - a, None), (None, len(cols))),
                                    comm=comm)
        X.setUp()
        if payload.get("rhs", "sparse") == "sparse":
            B = _sparse_rhs(service, comm, rows[cols], (a, b))
        else:
            B = X.duplicate()
            local_rhs = B.getDenseArray()
            local_rhs[:] = 0.0
            own = (rows[cols] >= a) & (rows[cols] < b)
            local_rhs[rows[cols][own] - a, np.flatnonzero(own)] = 1.0
            B.assemble()
        obj["ksp"].getPC().getFactorMatrix().matSolve(B, X)  # MatMatSolve
        out[:, cols] = X.getDenseArray()[rows[mine] - a]
        B.destroy()
        X.destroy()
    parts = service.comm.gather((mine, out), root=0)
    if not service.root:
        return None
    G = np.zeros((len(rows), len(rows)))
    for idx, vals in parts:
        G[idx] = vals
    return G


def _sparse_rhs(service, comm, rows, own_range):
    """The block [e_r for r in rows] as the transpose of a sparse k×n AIJ
    matrix (its rows on rank 0): MUMPS then takes a sparse right-hand side
    (ICNTL(20)) and prunes its forward solve."""
    from petsc4py import PETSc

    k = len(rows) if service.root else 0
    a, b = own_range
    Bt = PETSc.Mat().createAIJ(size=((k, len(rows)), (b - a, None)),
                               nnz=(1, 1), comm=comm)
    for j, r in enumerate(rows if service.root else ()):
        Bt.setValue(j, int(r), 1.0)
    Bt.assemble()
    return PETSc.Mat().createTranspose(Bt)
