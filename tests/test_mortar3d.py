"""The 3D dual mortar of solver.geometry.mortar.triangles against closed
forms: biorthogonality (a matching master gives M = diag(D)), D = ∫N_j (a
third of the slave triangles' areas at j), the partition of unity
Σ_k M_jk = D_jj on a fully covered slave, exactness for linear fields on
flat non-matching meshes (M x = D x: the discrete form of the contact
patch test), the weighted gap of a lifted master, the overlap polygons of
two triangles (areas by hand), the bounding-box pair search against
brute force on 10⁴ × 10⁴ triangles, and the patch-recovered pressure on a
square of two triangles (by hand) and on a jittered mesh (a uniform λ
recovered exactly)."""

import numpy as np
import pytest
from scipy.spatial import Delaunay

from solver.geometry.mortar import (box_pairs, overlap_polygons,
                                    patch_pressure, triangle_coupling)


def square_mesh(n, rng, z=0.0, up=True, jitter=0.3, size=1.0):
    """Delaunay triangles of [0, size]² at height z with jittered interior
    nodes (the boundary nodes stay on the square's edges); outward normal
    +z (``up``) or −z."""
    x = np.linspace(0, size, n + 1)
    X, Y = np.meshgrid(x, x, indexing="ij")
    P = np.c_[X.ravel(), Y.ravel()]
    h = size / n
    inner = (P > 1e-9 * size).all(1) & (P < size * (1 - 1e-9)).all(1)
    P[inner] += rng.uniform(-jitter * h, jitter * h, (inner.sum(), 2))
    tri = Delaunay(P).simplices
    e1, e2 = P[tri[:, 1]] - P[tri[:, 0]], P[tri[:, 2]] - P[tri[:, 0]]
    ccw = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] > 0
    tri[~ccw] = tri[~ccw][:, [0, 2, 1]]
    if not up:
        tri = tri[:, [0, 2, 1]]
    return np.c_[P, np.full(len(P), z)], tri


def interface(n_slave, n_master, gap=0.0, seed=0):
    """A slave square (body above, normal −z) on a master square (body
    below) ``gap`` lower, meshed independently."""
    rng = np.random.default_rng(seed)
    ns, ts = square_mesh(n_slave, rng, up=False)
    nm, tm = square_mesh(n_master, rng, z=-gap, up=True)
    return np.r_[ns, nm], ts, tm + len(ns)


def test_matching_master_gives_a_diagonal_M():
    """Biorthogonality, ∫ψ_a N_b = δ_ab ∫N_a (Wohlmuth 2000): a master
    triangle equal to the slave one gives M = diag(D), D = area/3."""
    tri = np.array([[0.0, 0, 0], [2, 0, 0], [0.5, 1.5, 0]])
    nodes = np.r_[tri, tri]
    c = triangle_coupling(nodes, np.array([[0, 2, 1]]),
                          np.array([[3, 4, 5]]))
    assert np.allclose(c.D, 0.5, rtol=1e-15)           # area 1.5, / 3
    assert np.allclose(c.M.toarray()[:, 3:], np.diag(c.D), atol=1e-15)
    assert np.allclose(c.normal, [0, 0, -1])


@pytest.mark.parametrize("n_slave, n_master", [(7, 4), (4, 7), (6, 6)])
def test_partition_of_unity_and_linear_exactness(n_slave, n_master):
    """Non-matching flat meshes covering the same square: D sums to the
    area, Σ_k M_jk = D_jj at every slave node (coverage 1) and
    M x = D x for x, y and z (the patch test's linear fields)."""
    nodes, slave, master = interface(n_slave, n_master,
                                     seed=n_slave * n_master)
    c = triangle_coupling(nodes, slave, master)
    assert np.isclose(c.D.sum(), 1.0, rtol=1e-14)
    assert np.abs(c.coverage - 1).max() < 1e-13
    for field in nodes.T:
        assert np.abs(c.M @ field - c.D * field[c.slave_nodes]).max() \
            < 1e-15
    assert np.abs(c.gap).max() < 1e-16


def test_slave_nodal_areas():
    """D_jj = ∫N_j = a third of the areas of the triangles at j: on a
    regular grid of h = 1/4 (each square cut into 2) a corner node with one
    triangle has h²/6, an inner node with six has h²."""
    rng = np.random.default_rng(0)
    nodes, tri = square_mesh(4, rng, jitter=0.0, up=False)
    nodes2 = np.r_[nodes, nodes - [0, 0, 0.1]]
    c = triangle_coupling(nodes2, tri, tri[:, [0, 2, 1]] + len(nodes))
    counts = np.bincount(tri.ravel(), minlength=len(nodes))[c.slave_nodes]
    assert np.allclose(c.D, counts * (1 / 16) / 6, rtol=1e-13)
    assert np.allclose(c.gap, 0.1 * c.D, rtol=1e-12)   # lifted master


