r"""Fill-reducing orderings for the sparse factorisations of K:
:func:`nested_dissection` of the mesh nodes (which SciPy's SuperLU does
not offer; fewer factor nonzeros than its COLAMD, benchmarks/README.md),
and :func:`dof_ordering`, which lifts it to the DOFs and puts a given set
(the contact DOFs) last, so that the trailing block of the factors is the
Schur complement on that set (:mod:`solver.linalg.superlu`,
:mod:`solver.linalg.cholmod`)."""

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

__all__ = ["LEAF_SIZE", "nested_dissection", "dof_ordering"]

#: Subdomains of at most this many nodes are not bisected further.
LEAF_SIZE = 16


def nested_dissection(points, edges, leaf=LEAF_SIZE):
    """Fill-reducing node ordering by geometric nested dissection (George
    1973; recursive coordinate bisection with vertex separators): the
    ``points`` (n, d) in elimination order, from the graph ``edges`` (m, 2).
    Every subdomain with more than ``leaf`` nodes is split at the median of
    its most spread-out coordinate; the upper half's nodes that share an edge
    with the lower half form the separator, ordered after both halves. All
    subdomains of a level are split at once: one integer sort of the active
    nodes and one pass over the edges still inside a subdomain per level."""
    points = np.asarray(points, float)
    n = len(points)
    i, j = _unique_edges(edges, n)
    # each node's rank along each axis (ties by index), once: sorting a
    # subdomain by (coordinate, index) is then sorting integers
    coordinate_rank = np.empty((points.shape[1], n), np.int64)
    for axis, x in enumerate(points.T):
        coordinate_rank[axis, np.lexsort((np.arange(n), x))] = np.arange(n)
    domain = np.zeros(n, np.int64)         # subdomain id within its level
    path = np.zeros(n, np.int64)           # subdomain id when it was ordered
    depth = np.zeros(n, np.int64)          # level at which it was ordered
    active = np.ones(n, bool)
    level = 0
    while active.any():
        idx = np.flatnonzero(active)
        # the subdomains present (ids < 2^level): np.unique without a sort
        present = np.bincount(domain[idx], minlength=1)
        ids = np.flatnonzero(present)
        size = present[ids]
        inv = (np.cumsum(present > 0) - 1)[domain[idx]]
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
        order = np.argsort(inv * n + coordinate_rank[axis, idx])
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        rank = np.empty(len(idx), np.int64)
        rank[order] = np.arange(len(idx)) - starts[inv[order]]
        upper = rank >= counts[inv] // 2
        # key = 2·domain + upper (the child subdomain), −1 if not split now:
        # an edge is cut iff both ends are split, in one domain, not one half
        key = np.full(n, -1, np.int64)
        key[idx] = 2 * domain[idx] + upper
        ki, kj = key[i], key[j]
        cut = (ki != kj) & (ki >> 1 == kj >> 1) & (ki >= 0) & (kj >= 0)
        separator = np.unique(np.where(ki[cut] & 1, i[cut], j[cut]))
        path[separator], depth[separator] = domain[separator], level
        active[separator] = False
        domain[idx] = key[idx]
        # only edges inside one child subdomain can be cut later
        inside = (ki == kj) & (ki >= 0)
        i, j = i[inside], j[inside]
        level += 1
    # Post-order of the bisection tree: a subdomain (or separator) ordered
    # at depth d with id q comes after every subdomain below it.
    shift = level + 1 - depth
    key = (path << shift) + (np.int64(1) << shift) - 1
    return np.lexsort((np.arange(n), -depth, key))


def _unique_edges(edges, n):
    """(i, j) of the distinct edges i < j of ``edges`` (loops dropped)."""
    edges = np.sort(np.asarray(edges, np.int64).reshape(-1, 2), axis=1)
    edges = edges[edges[:, 0] != edges[:, 1]]
    code = np.sort(edges[:, 0] * n + edges[:, 1])
    code = code[np.concatenate([[True], code[1:] != code[:-1]])]
    return code // n, code % n


def dof_ordering(problem, last=None):
    """A fill-reducing permutation of the reduced DOFs with ``last`` at the
    end (taken out of the graph): nested dissection of the mesh nodes (a
    node's DOFs together) or of a problem's ``node_graph()`` (the two-body
    problem in v); reverse Cuthill-McKee of K for other discrete problems."""
    n = problem.n_dofs
    last = np.zeros(0, np.int64) if last is None else \
        np.asarray(last, np.int64).ravel()
    is_last = np.zeros(n, bool)
    is_last[last] = True
    graph = getattr(problem, "node_graph", None)  # (points, edges, dof_map)
    if problem.kind == "mesh" or graph is not None:
        if graph is None:
            cells = np.asarray(problem.cells, np.int64)
            k = cells.shape[1]
            edges = np.concatenate([cells[:, [a, b]] for a in range(k)
                                    for b in range(a + 1, k)])
            points, dof_map = problem.nodes, problem.dof_map
        else:
            points, edges, dof_map = graph()
        node = dof_map[:, 0]
        excluded = np.zeros(len(points), bool)
        excluded[node[last]] = True
        edges = edges[~excluded[edges].any(axis=1)]
        nodes = nested_dissection(points, edges)
        rank = np.empty(len(points), np.int64)
        rank[nodes] = np.arange(len(nodes))
        order = np.lexsort((dof_map[:, 1], rank[node]))
    else:
        order = csgraph.reverse_cuthill_mckee(sp.csr_matrix(problem.K),
                                              symmetric_mode=True)
    order = order[~is_last[order]]
    return np.concatenate([order, last])
