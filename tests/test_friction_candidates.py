"""Coulomb friction on candidate nodes (solver/contact/strategies/friction_candidates.py,
issue 18 part 6).

Reference: the same run condensed onto every DOF of every free contact node
(``candidates=False``, the path that screens nothing), and, for one case,
the run on the full sparse system (``condense=False``); both independent of
the screening. The problem is tests/test_core3d.py's dome: a P1 block pressed
onto a paraboloid bump (only a patch touches), and the same block dragged
sideways after the press (a load path).
"""

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

from tet_elasticity import box, mesh_problem, stiffness  # noqa: E402
from test_core3d import bottom_faces, dome_block  # noqa: E402
from solver import solve_friction  # noqa: E402
from solver.contact import ContactGeometry
from solver.contact.strategies.friction_candidates import (  # noqa: E402
    first_candidates, remaining_gap)
from solver.front.cases import DEFAULTS, Case, resolve  # noqa: E402
from solver.errors import SolverError  # noqa: E402

FIELDS = ("u", "displacement", "contact_force", "friction_traction",
          "tangential_displacement", "friction_bound")
RUN = dict(formulation="projection", steps=5, tol=1e-13)


def assert_same_run(result, reference, rtol=1e-10):
    """Every per-step field equal to ``rtol`` of its largest entry."""
    assert result.success and reference.success, result.message
    assert result.steps_completed == reference.steps_completed
    for key in FIELDS:
        a, b = np.asarray(result[key]), np.asarray(reference[key])
        assert a.shape == b.shape, key
        assert np.array_equal(np.isnan(a), np.isnan(b)), key
        scale = np.nanmax(np.abs(b))
        assert np.nanmax(np.abs(a - b)) <= rtol * scale, key
    assert [r["n_contact"] for r in result.records] == \
        [r["n_contact"] for r in reference.records]
    np.testing.assert_array_equal(result.gap, reference.gap)
    np.testing.assert_array_equal(result.normal, reference.normal)


@pytest.fixture(scope="module")
def dome():
    return dome_block()


@pytest.fixture(scope="module")
def dragged():
    return dragged_dome()


def dragged_dome(drag=0.05):
    """tests/test_core3d.py's dome (curvature 0.5, 6×6×3 cells) pressed by
    0.05 (2 steps), then its top moved by ``drag`` along x (3 steps): a
    load path whose contact patch shifts and slides."""
    nodes, tets = box((6, 6, 3))
    z = nodes[:, 2]
    top = np.isclose(z, 1.0)
    K = stiffness(nodes, tets, 100.0, 0.3)
    ids = np.arange(len(nodes)).reshape(7, 7, 4)

    def problem_for(value):
        prescribed = np.full(nodes.shape, np.nan)
        prescribed[top] = value
        return mesh_problem(nodes, tets, K, prescribed,
                            np.flatnonzero(np.isclose(z, 0.0)),
                            bottom_faces(ids))

    press = problem_for([0.0, 0.0, -0.05])
    end = problem_for([drag, 0.0, -0.05])
    problem = dataclasses.replace(
        end, load_path=np.array([press.f, end.f]),
        load_path_steps=np.array([2, 3]), load_path_friction=np.ones(2),
        load_path_prescribed=np.array([press.u_prescribed,
                                       end.u_prescribed]))
    free = np.flatnonzero((problem.contact_dofs >= 0).all(axis=1))
    px, py = nodes[problem.contact_nodes[free], :2].T - 0.5
    normal = np.column_stack([-px, -py, -np.ones(len(free))])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    geometry = ContactGeometry(free, problem.contact_dofs[free],
                               0.5 * (px ** 2 + py ** 2), normal)
    return problem, geometry


@pytest.mark.parametrize("method", ["min", "fb"])
@pytest.mark.parametrize("coulomb", ["lagged", "implicit"])
def test_candidates_equal_every_contact_dof(dome, method, coulomb):
    """The default 3D path (candidates) = every DOF of Γc, to 1e-10."""
    problem, geometry = dome
    kw = dict(RUN, method=method, coulomb=coulomb, geometry=geometry)
    result = solve_friction(problem, 0.3, **kw)
    reference = solve_friction(problem, 0.3, candidates=False, **kw)
    assert result.condensation == "candidates"
    screening = result.candidates
    assert screening["n_candidates"] < len(geometry.gap)  # fewer nodes
    assert screening["n_candidates"] >= result.records[-1]["n_contact"]
    assert result.verification["passed"]
    assert_same_run(result, reference)


