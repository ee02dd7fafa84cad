"""Edge cases that must work, on the thesis block (118 triangles).

Variants of the exported problem are made by replacing the obstacle or the
load of the loaded problem (``dataclasses.replace``), the zero load also
through the SfePy export itself.

Counting (solver.ncp.solve_ncp): ``nit`` = Newton iterations = ``njev``
(one Jacobian each); ``nfev`` counts residual evaluations, the one at the
start point included. The stopping test is made before every iteration,
so "solved in one iteration" is nit = njev = 1, nfev = 2 (start, full
step accepted), and "solved at the start" is nit = njev = 0, nfev = 1.
"""

import contextlib
import dataclasses
import json

import numpy as np
import pytest
import scipy.sparse.linalg as sla

from solver import ParametricCurve, load_problem
from solver.cli import main
from solver import solve_friction, solve_frictionless
from solver.contact import contact_geometry
from solver.errors import InitialPenetrationWarning, PenetrationWarning

# Tests that place the obstacle inside the body on purpose expect the
# warnings (pytest.warns): the initial penetration, and the clamped corner
# (5, -10) of Γc, a support, inside the obstacle at the answer; any other
# penetration warning here is an error.
pytestmark = [
    pytest.mark.filterwarnings(
        "error::solver.errors.InitialPenetrationWarning"),
    pytest.mark.filterwarnings("error::solver.errors.PenetrationWarning")]


def inside_the_body(nodes):
    """The warnings of the flat obstacle x = 4.9, 0.1 inside the body:
    ``nodes`` free contact nodes penetrate initially, and the support
    node at the answer."""
    stack = contextlib.ExitStack()
    stack.enter_context(pytest.warns(
        PenetrationWarning, match=r"1 contact node left out of contact as "
                                  r"support \(\d+\).*deepest 0.1"))
    stack.enter_context(pytest.warns(
        InitialPenetrationWarning,
        match=f"penetrates the undeformed body at {nodes} contact nodes"))
    return stack


METHODS = ("min", "fb")
GAPS = ("obstacle", "body")


@pytest.fixture(scope="module")
def block(exported):
    return load_problem(exported(118)[0])


def with_obstacle(problem, x, y="t"):
    return dataclasses.replace(problem, obstacle=ParametricCurve(x, y))


def free(result):
    return np.isfinite(result.gap)  # supports carry NaN


@pytest.mark.parametrize("condense", [False, True])
@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("gap", GAPS)
def test_obstacle_far_away(block, method, gap, condense):
    """No contact: the unconstrained solution K⁻¹f. The full system needs
    one iteration (the Newton step from u = 0 solves Ku = f exactly: every
    contact row is a force row λ = 0 ≤ gap); the condensed one none (it
    starts from λ = 0, i.e. from K⁻¹f)."""
    far = with_obstacle(block, "50 + 0.005*t**2")
    result = solve_frictionless(far, method=method, gap=gap,
                                condense=condense)
    assert result.success, result.message
    assert (result.nit, result.njev, result.nfev) == \
        ((0, 0, 1) if condense else (1, 1, 2))
    assert result.n_contact == 0 and not result.in_contact.any()
    assert np.nanmin(result.gap) > 40
    reference = sla.spsolve(block.K.tocsc(), block.f)
    np.testing.assert_allclose(result.u, reference, rtol=0,
                               atol=1e-12 * np.abs(reference).max())


@pytest.mark.parametrize("condense", [False, True])
def test_obstacle_far_away_with_friction(block, condense):
    far = with_obstacle(block, "50 + 0.005*t**2")
    result = solve_friction(far, 0.3, steps=4, formulation="projection",
                            method="min", condense=condense)
    assert result.success, result.message
    assert not result.in_contact.any()
    scale = np.linalg.norm(block.f)
    assert np.abs(result.friction_traction).max() <= 1e-9 * scale
    reference = sla.spsolve(block.K.tocsc(), block.f)
    np.testing.assert_allclose(result.u[-1], reference, rtol=0,
                               atol=1e-12 * np.abs(reference).max())
    # full: one Newton step solves step 1; condensed: every step starts from
    # the unconstrained increment, already the solution
    if condense:
        assert [r["njev"] for r in result.records] == [0] * 4
    else:
        assert result.records[0]["njev"] == 1


