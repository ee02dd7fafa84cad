"""The mortar pair search's sweep by width classes
(solver.geometry.mortar.search.box_pairs) finds the pairs of a
brute-force comparison of graded boxes: a few coarse boxes (a graded
mesh's rim facets) among many fine ones, and degenerate (point) boxes.
Reference: the brute force compares every slave box with every master
box."""

import numpy as np

from solver.geometry.mortar import box_pairs


def test_box_pairs_graded_against_brute_force():
    rng = np.random.default_rng(3)
    centre_s, centre_m = rng.random((800, 3)), rng.random((700, 3))
    # widths from 1e-3 to 0.3: a graded mesh's fine facets, few coarse ones
    size_s = 10 ** rng.uniform(-3, -1.5, (800, 1))
    size_m = 10 ** rng.uniform(-3, -0.5, (700, 1))
    size_m[:5] = 0.0                                   # points count too
    lo_s, hi_s = centre_s - size_s, centre_s + size_s
    lo_m, hi_m = centre_m - size_m, centre_m + size_m
    I, J = box_pairs(lo_s, hi_s, lo_m, hi_m)
    hit = ((lo_s[:, None] <= hi_m[None]) & (lo_m[None] <= hi_s[:, None])
           ).all(axis=2)
    assert len(I) > 100
    assert set(zip(I.tolist(), J.tolist())) == set(zip(*np.nonzero(hit)))
    assert len(set(zip(I.tolist(), J.tolist()))) == len(I)
    assert np.all(np.diff(I) >= 0)
