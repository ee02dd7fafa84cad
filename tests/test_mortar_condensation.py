"""The candidates' condensation of a two-body problem from a factorisation
of K itself (solver.contact.strategies.mortar_condensation) gives the
numbers of the condensation of K̃ = T⁻ᵀKT⁻¹ (candidates.NormalCondensation)
to rounding, on every backend: S, g̃ and the displacement back in v; and
the pair search's sweep by width classes finds the pairs of a brute-force
comparison of graded boxes (a few coarse boxes among many fine ones).

References: the K̃ route is the formula of the nodewise problem itself
(the docstring of solver.contact.two_body); the brute force compares every
slave box with every master box."""

import numpy as np
import pytest

from solver.contact import TwoBodyMap
from solver.contact.geometry import contact_geometry
from solver.contact.strategies.candidates import NormalCondensation
from solver.contact.strategies.mortar_condensation import \
    MortarCondensation
from solver.geometry.mortar import box_pairs
from tet_two_body import stacked_boxes


@pytest.mark.parametrize("backend", ["superlu", "pardiso", "cholmod"])
@pytest.mark.parametrize("slave", ["upper", "lower"])
def test_same_condensation_as_the_transformed_stiffness(backend, slave):
    problem, _, _ = stacked_boxes(n_upper=(4, 4, 2), n_lower=(5, 5, 2),
                                  slave=slave)
    equivalent = TwoBodyMap(problem).equivalent
    geometry = contact_geometry(equivalent, "obstacle")
    nodes = np.arange(0, len(geometry.index), 2)      # some candidates
    reference = NormalCondensation(equivalent, geometry, backend)
    ours = MortarCondensation(equivalent, geometry, backend,
                              *equivalent.mortar_interface)
    S_ref, g_ref, w_ref = reference.factorize(nodes)
    S, g, w = ours.factorize(nodes)
    assert np.abs(S - S_ref).max() <= 1e-11 * np.abs(S_ref).max()
    assert np.abs(g - g_ref).max() <= 1e-11 * np.abs(g_ref).max()
    assert np.abs(w - w_ref).max() <= 1e-11 * np.abs(w_ref).max()
    u_n = w_ref - 0.3 * np.abs(w_ref).max()
    v_ref, n_ref = reference.displacement(u_n)
    v, n = ours.displacement(u_n)
    assert np.abs(v - v_ref).max() <= 1e-11 * np.abs(v_ref).max()
    assert np.abs(n - n_ref).max() <= 1e-11 * np.abs(n_ref).max()
    assert np.allclose(n[nodes], u_n, rtol=0, atol=1e-12 * np.abs(u_n).max())


def test_no_candidates():
    problem, _, _ = stacked_boxes()
    equivalent = TwoBodyMap(problem).equivalent
    geometry = contact_geometry(equivalent, "obstacle")
    reference = NormalCondensation(equivalent, geometry, "superlu")
    ours = MortarCondensation(equivalent, geometry, "superlu",
                              *equivalent.mortar_interface)
    reference.factorize([]), ours.factorize([])
    v_ref, _ = reference.displacement(np.zeros(0))
    v, _ = ours.displacement(np.zeros(0))
    assert np.abs(v - v_ref).max() <= 1e-12 * np.abs(v_ref).max()


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
