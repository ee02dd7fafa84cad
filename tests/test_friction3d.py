"""Coulomb friction in 3D (issue 18 part 5): the projection onto the
Coulomb disc |g_t| ≤ f_c p in the tangent plane.

The problems are P1 tetrahedral blocks (tests/tet_elasticity.py, independent
of SfePy and of the solver) on the rigid plane z = 0 (gaps 0, ν = −z),
pressed down, then dragged by their top face in a direction at an angle θ in
the plane (a load path of two stages). Independent references: Coulomb's
law itself (full slip: every nodal friction force at the bound, so the total
friction force is f_c × the total normal force, against the drag: a disc; a
square |g_x|, |g_y| ≤ f_c p would give up to √2 of it off the axes), global
equilibrium of the block (stick), and the frictionless solver (f_c = 0).
"""

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

from tet_elasticity import box, mesh_problem, stiffness  # noqa: E402
from test_core3d import bottom_faces  # noqa: E402
from solver import solve_friction, solve_frictionless
from solver.contact import ContactGeometry
from solver.errors import SolverError  # noqa: E402


def dragged_block(theta, slide, dz=0.01, nu=0.0, n=(4, 4, 2), steps=(1, 4)):
    """The unit block (E = 100) pressed by dz, then its top moved by
    ``slide`` along (cos θ, sin θ, 0). Returns (problem, geometry, K full,
    top nodes)."""
    nodes, tets = box(n)
    z = nodes[:, 2]
    top = np.isclose(z, 1.0)
    K = stiffness(nodes, tets, 100.0, nu)
    ids = np.arange(len(nodes)).reshape(tuple(m + 1 for m in n))

    def problem_for(value):
        prescribed = np.full(nodes.shape, np.nan)
        prescribed[top] = value
        return mesh_problem(nodes, tets, K, prescribed,
                            np.flatnonzero(np.isclose(z, 0.0)),
                            bottom_faces(ids))

    press = problem_for([0.0, 0.0, -dz])
    end = problem_for([slide * np.cos(theta), slide * np.sin(theta), -dz])
    problem = dataclasses.replace(
        end, load_path=np.array([press.f, end.f]),
        load_path_steps=np.array(steps), load_path_friction=np.ones(2),
        load_path_prescribed=np.array([press.u_prescribed,
                                       end.u_prescribed]))
    free = np.flatnonzero((problem.contact_dofs >= 0).all(axis=1))
    m = len(free)
    geometry = ContactGeometry(free, problem.contact_dofs[free], np.zeros(m),
                               np.tile([0.0, 0.0, -1.0], (m, 1)))
    return problem, geometry, K, top


def friction_vector(problem, geometry, result, step=-1):
    """Σ_i D_ii g_t,i in global coordinates (the total friction force)."""
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()[geometry.index]
    g = result.friction_traction[step][geometry.index]  # (m, 2)
    return np.einsum("i,ik,ikj->j", lumped, g, geometry.tangents)


@pytest.mark.parametrize("method", ["min", "fb"])
@pytest.mark.parametrize("coulomb", ["lagged", "implicit"])
@pytest.mark.parametrize("theta", [30.0, 45.0])
@pytest.mark.parametrize("condense", [True, False], ids=["condensed",
                                                         "full"])
def test_sliding_block_disc(method, coulomb, theta, condense):
    """Full slip: the total friction force = f_c × the total normal force
    (the bound's, p_{κ−1} if lagged) to 1e-8, against the drag."""
    angle = np.radians(theta)
    problem, geometry, _, _ = dragged_block(angle, 0.05)
    fc = 0.3
    result = solve_friction(problem, fc, formulation="projection",
                            coulomb=coulomb, method=method,
                            geometry=geometry, condense=condense, tol=1e-12)
    assert result.success, result.message
    assert result.verification["passed"]
    assert result.friction_traction.shape[1:] == (problem.n_contact, 2)
    contact = result.in_contact[-1]
    assert contact.sum() >= 0.8 * len(geometry.index)
    assert np.array_equal(result.slip[-1], contact)  # full slip
    assert not result.stick[-1].any()
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()
    normal_total = (lumped * result.friction_bound[-1]).sum()
    if coulomb == "implicit":
        assert normal_total == pytest.approx(fc * result.contact_force[
            -1].sum(), rel=1e-10)
    vector = friction_vector(problem, geometry, result)
    size = np.linalg.norm(vector)
    assert abs(size / normal_total - 1) <= 1e-8
    assert abs(vector[2]) <= 1e-12 * size
    drag = np.array([np.cos(angle), np.sin(angle), 0.0])
    # against the drag (the slip follows it up to the mesh's anisotropy)
    assert vector @ drag / size <= -(1 - 1e-6)


@pytest.mark.parametrize("method", ["min", "fb"])
def test_stick_balances_the_load(method):
    """A small drag: every node in contact sticks, and the friction force
    balances the tangential force on the top face exactly (global
    equilibrium: K annihilates the rigid translations)."""
    angle = np.radians(30.0)
    problem, geometry, K, top = dragged_block(angle, 1e-5, steps=(1, 2))
    result = solve_friction(problem, 0.3, formulation="projection",
                            method=method, geometry=geometry, tol=1e-12)
    assert result.success, result.message
    contact = result.in_contact[-1]
    assert contact.sum() >= 0.8 * len(geometry.index)
    assert np.array_equal(result.stick[-1], contact)
    assert not result.slip[-1].any()
    internal = (K @ result.displacement[-1].ravel()).reshape(-1, 3)
    drag = internal[top, :2].sum(axis=0)  # force applied on the top face
    vector = friction_vector(problem, geometry, result)
    np.testing.assert_allclose(-vector[:2], drag, rtol=1e-8,
                               atol=1e-10 * np.abs(drag).max())
    assert np.linalg.norm(drag) > 0


