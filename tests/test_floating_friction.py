"""Coulomb friction on a body held only by contact (issue 31): the
tangential rigid-body modes are held by friction, and the condensed
system's equilibrium rows Rᵀ(f − Bᵀλ − Tᵀt) = 0 include the tangential
contact forces (solver/contact/strategies/floating.py).

References: Cattaneo–Mindlin partial slip, c = a√(1 − Q/(f_c P))
(Johnson 1985, §7.1) with a from Hertz for the given P (a floating
half-cylinder pressed by P, then sheared by Q with the couple Q·R that
keeps the moment about the contact zero: the classical loading, no
rolling); statics (the contact forces balance the load to round-off);
the Coulomb cone for the refusals (a load outside every node's cone,
or outside what the previous step's pressure bounds under the lagged
bound, has no answer)."""

import dataclasses

import numpy as np
import pytest

import solver
from solver.errors import ProblemError, SolverError
from solver.geometry.curves.parametric import ParametricCurve
from solver.verification import (cattaneo_mindlin_stick_half_width,
                                 hertz_line_contact, zone_of)
from tet_elasticity import box, mesh_problem, stiffness
from tri_elasticity import (floor_block, floor_block_beyond_lagged,
                            graded_half_disk)

E, NU, P, FC = 2e5, 0.3, 435.0, 0.5


def floating_cylinder(ratio=0.5, h0=0.0015, steps=(5, 10)):
    """The half-disc R = 1 below y = 0 on the rigid line y = −1, no
    Dirichlet condition (three rigid modes); a load path: the uniform
    traction P on the top edge (frictionless stage), then the tangential
    Q = ``ratio`` f_c P added on the top edge with the couple ±Q/2 at its
    corners (zero moment about the contact point). Returns (problem, the
    contact nodes' x)."""
    nodes, tri, arc, flat = graded_half_disk(1.0, h0, 0.07, 0.15)
    contact = arc[np.abs(nodes[arc, 0]) <= 0.1]
    contact = contact[np.argsort(nodes[contact, 0])]
    problem = mesh_problem(nodes, tri, stiffness(nodes, tri, E, NU),
                           np.full(nodes.shape, np.nan), contact,
                           np.c_[contact[:-1], contact[1:]])
    problem.obstacle = ParametricCurve("t", "-1")
    problem.meta = {"E": E, "nu": NU, "plane": "strain"}
    top = flat[np.argsort(nodes[flat, 0])]
    share = np.zeros(len(top))
    share[:-1] += 0.5 * np.diff(nodes[top, 0])
    share[1:] += 0.5 * np.diff(nodes[top, 0])
    share /= share.sum()  # the top edge's length 2R: traction · 2R
    Q = ratio * FC * P
    normal = np.zeros(nodes.shape)
    normal[top, 1] = -P * share
    shear = normal.copy()
    shear[top, 0] += Q * share
    shear[top[-1], 1] += Q / 2
    shear[top[0], 1] -= Q / 2
    reduced = [F[problem.dof_map[:, 0], problem.dof_map[:, 1]]
               for F in (normal, shear)]
    problem = dataclasses.replace(
        problem, f=reduced[1], load_path=np.stack(reduced),
        load_path_steps=np.array(steps),
        load_path_friction=np.array([0.0, 1.0]))
    return problem, nodes[contact, 0]


@pytest.fixture(scope="module")
def cylinder():
    return floating_cylinder()


@pytest.mark.parametrize("coulomb, method", [("lagged", "min"),
                                             ("implicit", "min"),
                                             ("lagged", "fb"),
                                             ("implicit", "fb")])
def test_cattaneo_mindlin_on_a_floating_cylinder(cylinder, coulomb, method):
    """The stick half-length within 3 % of Cattaneo–Mindlin's c
    (measured −0.7 % for each); the contact forces balance P and Q to
    1e-10 (the body's x translation held by friction alone); ≥ 40 nodes
    in contact; every step verified. φ_FB with the implicit bound stalled
    at the first friction step (its monotone line search crawled from the
    all-stick start) until the floating steps got φ_FB's watchdog: now 3
    Newton steps per friction step, as φ_min's."""
    problem, x = cylinder
    assert problem.rigid_modes()[0].shape[1] == 3
    r = solver.solve(problem, friction=FC, coulomb=coulomb, method=method)
    assert r.success, r.message
    assert r.steps_completed == 15
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()
    total_n = r.contact_force[-1].sum()
    total_t = (lumped * r.friction_traction[-1]).sum()
    assert abs(total_n - P) <= 1e-10 * P
    assert abs(abs(total_t) - 0.5 * FC * P) <= 1e-10 * P
    assert r.in_contact[-1].sum() >= 40
    a, _ = hertz_line_contact(P, 1.0, E, NU)
    c = cattaneo_mindlin_stick_half_width(a, abs(total_t), total_n, FC)
    half, _ = zone_of(x, r.stick[-1])
    assert abs(half / c - 1) < 0.03, half / c - 1
    contact = r.in_contact[-1]
    assert r.slip[-1][contact].sum() >= 4  # partial slip, not all stick
    # the frictionless stage left no friction traction
    assert np.abs(r.friction_traction[r.stage == 0]).max() \
        <= 1e-12 * r.contact_pressure.max()
    assert r.verification["passed"]
    if method == "fb":  # the watchdog's full steps: no crawling
        friction_steps = [s for s in r.records if s["stage"] == 1]
        assert max(s["nit"] for s in friction_steps) <= 6


