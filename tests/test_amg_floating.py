"""Bodies held by contact only on the iterative path (``backend='amg'``,
issue 33 point 1): K singular (its kernel the rigid-body modes), the
active set method started from the rigid placement, each Newton system by
CG on the eliminated K̂_FF, the modes no active normal sees projected out,
the hierarchy's coarsest level by a pseudo-inverse
(solver/contact/strategies/floating.py RigidPlacement,
solver/contact/frictionless/active_set.py).

Independent reference: the factorisation path (condensed with K⁺ and the
modes' amplitudes, a dense Newton system solved by LAPACK; another
algorithm and another linear solver) on the same problems: the floating
block of P1 triangles and tetrahedra on a floor, the Hertz half-cylinder
and the quarter sphere (a/h 4) exported by SfePy under a force, the upper
of two Hertz cylinders and of two stacked boxes (dual mortar); statics
(the contact forces balance the load); Farkas' lemma for the unbalanced
load (the same one line as the factorisation path)."""

import numpy as np
import pytest

import solver
from solver.errors import ProblemError
from solver.linalg import amg
from test_floating import P as P_CYLINDER
from test_floating import hertz_force  # noqa: F401 (a fixture)
from test_floating_friction import _block3
from test_floating_full import sphere_under_a_force
from tet_two_body import stacked_boxes
from tri_elasticity import floor_block, two_cylinders

pytestmark = pytest.mark.skipif(not amg.available(),
                                reason="pyamg not installed (.[amg])")

R2, MATERIALS, P2 = (1.0, 1.5), ((1.0, 0.3), (2.0, 0.25)), 0.0065


def _both(problem):
    """(factorisation, AMG) answers, both converged and verified on every
    node (finite, feasible, complementary)."""
    direct = solver.solve(problem, tol=1e-10)
    iterative = solver.solve(problem, backend="amg", tol=1e-10)
    for r in (direct, iterative):
        assert r.success and r.verification["passed"], r.message
    assert iterative.linear_solver == "amg"
    assert iterative.engine["levels"] >= 2
    return direct, iterative


def _same(direct, iterative, rtol=1e-8):
    """The same u to ``rtol`` of max |u| and the same contact set."""
    scale = np.abs(direct.u).max()
    assert np.abs(iterative.u - direct.u).max() <= rtol * scale, \
        np.abs(iterative.u - direct.u).max() / scale
    np.testing.assert_array_equal(iterative.in_contact, direct.in_contact)


@pytest.mark.parametrize("make, weight", [
    (lambda: floor_block(n=(40, 20)), (0.0, 2.0)),
    (lambda: floor_block(n=(40, 20), floor=-0.01), (0.0, 2.0)),
    (lambda: _block3((0.0, 0.0, -1.0), n=(10, 10, 4)), (0.0, 0.0, 1.0)),
], ids=["2d block on the floor", "2d block dropped onto it",
        "3d block on the plane"])
def test_block_on_the_floor(make, weight):
    """The floating block under its weight (2D: 40 × 20 cells, three
    modes, the horizontal slide seen by no normal; 3D: 10 × 10 × 4, six),
    on hierarchies of two levels or more: the factorisation's u to
    1e-8 (measured 3.3e-12 / 1.1e-12 / 5.1e-12, two Newton systems
    of 5–10 CG iterations), the contact force = weight to 1e-10, no
    slide along the free horizontal mode (projected out, as the
    factorisation path removes it)."""
    direct, iterative = _both(make())
    _same(direct, iterative)
    np.testing.assert_allclose(iterative.total_contact_force, weight,
                               rtol=0, atol=1e-10)
    assert abs(iterative.rigid_body["translation"][0]) <= 1e-12
    assert iterative.rigid_body["start_nodes"] >= 1


def test_hertz_cylinder_under_a_force(hertz_force):  # noqa: F811
    """The Hertz half-cylinder under P (SfePy export, 7,147 DOFs, two
    modes): the factorisation's u to 1e-8 (measured 1.8e-12) and contact
    set, the contact forces balance P to 1e-10; 17 Newton systems from the
    rigid placement (the full system's factorisation path takes 15)."""
    direct, iterative = _both(hertz_force)
    _same(direct, iterative)
    total = iterative.total_contact_force
    assert abs(total[1] - P_CYLINDER) <= 1e-10 * P_CYLINDER
    assert iterative.njev <= 25


def test_3d_hertz_sphere_under_a_force(tmp_path):
    """The quarter sphere (a/h 4, committed mesh) under P (the vertical
    translation held by contact only): the factorisation's u to 1e-8
    (measured 3.7e-12) and contact set, the force P/4 balanced."""
    direct, iterative = _both(sphere_under_a_force(tmp_path))
    _same(direct, iterative)
    assert abs(4 * iterative.total_contact_force[2] - 36.63) <= 1e-10 * 36.63


