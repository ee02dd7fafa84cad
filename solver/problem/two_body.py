"""Validation of the two-body keys of a mesh file (format version 4):
two elastic bodies in one mesh, their interface given as slave and master
segments (2D) or triangles (3D) (dual mortar, :mod:`solver.geometry.
mortar`), checked by the rules of docs/npz-format.md ("Two bodies"); each
failure a one-line :class:`~solver.errors.ProblemError` naming the key."""

import numpy as np

from ..geometry.cells import cell_name, simplices
from .checks import check_array, check_range, fail
from .format import TWO_BODY
from .geometry3d import check_contact_faces
from .meta import check_bodies

__all__ = ["validate_body", "validate_two_body", "check_block_diagonal"]


def validate_body(arrays, cells, n_nodes, dim=None):
    """The ``body`` key, or None if absent (one body); ``dim`` names the
    cells in messages (default: triangles or tetrahedra by their width)."""
    if "body" not in arrays:
        return None
    body = check_array(arrays, "body", "int", 1, (n_nodes,))
    check_range("body", body, 0, n_nodes)
    used = np.bincount(body, minlength=int(body.max(initial=0)) + 1) > 0
    if not used.all():
        fail("body", f"no node of body {int(np.argmin(used))} (the ids must "
                     f"run 0 … B−1, B = {len(used)})")
    ids = body[cells]
    mixed = np.flatnonzero((ids != ids[:, :1]).any(axis=1))
    if len(mixed):
        i = int(mixed[0])
        name = cell_name(dim, cells.shape[1]) if dim else \
            {3: "triangle", 4: "tetrahedron"}.get(cells.shape[1], "cell")
        fail("cells", f"{name} {i} joins nodes of bodies "
                      f"{sorted(set(ids[i].tolist()))} (the bodies must "
                      "share no node)")
    return body


def _segments(arrays, key, nodes, cells):
    """Range, length, boundary edge and orientation of one segment key."""
    segments = check_array(arrays, key, "int", 2, (None, 2))
    if not len(segments):
        fail(key, "no segments")
    check_range(key, segments, 0, len(nodes))
    a, b = segments[:, 0], segments[:, 1]
    n = len(nodes)
    extent = float(np.ptp(nodes, axis=0).max())
    t = nodes[b] - nodes[a]
    length = np.hypot(t[:, 0], t[:, 1])
    short = np.flatnonzero(length <= 1e-14 * extent)
    if len(short):
        i = int(short[0])
        fail(key, f"segment {i} ({a[i]}, {b[i]}) has zero length")
    keys = np.minimum(a, b) * n + np.maximum(a, b)
    unique, counts = np.unique(keys, return_counts=True)
    if (counts > 1).any():
        i = int(np.flatnonzero(keys == unique[np.argmax(counts > 1)])[0])
        fail(key, f"segment {i} ({a[i]}, {b[i]}) appears twice")
    # every edge of every triangle, with the vertex opposite to it
    edge = np.concatenate([cells[:, [0, 1, 2]], cells[:, [1, 2, 0]],
                           cells[:, [2, 0, 1]]])
    edge_keys = np.minimum(edge[:, 0], edge[:, 1]) * n \
        + np.maximum(edge[:, 0], edge[:, 1])
    order = np.argsort(edge_keys, kind="stable")
    edge_keys, edge = edge_keys[order], edge[order]
    lo = np.searchsorted(edge_keys, keys, side="left")
    hi = np.searchsorted(edge_keys, keys, side="right")
    bad = np.flatnonzero(hi - lo != 1)
    if len(bad):
        i = int(bad[0])
        what = "no edge of a triangle" if hi[i] == lo[i] else \
            "an interior edge (it bounds two triangles)"
        fail(key, f"segment {i} ({a[i]}, {b[i]}) is {what}, not a boundary "
                  "edge of the mesh")
    c = nodes[edge[lo, 2]] - nodes[a]
    cross = t[:, 0] * c[:, 1] - t[:, 1] * c[:, 0]
    wrong = np.flatnonzero(cross <= 0)
    if len(wrong):
        i = int(wrong[0])
        fail(key, f"segment {i} ({a[i]}, {b[i]}) is oriented with its body "
                  f"on the right ({len(wrong)} segments): the body must lie "
                  "on the left of a→b (outward normal (t_y, −t_x))")
    return segments


