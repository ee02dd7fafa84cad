r"""Rows partitioned by nodes: the padded numbering and the scatters.

Every node of the mesh keeps its ``dim`` rows, row ``dim·node +
component``: a Dirichlet DOF becomes an identity row (scaled by the mean
diagonal of K; its solution is 0). Rank r owns the nodes
``starts[r]:starts[r+1]``, so a node's DOFs, and a contact node's normal
row, live on one rank. Only rank 0 holds the reduced arrays; the scatters
send each rank its rows, :func:`gather_vector` brings a vector back."""

import numpy as np
import scipy.sparse as sp

__all__ = ["Layout", "mesh_of", "scatter_matrix", "scatter_vector",
           "gather_vector"]


def mesh_of(problem):
    """The problem whose ``nodes`` and ``dof_map`` number the DOFs of
    ``problem``: itself, or for the nodewise problem of two bodies in
    v = Tu (:mod:`solver.contact.two_body`, whose K̃ keeps the bodies'
    reduced DOF numbering) the bodies' own problem (its ``bodies``);
    None for a discrete problem without a mesh."""
    bodies = getattr(problem, "bodies", None)
    mesh = problem if bodies is None else bodies
    return mesh if getattr(mesh, "nodes", None) is not None else None


class Layout:
    """The padded numbering of ``problem`` on ``size`` ranks (rank 0):
    ``red_to_pad`` (reduced DOF → padded row), ``starts`` (each rank's first
    row), ``dirichlet`` (the rows of prescribed DOFs). Two bodies' nodewise
    problem is laid out by the bodies' mesh (:func:`mesh_of`)."""

    def __init__(self, problem, size):
        mesh = mesh_of(problem)
        self.dim = mesh.dim
        n_nodes = len(mesh.nodes)
        self.n = n_nodes * self.dim
        self.red_to_pad = (mesh.dof_map[:, 0] * self.dim
                           + mesh.dof_map[:, 1]).astype(np.int64)
        node_starts = (np.arange(size + 1) * n_nodes) // size
        self.starts = node_starts * self.dim
        free = np.zeros(self.n, bool)
        free[self.red_to_pad] = True
        self.dirichlet = np.flatnonzero(~free)

    def pad(self, v):
        """A reduced vector (Ñ,) or (Ñ, k) in padded numbering (0 at
        Dirichlet rows)."""
        v = np.asarray(v, float)
        out = np.zeros((self.n,) + v.shape[1:])
        out[self.red_to_pad] = v
        return out

    def unpad(self, v):
        return np.asarray(v)[self.red_to_pad]

    def matrix(self, A):
        """The reduced sparse A as the padded CSR (identity rows, scaled by
        mean diag A, at the Dirichlet DOFs), sorted column indices: with the
        nodes' order kept (``red_to_pad`` increasing, as every exported problem
        has it) each row is copied and only its column indices renumbered, one
        pass with 32-bit indices; another numbering goes through COO."""
        A = sp.csr_matrix(A, dtype=np.float64)
        if not A.has_canonical_format:
            A = A.copy()
            A.sum_duplicates()  # also sorts each row's indices
        scale = float(np.mean(A.diagonal())) if A.shape[0] else 1.0
        r = self.red_to_pad
        if len(r) > 1 and not np.all(r[1:] > r[:-1]):
            return self._matrix_coo(A, scale)
        lengths = np.ones(self.n, np.int64)  # 1: a Dirichlet row's diagonal
        lengths[r] = np.diff(A.indptr)
        total = int(lengths.sum())
        itype = np.int32 if max(total, self.n) < 2 ** 31 else np.int64
        indptr = np.zeros(self.n + 1, itype)
        np.cumsum(lengths, out=indptr[1:])
        del lengths
        indices, data = np.empty(total, itype), np.empty(total)
        diagonal = indptr[self.dirichlet]  # those rows' one entry
        copied = np.ones(total, bool)
        copied[diagonal] = False
        indices[copied] = r.astype(itype)[A.indices]
        data[copied] = A.data
        indices[diagonal], data[diagonal] = self.dirichlet, scale
        return sp.csr_matrix((data, indices, indptr), shape=(self.n, self.n))

    def _matrix_coo(self, A, scale):
        A = A.tocoo()
        rows = np.concatenate([self.red_to_pad[A.row], self.dirichlet])
        cols = np.concatenate([self.red_to_pad[A.col], self.dirichlet])
        vals = np.concatenate([A.data, np.full(len(self.dirichlet), scale)])
        return sp.csr_matrix((vals, (rows, cols)), shape=(self.n, self.n))

    def owner(self, rows):
        """The rank owning each padded row."""
        return np.searchsorted(self.starts, rows, side="right") - 1

    def ranges(self):
        return [(int(a), int(b)) for a, b in zip(self.starts[:-1],
                                                 self.starts[1:])]


