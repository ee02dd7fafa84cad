"""Bodies held only by contact on the full system (``system="full"``,
issue 31 point 2): all DOFs unknowns, the r DOFs F replaced by the
rigid-body modes' amplitudes α (solver/contact/strategies/
floating_full.py).

References: the condensed system of the same floating problem (K⁺ and
the equilibrium Rᵀ(f − Bᵀλ − Tᵀt) = 0, tests/test_floating*.py), which
poses the same equations: the same u to 1e-8 relative; Hertz's line
contact (a = 2√(PR/πE*), solver.verification.hertz_line_contact) for the
force-loaded half-cylinder; statics (the contact forces balance the load
to round-off); Farkas' lemma for the refusals (tests/faults)."""

import pathlib
import warnings

import numpy as np
import pytest

import solver
from test_export3d import export_module
from test_floating import P, assert_hertz_force
from test_floating import hertz_force  # noqa: F401 (a fixture)
from test_floating_friction import FC, _block3, floating_cylinder
from tri_elasticity import floor_block

ROOT = pathlib.Path(__file__).resolve().parents[1]


def _same_u(full, condensed, rtol=1e-8):
    """The full system's u equals the condensed one's to ``rtol`` relative
    (the last step's with friction)."""
    u, v = (np.atleast_2d(r.u)[-1] for r in (full, condensed))
    assert np.abs(u - v).max() <= rtol * np.abs(v).max(), \
        np.abs(u - v).max() / np.abs(v).max()


def _both(problem, **options):
    """(condensed, full) solves of ``problem``, both converged and
    verified on every node."""
    results = [solver.solve(problem, system=s, **options)
               for s in ("condensed", "full")]
    for r in results:
        assert r.success, r.message
        assert r.verification["passed"]
    assert not results[1].condensed and results[0].condensed
    return results


def test_hertz_cylinder_under_a_force_full(hertz_force):
    """--system full on the force-loaded Hertz cylinder (two modes): a
    within 0.5 % of Hertz (measured +0.07 %), p0 (fitted) within 1 %
    (−0.19 %), ≥ 40 nodes in contact, the contact forces balance P to
    1e-10 and u is the condensed system's to
    1e-8 (measured 9e-13). φ_min: 15 Jacobians from the rigid start,
    against 8 condensed with the nested start (φ_FB: benchmarks/
    floating_full.py)."""
    condensed, full = _both(hertz_force)
    _same_u(full, condensed)
    assert_hertz_force(hertz_force, full)
    assert full.start == "rigid"
    t = np.asarray(condensed.rigid_body["translation"])
    np.testing.assert_allclose(full.rigid_body["translation"], t, rtol=0,
                               atol=1e-8 * np.abs(t).max())


@pytest.mark.parametrize("method", ["min", "fb"])
@pytest.mark.parametrize("floor", [0.0, -0.01])
def test_block_under_its_weight_full(method, floor):
    """The 2 × 1 block under its weight on the floor (three modes, the
    horizontal one seen by no normal): total contact force = weight to
    1e-10, the same u as condensed; on a floor 0.01 below it drops onto
    it (the rigid start)."""
    problem = floor_block(floor=floor)
    condensed, full = _both(problem, method=method)
    _same_u(full, condensed)
    weight = -problem.f[problem.dof_map[:, 1] == 1].sum()
    assert abs(full.total_contact_force[1] - weight) <= 1e-10 * weight
    assert abs(full.total_contact_force[0]) <= 1e-10 * weight
    assert abs(full.rigid_body["translation"][0]) <= 1e-12


def test_3d_block_full():
    """A floating tetrahedral block (six modes) on the plane z = 0 under
    (0, 0, −1): the same u as condensed, the contact force 1 to 1e-10."""
    condensed, full = _both(_block3((0.0, 0.0, -1.0)))
    _same_u(full, condensed)
    assert abs(full.total_contact_force[2] - 1.0) <= 1e-10


def sphere_under_a_force(folder, P=36.63):
    """The quarter sphere (a/h 4, committed mesh) exported by SfePy under
    P (load='force': one rigid mode, the vertical translation, held by
    contact only), loaded (also of tests/test_amg_floating.py)."""
    path = folder / "sphere_force.npz"
    export_module().export_only(
        ROOT / "sfepy_problems" / "hertz_sphere.py",
        mesh=str(ROOT / "meshes" / "hertz_sphere_4.mesh"), output=str(path),
        load="force", P=P)
    problem = solver.load_problem(path)
    assert problem.rigid_modes()[0].shape[1] == 1
    return problem


def test_3d_hertz_sphere_under_a_force_full(tmp_path):
    """The quarter sphere (a/h 4, committed mesh) under P (load='force',
    the vertical translation held by contact only) against the sphere
    surface's rollers on the symmetry planes: the same u as condensed."""
    problem = sphere_under_a_force(tmp_path)
    condensed, full = _both(problem)
    _same_u(full, condensed)
    assert abs(4 * full.total_contact_force[2] - 36.63) <= 1e-10 * 36.63


@pytest.mark.parametrize("slave", ["upper", "lower"])
def test_3d_patch_test_upper_box_floating_full(slave):
    """3D mortar patch test, the upper box floating (six modes): the
    interface pressure p at every node to 1e-10, as condensed."""
    from tet_two_body import stacked_boxes

    p = 0.01
    problem, _, _ = stacked_boxes(pressure=p, slave=slave, squeeze=0.0)
    condensed, full = _both(problem)
    _same_u(full, condensed)
    np.testing.assert_allclose(full.contact_pressure[full.covered], p,
                               rtol=1e-10)


@pytest.mark.parametrize("problem, options", [
    (floor_block(load=(0.2, -1.0)), dict(coulomb="implicit", steps=4)),
    (floor_block(), dict(steps=3)),
    (_block3((0.1, 0.05, -1.0)), dict(coulomb="implicit", steps=3)),
], ids=["2d sideways implicit", "2d weight lagged", "3d sideways implicit"])
def test_friction_full(problem, options):
    """Coulomb friction (projection formulation) on the full system of a
    floating block: the same u as condensed at the last step, every step
    verified; the normal contact forces balance the load's normal part
    (the block's weight 2, or 1 in 3D) to 1e-10."""
    condensed, full = _both(problem, friction=FC, **options)
    _same_u(full, condensed)
    weight = 1.0 if problem.dim == 3 else 2.0
    assert abs(full.contact_force[-1].sum() - weight) <= 1e-10


def test_cattaneo_mindlin_on_a_floating_cylinder_full():
    """The floating half-cylinder, P then Q = ½ f_c P (a load path, the
    first stage frictionless: its slide is left undetermined and taken
    as none on both systems), lagged bound, coarse grading: the same u as
    condensed in every step to 1e-8 and the stick zone the same nodes."""
    problem, _ = floating_cylinder(h0=0.004)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no kinematic breach either
        condensed, full = _both(problem, friction=FC)
    assert full.steps_completed == condensed.steps_completed == 15
    scale = np.abs(condensed.u).max()
    assert np.abs(full.u - condensed.u).max() <= 1e-8 * scale
    np.testing.assert_array_equal(full.stick[-1], condensed.stick[-1])
