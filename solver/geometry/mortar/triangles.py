r"""Dual mortar coupling of two 3D bodies on triangulated interfaces,
computed once on the undeformed interface (small deformation and small
sliding: the overlaps are not updated as the bodies move).

On each slave triangle the dual basis ψ_a = 3N_a − N_b − N_c = 4N_a − 1
is biorthogonal to the P1 basis (∫ψ_a N_b = δ_ab ∫N_a; Wohlmuth 2000;
Popp, Gitterle, Gee & Wall, IJNME 83 (2010) 1428, (20)), so that

.. math::
    D_{jj} = \int_{Γ_s} N_j, \qquad
    M_{jk} = \int_{Γ_s} ψ_j\, N^m_k,

D diagonal (a third of the slave triangles' areas at j), M sparse,
integrated segment to segment (Puso & Laursen, CMAME 193 (2004) 601;
Popp et al. 2010, §3.3-3.4): for each facing slave/master triangle pair
whose bounding boxes overlap (:func:`~.search.candidate_pairs`, the
slave's enlarged by :func:`~.search.facet_reach`), both
triangles are projected onto the auxiliary plane through the slave
triangle's centroid with normal n₀ (the slave's nodal normals averaged at
the centroid), the projected master triangle is clipped by the projected
slave triangle, the convex overlap is split into triangles about its
centroid, and on each a 7-point Gauss rule of degree 5 (Radon; exact for
the quadratic ψ_j N_k of a flat interface) gives the integrand at points
whose slave and master shape functions are the barycentric coordinates of
the point in the two projected triangles. The projection of the slave
triangle is affine, so the weights are the overlap's share of the
projected slave triangle times the slave triangle's area: Σ_k M_jk =
D_jj exactly where the master covers a slave node's whole support (the
partition of unity), and M x = D x for every linear field on a flat
interface (the contact patch test).

The overlap polygon is clipped as Sutherland–Hodgman's algorithm would
clip two convex polygons, vectorised over the pairs: its vertices are
the vertices of each triangle inside the other and the crossings of
their edges (at most 15 points, a mask for those that exist), ordered by
their angle about their mean. n_j, the slave nodal normal, is the
angle-weighted average of the slave triangles' normals at j
(:func:`~solver.geometry.surfaces.normals.surface_normals`); the two
tangents per node are those of the rigid case
(:func:`~solver.geometry.frames.tangent_basis`)."""

import numpy as np

from ..frames import tangent_basis
from ..surfaces.normals import surface_normals
from .coupling import assemble_coupling
from .search import candidate_pairs, facet_reach

__all__ = ["GAUSS_TRIANGLE", "TRIANGLE_PAIR_CHUNK", "triangle_areas",
           "triangle_coupling", "overlap_polygons", "node_to_triangle"]


def _radon():
    """Radon's 7-point rule on the unit triangle, degree 5 (Stroud, T2:5-1):
    barycentric (r, s) points and weights summing to 1."""
    r15 = np.sqrt(15.0)
    a, b = (6 - r15) / 21, (6 + r15) / 21
    wa, wb = (155 - r15) / 1200, (155 + r15) / 1200
    points = np.array([[1 / 3, 1 / 3], [a, a], [1 - 2 * a, a],
                       [a, 1 - 2 * a], [b, b], [1 - 2 * b, b],
                       [b, 1 - 2 * b]])
    weights = np.array([9 / 40, wa, wa, wa, wb, wb, wb])
    return points, weights


#: The rule on every triangle of an overlap: (points (7, 2), weights (7,)).
GAUSS_TRIANGLE = _radon()

#: Slave/master pairs integrated at once (each holds up to 15 triangles of
#: 7 points: a few arrays of this many × 105 floats).
TRIANGLE_PAIR_CHUNK = 20_000

#: Relative tolerance of "inside" and of an edge crossing (in units of the
#: triangles' size): a vertex on the other triangle's edge is inside.
INSIDE_TOL = 1e-12


