"""Nodal normals of a triangulated contact surface
(solver/geometry/surfaces/normals.py, surface_jets.py).

References: the exact radial normal of the unit sphere (triangulated by a
refined, jittered icosahedron), the exact normal of a plane, and the
expected orders (Meek & Walton 2000 for facet averages: first order on
irregular meshes; Cazals & Pouget 2005: a cubic jet's normal is third
order).
"""

import numpy as np
import pytest
from scipy.spatial import Delaunay

from solver.errors import GeometryError, ProblemError
from solver.geometry.surfaces.normals import surface_normals

T = (1 + 5 ** 0.5) / 2
ICOSAHEDRON = np.array([[-1, T, 0], [1, T, 0], [-1, -T, 0], [1, -T, 0],
                        [0, -1, T], [0, 1, T], [0, -1, -T], [0, 1, -T],
                        [T, 0, -1], [T, 0, 1], [-T, 0, -1], [-T, 0, 1]])
ICOSAHEDRON_FACES = np.array([
    [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9],
    [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2],
    [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10],
    [8, 6, 7], [9, 8, 1]])


def icosphere(level, jitter=0.25, seed=0):
    """Unit sphere: the icosahedron refined ``level`` times (each triangle
    into four, midpoints projected), every node then moved by up to
    ``jitter`` × edge length at random and projected back (an irregular
    mesh); faces oriented outward."""
    v = ICOSAHEDRON / np.linalg.norm(ICOSAHEDRON, axis=1)[:, None]
    f = ICOSAHEDRON_FACES.copy()
    for _ in range(level):
        edges = np.sort(np.r_[f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]], 1)
        unique, index = np.unique(edges, axis=0, return_inverse=True)
        mid = v[unique[:, 0]] + v[unique[:, 1]]
        index = len(v) + index.ravel().reshape(3, -1)
        v = np.r_[v, mid / np.linalg.norm(mid, axis=1)[:, None]]
        a, b, c = f.T
        ab, bc, ca = index
        f = np.r_[np.c_[a, ab, ca], np.c_[b, bc, ab], np.c_[c, ca, bc],
                  np.c_[ab, bc, ca]]
    edge = np.sqrt(4 * np.pi / len(f) * 4 / np.sqrt(3))
    v = v + jitter * edge * np.random.default_rng(seed).uniform(-1, 1,
                                                                 v.shape)
    v /= np.linalg.norm(v, axis=1)[:, None]
    cross = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    inward = np.sum(cross * v[f].mean(axis=1), axis=1) < 0
    f[inward] = f[inward][:, ::-1]
    return v, f, edge


def _errors(level, weighting, cap=None):
    v, f, h = icosphere(level)
    if cap is not None:  # a spherical cap: a patch with a boundary
        f = f[v[f].mean(axis=1)[:, 2] > cap]
    nodes = np.unique(f)
    n = surface_normals(v, f, nodes, weighting)
    angle = np.arccos(np.clip(np.sum(n * v[nodes], axis=1), -1, 1))
    return h, angle.max()


@pytest.mark.parametrize("weighting, order", [("angle", 0.8), ("area", 0.8),
                                              ("smooth", 2.6)])
def test_sphere_normals_converge_with_expected_order(weighting, order):
    (h1, e1), (h2, e2) = (_errors(level, weighting) for level in (4, 5))
    assert np.log(e1 / e2) / np.log(h1 / h2) >= order
    assert e2 < 0.03


def test_smooth_normals_beat_facet_averages_and_converge_on_a_cap():
    # measured: angle 1.7e-2, smooth 3.6e-4 at level 4 (whole sphere)
    assert _errors(4, "smooth")[1] < _errors(4, "angle")[1] / 20
    # a cap with its boundary (one-sided 2-rings): still third order
    (h1, e1), (h2, e2) = (_errors(level, "smooth", cap=0.6)
                          for level in (4, 5))
    assert np.log(e1 / e2) / np.log(h1 / h2) >= 2.6
    assert _errors(5, "angle", cap=0.6)[1] > 10 * e2


