"""Bodies held only by contact (issue 31): K singular with the rigid-body
modes as its kernel, solved exactly with K⁺ and the equilibrium
Rᵀ(f − Bᵀλ) = 0 (solver/contact/strategies/floating.py).

References: Hertz's line contact (a = 2√(PR/πE*), p0 = 2P/(πa),
solver.verification.hertz_line_contact); the displacement-controlled
solve of the same body (a supported K, the project's checked path), whose
support reactions, applied as the load, must give the same u; statics
(the contact forces balance the load: Σλ = weight); Farkas' lemma for the
refusals (a load along a motion no contact resists has no solution)."""

import dataclasses
import pathlib

import numpy as np
import pytest
import scipy.sparse as sp

import solver
from solver.errors import ProblemError, SolverError
from solver.verification import fit_semi_ellipse, hertz_line_contact
from test_export3d import export_module
from tri_elasticity import floor_block as block, two_floor_blocks

ROOT = pathlib.Path(__file__).resolve().parents[1]
E, NU, P = 2e5, 0.3, 1739.6


@pytest.fixture(scope="module")
def hertz_force(tmp_path_factory):
    """The Hertz half-cylinder under the force P (load='force')."""
    path = tmp_path_factory.mktemp("floating") / "hertz_force.npz"
    export_module().export_only(
        ROOT / "sfepy_problems" / "hertz_cylinder.py",
        mesh=str(ROOT / "meshes" / "hertz.mesh"), output=str(path),
        load="force", P=P)
    return solver.load_problem(path)


@pytest.fixture(scope="module")
def hertz_result(hertz_force):
    result = solver.solve(hertz_force)
    assert result.success, result.message
    return result


def test_modes_found_from_the_geometry(hertz_force):
    """u_x pinned at the top centre (0, 0): the translation along y and the
    rotation about (0, 0) stay free, exactly the kernel of K."""
    R, _ = hertz_force.rigid_modes()
    assert R.shape[1] == 2
    assert np.abs(hertz_force.K @ R).max() <= 1e-9 * abs(hertz_force.K).max()
    x, y = hertz_force.dof_points().T
    comp = hertz_force.dof_map[:, 1]
    for v in (comp == 1.0, np.where(comp == 0, -y, x)):
        v = np.asarray(v, float)
        assert np.linalg.norm(v - R @ (R.T @ v)) <= 1e-10 * np.linalg.norm(v)


def test_hertz_cylinder_under_a_force(hertz_force, hertz_result):
    """a within 0.5 %, the fitted p0 within 1 % of Hertz for the given P,
    ≥ 40 nodes in contact, and the contact forces balance P to 1e-10."""
    assert_hertz_force(hertz_force, hertz_result)


def assert_hertz_force(hertz_force, r):
    """The checks of :func:`test_hertz_cylinder_under_a_force` on the
    result ``r`` (also of tests/test_floating_full.py)."""
    total = r.total_contact_force
    assert abs(total[1] - P) <= 1e-10 * P and abs(total[0]) <= 1e-10 * P
    assert r.n_contact >= 40
    a_h, p0_h = hertz_line_contact(P, 1.0, E, NU)
    x = hertz_force.nodes[hertz_force.contact_nodes, 0]
    inside = np.flatnonzero(r.in_contact)
    a, p0, _ = fit_semi_ellipse(x[inside], r.contact_pressure[inside],
                                (a_h, p0_h))
    assert abs(a / a_h - 1) < 0.005, a / a_h - 1
    assert abs(p0 / p0_h - 1) < 0.01, p0 / p0_h - 1
    assert r.rigid_body["modes"] == 2
    assert r.verification["passed"]


def _displacement_controlled(problem, top, d):
    """``problem`` (the force-loaded export) with u_y = −d prescribed at
    the nodes ``top``: the supported problem of hertz_cylinder.py."""
    n = problem.n_dofs
    fixed = np.isin(problem.dof_map[:, 0], top) & (problem.dof_map[:, 1] == 1)
    keep = np.flatnonzero(~fixed)
    new = np.full(n, -1)
    new[keep] = np.arange(len(keep))
    K = sp.csr_matrix(problem.K)
    u_D = np.where(fixed, -d, 0.0)
    prescribed = problem.u_prescribed.copy()
    prescribed[top, 1] = -d
    contact = np.where(problem.contact_dofs >= 0,
                       new[np.maximum(problem.contact_dofs, 0)], -1)
    return dataclasses.replace(
        problem, K=K[keep][:, keep].tocsr(), f=-(K[keep] @ u_D),
        dof_map=problem.dof_map[keep], u_prescribed=prescribed,
        contact_dofs=contact), keep, fixed