@pytest.mark.parametrize("slave", ["upper", "lower"])
def test_3d_boxes_upper_floating(slave):
    """Two stacked boxes (dual mortar), the upper one held by contact only
    (six modes) under the pressure p: the factorisation's u to 1e-8
    (measured 1.1e-11 / 1.3e-11), the interface pressure p everywhere
    (the exact σ_zz = −p) to 1e-10."""
    p = 0.01
    problem, _, _ = stacked_boxes(pressure=p, slave=slave, squeeze=0.0)
    direct, iterative = _both(problem)
    _same(direct, iterative)
    np.testing.assert_allclose(
        iterative.contact_pressure[iterative.covered], p, rtol=1e-10)


@pytest.mark.filterwarnings(
    "ignore:slave node .* relative to the master:"
    "solver.errors.KinematicsWarning",
    "ignore:the rigid-body motion .* is held by the contact only weakly:"
    "solver.errors.WeaklyHeldWarning")
@pytest.mark.parametrize("roller", [False, True], ids=["3 modes", "4 modes"])
def test_two_cylinders_upper_floating(roller):
    """The upper Hertz cylinder held by contact only (three modes; with the
    lower one on a roller, four). Its spin about its centre is held only
    by the polygon's facets (WeaklyHeldWarning: set by the discretisation,
    0.018 rad here, and by the tolerance), so u is compared without each
    answer's best-fitting rigid motion: the deformation equals the
    factorisation's to 1e-8 (measured 1.1e-10 / 5e-11), the contact set
    is the same, the pressure to 1e-6 of p₀ (measured 3.9e-8 / 1.8e-8)
    and the contact force balances P to 1e-10."""
    problem, _, _ = two_cylinders(R2, MATERIALS, force=P2, roller=roller)
    direct, iterative = _both(problem)
    R, _ = problem.rigid_modes()
    strain = [r.u - R @ (R.T @ r.u) for r in (direct, iterative)]
    scale = np.abs(direct.u).max()
    assert np.abs(strain[1] - strain[0]).max() <= 1e-8 * scale
    np.testing.assert_array_equal(iterative.in_contact, direct.in_contact)
    p0 = direct.contact_pressure.max()
    assert np.abs(iterative.contact_pressure
                  - direct.contact_pressure).max() <= 1e-6 * p0
    assert abs(iterative.total_contact_force[1] - P2) <= 1e-10 * P2


@pytest.mark.parametrize("make", [
    lambda: floor_block(load=(0.5, -1.0)),
    lambda: two_cylinders(R2, MATERIALS, force=-P2)[0],
], ids=["block pushed sideways", "upper cylinder pulled away"])
def test_unbalanced_load_same_line_as_the_factorisation(make):
    """A load no frictionless contact balances (Farkas: a rigid motion
    that moves no node into the obstacle and along which the load does
    work): the same one-line ProblemError as the factorisation path,
    before any Newton system."""
    messages = []
    for backend in ("auto", "amg"):
        with pytest.raises(ProblemError) as info:
            solver.solve(make(), backend=backend)
        messages.append(str(info.value))
    assert "\n" not in messages[1]
    assert "rigid-body motion" in messages[1]
    assert messages[1] == messages[0]


def test_auto_takes_amg_when_the_factor_does_not_fit(monkeypatch):
    """``backend="auto"`` on a body held by contact only: with the
    machine's memory it factorises; with (pretend) 100 kB available the
    AMG path runs, says why, and gives the factorisation's u to 1e-8."""
    problem = floor_block(n=(40, 20))
    direct = solver.solve(problem)
    assert direct.linear_solver != "amg"
    monkeypatch.setattr(amg, "available_memory", lambda: 1e5)
    chosen = solver.solve(problem)
    assert chosen.linear_solver == "amg" and chosen.success, chosen.message
    assert "AMG" in chosen.linear_solver_reason
    _same(direct, chosen)


def test_hold_keeps_the_active_normals_seeing_every_held_mode():
    """RigidPlacement.hold: on the floor block (three modes; the normals
    see two, the vertical translation and the rotation) one active node
    sees only one combination, so the node of largest score is added
    (a second one, and no more); a set that already sees both is kept."""
    from solver.contact import contact_geometry
    from solver.contact.strategies.floating import RigidPlacement

    problem = floor_block()
    geometry = contact_geometry(problem, "obstacle")
    placement = RigidPlacement(problem, geometry)
    assert placement.free.shape[1] == 1  # the horizontal slide
    m = len(geometry.gap)
    one = np.zeros(m, bool)
    one[0] = True
    score = np.arange(m, dtype=float)  # the last node scores highest
    held = placement.hold(one, score)
    assert held.sum() == 2 and held[0] and held[-1]
    both = one.copy()
    both[3] = True
    np.testing.assert_array_equal(placement.hold(both, score), both)
