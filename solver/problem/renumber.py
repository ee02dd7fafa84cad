r"""A mesh problem with its nodes renumbered so that consecutive node
ranges are compact pieces of the body (``python -m solver convert X.npz
DIR`` does by default; ``--no-renumber`` keeps the file's order). The
order is computed from the cells alone (:func:`node_order`), so the
converter renumbers a streamed file's stand-in problem (K's diagonal in
K's place) here and writes K itself in the new order by blocks
(the bucket pass of :mod:`solver.mpi.convert`; :func:`dof_order`).

The partitioned folder gives every rank a consecutive range of nodes
(:mod:`solver.problem.partitioned`). A mesh generator's numbering need not
keep neighbours close: in a gmsh mesh the nodes of one range are spread
over the whole body, so that every rank's rows of K couple to almost
every other rank's (the 1.93·10⁶-DOF block at 2 ranks: 43 % of K's
entries outside the diagonal blocks, each rank's ghost columns all of the
other's rows), and the ghost vectors, the off-diagonal blocks and
GAMG's setup then grow on every rank with the global size, not with its
rows (benchmarks/README.md, "The folder's Krylov path: memory per rank").
The reverse Cuthill–McKee order of the node graph (Cuthill & McKee 1969;
George & Liu, *Computer Solution of Large Sparse Positive Definite
Systems*, 1981, §4.3) numbers the nodes level set by level set, so a
range is a band of level sets, whose cut with the next is one level set.

The renumbered problem is the same problem: node k of it is node
``order[k]`` of the original, the reduced DOFs follow their nodes (K, f,
``dof_map``, ``contact_dofs``, ``load_path`` permuted alike), the contact
nodes keep their order (so M is unchanged) with new numbers."""

import numpy as np
import scipy.sparse as sp
from scipy.sparse import csgraph

from ..errors import ProblemError
from .core import validate_arrays

__all__ = ["renumbered", "node_order", "dof_order", "cut_cells"]


def node_order(cells, n_nodes):
    """The reverse Cuthill–McKee order of the nodes of ``cells`` (node
    graph: two nodes adjacent when they share a cell): ``order[k]`` is
    the node numbered k."""
    cells = np.asarray(cells, np.int64)
    k = cells.shape[1]
    rows = np.repeat(cells, k, axis=1).ravel()
    cols = np.tile(cells, (1, k)).ravel()
    graph = sp.csr_matrix((np.ones(len(rows), np.int8), (rows, cols)),
                          shape=(n_nodes, n_nodes))
    return np.asarray(csgraph.reverse_cuthill_mckee(
        graph, symmetric_mode=True), np.int64)


def dof_order(dof_map, order):
    """The reduced DOFs in the renumbered problem's order: ``dofs[j]`` is
    the original reduced DOF that becomes reduced DOF j (sorted by new
    node, then component; ``dof_map``'s rows are (node, component),
    ``order`` is :func:`node_order`'s)."""
    dof_map = np.asarray(dof_map, np.int64)
    new = np.empty(len(order), np.int64)
    new[order] = np.arange(len(order))
    d = int(dof_map[:, 1].max()) + 1 if len(dof_map) else 1
    return np.argsort(new[dof_map[:, 0]] * d + dof_map[:, 1], kind="stable")


def cut_cells(cells, starts):
    """The share of ``cells`` whose nodes lie in more than one of the
    consecutive node ranges ``starts`` (range r = [starts[r],
    starts[r + 1])): the cells that couple two ranks' rows of K."""
    cells = np.asarray(cells, np.int64)
    if not len(cells):
        return 0.0
    low = np.searchsorted(starts, cells.min(axis=1), side="right")
    high = np.searchsorted(starts, cells.max(axis=1), side="right")
    return float(np.count_nonzero(low != high)) / len(cells)


def renumbered(problem):
    """(the problem with its nodes in :func:`node_order`, ``order``):
    module docstring. A mesh problem only (ProblemError otherwise)."""
    if problem.kind != "mesh":
        raise ProblemError("renumber: a problem without a mesh has no "
                           "nodes to renumber")
    arrays = problem.to_arrays()
    n_nodes = len(arrays["nodes"])
    order = node_order(arrays["cells"], n_nodes)
    new = np.empty(n_nodes, np.int64)
    new[order] = np.arange(n_nodes)
    dof_map = np.asarray(arrays["dof_map"], np.int64)
    dofs = dof_order(dof_map, order)
    dof_new = np.empty(len(dofs), np.int64)
    dof_new[dofs] = np.arange(len(dofs))
    K = sp.csr_matrix((arrays["K_data"], arrays["K_indices"],
                       arrays["K_indptr"]), shape=tuple(arrays["K_shape"]))
    K = K[dofs][:, dofs].tocsr()
    K.sort_indices()
    contact_dofs = np.asarray(arrays["contact_dofs"], np.int64)
    arrays.update(
        K_data=K.data, K_indices=K.indices, K_indptr=K.indptr,
        f=np.asarray(arrays["f"])[dofs],
        nodes=np.asarray(arrays["nodes"])[order],
        cells=new[np.asarray(arrays["cells"], np.int64)],
        dof_map=np.c_[new[dof_map[dofs, 0]], dof_map[dofs, 1]],
        u_prescribed=np.asarray(arrays["u_prescribed"])[order],
        contact_nodes=new[np.asarray(arrays["contact_nodes"], np.int64)],
        contact_dofs=np.where(contact_dofs >= 0,
                              dof_new[np.maximum(contact_dofs, 0)], -1))
    del K
    for name in ("contact_faces", "mortar_slave", "mortar_master"):
        if name in arrays:
            arrays[name] = new[np.asarray(arrays[name], np.int64)]
    if "body" in arrays:
        arrays["body"] = np.asarray(arrays["body"])[order]
    if "load_path" in arrays:
        arrays["load_path"] = np.asarray(arrays["load_path"])[:, dofs]
    if "load_path_prescribed" in arrays:
        arrays["load_path_prescribed"] = np.asarray(
            arrays["load_path_prescribed"])[:, order]
    out = validate_arrays(arrays)
    out.source = problem.source
    return out, order