def _scatterv(comm, send, counts, dtype):
    """Rank 0's contiguous ``send`` cut into ``counts`` pieces, piece r to
    rank r (MPI_Scatterv of the buffer, no pickling). Rank 0's own piece
    stays a view of ``send`` (MPI_IN_PLACE); the others are new arrays."""
    from mpi4py import MPI

    counts = np.asarray(counts, np.int64)
    if counts.max(initial=0) >= 2 ** 31:  # MPI's counts are C ints
        raise ValueError("a rank's share exceeds 2^31 entries: use more "
                         "ranks")
    displs = np.concatenate([[0], np.cumsum(counts)[:-1]])
    rank = comm.Get_rank()
    if rank == 0:
        send = np.ascontiguousarray(send, dtype)
        comm.Scatterv([send, (counts.tolist(), displs.tolist())],
                      MPI.IN_PLACE, root=0)
        return send[displs[0]:displs[0] + counts[0]]
    out = np.empty(int(counts[rank]), dtype)
    comm.Scatterv(None, out, root=0)
    return out


def scatter_matrix(service, A_pad, bsize):
    """A distributed PETSc AIJ matrix from rank 0's padded CSR ``A_pad``:
    each rank receives its rows by three buffer scatters (no pickled copies),
    and the caller's ``A_pad`` is then the only copy on rank 0."""
    from petsc4py import PETSc

    comm = service.comm
    ranges = service.objects["ranges"]
    a, b = ranges[service.rank]
    n = ranges[-1][1]
    starts = np.array([r[0] for r in ranges] + [n], np.int64)
    indptr = A_pad.indptr if service.root else None
    nnz = comm.bcast(None if indptr is None else np.diff(
        np.asarray(indptr, np.int64)[starts]), root=0)
    itype = np.dtype(PETSc.IntType)
    ptr = _scatterv(comm, indptr, np.diff(starts), itype)
    indices = _scatterv(comm, None if indptr is None else A_pad.indices,
                        nnz, itype)
    data = _scatterv(comm, None if indptr is None else A_pad.data, nnz,
                     PETSc.ScalarType)
    local_ptr = np.empty(b - a + 1, itype)
    local_ptr[:-1] = ptr - (ptr[0] if len(ptr) else 0)
    local_ptr[-1] = len(data)
    M = PETSc.Mat().createAIJ(size=((b - a, n), (b - a, n)), bsize=bsize,
                              csr=(local_ptr, indices, data),
                              comm=comm.tompi4py() if hasattr(
                                  comm, "tompi4py") else comm)
    M.assemble()
    counts = service.objects.setdefault("counts", {})
    counts.update(rows=b - a, nnz=int(len(data)))
    return M


def scatter_vector(service, v_pad, vec):
    """Fill the PETSc vector ``vec`` from rank 0's padded array (one
    buffer scatter)."""
    ranges = service.objects["ranges"]
    part = _scatterv(service.comm, v_pad, [b - a for a, b in ranges],
                     np.float64)
    vec.setArray(part)
    return vec


def gather_vector(service, vec):
    """The PETSc vector ``vec`` as one padded array on rank 0 (None
    elsewhere; one buffer gather)."""
    ranges = service.objects["ranges"]
    counts = [b - a for a, b in ranges]
    out = np.empty(ranges[-1][1]) if service.root else None
    service.comm.Gatherv(np.ascontiguousarray(vec.getArray(), float),
                         None if out is None else
                         [out, (counts, [a for a, _ in ranges])], root=0)
    return out


def _layout_command():
    from .service import command

    @command("layout")
    def _layout(service, payload, local):
        service.objects["ranges"] = payload
        a, b = payload[service.rank]
        service.objects.setdefault("counts", {}).update(rows=b - a)


_layout_command()