def test_partly_covered_slave():
    """A master covering x ≤ 1/2 of the slave only: the slave nodes whose
    support it covers keep coverage 1, those beyond it lose it."""
    rng = np.random.default_rng(3)
    ns, ts = square_mesh(6, rng, up=False, jitter=0.0)
    nm, tm = square_mesh(5, rng, up=True, size=0.5)
    c = triangle_coupling(np.r_[ns, nm], ts, tm + len(ns))
    x, y = ns[c.slave_nodes, 0], ns[c.slave_nodes, 1]
    inside = (x < 0.5 - 1 / 6 - 1e-9) & (y < 0.5 - 1 / 6 - 1e-9)
    assert np.abs(c.coverage[inside] - 1).max() < 1e-13
    assert (c.coverage[x > 0.5 + 1e-9] < 1e-12).all()


def test_overlap_of_two_triangles_by_hand():
    """The overlap polygon of the triangle (0,0), (1,0), (0,1) and its
    mirror (1,1), (0,1), (1,0) is the segment x + y = 1 (area 0); of the
    first and the square's lower half shifted by ½ in x it is the
    triangle (½,0), (1,0), (½,½): area 1/8 (the fan's sub-triangles)."""
    a = np.array([[[0.0, 0], [1, 0], [0, 1]]])
    b = np.array([[[0.5, 0], [1.5, 0], [0.5, 1]]])
    poly, count = overlap_polygons(a, b)
    p = poly[0, :count[0]]
    area = 0.5 * abs(np.sum(p[:, 0] * np.roll(p[:, 1], -1)
                            - np.roll(p[:, 0], -1) * p[:, 1]))
    assert np.isclose(area, 1 / 8, rtol=1e-14)
    unique = np.unique(np.round(p, 12), axis=0)
    assert np.allclose(unique, [[0.5, 0], [0.5, 0.5], [1, 0]])
    mirror = np.array([[[1.0, 1], [0, 1], [1, 0]]])
    poly, count = overlap_polygons(a, mirror)
    p = poly[0, :count[0]]
    assert np.allclose(p.sum(axis=1), 1.0)             # on x + y = 1


def test_pair_search_against_brute_force():
    """10⁴ × 10⁴ random triangles in a unit cube slab: the sort-and-sweep
    pairs are exactly the brute-force overlapping boxes (checked in
    blocks of slave rows)."""
    rng = np.random.default_rng(32)
    n = 10_000

    def boxes():
        corner = rng.uniform(0, 1, (n, 1, 3)) * [1, 1, 0.05]
        p = corner + rng.uniform(0, 0.02, (n, 3, 3))
        return p.min(axis=1), p.max(axis=1)
    lo_s, hi_s = boxes()
    lo_m, hi_m = boxes()
    I, J = box_pairs(lo_s, hi_s, lo_m, hi_m)
    found = set(zip(I.tolist(), J.tolist()))
    assert len(found) == len(I)                        # no pair twice
    brute = set()
    for k in range(0, n, 1000):
        hit = ((lo_s[k:k + 1000, None] <= hi_m[None])
               & (lo_m[None] <= hi_s[k:k + 1000, None])).all(axis=2)
        i, j = np.nonzero(hit)
        brute.update(zip((i + k).tolist(), j.tolist()))
    assert 0 < len(brute) < n * n / 100
    assert found == brute


def test_patch_pressure_by_hand():
    """The unit square as triangles (0, 1, 2), (0, 2, 3): D = ∫N_j = (1/3,
    1/6, 1/3, 1/6); with λ = (1, 2, 3, 4) the forces D λ are (1/3, 1/3, 1,
    2/3), and p̄_j is the star's force over its area: node 1 (star 0, 1,
    2) (5/3)/(5/6) = 2, node 3 (star 0, 2, 3) 2/(5/6) = 2.4, nodes 0 and 2
    (every node) 7/3. Without node 3 (it takes no part): nodes 0 and 2 get
    (5/3)/(5/6) = 2, node 3 gets 0. Per step (a friction run) row by
    row."""
    facets = np.array([[10, 11, 12], [10, 12, 13]])
    ids = np.array([10, 11, 12, 13])
    D = np.array([1 / 3, 1 / 6, 1 / 3, 1 / 6])
    lam = np.array([1.0, 2.0, 3.0, 4.0])
    assert np.allclose(patch_pressure(facets, ids, D, lam),
                       [7 / 3, 2, 7 / 3, 2.4], rtol=1e-14)
    part = np.array([True, True, True, False])
    assert np.allclose(patch_pressure(facets, ids, D, lam, part),
                       [2, 2, 2, 0], rtol=1e-14)
    steps = patch_pressure(facets, ids, D, np.array([lam, 2 * lam]))
    assert steps.shape == (2, 4)
    assert np.allclose(steps[1], 2 * steps[0], rtol=1e-14)


def test_patch_pressure_uniform_on_a_jittered_mesh():
    """A uniform λ = p is recovered as p at every node that takes part (the
    patch test), whatever the stars; 0 at the others."""
    rng = np.random.default_rng(3)
    nodes, tri = square_mesh(7, rng)
    ids = np.unique(tri)
    a = nodes[tri]
    area = 0.5 * np.linalg.norm(np.cross(a[:, 1] - a[:, 0],
                                         a[:, 2] - a[:, 0]), axis=1)
    D = np.bincount(tri.ravel(), np.repeat(area / 3, 3))[ids]
    part = rng.random(len(ids)) < 0.8
    p = patch_pressure(tri, ids, D, np.where(part, 2.5, 0.0), part)
    assert np.abs(p[part] - 2.5).max() <= 1e-14 * 2.5
    assert not p[~part].any()
