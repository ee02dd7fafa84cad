"""Which Hertz curve a 3D pressure figure draws (solver/output/
hertz_reference.py): found from the problem, never from keys only the
shipped problem file writes, and no curve rather than a wrong one.

Independent references: the shipped a/h = 4 quarter sphere's whole-sphere
force and Hertz radius as recorded in sfepy_problems/README.md (P = 37.3,
a = 0.0503), Hertz's formulas (Johnson 1985, §4.2) written out here, and
the whole model of tests/test_rollers.py's mirror-symmetric block, whose
half and quarter must give the whole body's force.
"""

import dataclasses

import numpy as np
import pytest

from conftest import MESHES
from solver import load_problem, save_problem, solve_frictionless
from solver.output.figures import pyplot
from solver.output.figures3d import plot_pressure_vs_radius
from solver.output.hertz_reference import (first_contact, hertz_reference,
                                           symmetry_planes)
from test_export3d import SPHERE, export_module


@pytest.fixture(autouse=True)
def close_figures():
    yield
    pyplot().close("all")


@pytest.fixture(scope="module")
def sphere(tmp_path_factory):
    """The shipped quarter sphere (a/h = 4) and its frictionless solve."""
    path = tmp_path_factory.mktemp("sphere") / "hertz_sphere_4.npz"
    export_module().export_only(
        SPHERE, mesh=str(MESHES / "hertz_sphere_4.mesh"), output=str(path))
    problem = load_problem(path)
    return path, problem, solve_frictionless(problem, method="min")


def _with_meta(problem, tmp_path, drop=(), **changes):
    """``problem`` written with save_problem and read back, its meta
    without the keys ``drop`` and with ``changes``: a user-built file."""
    meta = {k: v for k, v in problem.meta.items() if k not in drop}
    meta.update(changes)
    path = tmp_path / "user.npz"
    save_problem(path, dataclasses.replace(problem, meta=meta))
    return path, load_problem(path)


def _hertz(P, R, E, nu):
    """Hertz's sphere on a rigid flat, written out (Johnson §4.2)."""
    a = (3 * P * R * (1 - nu ** 2) / (4 * E)) ** (1 / 3)
    return a, 3 * P / (2 * np.pi * a * a)


def test_quarter_sphere_without_its_keys_gets_the_same_curve(sphere,
                                                             tmp_path):
    """The shipped file says quarter and contact_center; a file without
    them gets the same reference from its rollers and gaps: 2 symmetry
    planes, P = 4 × the model's force (before: P 4× too small, radii from
    the node of largest pressure), the centre on the axis."""
    _, problem, result = sphere
    _, user = _with_meta(problem, tmp_path,
                         drop=("quarter", "contact_center"))
    shipped, derived = hertz_reference(problem, result), \
        hertz_reference(user, result)
    for ref in (shipped, derived):
        assert ref.drawn, ref.note
        assert ref.planes == ((0, 0.0), (1, 0.0)) and ref.copies == 4
        np.testing.assert_allclose(ref.center, 0.0, atol=1e-6)
        np.testing.assert_allclose(ref.axis, [0, 0, -1], atol=1e-12)
        assert ref.force == pytest.approx(37.3, rel=2e-3)
        assert ref.a == pytest.approx(0.0503, rel=1e-3)
        assert (ref.a, ref.p0) == pytest.approx(
            _hertz(ref.force, 1.0, problem.meta["E"], problem.meta["nu"]),
            rel=1e-12)
    assert (derived.force, derived.a, derived.p0) == \
        (shipped.force, shipped.a, shipped.p0)
    np.testing.assert_array_equal(derived.center, shipped.center)