@pytest.fixture(scope="module")
def touching(block):
    """The parabola moved onto the contact node nearest to y = 0 (the
    mesh has it at y = -1.2e-11): zero gap there at t = 0, without load."""
    nodes = block.nodes[block.contact_nodes]
    i = int(np.argmin(np.abs(nodes[:, 1])))
    x0, y0 = (float(v) for v in nodes[i])
    assert x0 == 5.0 and abs(y0) < 1e-9
    return with_obstacle(block, f"5 + 0.005*(t - ({y0!r}))**2",
                         f"t + ({y0!r})"), i


@pytest.mark.parametrize("gap", GAPS)
def test_obstacle_touching_at_start(touching, gap):
    """s = 0 at one node: at u = 0 its pair is (λ, s) = (0, 0), the kink of
    both NCP functions (φ_FB takes DFK's direction z there). Both methods
    converge to the same solution, with that node in contact."""
    problem, i = touching
    geometry = contact_geometry(problem, gap)
    k = int(np.flatnonzero(geometry.index == i)[0])
    assert abs(geometry.gap[k]) <= 1e-15
    assert np.delete(geometry.gap, k).min() > 0.01
    results = [solve_frictionless(problem, method=m, gap=gap,
                                  geometry=geometry) for m in METHODS]
    scale = np.linalg.norm(problem.f)
    for result in results:
        assert result.success, result.message
        assert result.complementarity <= 1e-10 * scale
        assert result.in_contact[i]
    assert results[1].history["step"][0] == "newton"
    a, b = (r.u for r in results)
    assert np.abs(a - b).max() <= 1e-8 * np.abs(a).max()


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("gap", GAPS)
def test_every_contact_node_in_contact(block, method, gap):
    """A flat obstacle 0.1 inside the body (negative initial gaps are
    allowed): every free contact node ends in contact with u_n = s; the
    clamped corner (5, -10) is a support and never is."""
    problem = with_obstacle(block, "4.9 + 0*t")
    with inside_the_body(10):
        result = solve_frictionless(problem, method=method, gap=gap)
    assert result.success, result.message
    mask = free(result)
    assert mask.sum() == 10 and not mask[0]
    np.testing.assert_allclose(result.gap[mask], -0.1, rtol=1e-12)
    assert result.in_contact[mask].all() and not result.in_contact[~mask].any()
    assert result.n_contact == 10
    assert (result.contact_force[mask] > 0).all()
    np.testing.assert_allclose(result.normal_displacement[mask], -0.1,
                               atol=1e-12)
    if method == "min":
        # every pair is a gap row from the start (λ = 0, all penetrating):
        # one exact step on each level of the nested start, 10 nodes and
        # the coarse level's 6 (10 > COARSEST = 8)
        assert [(lv["n_nodes"], lv["njev"]) for lv in result.levels] == \
            [(6, 1), (10, 1)]


@pytest.fixture(scope="module")
def unloaded(tmp_path_factory):
    """The block exported by SfePy with F = (0, 0)."""
    from conftest import MESHES, solve_block

    path = tmp_path_factory.mktemp("f0") / "block_118_f0.npz"
    solve_block(MESHES / "block_118.mesh", path, F=(0.0, 0.0))
    problem = load_problem(path)
    assert not problem.f.any()
    return path, problem


@pytest.mark.parametrize("method", METHODS)
def test_zero_load(unloaded, method):
    """f = 0: u = 0 is the solution and is recognised at the start."""
    result = solve_frictionless(unloaded[1], method=method)
    assert result.success
    assert (result.nit, result.njev, result.nfev) == (0, 0, 1)
    assert not result.u.any() and not result.contact_force.any()
    assert result.n_contact == 0
    assert not np.signbit(result.contact_pressure).any()  # no -0.0


def test_zero_load_command_line(unloaded, tmp_path, capsys):
    path = unloaded[0]
    assert main([str(path), "-o", str(tmp_path / "a")]) == 0
    out = capsys.readouterr().out
    assert "iterations        0" in out and "max pressure      0 " in out
    assert main([str(path), "--friction", "0.3", "--steps", "3", "-o",
                 str(tmp_path / "b")]) == 0
    summary = json.loads((tmp_path / "b" / "summary.json").read_text())
    assert summary["converged"] and summary["n_jacobian"] == 0
    with np.load(tmp_path / "b" / "result.npz") as result:
        assert not result["u"].any()