@pytest.mark.parametrize("method", ["min", "fb"])
def test_zero_friction_is_frictionless(method):
    """f_c = 0: the frictionless answer of the last step's problem."""
    problem, geometry, _, _ = dragged_block(np.radians(30.0), 0.05)
    result = solve_friction(problem, 0.0, formulation="projection",
                            method=method, geometry=geometry, tol=1e-13)
    assert result.success, result.message
    assert np.abs(result.friction_traction).max() == 0.0
    final = dataclasses.replace(problem, load_path=None,
                                load_path_steps=None,
                                load_path_friction=None,
                                load_path_prescribed=None)
    reference = solve_frictionless(final, method, geometry=geometry,
                                   condense=False, tol=1e-13)
    assert reference.success
    scale = np.abs(reference.u).max()
    assert np.abs(result.u[-1] - reference.u).max() <= 1e-10 * scale


def test_thesis_formulation_refused_in_3d():
    problem, geometry, _, _ = dragged_block(0.0, 0.01)
    with pytest.raises(SolverError, match="2D-only.*formulation="
                       "'projection'") as info:
        solve_friction(problem, 0.3, formulation="thesis",
                       geometry=geometry)
    assert "\n" not in str(info.value)


def test_cli_3d_friction_run(tmp_path):
    """python -m solver X.npz --friction 0.3 --formulation projection
    --steps 3 --plots on a 3D file writes its result, VTU steps (read back)
    and the history figure;
    the thesis's formulation is refused with exit code 2 and one line."""
    import subprocess

    meshio = pytest.importorskip("meshio")
    from solver.geometry.surfaces import surface_from_spec

    problem, _, _, _ = dragged_block(np.radians(30.0), 0.05)
    final = dataclasses.replace(
        problem, load_path=None, load_path_steps=None,
        load_path_friction=None, load_path_prescribed=None,
        contact_faces=bottom_faces(np.arange(75).reshape(5, 5, 3)),
        meta=dict(E=100.0, nu=0.0, load="top dragged", mesh="box 4x4x2"),
        obstacle=surface_from_spec({"kind": "plane", "point": [0, 0, 0],
                                    "normal": [0, 0, 1]}))
    np.savez(tmp_path / "X.npz", **final.to_arrays())
    run = subprocess.run([sys.executable, "-m", "solver", "X.npz",
                          "--friction", "0.3", "--formulation",
                          "projection", "--steps", "3", "--plots"],
                         cwd=tmp_path,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    out = tmp_path / "X-fc0.3-3steps-projection-lagged-min"
    with np.load(out / "result.npz") as result:
        assert result["friction_traction"].shape == (3, 25, 2)
        assert result["slip"][-1].sum() == 25
    assert (out / "history.png").is_file()  # 3D: the history figure only
    mesh = meshio.read(out / "steps" / "step_0003.vtu")
    assert mesh.cells[0].type == "tetra"
    assert mesh.point_data["friction_traction"].shape == (75, 3)  # x, y, z
    refused = subprocess.run([sys.executable, "-m", "solver", "X.npz",
                              "--friction", "0.3", "--steps", "3",
                              "--formulation", "thesis"],
                             cwd=tmp_path, capture_output=True, text=True,
                             timeout=300)
    assert refused.returncode == 2
    assert "2D-only" in refused.stderr
    assert len(refused.stderr.strip().splitlines()) == 1


@pytest.mark.parametrize("coulomb", ["lagged", "implicit"])
def test_disc_jacobian_matches_finite_differences(coulomb):
    """The generalised Jacobian of the disc projection (stick: I; slip:
    b/|w|(I − ŵŵᵀ), ŵ ∂b) against central differences of the residual, at
    an iterate with stick and slip nodes (away from the kinks)."""
    from solver.contact.friction.projection import ProjectionSystem

    problem, geometry, _, _ = dragged_block(np.radians(30.0), 0.05)
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()[geometry.index]
    system = ProjectionSystem(problem.K, problem.f, geometry, lumped, 0.3,
                              coulomb)
    m = system.m
    rng = np.random.default_rng(3)
    system.set_step(np.zeros(system.n), 1.0, rng.uniform(0.5, 1.5, m))
    x = rng.normal(scale=1e-3, size=system.n_unknowns)
    du = x[:system.n]
    b = system.bound(system._force(du), False)[0]
    factor = np.where(np.arange(m) % 2, 0.5, 2.0) * np.maximum(b, 0.1)
    w = rng.normal(size=(m, 2))
    w *= (factor / np.linalg.norm(w, axis=1))[:, None]
    g = w.ravel() + system.c_t * (system.R @ du)[system.t_rows]
    x[system.n:] = g / system.c_t
    JE, JA, JB = system.jacobian(x)
    J = np.vstack([JE.toarray(), JA.toarray(), JB.toarray()])
    h = 1e-7 * np.abs(x).max()
    numeric = np.empty_like(J)
    for j in range(len(x)):
        e = np.zeros_like(x)
        e[j] = h
        plus = np.concatenate(system.residual(x + e))
        minus = np.concatenate(system.residual(x - e))
        numeric[:, j] = (plus - minus) / (2 * h)
    E = system.residual(x)[0]
    size = np.linalg.norm(w, axis=1)
    assert (size < b).any() and (size > b).any()  # stick and slip nodes
    assert np.all(np.abs(size - b) > 1e-3 * b)  # no kink within h
    assert len(E) == system.n - m + 2 * m
    np.testing.assert_allclose(J, numeric, atol=1e-6 * np.abs(J).max())
