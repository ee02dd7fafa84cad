r"""Fill-reducing orderings for the sparse factorisations of K.

* :func:`nested_dissection` orders the nodes of a mesh by geometric nested
  dissection (George 1973; recursive coordinate bisection with vertex
  separators), a fill-reducing ordering that SciPy's SuperLU does not offer.
  On the refined thesis block it gives 30-40 % fewer factor nonzeros than
  SuperLU's COLAMD (SciPy's default) and, ordering included, a 1.3-3.9×
  faster solve from 3·10⁴ to 9·10⁵ DOFs (``benchmarks/README.md``).
* :func:`dof_ordering` lifts it to the DOFs and puts a given set (the
  contact DOFs) last, so that the trailing block of the factors is the
  Schur complement on that set (:mod:`solver.linalg.superlu`,
  :mod:`solver.linalg.cholmod`).
"""

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

__all__ = ["LEAF_SIZE", "nested_dissection", "dof_ordering"]

#: Subdomains of at most this many nodes are not bisected further; 16 was
#: the fastest of 16/64/256 on the refined thesis block (480k DOFs).
LEAF_SIZE = 16


def nested_dissection(points, edges, leaf=LEAF_SIZE):
    """Fill-reducing node ordering by geometric nested dissection.

    Every subdomain (all nodes at first) with more than ``leaf`` nodes is
    split at the median of the coordinate in which it is most spread out;
    the nodes of the upper half that share an edge with the lower half form
    the separator, which is ordered after both halves (recursively). All
    subdomains of one level are split at once (vectorised; no loop over
    nodes or subdomains).

    Parameters
    ----------
    points : (n, d) array
        Node coordinates.
    edges : (m, 2) int array
        Graph edges (e.g. the edges of the mesh cells; repeats allowed).
    leaf : int
        Size below which a subdomain is not split.

    Returns
    -------
    (n,) int array
        The nodes in elimination order.
    """
    points = np.asarray(points, float)
    n = len(points)
    i, j = np.asarray(edges, np.int64).T
    domain = np.zeros(n, np.int64)         # subdomain id within its level
    path = np.zeros(n, np.int64)           # subdomain id when it was ordered
    depth = np.zeros(n, np.int64)          # level at which it was ordered
    active = np.ones(n, bool)
    level = 0
    while active.any():
        idx = np.flatnonzero(active)
        ids, inv, size = np.unique(domain[idx], return_inverse=True,
                                   return_counts=True)
        done = (size <= leaf)[inv]
        path[idx[done]], depth[idx[done]] = domain[idx[done]], level
        active[idx[done]] = False
        keep = ~done
        idx, inv = idx[keep], inv[keep]
        if not len(idx):
            break
        counts = np.maximum(np.bincount(inv, minlength=len(ids)), 1)
        spread = np.column_stack([  # variance of each coordinate
            np.bincount(inv, x * x, len(ids)) / counts
            - (np.bincount(inv, x, len(ids)) / counts) ** 2
            for x in points[idx].T])
        axis = np.argmax(spread, axis=1)[inv]
        order = np.lexsort((idx, points[idx, axis], inv))
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        rank = np.empty(len(idx), np.int64)
        rank[order] = np.arange(len(idx)) - starts[inv[order]]
        upper = np.full(n, -1, np.int64)
        upper[idx] = rank >= counts[inv] // 2
        cut = (active[i] & active[j] & (domain[i] == domain[j])
               & (upper[i] != upper[j]))
        separator = np.unique(np.where(upper[i[cut]] == 1, i[cut], j[cut]))
        path[separator], depth[separator] = domain[separator], level
        active[separator] = False
        domain[idx] = 2 * domain[idx] + upper[idx]
        level += 1
    # Post-order of the bisection tree: a subdomain (or separator) ordered
    # at depth d with id q comes after every subdomain below it.
    shift = level + 1 - depth
    key = (path << shift) + (np.int64(1) << shift) - 1
    return np.lexsort((np.arange(n), -depth, key))


def dof_ordering(problem, last=None):
    """A fill-reducing permutation of the reduced DOFs, ``last`` at the end.

    Mesh problems: nested dissection of the mesh nodes (both DOFs of a node
    stay together). Discrete problems (no mesh): reverse Cuthill-McKee of K.
    ``last`` (DOF indices, in the order wanted) are taken out of the graph
    and appended.
    """
    n = problem.n_dofs
    last = np.zeros(0, np.int64) if last is None else \
        np.asarray(last, np.int64).ravel()
    is_last = np.zeros(n, bool)
    is_last[last] = True
    if problem.kind == "mesh":
        cells = np.asarray(problem.cells, np.int64)
        k = cells.shape[1]
        edges = np.concatenate([cells[:, [a, b]] for a in range(k)
                                for b in range(a + 1, k)])
        node = problem.dof_map[:, 0]
        excluded = np.zeros(len(problem.nodes), bool)
        excluded[node[last]] = True
        edges = edges[~excluded[edges].any(axis=1)]
        nodes = nested_dissection(problem.nodes, edges)
        rank = np.empty(len(problem.nodes), np.int64)
        rank[nodes] = np.arange(len(nodes))
        order = np.lexsort((problem.dof_map[:, 1], rank[node]))
    else:
        order = csgraph.reverse_cuthill_mckee(sp.csr_matrix(problem.K),
                                              symmetric_mode=True)
    order = order[~is_last[order]]
    return np.concatenate([order, last])