def test_candidates_equal_the_full_system(dome):
    """... and the run on the full sparse system (no condensation)."""
    problem, geometry = dome
    kw = dict(RUN, method="min", geometry=geometry)
    result = solve_friction(problem, 0.3, **kw)
    reference = solve_friction(problem, 0.3, condense=False, **kw)
    assert_same_run(result, reference, 1e-9)


@pytest.mark.parametrize("method", ["min", "fb"])
def test_candidates_grow_and_restart(dome, method):
    """margin = 0: the first candidates are exactly the frictionless
    contact set at the final load; with friction earlier steps touch
    outside it, the check finds it, the set grows and the run restarts:
    still the every-DOF run to 1e-10, every step delivered once, in
    order, and the progress reported once per step."""
    problem, geometry = dome
    kw = dict(RUN, method=method, geometry=geometry)
    delivered, reported = [], []
    result = solve_friction(
        problem, 0.3, margin=0.0, keep_steps=True,
        on_step=lambda fields: delivered.append(
            (fields["load_factor"], fields["tangential_displacement"].copy())),
        progress=lambda record: reported.append(record["step"]), **kw)
    reference = solve_friction(problem, 0.3, candidates=False, **kw)
    rounds = result.candidates["rounds"]
    assert result.candidates["enlarged"] >= 1
    assert rounds[1]["stage"] == "steps" and rounds[1]["penetrating"] > 0
    assert rounds[1]["step"] is not None
    assert rounds[-1]["penetrating"] == 0
    sizes = [r["n_candidates"] for r in rounds]
    assert sizes == sorted(sizes) and sizes[-1] > sizes[0]
    assert_same_run(result, reference)
    assert [d[0] for d in delivered] == pytest.approx([0.2, 0.4, 0.6, 0.8,
                                                        1.0])
    assert reported == [1, 2, 3, 4, 5]
    for (_, ut), expected in zip(delivered,
                                 reference.tangential_displacement):
        assert np.nanmax(np.abs(ut - expected)) <= 1e-10 * np.nanmax(
            np.abs(expected))


def test_load_path_with_drag(dragged):
    """Press, then drag: the patch moves and slides (the candidates grow
    once); the same run as every contact DOF."""
    problem, geometry = dragged
    kw = dict(formulation="projection", method="min", tol=1e-13,
              geometry=geometry)
    result = solve_friction(problem, 0.3, **kw)
    reference = solve_friction(problem, 0.3, candidates=False, **kw)
    assert result.records[-1]["n_slip"] > 0  # the drag makes nodes slide
    assert_same_run(result, reference)


def test_keep_steps_false_streams_the_same_steps(dome):
    problem, geometry = dome
    steps = []
    result = solve_friction(problem, 0.3, geometry=geometry, margin=0.0,
                            keep_steps=False, method="min",
                            on_step=lambda f: steps.append(f["u"].copy()),
                            **RUN)
    reference = solve_friction(problem, 0.3, geometry=geometry,
                               candidates=False, method="min", **RUN)
    assert result.success and result.steps_completed == 5
    assert "u" not in result
    np.testing.assert_allclose(np.array(steps), reference.u, rtol=0,
                               atol=1e-10 * np.abs(reference.u).max())


def test_rules_and_refusals(dome):
    problem, geometry = dome
    remaining = np.array([0.0, 0.0, 0.01, 0.5, 1.0])
    nodes, delta = first_candidates(remaining)
    assert delta == pytest.approx(0.01) and list(nodes) == [0, 1, 2]
    assert list(first_candidates(remaining, 0.6)[0]) == [0, 1, 2, 3]
    u = np.zeros(problem.n_dofs)
    u[geometry.dofs[:, 2]] = -0.01  # every node 0.01 down, ν ≈ −z
    np.testing.assert_allclose(remaining_gap(geometry, u),
                               geometry.gap - 0.01 * np.abs(
                                   geometry.normal[:, 2]))

    def candidates(dim, **options):
        case = Case(dim, "rigid", "friction", "serial")
        return resolve(case, dict(DEFAULTS, friction=0.3,
                                  **options))["candidates"]

    assert candidates(3)
    assert not candidates(2)  # 2D unchanged
    assert not candidates(3, system="full")
    with pytest.raises(SolverError, match="candidates are a condensation"):
        candidates(3, system="full", candidates=True)
    with pytest.raises(SolverError, match="candidates are a condensation"):
        solve_friction(problem, 0.3, geometry=geometry, candidates=True,
                       condense=False, formulation="projection")


