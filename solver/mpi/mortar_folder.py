r"""Two bodies (dual mortar) on the partitioned folder under ``mpiexec``:
the ranks solve the nodewise problem in v = T u of
:mod:`solver.contact.two_body` with no rank holding the whole problem.

The folder keeps K and f as the bodies' (:mod:`.convert_mortar`) and
E of T⁻¹ = I + E (slave DOF rows × master DOF columns, padded numbering).
Each rank reads the rows of E at its own slave DOFs (:func:`read_E`); the
columns may be other ranks' master DOFs, which PETSc's distributed
products fetch. With P = T⁻¹Rᵀ (:func:`coupled_map`) the frictionless and
friction paths of :mod:`.partitioned_full` and :mod:`.krylov_friction`
run unchanged on

.. math::
    K̂ = R T^{-T} K T^{-1} R^T = P^T K P, \qquad f̂ = P^T f = R\,T^{-T} f,

the same ``PtAP`` as one body (f̃ = T⁻ᵀf replaces f on the ranks). GAMG's
near-null space is each body's rigid-body modes B (zero on the other
body) in v, T B = B − E B, then rotated by R and orthonormalised over the
ranks (:func:`body_modes`; Wiesner et al., IJNME 122, 2021). The answer
goes back to the bodies' displacements by one distributed product,
u = T⁻¹ v, and the contact force in v, f_v (−D_jj λ_j n_j plus the
friction traction at slave node j), to the mortar forces in u,
K u − f = Tᵀ (K̃ v − f̃) = (I − Eᵀ) f_v: D_jj-weighted on the slave nodes,
−Σ_j M_jk (…) on the master nodes (:func:`in_bodies`)."""

import os

import numpy as np

from ..problem.partitioned import MORTAR_DIR

__all__ = ["read_E", "coupled_map", "body_modes", "in_bodies"]


def read_E(folder, lo, hi):
    """(rows, columns, values) of E at the padded rows lo ≤ row < hi, the
    folder's sorted rows memory-mapped and only that slice read."""
    path = os.path.join(os.fspath(folder), MORTAR_DIR)
    rows = np.load(os.path.join(path, "E_row.npy"), mmap_mode="r")
    a, b = np.searchsorted(rows, [lo, hi])
    cols = np.load(os.path.join(path, "E_col.npy"), mmap_mode="r")
    vals = np.load(os.path.join(path, "E_val.npy"), mmap_mode="r")
    return (np.array(rows[a:b], np.int64), np.array(cols[a:b], np.int64),
            np.array(vals[a:b], float))


def coupled_map(obj, folder, A, RT):
    """(every rank) P = T⁻¹Rᵀ from the rank's rows of T⁻¹ = I + E and its
    block ``RT`` of Rᵀ (both distributed AIJ, rows as K's ``A``); T⁻¹ is
    kept as ``obj["T_inv"]`` for the outputs, f in ``obj["f"]`` becomes
    f̃ = T⁻ᵀ f. Returns P (the caller destroys ``RT``)."""
    from petsc4py import PETSc

    lo, hi = A.getOwnershipRange()
    n = A.getSize()[0]
    rows, cols, vals = read_E(folder, lo, hi)
    obj["E_entries"] = len(rows)  # this rank's share of E, no more
    local = np.arange(lo, hi)
    r = np.concatenate([local, rows]) - lo
    c = np.concatenate([local, cols])
    v = np.concatenate([np.ones(hi - lo), vals])
    order = np.lexsort((c, r))
    r, c, v = r[order], c[order], v[order]
    indptr = np.searchsorted(r, np.arange(hi - lo + 1))
    T_inv = PETSc.Mat().createAIJ(
        size=((hi - lo, n), (hi - lo, n)),
        csr=(indptr.astype(PETSc.IntType), c.astype(PETSc.IntType), v),
        comm=A.getComm())
    T_inv.assemble()
    P = T_inv.matMult(RT)
    f = obj["f"]
    f_tilde = f.duplicate()
    T_inv.multTranspose(f, f_tilde)
    obj["f"] = f_tilde
    f.destroy()
    obj["T_inv"] = T_inv
    return P


def body_modes(folder, lo, hi, dim, R, T_inv, comm):
    """The near-null space of K̂ on this rank's rows (module docstring):
    each body's rigid-body modes about its own centroid (2D: 3 per body,
    3D: 6), zero on the other body's nodes, mapped by T = 2I − T⁻¹ (one
    distributed product each), rotated by R, orthonormal over all ranks
    (their Gram matrix summed, then its Cholesky factor)."""
    x = np.array(np.load(os.path.join(folder, "nodes.npy"),
                         mmap_mode="r")[lo // dim:hi // dim], float)[:, :dim]
    body = np.array(np.load(os.path.join(folder, MORTAR_DIR, "body.npy"),
                            mmap_mode="r")[lo // dim:hi // dim], np.int64)
    n = len(x)
    pairs = [(0, 1)] if dim == 2 else [(0, 1), (1, 2), (2, 0)]
    columns = []
    for b in (0, 1):
        mine = body == b
        total = comm.allreduce(x[mine].sum(axis=0))
        count = comm.allreduce(int(mine.sum()))
        y = np.where(mine[:, None], x - total / max(count, 1), 0.0)
        for k in range(dim):
            m = np.zeros((n, dim))
            m[mine, k] = 1.0
            columns.append(m.ravel())
        for a, c in pairs:
            m = np.zeros((n, dim))
            m[:, a], m[:, c] = -y[:, c], y[:, a]
            columns.append(m.ravel())
    z, w = T_inv.createVecRight(), T_inv.createVecLeft()
    mapped = []
    for column in columns:
        z.setArray(column)
        T_inv.mult(z, w)
        mapped.append(2.0 * column - w.getArray())
    z.destroy(), w.destroy()
    Z = R @ np.column_stack(mapped)
    gram = comm.allreduce(Z.T @ Z)
    return np.linalg.solve(np.linalg.cholesky(gram), Z.T).T


def in_bodies(obj):
    """(every rank) The Vecs the writer gives for u and the nodal contact
    force: u itself and None for one body; for two bodies u = T⁻¹ v and
    the mortar forces (I − Eᵀ) f_v = 2 f_v − T⁻ᵀ f_v from the contact
    force in v kept as ``obj["force_v"]`` (an array of this rank's rows).
    The caller destroys what it is given when ``obj`` holds ``T_inv``."""
    if "T_inv" not in obj:
        return obj["u"], None
    T_inv = obj["T_inv"]
    u = T_inv.createVecLeft()
    T_inv.mult(obj["u"], u)
    force = None
    if "force_v" in obj:
        f_v = T_inv.createVecRight()
        f_v.setArray(obj["force_v"])
        force = T_inv.createVecRight()
        T_inv.multTranspose(f_v, force)
        force.aypx(-1.0, f_v)  # f_v − T⁻ᵀ f_v
        force.axpy(1.0, f_v)
        f_v.destroy()
    return u, force
