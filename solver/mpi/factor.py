r"""One distributed MUMPS factorisation, its Schur complement and solves.

:class:`PetscFactor` is a :class:`solver.linalg.base.Factor` whose work
runs on every rank: K (reduced numbering, rank 0) is padded and scattered
(:mod:`~solver.mpi.layout`) once and factorised by MUMPS (``PCCHOLESKY``;
controls through the options database, ``-k_mat_mumps_icntl_*``). The
Schur complement S = K_cc − K_ci K_ii⁻¹ K_ic on the DOFs c (thesis
(63)-(66)) comes from **MUMPS's own Schur mode** (:mod:`~solver.mpi.schur`:
S on rank 0, no solves); the factor then solves with K_ii only, so a
solve with K is the block elimination x_c = S⁻¹(b_c − K_ci K_ii⁻¹b_i),
x_i = K_ii⁻¹(b_i − K_ic x_c) (S⁻¹ by a dense Cholesky on rank 0). A new
candidate set is a new factorisation; K is not scattered again.
``block=k`` instead forms S = ((K⁻¹)_cc)⁻¹ from k columns K⁻¹e_c at a
time (``MatMatSolve``, ICNTL(20)): the engine's first, slower way, kept
for comparison."""

import numpy as np
import scipy.linalg as la

from ..linalg.base import Factor
from .layout import gather_vector, scatter_matrix, scatter_vector
from .pivots import schur_cholesky
from .service import EngineError, command

__all__ = ["PetscFactor", "SCHUR_BLOCK"]

#: Default Schur complement: None = MUMPS's Schur mode; k = KSPMatSolve
#: of k columns at a time.
SCHUR_BLOCK = None


class PetscFactor(Factor):
    """Rank 0's handle of a distributed factorisation of the reduced SPD
    ``A`` (sparse, or a function returning it: held only while padded), with
    the Schur complement on ``schur`` (optional); ``key`` names it in the
    service's objects, ``block`` as :data:`SCHUR_BLOCK`."""

    backend = "petsc-mumps"

    def __init__(self, service, layout, A, schur=None, key="K",
                 block=SCHUR_BLOCK):
        self.service, self.layout, self.key = service, layout, key
        self.block, self._cho, self._rows = block, None, None
        A_pad = layout.matrix(A() if callable(A) else A)
        self.scale = float(A_pad.diagonal().max())  # for the pivot test
        del A  # a callable's K lived only while padding
        self.n = len(layout.red_to_pad)
        service.mark("pad")
        service.call("scatter_matrix", dict(key=key, bsize=layout.dim),
                     A_pad)
        del A_pad  # rank 0 keeps no copy during the factorisation
        self.factorizations = 0
        if block is not None or schur is None or not len(schur):
            self._factor(None)
        self.schur(schur)

    def _factor(self, rows):
        S = self.service.call("factor", dict(key=self.key, schur=rows))
        self.factorizations += 1
        return S

    def schur(self, dofs):
        """(Re)compute S on the reduced DOFs ``dofs``."""
        self.schur_dofs = None if dofs is None else \
            np.asarray(dofs, np.int64)
        self._cho, self.S = None, None
        if dofs is None or not len(dofs):
            if self.block is None and self.factorizations and \
                    self._rows is not None:  # drop the old Schur set
                self._factor(None)
            self._rows = None
            self.S = None if dofs is None else np.zeros((0, 0))
            return self.S
        self._rows = self.layout.red_to_pad[self.schur_dofs]
        if self.block is None:  # MUMPS's Schur mode
            S = self._factor(self._rows)  # K_ii checked by MUMPS
            self._cho = schur_cholesky(S, self.scale)
        else:
            G = self.service.call("inverse_block", dict(
                key=self.key, rows=self._rows, block=int(self.block)))
            S = np.linalg.inv(0.5 * (G + G.T))
        self.S = 0.5 * (S + S.T)
        return self.S

    def solve(self, b):
        """K⁻¹b, b of shape (n,) or (n, k) (k solves)."""
        b = np.asarray(b, float)
        if b.ndim == 2:
            return np.column_stack([self.solve(col) for col in b.T])
        if self._cho is None:
            x = self.service.call("solve", dict(key=self.key),
                                  self.layout.pad(b))
        else:
            x = self.service.call("schur_solve", dict(
                key=self.key, rows=self._rows), (self.layout.pad(b),
                                                 self._cho))
        return self.layout.unpad(x)

    def solve_schur(self, r):
        """S⁻¹r on rank 0, by the Cholesky factor of S made with it (Schur
        mode), else by a dense solve (``block`` mode)."""
        if self._cho is not None:
            return la.cho_solve(self._cho, r)
        return np.linalg.solve(self.S, r)

    def condensed_rhs(self, b):
        """g̃ = b_c − K_ci K_ii⁻¹ b_i, b of shape (n,): one interior solve in
        the Schur mode (a solve with K costs two), else as :class:`Factor`."""
        if self._cho is None:
            return super().condensed_rhs(b)
        return self.service.call("condensed_rhs", dict(
            key=self.key, rows=self._rows), self.layout.pad(
                np.asarray(b, float)))

    def back_substitute(self, b, u_c):
        """u with u_c on c, K_ii u_i = b_i − K_ic u_c: one interior solve
        in the Schur mode (else as :class:`Factor`)."""
        u_c = np.asarray(u_c, float)
        if self._cho is None:
            return super().back_substitute(b, u_c)
        if u_c.ndim == 2:
            return np.column_stack([self.back_substitute(
                None if b is None else b[:, j], u_c[:, j])
                for j in range(u_c.shape[1])])
        x = self.service.call("interior_solve", dict(
            key=self.key, rows=self._rows, rhs=b is not None), (
            None if b is None else self.layout.pad(b), u_c))
        return self.layout.unpad(x)