def test_shear_above_the_friction_limit_is_refused():
    """Q = 1.2 f_c P: no contact forces within the Coulomb cones balance
    it; one line naming the motion, before any step is solved."""
    problem, _ = floating_cylinder(ratio=1.2, h0=0.004)
    with pytest.raises(ProblemError) as info:
        solver.solve(problem, friction=FC)
    message = str(info.value)
    assert "\n" not in message
    assert "along the rigid-body motion translation (" in message
    assert "contact with friction f_c = 0.5 cannot resist" in message
    # what --info says (problem.refusals): statics, Q/P = 1.2·0.5 = 0.6;
    # a load path, so no word on the lagged bound's first step
    refusal, = problem.refusals()
    assert "it needs friction: friction=F with F ≥ 0.6 (" in refusal
    assert "coulomb=" not in refusal


def test_block_held_sideways_by_friction():
    """The 2 × 1 block under (0.2, −1) per unit area (f_c = 0.5 holds
    0.5): Σλ = 2 and Σ|t| = 0.4 to 1e-10; the lagged bound gives the
    first step no friction, so it is refused there, and the implicit one
    solves."""
    problem = floor_block(load=(0.2, -1.0))
    r = solver.solve(problem, friction=FC, coulomb="implicit", steps=4)
    assert r.success, r.message
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()
    assert abs(r.contact_force[-1].sum() - 2.0) <= 1e-10
    assert abs(abs((lumped * r.friction_traction[-1]).sum()) - 0.4) <= 1e-10
    # the body's rigid motion at the last step (summary.json's): it slid
    # towards +x, held by friction (elastic shear of the block)
    assert r.rigid_body["modes"] == 3 and r.rigid_body["translation"][0] > 0
    with pytest.raises(ProblemError, match="coulomb='lagged' bounds the "
                       "first load step's friction"):
        solver.solve(problem, friction=FC, coulomb="lagged", steps=4)


def test_lagged_step_that_cannot_hold_the_body_ends_the_run():
    """A load path: (0, −0.5) frictionless in one step, then (0.4, −1) in
    two steps with f_c = 0.5. Step 3 needs 0.8 of friction, the lagged
    bound from step 2's pressure allows 0.75: no answer exists; the run
    ends there (two steps kept), not with a wrong answer."""
    problem = floor_block_beyond_lagged()
    r = solver.solve(problem, friction=FC, coulomb="lagged")
    assert not r.success and r.failed_step == 3
    assert r.steps_completed == 2
    assert "load step 3 of 3 has no answer" in r.message
    assert "translation (" in r.message and "\n" not in r.message
    implicit = solver.solve(problem, friction=FC, coulomb="implicit")
    assert implicit.success, implicit.message


def test_frictionless_stage_leaves_the_sliding_free():
    """The weight only, f_c = 0.5, lagged (the first step frictionless,
    the sliding left undetermined there and taken as none): every step
    converges; friction resists the bottom's Poisson spread only, so its
    forces sum to 0 (statics: no tangential load)."""
    problem = floor_block()
    r = solver.solve(problem, friction=FC, steps=3)
    assert r.success, r.message
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()
    g = r.friction_traction[-1]
    assert np.abs(g).max() > 0.1  # friction acts
    assert abs((lumped * g).sum()) <= 1e-10
    assert abs(r.contact_force[-1].sum() - 2.0) <= 1e-10


def _block3(load, n=(4, 4, 2)):
    """A 1 × 1 × 0.5 tetrahedral block of ``n`` cells on the plane z = 0,
    no Dirichlet condition (six rigid modes), ``load`` spread over its top
    nodes."""
    from solver.geometry.surfaces import surface_from_spec
    from test_friction3d import bottom_faces

    nodes, tets = box(n, (1.0, 1.0, 0.5))
    ids = np.arange(len(nodes)).reshape(*(k + 1 for k in n))
    problem = mesh_problem(nodes, tets, stiffness(nodes, tets, 100.0, 0.3),
                           np.full(nodes.shape, np.nan),
                           ids[:, :, 0].ravel(), bottom_faces(ids))
    problem.obstacle = surface_from_spec(
        {"kind": "plane", "point": [0, 0, 0], "normal": [0, 0, 1]})
    top = nodes[:, 2] == 0.5
    F = np.zeros(nodes.shape)
    F[top] = np.asarray(load) / top.sum()
    problem.f = F[problem.dof_map[:, 0], problem.dof_map[:, 1]]
    problem.meta = {"E": 100.0, "nu": 0.3}
    return problem


def test_3d_block_held_sideways_by_friction():
    """(0.1, 0.05, −1) on a floating 3D block, f_c = 0.5, implicit: the
    contact forces balance the load to 1e-10; (0.6, 0, −1) is refused."""
    problem = _block3((0.1, 0.05, -1.0))
    assert problem.rigid_modes()[0].shape[1] == 6
    r = solver.solve(problem, friction=FC, coulomb="implicit", steps=3)
    assert r.success, r.message
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()
    assert abs(r.contact_force[-1].sum() - 1.0) <= 1e-10
    t = (lumped[:, None] * r.friction_traction[-1]).sum(axis=0)
    assert abs(np.linalg.norm(t) - np.hypot(0.1, 0.05)) <= 1e-10
    with pytest.raises(ProblemError, match="friction f_c = 0.5 cannot"):
        solver.solve(_block3((0.6, 0.0, -1.0)), friction=FC,
                     coulomb="implicit")


def test_thesis_formulation_refused_for_a_floating_body():
    with pytest.raises(SolverError, match="formulation='thesis' is not "
                       "supported for 2D, rigid, held by contact only"):
        solver.solve(floor_block(), friction=FC, formulation="thesis")
