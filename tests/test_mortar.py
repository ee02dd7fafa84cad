"""The dual mortar matrices of solver.geometry.mortar against closed forms:
D = ∫N_j (tributary length), partition of unity Σ_k M_jk = D_jj where the
master covers the support, exactness for linear fields (M x = D x on a
flat interface), the 2-segment integrals by hand, refinement and the
node-to-segment variant."""

import numpy as np
import pytest

from solver.geometry.mortar import (chain_order, mortar_coupling,
                                    nodal_normals, node_to_segment)


def flat(slave_x, master_x, y_master=0.0):
    """Slave chain on y = 0 (body above: a → b in +x), master chain on
    y = y_master (body below: a → b in −x)."""
    xs, xm = np.asarray(slave_x, float), np.asarray(master_x, float)
    nodes = np.r_[np.c_[xs, 0 * xs], np.c_[xm, y_master + 0 * xm]]
    s = np.arange(len(xs))
    m = np.arange(len(xs), len(xs) + len(xm))[::-1]
    return nodes, np.c_[s[:-1], s[1:]], np.c_[m[:-1], m[1:]]


def test_two_segments_by_hand():
    """One slave segment [0, 1] against a master [0, 1] split at x = ½.
    ψ_a = 2 − 3x; master hats N₀ = 1 − 2x on [0, ½], N_½ = 2x | 2 − 2x,
    N₁ = 2x − 1 on [½, 1]. By hand: ∫₀^½ (2 − 3x)(1 − 2x) = 3/8,
    ∫₀^½ (2 − 3x)2x + ∫_½^1 (2 − 3x)(2 − 2x) = 1/4 + 0,
    ∫_½^1 (2 − 3x)(2x − 1) = −1/8; node b by symmetry."""
    nodes, slave, master = flat([0, 1], [0, 0.5, 1])
    c = mortar_coupling(nodes, slave, master)
    assert np.allclose(c.D, [0.5, 0.5], rtol=1e-15)
    M = c.M.toarray()[:, 2:]                           # x = 0, ½, 1
    assert np.allclose(M, [[3 / 8, 1 / 4, -1 / 8], [-1 / 8, 1 / 4, 3 / 8]],
                       rtol=0, atol=1e-15)
    assert np.allclose(c.coverage, 1, rtol=0, atol=1e-14)
    assert np.allclose(c.normal, [[0, -1], [0, -1]])


@pytest.mark.parametrize("ns, nm", [(4, 7), (7, 4), (5, 5), (13, 3)])
def test_partition_of_unity_and_linear_exactness(ns, nm):
    """Non-matching flat meshes (graded master): Σ_k M_jk = D_jj and
    M x = D x for x and y (any linear field), to round-off."""
    rng = np.random.default_rng(ns * nm)
    xm = np.r_[0, np.sort(rng.uniform(0, 2, nm - 2)), 2]
    nodes, slave, master = flat(np.linspace(0, 2, ns), xm, 0.0)
    c = mortar_coupling(nodes, slave, master)
    assert np.abs(c.coverage - 1).max() < 1e-13
    field = 0.3 + 1.7 * nodes[:, 0] - 0.4 * nodes[:, 1]
    assert np.abs(c.M @ field - c.D * field[c.slave_nodes]).max() < 1e-13
    assert np.abs(c.gap).max() < 1e-14
    assert np.isclose(c.D.sum(), 2.0)


def test_gap_of_a_lifted_master():
    """A master 0.1 below the slave: g̃_j = 0.1·D_jj (gap along n = −e_y)."""
    nodes, slave, master = flat(np.linspace(0, 1, 5), np.linspace(0, 1, 3),
                                -0.1)
    c = mortar_coupling(nodes, slave, master)
    assert np.allclose(c.gap, 0.1 * c.D, rtol=1e-13)


def test_partial_cover_and_no_cover():
    """A master on [0, 1] under a slave on [0, 2]: x = 0, ½ covered, x = 1
    half (∫ψ over [½, 1] = ¼ of D = ½), x = 1.5 and 2 not at all."""
    nodes, slave, master = flat([0, 0.5, 1, 1.5, 2], [0, 0.5, 1])
    c = mortar_coupling(nodes, slave, master)
    assert np.allclose(c.coverage, [1, 1, 0.5, 0, 0], rtol=0, atol=1e-14)