@pytest.mark.parametrize("weighting", ["angle", "area", "smooth"])
def test_flat_plane_gives_the_exact_normal(weighting):
    # a jittered 17 x 17 grid, Delaunay-triangulated, on a tilted plane
    # through the origin (coordinates of size ~h: rounding of the input
    # itself stays below 1e-15 relative)
    rng = np.random.default_rng(1)
    g = np.linspace(-1, 1, 17)
    uv = np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
    uv += 0.25 * (g[1] - g[0]) * rng.uniform(-1, 1, uv.shape)
    faces = Delaunay(uv).simplices
    normal = np.array([1.0, -2.0, 2.0]) / 3
    e1 = np.array([2.0, 1.0, 0.0]) / np.sqrt(5)
    e2 = np.cross(normal, e1)
    nodes = uv[:, :1] * e1 + uv[:, 1:] * e2
    # orient every face like e1 × e2 = normal
    d1 = uv[faces[:, 1]] - uv[faces[:, 0]]
    d2 = uv[faces[:, 2]] - uv[faces[:, 0]]
    flip = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0] < 0
    faces[flip] = faces[flip][:, ::-1]
    result = surface_normals(nodes, faces, np.arange(len(uv)), weighting)
    np.testing.assert_allclose(result, np.tile(normal, (len(uv), 1)),
                               rtol=0, atol=1e-14)


@pytest.mark.parametrize("weighting", ["angle", "area", "smooth"])
def test_inward_faces_give_inward_normals(weighting):
    v, f, _ = icosphere(3)
    nodes = np.arange(len(v))
    outward = surface_normals(v, f, nodes, weighting)
    inward = surface_normals(v, f[:, ::-1], nodes, weighting)
    np.testing.assert_allclose(inward, -outward, rtol=0, atol=1e-14)
    assert (np.sum(outward * v, axis=1) > 0.99).all()


def test_only_the_requested_nodes_in_their_order():
    v, f, _ = icosphere(3)
    all_nodes = surface_normals(v, f, np.arange(len(v)), "smooth")
    some = np.array([40, 3, 17])
    np.testing.assert_array_equal(surface_normals(v, f, some, "smooth"),
                                  all_nodes[some])


def _bad(**change):
    v, f, _ = icosphere(1)
    args = dict(nodes=v, faces=f, contact_nodes=np.arange(len(v)),
                weighting="angle")
    args.update(change)
    return args


@pytest.mark.parametrize("change, error, fragment", [
    (dict(weighting="spline"), ProblemError, "normal weighting: unknown"),
    (dict(faces=np.array([[0, 1, 999]])), ProblemError,
     "contact_faces: node id out of range"),
    (dict(faces=np.array([[0.0, 1.0, 2.0]])), ProblemError,
     "contact_faces: need integer node ids"),
    (dict(contact_nodes=np.array([-1])), ProblemError,
     "contact_nodes: node id out of range"),
    (dict(nodes=np.zeros((5, 2))), ProblemError, "nodes: need finite (n, 3)"),
    (dict(faces=np.array([[0, 11, 5], [1, 2, 2]])), GeometryError,
     "1 triangles of zero area"),
    (dict(faces=np.array([[0, 11, 5], [0, 11, 1]])), GeometryError,
     "inconsistent orientation"),
    (dict(faces=np.array([[0, 11, 5]]), contact_nodes=np.array([0, 7])),
     GeometryError, "lie on no contact face"),
])
def test_bad_input_gives_one_line_errors(change, error, fragment):
    with pytest.raises(error) as info:
        surface_normals(**_bad(**change))
    assert fragment in str(info.value) and "\n" not in str(info.value)


def folded_sheet(n=9):
    """The top face z = 0 (y ≥ 0, outward +z) and the side face y = 0
    (z ≤ 0, outward −y) of a block, meeting at a right-angled edge along x:
    the grid (x, w) ∈ [0, 1] × [−1, 1] mapped to (x, w, 0) for w ≥ 0 and
    (x, 0, w) for w < 0, triangulated counterclockwise in (x, w)."""
    x = np.linspace(0, 1, n)
    w = np.linspace(-1, 1, 2 * n - 1)
    X, W = (a.ravel() for a in np.meshgrid(x, w, indexing="ij"))
    nodes = np.c_[X, np.maximum(W, 0), np.minimum(W, 0)]
    k = np.arange(len(X)).reshape(n, 2 * n - 1)
    a, b, c, d = k[:-1, :-1], k[1:, :-1], k[1:, 1:], k[:-1, 1:]
    faces = np.r_[np.c_[a.ravel(), b.ravel(), c.ravel()],
                  np.c_[a.ravel(), c.ravel(), d.ravel()]]
    return nodes, faces, W


@pytest.mark.parametrize("weighting", ["angle", "smooth"])
def test_edge_of_the_body_keeps_one_sided_normals(weighting):
    nodes, faces, w = folded_sheet()
    expected = np.where((w > 0)[:, None], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0])
    expected[w == 0] = [0.0, -np.sqrt(0.5), np.sqrt(0.5)]  # the bisector
    normals = surface_normals(nodes, faces, np.arange(len(nodes)), weighting)
    np.testing.assert_allclose(normals, expected, rtol=0, atol=1e-14)