def test_command_line_draws_it_for_a_user_file(sphere, tmp_path):
    """``python -m solver user.npz --plots`` (the job calls only
    write_figures3d) writes pressure_radius.png for the file without the
    shipped keys."""
    from solver.cli import main

    _, problem, _ = sphere
    path, _ = _with_meta(problem, tmp_path,
                         drop=("quarter", "contact_center"))
    out = tmp_path / "out"
    assert main([str(path), "--plots", "-o", str(out)]) == 0
    assert (out / "pressure_radius.png").read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize("drop, changes, why", [
    (("R",), {}, "meta has no R"),
    ((), {"R": 2.0}, "curvature radii"),
    (("quarter",), {"half": True}, "meta says half"),
    ((), {"contact_center": [0.3, 0.0, 0.0]}, "contact_center"),
], ids=["no R", "wrong R", "half on a quarter", "centre elsewhere"])
def test_no_curve_rather_than_a_wrong_one(sphere, tmp_path, drop, changes,
                                         why):
    """Without R, with an R the gap contradicts, or with keys that
    contradict the supports: no curve, and the title says why."""
    _, problem, result = sphere
    _, user = _with_meta(problem, tmp_path, drop=drop, **changes)
    ref = hertz_reference(user, result)
    assert not ref.drawn and ref.a is None and why in ref.note
    fig = plot_pressure_vs_radius(user, result)
    assert why in fig.axes[0].get_title()
    assert not any(line.get_label().startswith("Hertz")
                   for ax in fig.axes for line in ax.lines)


def test_half_and_quarter_give_the_whole_body(tmp_path):
    """The mirror-symmetric block on the paraboloid z = −κr² (gap κr²:
    R* = 1/(2κ)): whole, half and quarter give 0, 1 and 2 symmetry
    planes, the whole model's force, the same centre (the origin) and
    the same curve."""
    from test_rollers import KAPPA, block_3d

    refs = {}
    for part in ("whole", "half", "quarter"):
        problem = block_3d(part)
        problem.meta = {"R": 1 / (2 * KAPPA), "E": 100.0, "nu": 0.3}
        result = solve_frictionless(problem, "min", tol=1e-13)
        refs[part] = hertz_reference(problem, result)
        assert refs[part].drawn, refs[part].note
        if part == "whole":
            force = float(np.sum(result.contact_force
                                 * -result.normal[:, 2]))
    assert [len(refs[p].planes) for p in refs] == [0, 1, 2]
    assert [refs[p].copies for p in refs] == [1, 2, 4]
    for ref in refs.values():
        assert ref.force == pytest.approx(force, rel=1e-9)
        np.testing.assert_allclose(ref.center, 0.0, atol=1e-9)
        np.testing.assert_allclose(ref.curvature_radii, 1 / (2 * KAPPA),
                                   rtol=1e-9)
        assert (ref.a, ref.p0) == pytest.approx(
            _hertz(force, 1 / (2 * KAPPA), 100.0, 0.3), rel=1e-9)


def test_planes_need_rollers_on_one_plane():
    """u_z = 0 at every node of a slab is not a mirror (its nodes are on
    two planes); nor is a plane whose nodes' normals cross it."""
    from test_rollers import block_3d

    problem = block_3d("quarter")
    normal = np.tile([0.0, 0.0, -1.0], (problem.n_contact, 1))
    assert symmetry_planes(problem, normal) == ((0, 0.0), (1, 0.0))
    normal[:, 0] = 0.1
    assert symmetry_planes(problem, normal) == ((1, 0.0),)
    slab = dataclasses.replace(problem, contact_dofs=np.where(
        np.arange(3) == 2, -1, np.abs(problem.contact_dofs)))
    slab.nodes = problem.nodes.copy()
    slab.nodes[slab.contact_nodes[::2], 2] += 1.0
    assert symmetry_planes(slab) == ()


def test_a_line_contact_has_no_centre():
    """A cylinder's gap κx² has no single minimum: no centre, no axis."""
    x, y = np.meshgrid(np.linspace(-1, 1, 9), np.linspace(-1, 1, 9))
    points = np.column_stack([x.ravel(), y.ravel(), 0 * x.ravel()])
    normal = np.tile([0.0, 0.0, -1.0], (len(points), 1))
    center, axis, why = first_contact(points, 0.25 * points[:, 0] ** 2,
                                      normal)
    assert center is None and axis is None and "single minimum" in why


def test_a_2d_problem_gets_no_point_contact_curve(exported):
    problem = load_problem(exported(118)[0])
    ref = hertz_reference(problem, solve_frictionless(problem))
    assert not ref.drawn and "3D" in ref.note


def test_a_result_without_gaps_gets_no_curve(sphere):
    """A result that carries no gaps (an engine that does not return
    them) gets no curve and the note names what is missing."""
    _, problem, result = sphere
    partial = {k: v for k, v in result.items() if k != "gap"}
    ref = hertz_reference(problem, partial)
    assert not ref.drawn and ref.note.endswith("has no gap")
