"""Obstacles whose numbers overflow (issue 16, class 2, obstacles).

An obstacle placed by numbers beyond double precision's reach (a sphere of
radius 1e300 centred at (0, 0, −1e300), a polyline vertex at 1e308, a
parameter range of 1e300) or whose expression's derivative overflows
(1e308·t², derivative 2e308·t) is refused when the problem is loaded: exit
2, one line naming the key (``obstacle_surface``, ``obstacle_points``,
``obstacle_x``), nothing written. Before, such files loaded and the solve
failed later for a reason that pointed elsewhere (an infinite gap and a
zero normal ended in "PARDISO phase 11 failed", or "K is not positive
definite ... is the body supported?").

A direction is only a direction: plane normals (0, 0, 1e308) and
(0, 0, 1e-320), whose squares overflow or underflow, and a curve run at
speed 1e300 give the same gaps and the same answer as (0, 0, 1) and the
plain line (references: the analytic gaps of a flat obstacle).

The body in 3D: the unit cube (2×2×2 boxes of 6 tetrahedra, P1 elasticity
from ``tests/tet_elasticity.py``), top face pressed down by 0.02, its
bottom z = 0 the contact surface above the plane z = −0.01. In 2D the
118-triangle thesis block (Γc: x = 5).
"""

import json

import numpy as np
import pytest

from fault_tools import PLANE, run_cli, unit_cube, write
from fault_tools import block  # noqa: F401  (the fixture)
from solver import solve_frictionless
from solver.contact import contact_geometry
from solver.errors import ProblemError
from solver.geometry.curves import GapError
from solver.problem import load_problem


@pytest.fixture(scope="module")
def cube():
    """The arrays of the pressed unit cube above PLANE (see the module)."""
    return unit_cube()


def with_surface(cube, spec):
    return dict(cube, obstacle_surface=np.array(json.dumps(spec)))


def refused_everywhere(path, phrases, tmp_path, capsys):
    """load_problem, the solve and --info: the same one line, nothing
    written."""
    with pytest.raises(ProblemError) as info:
        load_problem(path)
    message = str(info.value)
    assert "\n" not in message
    for phrase in phrases:
        assert phrase in message, (phrase, message)
    before = sorted(p.name for p in tmp_path.iterdir())
    for argv in ([path, "-o", tmp_path / "out"], [path, "--info"],
                 [path, "--linear-solver", "superlu", "-o", tmp_path / "o"]):
        code, out, err = run_cli(argv, capsys)
        assert code == 2, (argv, err)
        assert err == f"error: {message}\n" and out == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == before


# --------------------------------------------------------------------------
# 3D: refused at load, naming obstacle_surface and the field

SURFACES = [
    ("sphere of radius 1e300 at (0, 0, -1e300)",
     {"kind": "sphere", "center": [0.0, 0.0, -1e300], "radius": 1e300},
     ["obstacle_surface: surface center: 1e+300 is out of the supported "
      "range (at most 1e+30"]),
    ("sphere of radius 1e300 under the body",
     {"kind": "sphere", "center": [0.5, 0.5, -1.0], "radius": 1e300},
     ["obstacle_surface: surface radius: 1e+300 is out of the supported"]),
    ("sphere of radius 1e29: gaps below round-off",
     {"kind": "sphere", "center": [0.5, 0.5, -1e29], "radius": 1e29},
     ["obstacle_surface: the sphere's radius 1e+29 is more than 1e+08 "
      "times the body's size 1"]),
    ("plane through a point at 1e308",
     {"kind": "plane", "point": [0.0, 0.0, -1e308], "normal": [0, 0, 1]},
     ["obstacle_surface: surface point: 1e+308 is out of the supported"]),
    ("graph whose derivative overflows", {"kind": "graph",
                                          "z": "1e308*x**2 - 1"},
     ["obstacle_surface: surface z: '1e308*x**2 - 1': its derivative",
      "overflows", "not a finite real number"]),
    ("parametric range of 1e300",
     {"kind": "parametric", "x": "s/1e300", "y": "t", "z": "-0.01 + 0*s",
      "s_range": [-1e300, 2e300], "t_range": [-1, 2]},
     ["obstacle_surface: surface s_range: 2e+300 is out of the supported"]),
]


@pytest.mark.parametrize("name, spec, phrases", SURFACES,
                         ids=[c[0] for c in SURFACES])
def test_overflowing_surface_refused_at_load(cube, tmp_path, capsys, name,
                                             spec, phrases):
    refused_everywhere(write(tmp_path, with_surface(cube, spec)), phrases,
                       tmp_path, capsys)


def test_largest_sphere_that_resolves_the_body_loads(cube, tmp_path):
    """R = 1e7 (below 1e8 times the unit body): loaded, and its gaps are
    the distance to the sphere, −0.01 + the sag of the cap, to ~1e-8."""
    R = 1e7
    spec = {"kind": "sphere", "center": [0.5, 0.5, -0.01 - R], "radius": R}
    problem = load_problem(write(tmp_path, with_surface(cube, spec)))
    geometry = contact_geometry(problem, "obstacle", rollers=True)
    x, y, z = problem.nodes[problem.contact_nodes[geometry.index]].T
    exact = np.hypot(np.hypot(x - 0.5, y - 0.5), z + 0.01 + R) - R
    np.testing.assert_allclose(geometry.gap, exact, atol=1e-8)


# --------------------------------------------------------------------------
# 3D: a normal is a direction, whatever its length