@command("scatter_matrix")
def _scatter(service, payload, local):
    old = service.objects.pop(payload["key"], {})
    for item in old.values():
        item.destroy()
    A = scatter_matrix(service, local, payload["bsize"])
    x, b = A.createVecs()
    service.objects[payload["key"]] = dict(A=A, x=x, b=b)


def mumps_ksp(obj, key):
    """A new KSP (``preonly``, PC ``cholesky`` by MUMPS, options prefix
    ``key_``) on the scattered ``obj["A"]``, kept as ``obj["ksp"]`` (an
    older one destroyed); not set up yet. Returns (ksp, pc)."""
    from petsc4py import PETSc

    if "ksp" in obj:
        obj.pop("ksp").destroy()
    ksp = PETSc.KSP().create(comm=obj["A"].getComm())
    ksp.setOperators(obj["A"])
    ksp.setType("preonly")
    pc = ksp.getPC()
    pc.setType("cholesky")
    pc.setFactorSolverType("mumps")
    ksp.setOptionsPrefix(f"{key.lower()}_")
    ksp.setFromOptions()
    obj["ksp"] = ksp
    return ksp, pc


@command("factor")
def _factor(service, payload, local):
    """A MUMPS Cholesky of the scattered A, with the Schur set
    ``payload["schur"]`` (padded rows) if given: returns S on rank 0."""
    from .schur import (interior_solves, mumps_memory, schur_complement,
                        set_schur_is)

    from .pivots import set_up_checked

    obj = service.objects[payload["key"]]
    ksp, _ = mumps_ksp(obj, payload["key"])
    S, rows = None, payload.get("schur")

    def schur_set(F):
        set_schur_is(F, rows, obj["A"].getComm())

    # ProblemError if K is singular or indefinite
    F = set_up_checked(ksp, None if rows is None else schur_set)
    service.objects.setdefault("counts", {})["mumps_mb"] = mumps_memory(F)
    if payload.get("schur") is not None:
        if service.root:
            S = schur_complement(F)
        interior_solves(F)
    return S


@command("check_spd")
def _check_spd(service, payload, local):
    """Is the scattered ``objects[key]["A"]`` (K̂) positive definite? One
    MUMPS LDLᵀ with the pivot checks of :mod:`.pivots`, then dropped."""
    from .pivots import set_up_checked

    ksp, _ = mumps_ksp(dict(A=service.objects[payload["key"]]["A"]),
                       "check")
    try:
        set_up_checked(ksp)
    finally:
        ksp.destroy()


@command("solve")
def _solve(service, payload, local):
    obj = service.objects[payload["key"]]
    scatter_vector(service, local, obj["b"])
    obj["ksp"].solve(obj["b"], obj["x"])
    if obj["ksp"].getConvergedReason() < 0:  # checked factor: not expected
        raise EngineError(f"MUMPS's solve failed (KSP reason "
                          f"{obj['ksp'].getConvergedReason()})")
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