def _triangles(arrays, key, nodes, cells, contact_nodes):
    """The triangles of one facet key in 3D: faces of one tetrahedron each,
    oriented outwards (:func:`~.geometry3d.check_contact_faces`); the slave
    triangles' vertices are exactly ``contact_nodes``."""
    faces = check_array(arrays, key, "int", 2, (None, 3))
    if not len(faces):
        fail(key, "no triangles")
    check_range(key, faces, 0, len(nodes))
    own = contact_nodes if key == "mortar_slave" else np.unique(faces)
    check_contact_faces(faces, nodes, cells, own, key)
    return faces


def _slave_nodes_3d(slave, pair, contact_nodes, n_nodes):
    """3D: no node on the slave side of two pairs, contact_nodes listed
    pair by pair (any order inside a pair)."""
    node_pair = np.full(n_nodes, -1, dtype=np.int64)
    node_pair[slave.ravel()] = np.repeat(pair, 3)
    twice = np.flatnonzero(node_pair[slave] != pair[:, None])
    if len(twice):
        f, k = divmod(int(twice[0]), 3)
        fail("mortar_slave_pair", f"node {slave[f, k]} is on the slave side "
                                  f"of pairs {pair[f]} and "
                                  f"{node_pair[slave[f, k]]}")
    if (np.diff(node_pair[contact_nodes]) < 0).any():
        fail("contact_nodes", "not ordered pair by pair (the slave nodes of "
                              "pair 0 first, then of pair 1, ...)")


def _pairs(arrays, key, count):
    """Pair index per segment (zeros if the key is absent)."""
    if key not in arrays:
        return np.zeros(count, dtype=np.int64)
    pair = check_array(arrays, key, "int", 1, (count,))
    check_range(key, pair, 0, count)
    return pair


def _pair_bodies(key, segments, pair, body, n_pairs):
    """The one body of each pair's segments of ``key``."""
    ids = np.zeros(len(segments), dtype=np.int64) if body is None \
        else body[segments[:, 0]]
    first = np.full(n_pairs, -1, dtype=np.int64)
    first[pair[::-1]] = ids[::-1]
    other = np.flatnonzero(ids != first[pair])
    if len(other):
        i = int(other[0])
        fail(key, f"the segments of pair {int(pair[i])} lie in bodies "
                  f"{int(first[pair[i]])} and {int(ids[i])} (one body per "
                  "side of a pair)")
    return first


def _slave_chains(slave, pair, contact_nodes, n_nodes, n_pairs):
    """contact_nodes = the slave nodes, pair by pair, each pair's segments
    one open chain listed in their direction (module doc)."""
    ends = np.stack([pair, pair], axis=1).ravel()
    entries = np.unique(np.stack([slave.ravel(), ends], axis=1), axis=0)
    twice = np.flatnonzero(np.diff(entries[:, 0]) == 0)
    if len(twice):
        node, p, q = entries[twice[0], 0], entries[twice[0], 1], \
            entries[twice[0] + 1, 1]
        fail("mortar_slave_pair", f"node {node} is on the slave side of "
                                  f"pairs {p} and {q}")
    slave_nodes = entries[:, 0]
    if not np.array_equal(np.sort(contact_nodes), slave_nodes):
        extra = np.setdiff1d(contact_nodes, slave_nodes)
        if len(extra):
            fail("contact_nodes", f"node {extra[0]} is not a node of a "
                                  "mortar_slave segment (contact_nodes are "
                                  "the slave nodes)")
        missing = np.setdiff1d(slave_nodes, contact_nodes)
        fail("contact_nodes", f"slave node {missing[0]} is missing "
                              "(contact_nodes are the slave nodes)")
    node_pair = np.full(n_nodes, -1, dtype=np.int64)
    node_pair[entries[:, 0]] = entries[:, 1]
    p = node_pair[contact_nodes]
    if (np.diff(p) < 0).any():
        fail("contact_nodes", "not ordered pair by pair (the slave nodes of "
                              "pair 0 first, then of pair 1, ...)")
    n_seg = np.bincount(pair, minlength=n_pairs)
    n_pts = np.bincount(p, minlength=n_pairs)
    bad = np.flatnonzero(n_pts != n_seg + 1)
    if len(bad):
        q = int(bad[0])
        fail("mortar_slave", f"the slave segments of pair {q} do not form "
                             f"one open chain ({n_seg[q]} segments, "
                             f"{n_pts[q]} nodes)")
    inside = np.flatnonzero(p[:-1] == p[1:])
    steps = contact_nodes[inside] * n_nodes + contact_nodes[inside + 1]
    known = np.sort(slave[:, 0] * n_nodes + slave[:, 1])
    at = np.minimum(np.searchsorted(known, steps), len(known) - 1)
    gap = np.flatnonzero(known[at] != steps)
    if len(gap):
        i = int(inside[gap[0]])
        fail("contact_nodes", f"nodes {contact_nodes[i]} and "
                              f"{contact_nodes[i + 1]} are consecutive but no "
                              "slave segment runs from the first to the "
                              "second (list each pair's chain in the "
                              "direction of its segments)")


