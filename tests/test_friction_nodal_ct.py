"""c_t per contact node from the condensed stiffness (issue 33 point 2:
≤ 5 Jacobians per load step), :data:`solver.contact.friction.disc.
NODAL_CT`.

The projection's parameter of a condensed 3D friction step is, per node,
the mean over its free tangents of √(T_jj/C_jj)/D_j (T = R S Rᵀ, C = T⁻¹,
D the lumped Γc area): the geometric mean of the node's two stiffness
bounds, δ/C_jj (the rest of Γc free) and T_jj δ (the rest held).

Independent references: the definition on hand-made diagonals; C by
NumPy's inverse of T rebuilt from the system's S and R (not the system's
potri); the run with the scalar c_t = k̄/D̄ (``NODAL_CT = False``, the
path before), whose answer the parameter must not change (the solution of
g = P(g − c_t ZRΔu) does not depend on c_t > 0: same u, same stick, slip
and contact sets in every step).
"""

import numpy as np

# the a/h = 4 quarter Hertz sphere (a module fixture)
from test_friction_start import sphere_4  # noqa: F401
from test_friction_extrapolated import same_answer
from solver import solve_friction
from solver.contact.friction import disc


def test_parameter_by_hand():
    """Two tangents per node: the mean of √(T/C)/D over the free ones; a
    roller (one free tangent) takes that one's; a node with none the
    default."""
    T = np.array([4.0, 9.0, 16.0, 1.0, 1.0, 1.0])
    C = np.array([1.0, 1.0, 4.0, 100.0, 1.0, 1.0])
    D = np.array([1.0, 3.0, 2.0, 2.0, 1.0, 1.0])
    free = np.array([True, True, True, False, False, False])
    c = disc.nodal_parameter(T, C, D, free, 2, 7.0)
    # node 0: (2/1 + 3/3)/2; node 1: √(16/4)/2 only; node 2: the default
    assert np.allclose(c, [1.5, 1.5, 1.0, 1.0, 7.0, 7.0], rtol=1e-15)


def test_between_the_bounds(sphere_4, monkeypatch):
    """On the quarter sphere's condensed system: c_t is the definition
    with C = inv(T) by NumPy, one value per node, and lies between the
    node's bounds 1/(C_jj D_j) and T_jj/D_j."""
    systems = []
    original = disc.DiscSystem._nodal_ct

    def recorded(self):
        systems.append(self)
        return original(self)

    monkeypatch.setattr(disc.DiscSystem, "_nodal_ct", recorded)
    assert solve_friction(sphere_4, 0.3, steps=2).success
    (s,) = systems
    T = (s.R @ s.K @ s.R.T).toarray()
    C = np.linalg.inv(T)
    rows, k = s.t_rows[s.t_free], s.dim - 1
    D = s.lumped_t[s.t_free]
    c = np.broadcast_to(s.c_t, (s.mt,))
    assert np.ptp(c.reshape(-1, k), axis=1).max() == 0.0  # per node
    value = np.sqrt(np.diagonal(T)[rows] / np.diagonal(C)[rows]) / D
    expected = disc.nodal_parameter(
        np.diagonal(T)[np.where(s.t_free, s.t_rows, 0)],
        np.diagonal(C)[np.where(s.t_free, s.t_rows, 0)], s.lumped_t,
        s.t_free, k, s.stiffness / s.lumped.mean())  # none free: k̄/D̄
    assert np.allclose(c, expected, rtol=1e-9)
    low = 1.0 / (np.diagonal(C)[rows] * D)
    high = np.diagonal(T)[rows] / D
    assert (low < value).all() and (value < high).all()
    node = np.flatnonzero(s.t_free) // k  # the node of each free tangent
    lo, hi = np.full(s.m, np.inf), np.zeros(s.m)
    np.minimum.at(lo, node, low)
    np.maximum.at(hi, node, high)
    per_node, held = c.reshape(-1, k)[:, 0], np.isfinite(lo)
    assert held.any()
    assert (lo[held] <= per_node[held]).all()
    assert (per_node[held] <= hi[held]).all()


def test_same_answer_no_more_jacobians(sphere_4, monkeypatch):
    """The quarter sphere, f_c = 0.3 in 10 steps: the same u (to 1e-8,
    relative) and the same stick, slip and contact sets in every step as
    the run with the scalar c_t, verified on every node, and no more
    Jacobians (measured: 27 against 30, at most 4 in a step)."""
    ours, before = same_answer(sphere_4, monkeypatch, disc, "NODAL_CT")
    assert ours.njev <= before.njev
    assert max(r["njev"] for r in ours.records) <= 4