@pytest.mark.parametrize("coulomb", ["lagged", "implicit"])
def test_disc_direction_solves_the_whole_jacobian(dome, coulomb):
    """The Newton direction with the tractions eliminated (friction_disc)
    solves J d = −F of the sparse J that FrictionSystem assembles, to
    round-off, and rmatvec is Jᵀ F; at an iterate with stick and slip
    nodes and pairs of every kind (w_a, w_b of φ_FB and φ_min)."""
    import scipy.sparse as sp

    from solver.contact.friction.disc import DiscSystem
    from solver.contact.friction.system import FrictionSystem
    from solver.contact.strategies.reduction import condense_onto_contact

    problem, geometry = dome
    condensation, local = condense_onto_contact(problem, geometry, "superlu")
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()[geometry.index]
    system = DiscSystem(condensation.S, condensation.load(problem.f)[0],
                        local, lumped, 0.3, coulomb, 100.0, 100.0)
    rng = np.random.default_rng(18)
    m, n = system.m, system.n
    system.set_step(rng.normal(0, 1e-3, n), 0.5,
                    rng.uniform(0, 2, m) * (rng.random(m) < 0.7))
    x = np.concatenate([rng.normal(0, 1e-6, n),  # |g_t| ~ f_c p
                        rng.normal(0, 0.5 / system.c_t, system.mt)])
    jac = system.jacobian(x)
    slip = np.linalg.norm(jac.P.reshape(m, -1) - np.eye(2).ravel(), axis=1)
    assert (slip > 0).any() and (slip == 0).any()  # stick and slip nodes
    JE, JA, JB = FrictionSystem.jacobian(system, x)
    # DiscSystem's projection rows are D(g − P(w)) (nodal forces)
    rows = sp.diags(np.concatenate([np.ones(JE.shape[0] - system.mt),
                                    system.lumped_t]))
    for wa, wb in [(rng.uniform(-1, 0, m), rng.uniform(-1, 0, m)),
                   ((rng.random(m) < 0.5) * 1.0, None)]:
        wb = 1.0 - wa if wb is None else wb
        J = sp.vstack([rows @ JE, sp.diags(wa) @ JA
                       + sp.diags(wb) @ JB]).toarray()
        F = rng.normal(size=J.shape[0])
        combined = jac.combine(wa, wb)
        d = combined.direction(F)
        assert np.linalg.norm(J @ d + F) <= 1e-10 * (
            np.linalg.norm(J) * np.linalg.norm(d) + np.linalg.norm(F))
        np.testing.assert_allclose(combined.rmatvec(F), J.T @ F,
                                   rtol=0, atol=1e-12 * np.abs(J).max()
                                   * np.abs(F).sum())


def test_first_candidates_take_two_rings_of_surface_neighbours():
    """The default rule with contact triangles: the screening's contact
    set and RINGS = 2 rings of neighbours along the triangles' edges (by
    hand on a strip of 2 × 6 nodes, node ids ≠ Γc positions, a support
    left out of the geometry), δ the largest remaining gap among them; a
    given margin keeps the gap rule."""
    import types

    from solver.contact.strategies.friction_candidates import RINGS, surface_adjacency

    assert RINGS == 2
    ids = 100 + np.arange(12)  # Γc position p ↔ node id 100 + p
    grid = ids.reshape(2, 6)  # columns 0-5 along the strip
    faces = np.concatenate([
        np.column_stack([grid[0, :-1], grid[0, 1:], grid[1, :-1]]),
        np.column_stack([grid[0, 1:], grid[1, 1:], grid[1, :-1]])])
    problem = types.SimpleNamespace(contact_faces=faces, contact_nodes=ids)
    present = np.delete(np.arange(12), 11)  # position 11: a support
    geometry = types.SimpleNamespace(index=present)
    adjacency = surface_adjacency(problem, geometry)
    assert adjacency.shape == (11, 11)
    assert (adjacency != adjacency.T).nnz == 0
    contact = np.zeros(11, bool)
    contact[0] = True  # column 0, top row
    remaining = np.arange(11.0)
    nodes, delta = first_candidates(remaining, None, contact, adjacency)
    # ring 1: top 1, bottom 6 (position 6 = column 0, bottom); ring 2:
    # top 2, bottom 7 (neighbours of 1 and 6)
    assert list(nodes) == [0, 1, 2, 6, 7] and delta == 7.0
    assert list(first_candidates(remaining, 2.5, contact, adjacency)[0]) \
        == [0, 1, 2]
    no_faces = types.SimpleNamespace(contact_faces=None, contact_nodes=ids)
    assert surface_adjacency(no_faces, geometry) is None