@pytest.mark.parametrize("normal", [[0.0, 0.0, 1e308], [0.0, 0.0, 1e-320],
                                    [1e-300, 0.0, 1e300]],
                         ids=["1e308", "subnormal", "1e300 with 1e-300"])
def test_plane_normal_of_any_length(cube, tmp_path, normal):
    """The same plane as PLANE's (0, 0, 1): gaps 0.01 at every contact
    node along ν = (0, 0, −1), and the same displacement as the reference
    solve. Before: a zero normal and "PARDISO phase 11 failed" (1e308), or
    "surface normal: must be non-zero" (1e-320)."""
    reference = solve_frictionless(load_problem(write(tmp_path, cube,
                                                      "ref.npz")))
    spec = dict(PLANE, normal=normal)
    problem = load_problem(write(tmp_path, with_surface(cube, spec)))
    assert problem.obstacle.spec()["normal"] == normal  # kept as given
    geometry = contact_geometry(problem, "obstacle", rollers=True)
    np.testing.assert_allclose(geometry.gap, 0.01, rtol=1e-12)
    np.testing.assert_allclose(geometry.normal,
                               np.tile([0.0, 0.0, -1.0], (len(geometry.gap),
                                                          1)), atol=1e-12)
    result = solve_frictionless(problem)
    assert result.success and reference.success
    np.testing.assert_allclose(result.u, reference.u, rtol=0,
                               atol=1e-12 * np.abs(reference.u).max())
    assert result.in_contact.any()


# --------------------------------------------------------------------------
# 3D: surfaces out of range where the body is: a gap error that says so

@pytest.mark.parametrize("spec, phrase", [
    ({"kind": "graph", "z": "-1 + exp(100*x)"},
     "the obstacle height h(x, y) below the node is out of the supported "
     "range |z| <= 1e+30"),
    ({"kind": "parametric", "x": "s", "y": "t", "z": "-1e40 + s*t",
      "s_range": [-1, 2], "t_range": [-1, 2]},
     "the obstacle surface is not finite, or out of the supported range "
     "|x|, |y|, |z| <= 1e+30, at every sample of its parameter box"),
], ids=["graph beyond 1e30", "parametric beyond 1e30"])
def test_surface_out_of_range_at_the_body(cube, tmp_path, capsys, spec,
                                          phrase):
    """Legal specs (the expressions are finite somewhere), but not where
    the gaps are measured: refused before solving, naming the range, not
    "the closest-point Newton did not converge"."""
    path = write(tmp_path, with_surface(cube, spec))
    problem = load_problem(path)
    for mode in ("obstacle", "body"):
        with pytest.raises(GapError, match=phrase.replace("|", r"\|")
                           .replace("(", r"\(").replace(")", r"\)")
                           .replace("+", r"\+")):
            contact_geometry(problem, mode, rollers=True)
    code, out, err = run_cli([path, "-o", tmp_path / "out"], capsys)
    assert code == 2 and phrase in err and len(err.splitlines()) == 1, err
    assert not (tmp_path / "out").exists()


# --------------------------------------------------------------------------
# 2D curves

def without_curve(block):
    return {k: v for k, v in block.items()
            if k not in ("obstacle_x", "obstacle_y")}


CURVES = [
    ("polyline vertex at 1e308",
     lambda b: dict(without_curve(b), obstacle_points=np.array(
         [[5.05, -20.0], [1e308, 0.0], [5.05, 20.0]])),
     ["obstacle_points: point 1 at (1e+308, 0) is out of the supported "
      "range |x|, |y| <= 1e+30"]),
    ("polyline from -1e308 to 1e308 (its length overflows)",
     lambda b: dict(without_curve(b), obstacle_points=np.array(
         [[5.05, -1e308], [5.05, 1e308]])),
     ["obstacle_points: point 0 at (5.05, -1e+308) is out of the"]),
    ("expression whose derivative overflows",
     lambda b: dict(b, obstacle_x=np.array("5.05 + 1e308*t**2")),
     ["obstacle_x: '5.05 + 1e308*t**2': its derivative", "overflows"]),
    ("y expression whose derivative overflows",
     lambda b: dict(b, obstacle_y=np.array("t**3*1e308")),
     ["obstacle_y: 't**3*1e308': its derivative"]),
]


@pytest.mark.parametrize("name, mutate, phrases", CURVES,
                         ids=[c[0] for c in CURVES])
def test_overflowing_curve_refused_at_load(block, tmp_path, capsys, name,
                                           mutate, phrases):
    refused_everywhere(write(tmp_path, mutate(dict(block))), phrases,
                       tmp_path, capsys)


@pytest.mark.parametrize("x, y", [("5.05 + 0*t", "1e300*t"),
                                  ("5.05 + 1e-300*t**2", "1e300*t"),
                                  ("5.05 + 0*t", "1e308*t")])
@pytest.mark.parametrize("mode", ["obstacle", "body"])
def test_fast_parametrisation_of_a_line(block, tmp_path, mode, x, y):
    """x = 5.05 run at speed 1e300 is the line x = 5.05: gap 0.05 at every
    free node of Γc (x = 5), ν = (1, 0). Before: "the obstacle has no
    tangent" (the tangent's squared length overflowed)."""
    problem = load_problem(write(tmp_path, dict(
        block, obstacle_x=np.array(x), obstacle_y=np.array(y))))
    geometry = contact_geometry(problem, mode)
    np.testing.assert_allclose(geometry.gap, 0.05, rtol=1e-12)
    np.testing.assert_allclose(np.abs(geometry.normal[:, 0]), 1.0,
                               rtol=1e-12)