def test_refinement_converges_on_a_circle():
    """Slave: arc of the unit circle (body inside), master: arc of radius
    1.05 outside it (body outside). The weighted gaps / D tend to 0.05."""
    errors = []
    for n in (20, 40, 80):
        t = np.linspace(-0.6, 0.6, n + 1)
        inner = np.c_[np.sin(t), -np.cos(t)]          # bottom of a disc
        outer = 1.05 * np.c_[np.sin(t[::2]), -np.cos(t[::2])]
        nodes = np.r_[inner, outer]
        s = np.arange(n + 1)                          # disc on the left
        m = np.arange(n + 1, len(nodes))[::-1]        # outer body: left
        c = mortar_coupling(nodes, np.c_[s[:-1], s[1:]], np.c_[m[:-1], m[1:]])
        inside = np.abs(c.coverage - 1) < 1e-8
        assert inside.sum() > 0.8 * (n + 1)
        errors.append(np.abs(c.gap[inside] / c.D[inside] - 0.05).max())
    assert errors[2] < errors[0] / 3 and errors[2] < 1e-3


def test_nodal_normals_of_a_circle():
    t = np.linspace(0, 2 * np.pi, 33)[:-1]
    nodes = np.c_[np.cos(t), np.sin(t)]               # ccw: body left
    ids = np.arange(32)
    normal = nodal_normals(nodes, np.c_[ids, np.roll(ids, -1)], ids)
    assert np.allclose(normal, nodes, atol=1e-14)


def test_chain_order():
    segments = np.array([[5, 2], [7, 5], [2, 9]])
    assert chain_order(segments).tolist() == [7, 5, 2, 9]


def test_node_to_segment_flat():
    """Node-to-segment on a flat interface: M_jk/D_jj are the master shape
    functions at the closest point; rows sum to D (covered)."""
    nodes, slave, master = flat([0, 0.25, 1], [0, 0.5, 1], -0.2)
    c = node_to_segment(nodes, slave, master)
    P = c.M.toarray()[:, 3:] / c.D[:, None]            # x = 0, ½, 1
    assert np.allclose(P, [[1, 0, 0], [0.5, 0.5, 0], [0, 0, 1]], atol=1e-15)
    assert np.allclose(c.gap, 0.2 * c.D)
    assert np.allclose(c.coverage, 1)


def test_candidate_pairs_are_the_overlapping_boxes():
    """The sort-and-sweep screening finds exactly the segment pairs whose
    bounding boxes (the slave's enlarged by the reach) overlap, checked
    against the brute-force ns × nm comparison on random segments."""
    from solver.geometry.mortar import candidate_pairs

    rng = np.random.default_rng(19)
    nodes = rng.uniform(0, 10, (400, 2))
    slave = rng.integers(0, 200, (150, 2))
    master = rng.integers(200, 400, (170, 2))
    reach = 0.3
    I, J = candidate_pairs(nodes, slave, master, reach)
    lo_s = np.minimum(nodes[slave[:, 0]], nodes[slave[:, 1]])[:, None] - reach
    hi_s = np.maximum(nodes[slave[:, 0]], nodes[slave[:, 1]])[:, None] + reach
    lo_m = np.minimum(nodes[master[:, 0]], nodes[master[:, 1]])[None]
    hi_m = np.maximum(nodes[master[:, 0]], nodes[master[:, 1]])[None]
    brute = ((lo_s <= hi_m) & (lo_m <= hi_s)).all(axis=2)
    assert 0 < brute.sum() < brute.size
    assert sorted(zip(I.tolist(), J.tolist())) == \
        sorted(zip(*np.nonzero(brute)))


def test_large_interface_screens_few_pairs():
    """20 000 slave against 30 001 master segments on a wavy interface
    (the master 0.001 below, an element length): partition of unity and
    the gap of a lifted master hold, and the screening keeps O(ns + nm)
    candidate pairs (about (slave length + 2 reach) / master length per
    slave segment, reach ≈ 2 gap + 2 lengths: 12), not ns·nm = 6·10⁸."""
    from solver.geometry.mortar import candidate_pairs, default_reach

    xs, xm = np.linspace(0, 20, 20_001), np.linspace(0, 20, 30_002)
    nodes, slave, master = flat(xs, xm, 0.0)
    nodes[:, 1] += 0.05 * np.sin(nodes[:, 0])
    nodes[len(xs):, 1] -= 0.001
    I, _ = candidate_pairs(nodes, slave, master,
                           default_reach(nodes, slave, master))
    assert len(I) < 20 * len(slave)
    c = mortar_coupling(nodes, slave, master)
    inner = slice(2, -2)  # the wavy ends project partly off the master
    assert np.abs(c.coverage[inner] - 1).max() < 1e-12
    slope = 0.05 * np.cos(nodes[c.slave_nodes[inner], 0])
    assert np.allclose(c.gap[inner] / c.D[inner],            # along n_j
                       0.001 / np.sqrt(1 + slope ** 2), rtol=1e-5)