def triangle_areas(nodes, faces):
    """(unit normals (n_f, 3) by the right-hand rule, areas (n_f,))."""
    p = nodes[faces]
    cross = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    twice = np.linalg.norm(cross, axis=1)
    return cross / twice[:, None], 0.5 * twice


def _cross2(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _barycentric(tri, x):
    """Barycentric coordinates (…, 3) of the points x (P, g, 2) in the
    triangles tri (P, 3, 2)."""
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    det = _cross2(e1, e2)[:, None]
    rel = x - tri[:, None, 0]
    l1 = _cross2(rel, e2[:, None]) / det
    l2 = _cross2(e1[:, None], rel) / det
    return np.stack([1 - l1 - l2, l1, l2], axis=-1)


def overlap_polygons(s2, m2):
    """The overlap of the triangles s2 and m2 (P, 3, 2) as convex polygons:
    (points (P, 15, 2) ordered by angle about their mean, count (P,) of
    the valid ones, which come first). Module docstring."""
    size = np.maximum(np.ptp(s2, axis=1).max(axis=1),
                      np.ptp(m2, axis=1).max(axis=1))
    tol = INSIDE_TOL
    with np.errstate(divide="ignore", invalid="ignore"):
        in_m = (_barycentric(m2, s2) >= -tol).all(axis=2)
        in_s = (_barycentric(s2, m2) >= -tol).all(axis=2)
        p, e = s2, np.roll(s2, -1, axis=1) - s2          # (P, 3, 2)
        q, f = m2, np.roll(m2, -1, axis=1) - m2
        P, E = p[:, :, None], e[:, :, None]              # slave edge i
        Q, F = q[:, None], f[:, None]                    # master edge j
        den = _cross2(E, F)                              # (P, 3, 3)
        t = _cross2(Q - P, F) / den
        u = _cross2(Q - P, E) / den
        cross = (np.abs(den) > tol * size[:, None, None] ** 2) \
            & (t >= -tol) & (t <= 1 + tol) & (u >= -tol) & (u <= 1 + tol)
        hit = P + np.clip(t, 0, 1)[..., None] * E
    points = np.concatenate([s2, m2, hit.reshape(len(s2), 9, 2)], axis=1)
    valid = np.concatenate([in_m, in_s, cross.reshape(len(s2), 9)], axis=1)
    count = valid.sum(axis=1)
    points = np.where(valid[..., None], points, 0.0)     # no NaN left
    mean = points.sum(axis=1) / np.maximum(count, 1)[
        :, None]
    rel = points - mean[:, None]
    angle = np.where(valid, np.arctan2(rel[..., 1], rel[..., 0]), np.inf)
    order = np.argsort(angle, axis=1, kind="stable")
    return np.take_along_axis(points, order[..., None], axis=1), count


def _interface(nodes, slave, master, slave_nodes):
    """What both couplings start from: nodes, slave, master, slave_nodes
    (default sorted), each node's row ``pos`` (−1 off the slave side), the
    slave triangles' unit normals and areas, the master's unit normals, the
    slave nodal normals and D (a third of the areas at each node)."""
    nodes = np.asarray(nodes, float)
    slave, master = np.asarray(slave, np.int64), np.asarray(master, np.int64)
    slave_nodes = np.unique(slave) if slave_nodes is None \
        else np.asarray(slave_nodes, np.int64)
    pos = np.full(len(nodes), -1)
    pos[slave_nodes] = np.arange(len(slave_nodes))
    n_s, area_s = triangle_areas(nodes, slave)
    n_m, _ = triangle_areas(nodes, master)
    normal = surface_normals(nodes, slave, slave_nodes)
    D = np.bincount(pos[slave].ravel(), np.repeat(area_s / 3, 3),
                    minlength=len(slave_nodes))
    return nodes, slave, master, slave_nodes, pos, n_s, area_s, n_m, \
        normal, D


def triangle_coupling(nodes, slave, master, slave_nodes=None, search=None):
    """The dual mortar D, M, n_j, g̃_j of slave triangles ``slave`` against
    master triangles ``master`` (node ids, each oriented by the right-hand
    rule to its body's outward normal; module docstring), vectorised over
    the facing pairs of :func:`~.search.candidate_pairs` in chunks of
    :data:`TRIANGLE_PAIR_CHUNK`; rows in the order ``slave_nodes`` (default:
    sorted). The slave boxes are enlarged by ``search``, if given, and the
    pairs whose master lies farther than it from the auxiliary plane left
    out; by default facet by facet by the bound G of
    :func:`~.search.facet_reach` on the gap along n₀, axis k by G |n₀_k|
    (a master point X_s + g n₀ with g ≤ G lies in that box)."""
    nodes, slave, master, slave_nodes, pos, n_s, area_s, n_m, normal, D = \
        _interface(nodes, slave, master, slave_nodes)
    if search is None:  # the gap g along the plane's normal n₀ moves a
        # point by g |n₀_k| along axis k: the box grows by that much
        n0 = normal[pos[slave]].sum(axis=1)
        n0 /= np.linalg.norm(n0, axis=1)[:, None]
        size = float(np.ptp(nodes[slave].reshape(-1, 3), axis=0).max())
        reach = facet_reach(nodes, slave, master)[:, None] * np.abs(n0) \
            + INSIDE_TOL * size
    else:
        reach = float(search)
    I, J = candidate_pairs(nodes, slave, master, reach)
    facing = np.einsum("ij,ij->i", n_s[I], n_m[J]) < -1e-8
    I, J = I[facing], J[facing]
    chunk = TRIANGLE_PAIR_CHUNK
    parts = [_overlaps(nodes, slave, master, I[i:i + chunk],
                       J[i:i + chunk], area_s, normal, pos,
                       np.inf if search is None else reach)
             for i in range(0, max(len(I), 1), chunk)]
    rows, cols, vals = (np.concatenate([p[k] for p in parts])
                        for k in range(3))
    return assemble_coupling(slave_nodes, len(nodes), D, rows, cols, vals,
                             nodes, normal, "mortar")


def _overlaps(nodes, slave, master, I, J, area_s, normal, pos, search):
    """Triplets of M from the facing triangle pairs (slave I, master J).
    Only the pairs whose projected bounding boxes meet are clipped (the
    others have no overlap of positive area), and the Gauss rule runs on
    the overlap's sub-triangles alone (``count`` of the up to 15 slots
    of :func:`overlap_polygons`; about 4 on average), summed per pair."""
    S, Mv = nodes[slave[I]], nodes[master[J]]            # (P, 3, 3)
    n0 = normal[pos[slave[I]]].sum(axis=1)
    n0 /= np.linalg.norm(n0, axis=1)[:, None]
    x0 = S.mean(axis=1)
    basis = tangent_basis(n0)                            # (P, 2, 3)
    s2 = np.einsum("pvk,pak->pva", S - x0[:, None], basis)
    m2 = np.einsum("pvk,pak->pva", Mv - x0[:, None], basis)
    distance = np.abs(np.einsum("pvk,pk->pv", Mv - x0[:, None], n0))
    low_s, high_s = s2.min(axis=1), s2.max(axis=1)       # (P, 2)
    low_m, high_m = m2.min(axis=1), m2.max(axis=1)
    slack = INSIDE_TOL * np.maximum((high_s - low_s).max(axis=1),
                                    (high_m - low_m).max(axis=1))
    meet = ((low_m <= high_s + slack[:, None])
            & (low_s <= high_m + slack[:, None])).all(axis=1) \
        & (distance.min(axis=1) <= search)
    I, J, s2, m2 = I[meet], J[meet], s2[meet], m2[meet]
    polygon, count = overlap_polygons(s2, m2)
    keep = count >= 3
    I, J, s2, m2, polygon, count = (v[keep] for v in
                                    (I, J, s2, m2, polygon, count))
    if not len(I):
        empty = np.zeros(0)
        return empty.astype(np.int64), empty.astype(np.int64), empty
    k = polygon.shape[1]
    i = np.arange(k)
    centre = (polygon * (i < count[:, None])[..., None]).sum(
        axis=1) / count[:, None]
    # the sub-triangles (centre, vertex i, vertex i + 1) that exist, pair
    # by pair (np.nonzero is row-major: a pair's are consecutive)
    pair, corner = np.nonzero(i[None] < count[:, None])
    following = np.where(corner + 1 < count[pair], corner + 1, 0)
    a = polygon[pair, corner] - centre[pair]             # (T, 2)
    b = polygon[pair, following] - centre[pair]
    sub = 0.5 * np.abs(_cross2(a, b))
    projected = 0.5 * np.abs(_cross2(s2[:, 1] - s2[:, 0],
                                     s2[:, 2] - s2[:, 0]))
    scale = area_s[I] / projected                        # affine: exact
    points, weights = GAUSS_TRIANGLE
    x = (centre[pair][:, None] + a[:, None] * points[None, :, :1]
         + b[:, None] * points[None, :, 1:])             # (T, 7, 2)
    W = sub[:, None] * weights * scale[pair][:, None]    # (T, 7)
    with np.errstate(divide="ignore", invalid="ignore"):
        psi = 4 * _barycentric(s2[pair], x) - 1          # (T, 7, 3)
        N = _barycentric(m2[pair], x)
    per_triangle = np.matmul((W[..., None] * psi).transpose(0, 2, 1),
                             N)                          # (T, 3, 3)
    vals = np.add.reduceat(per_triangle, np.searchsorted(
        pair, np.arange(len(I))), axis=0)                # (P, 3, 3)
    rows = np.repeat(pos[slave[I]][:, :, None], 3, axis=2)
    cols = np.repeat(master[J][:, None, :], 3, axis=1)
    return rows.ravel(), cols.ravel(), vals.ravel()


def node_to_triangle(nodes, slave, master, slave_nodes=None):
    """The node-to-segment coupling in 3D, in the same form: D_jj = ∫N_j
    (a third of the slave areas at j), M_jk = D_jj N^m_k(ξ_j) at the
    closest point ξ_j of x_j on the facing master triangles (the
    barycentric coordinates of its projection, clipped to the triangle);
    coverage 0 where that point lies outside every master triangle. Dense
    over node × triangle: the contact patch test's foil (it fails it on
    non-matching meshes; Taylor & Papadopoulos, IJNME 31 (1991) 1087), not
    for large interfaces."""
    nodes, slave, master, slave_nodes, pos, _, _, n_m, normal, D = \
        _interface(nodes, slave, master, slave_nodes)
    x = nodes[slave_nodes]                              # (ns, 3)
    a = nodes[master[:, 0]]
    e1 = nodes[master[:, 1]] - a
    e2 = nodes[master[:, 2]] - a
    rel = x[:, None] - a[None]                          # (ns, nm, 3)
    g11, g12, g22 = (e1 * e1).sum(1), (e1 * e2).sum(1), (e2 * e2).sum(1)
    r1 = np.einsum("snk,nk->sn", rel, e1)
    r2 = np.einsum("snk,nk->sn", rel, e2)
    det = g11 * g22 - g12 * g12
    s = (g22 * r1 - g12 * r2) / det
    t = (g11 * r2 - g12 * r1) / det
    bary = np.stack([1 - s - t, s, t], axis=-1)          # (ns, nm, 3)
    inside = (bary >= -INSIDE_TOL).all(axis=-1)
    clipped = np.clip(bary, 0, None)
    clipped /= clipped.sum(axis=-1, keepdims=True)
    foot = np.einsum("snv,nvk->snk", clipped, nodes[master])
    dist = np.linalg.norm(x[:, None] - foot, axis=-1)
    dist[normal @ n_m.T >= 0] = np.inf                   # facing only
    k = np.argmin(dist, axis=1)
    j = np.arange(len(slave_nodes))
    covered = inside[j, k] & np.isfinite(dist[j, k])
    N = clipped[j, k] * (D * covered)[:, None]
    rows = np.repeat(j, 3)
    cols = master[k].ravel()
    return assemble_coupling(slave_nodes, len(nodes), D, rows, cols,
                             N.ravel(), nodes, normal, "node-to-segment")