def test_zero_load_with_penetration(unloaded):
    """No load but an obstacle 0.1 inside the body: it pushes the body out
    (not u = 0)."""
    problem = with_obstacle(unloaded[1], "4.9 + 0*t")
    with inside_the_body(10):
        result = solve_frictionless(problem)
    assert result.success and result.n_contact >= 1
    assert np.abs(result.u).max() > 0.05


@pytest.fixture(scope="module")
def frictionless_118(block):
    return solve_frictionless(block, method="min")


@pytest.mark.parametrize("formulation, method", [("thesis", "fb"),
                                                 ("projection", "min")])
def test_one_load_step(block, frictionless_118, formulation, method):
    """One step, lagged bound: the bound comes from the pressure before the
    step, p₀ = 0, so the one step is frictionless (thesis: Coulomb as a
    sequence of Tresca problems)."""
    result = solve_friction(block, 0.3, steps=1, formulation=formulation,
                            method=method)
    assert result.success and result.steps_completed == 1
    ref = frictionless_118.u
    assert np.abs(result.u[0] - ref).max() <= 1e-8 * np.abs(ref).max()
    assert not result.friction_bound.any()
    scale = np.linalg.norm(block.f)
    assert np.abs(result.friction_traction).max() <= 1e-9 * scale


def test_one_load_step_implicit(block):
    """One step with the current pressure: Coulomb's law holds at once."""
    result = solve_friction(block, 0.3, steps=1, formulation="projection",
                            coulomb="implicit", method="min")
    assert result.success, result.message
    scale = np.linalg.norm(block.f)
    g, bound = result.friction_traction[0], result.friction_bound[0]
    assert np.all(np.abs(g) <= bound + 1e-9 * scale)
    assert np.abs(g).max() > 0  # friction does act


def test_zero_friction_on_the_command_line(exported, tmp_path, capsys):
    """--friction 0 is allowed and gives the frictionless solution."""
    path = str(exported(118)[0])
    assert main([path, "-o", str(tmp_path / "plain")]) == 0
    assert main([path, "--friction", "0", "--steps", "5", "-o",
                 str(tmp_path / "fc0")]) == 0
    with np.load(tmp_path / "plain" / "result.npz") as plain, \
            np.load(tmp_path / "fc0" / "result.npz") as fc0:
        assert fc0["u"].shape[0] == 5
        ref = plain["u"]
        assert np.abs(fc0["u"][-1] - ref).max() <= 1e-8 * np.abs(ref).max()
        np.testing.assert_array_equal(fc0["in_contact"][-1],
                                      plain["in_contact"])
        assert not fc0["friction_bound"].any()
        assert np.abs(fc0["friction_traction"]).max() <= 1e-9 * 4000  # ‖f‖


def test_very_large_friction_on_the_command_line(exported, tmp_path,
                                                 capsys):
    """f_c = 1e6 with the defaults (thesis split, lagged, φ_FB): converges,
    and in the last step every node in contact sticks."""
    out = tmp_path / "out"
    assert main([str(exported(118)[0]), "--friction", "1e6", "--steps",
                 "10", "-o", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["converged"] and summary["final_n_contact"] > 0
    assert summary["final_n_slip"] == 0
    assert summary["final_n_stick"] == summary["final_n_contact"]


@pytest.mark.parametrize("formulation, method", [("thesis", "fb"),
                                                 ("projection", "min")])
def test_absurdly_large_friction(block, formulation, method):
    """f_c = 1e12 (lagged): nothing overflows, nodes stick once touched."""
    result = solve_friction(block, 1e12, steps=10, formulation=formulation,
                            method=method)
    assert result.success, result.message
    assert np.isfinite(result.u).all()
    contact = result.in_contact
    assert contact[-1].any() and not result.slip[-1].any()
    ut = result.tangential_displacement
    for node in np.flatnonzero(contact.any(axis=0)):
        first = np.argmax(contact[:, node])
        # lagged: the first contact step has a zero bound, then it sticks
        moved = ut[first + 1:, node] - ut[first, node]
        assert np.abs(moved).max(initial=0) <= 1e-8 * np.abs(result.u).max()
