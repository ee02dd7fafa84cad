"""Topology of 2D meshes (triangles or quadrilaterals, cut into triangles
by :func:`solver.geometry.cells.simplices`, which keeps the boundary):
boundary edges and the order of nodes on Γc, which problem files store ordered along Γc (the thesis's spline of
§2.1.3 runs through consecutive contact nodes); vectorised over the mesh."""

import numpy as np

from .cells import simplices

__all__ = ["boundary_edges", "order_along_boundary", "is_boundary_chain",
           "chain_pieces"]


def boundary_edges(cells):
    """Edges that belong to exactly one triangle (quadrilateral) of
    ``cells`` (n, 3) or (n, 4): an int64 array of rows ``(a, b)``,
    ``a < b``, in lexicographic order."""
    cells = np.asarray(simplices(cells, 2), dtype=np.int64)
    edges = np.concatenate([cells[:, [0, 1]], cells[:, [1, 2]],
                            cells[:, [2, 0]]])
    n = int(cells.max(initial=0)) + 1
    # one int64 key per edge (a·n + b sorts as (a, b)): a 1D sort, several
    # times faster than np.unique over rows
    keys, counts = np.unique(_edge_keys(edges, n), return_counts=True)
    once = keys[counts == 1]
    return np.stack([once // n, once % n], axis=1)


def _edge_keys(edges, n):
    edges = np.sort(np.asarray(edges, dtype=np.int64), axis=1)
    return edges[:, 0] * n + edges[:, 1]


def is_boundary_chain(chain, cells):
    """True if consecutive nodes of ``chain`` are joined by boundary edges."""
    chain = np.asarray(chain, dtype=np.int64)
    if len(chain) < 2:
        return len(chain) == 1
    n = int(max(np.max(cells), np.max(chain))) + 1
    known = _edge_keys(boundary_edges(cells), n)
    pairs = np.stack([chain[:-1], chain[1:]], axis=1)
    return bool(np.isin(_edge_keys(pairs, n), known).all())


def chain_pieces(chain, cells):
    """The pieces of Γc: (start, stop) slices of ``chain`` whose consecutive
    nodes are joined by boundary edges of ``cells``; a new piece starts
    where two consecutive nodes are not (Γc of several separate parts, such
    as two opposite sides of a block between two obstacles). A piece of one
    node has no edge (and no normal): the caller refuses it."""
    chain = np.asarray(chain, dtype=np.int64)
    if len(chain) < 2:
        return [(0, len(chain))]
    n = int(max(np.max(cells), np.max(chain))) + 1
    known = _edge_keys(boundary_edges(cells), n)
    pairs = np.stack([chain[:-1], chain[1:]], axis=1)
    breaks = np.flatnonzero(~np.isin(_edge_keys(pairs, n), known)) + 1
    bounds = np.r_[0, breaks, len(chain)]
    return list(zip(bounds[:-1].tolist(), bounds[1:].tolist()))


def order_along_boundary(nodes, cells, coordinates=None, pieces=False):
    """``nodes`` (the unordered nodes of a connected, open piece of the
    boundary of the triangles ``cells``, e.g. SfePy's region ``Gamma_c``)
    reordered into one chain whose consecutive entries share a boundary
    edge; with ``coordinates`` it starts at the end with the smaller ``y``
    (then ``x``), whatever the node numbering. ``pieces``: the nodes may
    form several open chains (Γc of separate parts, :func:`chain_pieces`),
    returned one after the other, each from its end of smaller ``y`` (then
    ``x``), the chains in that order of their first nodes. ValueError if
    the nodes do not form one open chain (``pieces``: open chains, each of
    at least two nodes) of boundary edges."""
    nodes = np.unique(np.asarray(nodes, dtype=np.int64))
    if len(nodes) < 2:
        return nodes
    edges = boundary_edges(cells)
    inside = np.isin(edges, nodes).all(axis=1)
    edges = edges[inside]
    # Degree of each chain node; an open chain has two ends of degree 1.
    degree = np.bincount(edges.ravel(), minlength=nodes.max() + 1)[nodes]
    ends = nodes[degree == 1]
    chains = len(ends) // 2 if pieces else 1
    if len(edges) != len(nodes) - chains or (degree > 2).any() \
            or (degree == 0).any() or len(ends) != 2 * chains \
            or not chains:
        what = "open chains" if pieces else "one open chain"
        raise ValueError(
            f"the {len(nodes)} nodes do not form {what} of boundary "
            f"edges ({len(edges)} boundary edges join them)")
    if coordinates is not None:
        xy = np.asarray(coordinates)[ends]
        ends = ends[np.lexsort((xy[:, 0], xy[:, 1]))]
    # Walk the chains through a neighbour table (two neighbours per node).
    index = np.full(nodes.max() + 1, -1, dtype=np.int64)
    index[nodes] = np.arange(len(nodes))
    neighbours = np.full((len(nodes), 2), -1, dtype=np.int64)
    slot = np.zeros(len(nodes), dtype=np.int64)
    for a, b in edges:  # O(Nc): the chain itself, not the mesh
        ia, ib = index[a], index[b]
        neighbours[ia, slot[ia]] = b
        neighbours[ib, slot[ib]] = a
        slot[ia] += 1
        slot[ib] += 1
    chain = np.empty(len(nodes), dtype=np.int64)
    seen = np.zeros(len(nodes), bool)
    k = 0
    for start in ends:  # each chain from its first end not yet walked
        if seen[index[start]]:
            continue
        current, previous = start, -1
        while True:
            chain[k], k = current, k + 1
            seen[index[current]] = True
            a, b = neighbours[index[current]]
            following = b if a == previous else a
            if following < 0:
                break
            previous, current = current, following
    return chain