def test_same_answer_as_the_displacement_controlled_solve(hertz_force):
    """The top edge pressed down by d (supported K): its support reactions,
    applied as the load of the force-loaded body, give the same u to
    1e-8 (both answers exact; the rigid motion found from the contact)."""
    top = np.flatnonzero(hertz_force.nodes[:, 1] == 0.0)
    supported, keep, fixed = _displacement_controlled(hertz_force, top,
                                                      0.016)
    assert not supported.floating
    ref = solver.solve(supported)
    assert ref.success, ref.message
    u = np.zeros(hertz_force.n_dofs)
    u[keep] = ref.u
    u[fixed] = -0.016
    load = np.where(fixed, hertz_force.K @ u, 0.0)  # the reactions
    loaded = dataclasses.replace(hertz_force, f=load)
    result = solver.solve(loaded)
    assert result.success, result.message
    assert np.abs(result.u - u).max() <= 1e-8 * np.abs(u).max()
    np.testing.assert_allclose(result.contact_force, ref.contact_force,
                               rtol=0, atol=1e-8 * ref.contact_force.max())


def test_block_under_its_weight():
    """Total contact force = weight to 1e-10; the free horizontal
    translation (no contact normal sees it, no load along it) is 0."""
    problem = block()
    assert problem.rigid_modes()[0].shape[1] == 3
    result = solver.solve(problem)
    assert result.success, result.message
    weight = -problem.f[problem.dof_map[:, 1] == 1].sum()
    assert abs(result.total_contact_force[1] - weight) <= 1e-10 * weight
    assert abs(result.total_contact_force[0]) <= 1e-10 * weight
    assert abs(result.rigid_body["translation"][0]) <= 1e-12
    assert result.verification["passed"]


def test_block_on_a_floor_below_it():
    """The floor 0.01 below: the body drops onto it (the rigid start),
    then the same forces; FB and the free start (no coarse levels) reach
    the same answer."""
    problem = block(floor=-0.01)
    a = solver.solve(problem)
    b = solver.solve(problem, method="fb")
    c = solver.solve(problem, start="free")
    assert a.success and b.success and c.success, (a.message, b.message)
    np.testing.assert_allclose(c.u, a.u, rtol=0,
                               atol=1e-8 * np.abs(a.u).max())
    bottom = problem.dof_map[:, 1] == 1
    bottom &= problem.nodes[problem.dof_map[:, 0], 1] == 0.0
    np.testing.assert_allclose(a.u[bottom], -0.01, rtol=0, atol=1e-12)
    np.testing.assert_allclose(b.u, a.u, rtol=0,
                               atol=1e-8 * np.abs(a.u).max())


@pytest.mark.parametrize("load, where, phrase", [
    ((0.0, 1.0), "all", "translation (0, 1)"),   # pulled away
    ((1.0, -1.0), "corner", "translation (1, 0)"),  # pushed sideways
])
def test_unresisted_load_is_refused(load, where, phrase):
    """A load along a rigid motion no frictionless contact resists: one
    line naming the motion and the load's component along it."""
    problem = block(load, where=where)
    with pytest.raises(ProblemError) as info:
        solver.solve(problem)
    message = str(info.value)
    assert "\n" not in message and phrase in message, message
    assert "component 1 along" in message or "component 2.0" in message \
        or "component" in message


def test_pulled_away_component_is_the_load():
    """Pulled up by the load (0, q) per unit area on the 2 × 1 block: the
    component along the unit upward translation is the total 2q."""
    with pytest.raises(ProblemError, match=r"component 2 along the "
                       r"rigid-body motion translation \(0, 1\)"):
        solver.solve(block((0.0, 1.0)))


def test_no_load_is_refused():
    with pytest.raises(ProblemError, match="no resultant"):
        solver.solve(block((0.0, 0.0)))


def test_singular_K_that_is_not_rigid_motion_is_still_refused():
    """Two separate blocks in one body: six zero pivots, three rigid
    motions of the whole; K with three DOFs held is still singular."""
    two = two_floor_blocks()
    assert two.rigid_modes()[0].shape[1] == 3
    with pytest.raises(ProblemError, match="K is not positive definite"):
        solver.solve(two)


@pytest.mark.parametrize("options, phrase", [
    (dict(friction=0.3, formulation="thesis"),
     "formulation='thesis' is not supported"),
    (dict(candidates=True), "candidates=True is not supported"),
])
def test_options_refused_for_a_floating_body(options, phrase):
    with pytest.raises(SolverError, match=phrase):
        solver.solve(block(), **options)