def check_block_diagonal(K, dof_map, body):
    """K couples no DOFs of two bodies (they share no node)."""
    coo = K.tocoo()
    of = body[dof_map[:, 0]]
    cross = np.flatnonzero(of[coo.row] != of[coo.col])
    if len(cross):
        i, j = int(coo.row[cross[0]]), int(coo.col[cross[0]])
        fail("K_data", f"K couples body {of[i]} (DOF {i}) and body {of[j]} "
                       f"(DOF {j}): bodies sharing no node give a "
                       "block-diagonal K")


def validate_two_body(arrays, fields, K, meta):
    """The two-body keys of a mesh file, given the ``fields`` of
    :func:`solver.problem.geometry.validate_mesh`: ``body``,
    ``mortar_slave``, ``mortar_master``, ``mortar_slave_pair``,
    ``mortar_master_pair`` (absent keys: None; the pair indices of a
    two-body file without them: zeros)."""
    out = dict.fromkeys(TWO_BODY)
    nodes, cells = fields["nodes"], fields["cells"]
    body = validate_body(arrays, cells, len(nodes), nodes.shape[1])
    out["body"] = body
    n_bodies = 1 if body is None else int(body.max()) + 1
    if body is not None:
        check_block_diagonal(K, fields["dof_map"], body)
    if "mortar_slave" not in arrays:
        for key in TWO_BODY[2:]:  # in an obstacle-free file (geometry.py)
            if key in arrays:
                fail(key, "given without mortar_slave")
        if n_bodies > 1:
            check_bodies(meta, n_bodies)
        return out
    if "mortar_master" not in arrays:
        fail("mortar_master", "missing (mortar_slave needs it)")
    if body is None:
        fail("mortar_slave", "a two-body file needs the key body (the slave "
                             "and master segments lie in different bodies)")
    dim = nodes.shape[1]
    if dim == 2:  # quadrilaterals by their cut, which keeps the boundary
        triangles = simplices(cells, 2)
        slave = _segments(arrays, "mortar_slave", nodes, triangles)
        master = _segments(arrays, "mortar_master", nodes, triangles)
    else:
        slave, master = (_triangles(arrays, key, nodes, cells,
                                    fields["contact_nodes"])
                         for key in ("mortar_slave", "mortar_master"))
    slave_pair = _pairs(arrays, "mortar_slave_pair", len(slave))
    master_pair = _pairs(arrays, "mortar_master_pair", len(master))
    n_pairs = int(max(slave_pair.max(), master_pair.max())) + 1
    for key, pair in (("mortar_slave_pair", slave_pair),
                      ("mortar_master_pair", master_pair)):
        used = np.bincount(pair, minlength=n_pairs) > 0
        if not used.all():
            side = key.split("_")[1]
            fail(key, f"pair {int(np.argmin(used))} has no {side} segment "
                      f"(the pairs must run 0 … P−1, P = {n_pairs})")
    slave_body = _pair_bodies("mortar_slave", slave, slave_pair, body,
                              n_pairs)
    master_body = _pair_bodies("mortar_master", master, master_pair, body,
                               n_pairs)
    same = np.flatnonzero(slave_body == master_body)
    if len(same):
        q = int(same[0])
        fail("mortar_master", f"pair {q}: the master segments lie in the "
                              f"slave body {int(slave_body[q])} (self-"
                              "contact is not supported)")
    if dim == 2:
        _slave_chains(slave, slave_pair, fields["contact_nodes"],
                      len(nodes), n_pairs)
    else:
        _slave_nodes_3d(slave, slave_pair, fields["contact_nodes"],
                        len(nodes))
    check_bodies(meta, n_bodies, slave_body, master_body)
    out.update(mortar_slave=slave, mortar_master=master,
               mortar_slave_pair=slave_pair, mortar_master_pair=master_pair)
    return out
