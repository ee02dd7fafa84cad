"""3D obstacle surfaces (solver/geometry/surface*.py).

References: closed forms written out here (sphere, plane, paraboloid
heights), the same surface in another representation (graph vs parametric,
sphere in spherical coordinates, plane as a parametric plane), and a brute
force (dense sampling + scipy.optimize.minimize) independent of the Newton
search.
"""

import json

import numpy as np
import pytest
from scipy.optimize import minimize

from solver.errors import ProblemError, SolverError
from solver.geometry.surfaces import search as surface_search
from solver.geometry.surfaces import GapError, surface_from_spec

R = 2.0
PARABOLOID = f"(x**2 + y**2)/(2*{R})"
PARABOLOID_ST = {"kind": "parametric", "x": "s", "y": "t",
                 "z": f"(s**2 + t**2)/(2*{R})", "s_range": [-4, 4],
                 "t_range": [-4, 4]}
SPHERE = {"kind": "sphere", "center": [0.5, -0.25, 1.0], "radius": 1.5}
# the same ball in spherical coordinates (s: polar angle, t: azimuth);
# c_s × c_t = sin(s)·(radial): outward
SPHERE_ST = {"kind": "parametric", "x": "0.5 + 1.5*sin(s)*cos(t)",
             "y": "-0.25 + 1.5*sin(s)*sin(t)", "z": "1.0 + 1.5*cos(s)",
             "s_range": [0.01, 3.0], "t_range": [-4, 4]}
PLANE = {"kind": "plane", "point": [0.0, 0.0, 1.0], "normal": [1.0, 2.0, 2.0]}


def _cap_points(m, seed=0):
    """Points around the upper cap of SPHERE, some inside the ball."""
    rng = np.random.default_rng(seed)
    polar = rng.uniform(0.3, 1.2, m)  # off the pole of SPHERE_ST
    azimuth = rng.uniform(-np.pi, np.pi, m)
    radius = rng.uniform(0.6, 3.0, m)
    u = np.c_[np.sin(polar) * np.cos(azimuth),
              np.sin(polar) * np.sin(azimuth), np.cos(polar)]
    return np.array(SPHERE["center"]) + radius[:, None] * u


def test_sphere_closest_points_closed_form_and_parametric():
    points = _cap_points(500)
    c, r = np.array(SPHERE["center"]), SPHERE["radius"]
    v = points - c
    rho = np.linalg.norm(v, axis=1)
    gap, nu, foot = surface_from_spec(SPHERE).gap_along_obstacle_normal(points)
    np.testing.assert_allclose(gap, rho - r, rtol=0, atol=1e-12)
    np.testing.assert_allclose(nu, -v / rho[:, None], rtol=0, atol=1e-12)
    np.testing.assert_allclose(foot, c + r * v / rho[:, None], atol=1e-12)
    assert (gap < 0).any() and (gap > 0).any()  # both sides tested
    g2, nu2, f2 = surface_from_spec(SPHERE_ST).gap_along_obstacle_normal(
        points)
    np.testing.assert_allclose(g2, rho - r, rtol=0, atol=1e-12)
    np.testing.assert_allclose(nu2, nu, rtol=0, atol=1e-10)
    np.testing.assert_allclose(f2, foot, rtol=0, atol=1e-10)


def test_plane_closest_points_closed_form_and_parametric():
    rng = np.random.default_rng(1)
    points = rng.uniform(-3, 3, (300, 3))
    n = np.array([1.0, 2.0, 2.0]) / 3.0
    expected = (points - [0, 0, 1]) @ n
    gap, nu, foot = surface_from_spec(PLANE).gap_along_obstacle_normal(points)
    np.testing.assert_allclose(gap, expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(nu, np.tile(-n, (300, 1)), atol=1e-15)
    np.testing.assert_allclose(foot, points - expected[:, None] * n,
                               atol=1e-12)
    # the plane p + s e1 + t e2 with e1 × e2 = n
    e1 = np.array([2.0, -1.0, 0.0]) / np.sqrt(5)
    e2 = np.cross(n, e1)
    spec = {"kind": "parametric", "s_range": [-20, 20], "t_range": [-20, 20]}
    for k, name in enumerate("xyz"):
        spec[name] = (f"{[0, 0, 1][k]} + ({float(e1[k])!r})*s"
                      f" + ({float(e2[k])!r})*t")
    g2, nu2, f2 = surface_from_spec(spec).gap_along_obstacle_normal(points)
    np.testing.assert_allclose(g2, expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(nu2, nu, atol=1e-12)


def test_paraboloid_graph_matches_parametric_and_brute_force():
    rng = np.random.default_rng(2)
    points = rng.uniform(-1.5, 1.5, (400, 3))
    points[:, 2] = rng.uniform(-0.3, 2.5, 400)
    graph = surface_from_spec({"kind": "graph", "z": PARABOLOID})
    gap, nu, foot = graph.gap_along_obstacle_normal(points)
    g2, nu2, f2 = surface_from_spec(PARABOLOID_ST) \
        .gap_along_obstacle_normal(points)
    np.testing.assert_allclose(gap, g2, rtol=0, atol=1e-12)
    np.testing.assert_allclose(foot, f2, rtol=0, atol=1e-9)
    # the foot is on the surface and the sign follows z - h
    np.testing.assert_allclose(foot[:, 2], (foot[:, 0] ** 2
                                            + foot[:, 1] ** 2) / (2 * R),
                               atol=1e-14)
    h = (points[:, 0] ** 2 + points[:, 1] ** 2) / (2 * R)
    assert (np.sign(gap) == np.sign(points[:, 2] - h)).all()
    # outward normal of z = h: (-h_x, -h_y, 1)/norm, nu = minus it
    grad = np.c_[-foot[:, :2] / R, np.ones(400)]
    np.testing.assert_allclose(
        nu, -grad / np.linalg.norm(grad, axis=1)[:, None], atol=1e-12)

    # brute force for a few points: best of a dense grid, then Nelder-Mead
    s = np.linspace(-3, 3, 601)
    S, T = np.meshgrid(s, s)
    cloud = np.c_[S.ravel(), T.ravel(), (S.ravel() ** 2 + T.ravel() ** 2)
                  / (2 * R)]
    for i in range(8):
        p = points[i]
        best = cloud[np.argmin(np.sum((cloud - p) ** 2, axis=1)), :2]
        res = minimize(lambda u: np.sum((np.r_[u, u @ u / (2 * R)] - p) ** 2),
                       best, method="Nelder-Mead",
                       options={"xatol": 1e-12, "fatol": 1e-16})
        assert abs(np.sqrt(res.fun) - abs(gap[i])) < 1e-9
        np.testing.assert_allclose(foot[i, :2], res.x, atol=1e-6)


def test_rays_plane_sphere_closed_form():
    rng = np.random.default_rng(3)
    points = rng.uniform(-2, 2, (200, 3)) + [0, 0, 3]
    d = rng.normal(size=(200, 3))
    d[:, 2] = -2 - np.abs(d[:, 2])
    d /= np.linalg.norm(d, axis=1)[:, None]
    n = np.array([1.0, 2.0, 2.0]) / 3
    tau, foot = surface_from_spec(PLANE).gap_along_rays(points, d)
    np.testing.assert_allclose(tau, -((points - [0, 0, 1]) @ n) / (d @ n),
                               rtol=1e-13)
    np.testing.assert_allclose((foot - [0, 0, 1]) @ n, 0, atol=1e-13)

    # sphere: rays from the cap points towards the centre, tilted a little
    points = _cap_points(300, seed=4)
    c, r = np.array(SPHERE["center"]), SPHERE["radius"]
    d = c - points + 0.1 * rng.normal(size=(300, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    v = points - c
    b, q = np.sum(d * v, 1), np.sum(v * v, 1) - r * r
    roots = np.stack([-b - np.sqrt(b * b - q), -b + np.sqrt(b * b - q)])
    expected = roots[np.argmin(np.abs(roots), axis=0), np.arange(300)]
    tau, foot = surface_from_spec(SPHERE).gap_along_rays(points, d)
    np.testing.assert_allclose(tau, expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(foot - c, axis=1), r,
                               atol=1e-12)
    # ... and the same ball in spherical coordinates (Newton)
    t2, f2 = surface_from_spec(SPHERE_ST).gap_along_rays(points, d)
    np.testing.assert_allclose(t2, expected, rtol=0, atol=1e-11)


def test_rays_paraboloid_vertical_closed_form():
    rng = np.random.default_rng(5)
    points = rng.uniform(-1.5, 1.5, (300, 3))
    down = np.tile([0.0, 0.0, -1.0], (300, 1))
    h = (points[:, 0] ** 2 + points[:, 1] ** 2) / (2 * R)
    for spec in ({"kind": "graph", "z": PARABOLOID}, PARABOLOID_ST):
        tau, foot = surface_from_spec(spec).gap_along_rays(points, down)
        np.testing.assert_allclose(tau, points[:, 2] - h, rtol=0, atol=1e-13)


def test_gap_along_normals_of_the_obstacle_equals_closest_point_gap():
    points = _cap_points(100, seed=6)
    for spec in (SPHERE, SPHERE_ST):
        surface = surface_from_spec(spec)
        gap, nu, _ = surface.gap_along_obstacle_normal(points)
        tau, _ = surface.gap_along_rays(points, nu)
        np.testing.assert_allclose(tau, gap, rtol=0, atol=1e-12)


@pytest.mark.parametrize("spec", [SPHERE, PLANE, PARABOLOID_ST,
                                  {"kind": "graph", "z": PARABOLOID}])
def test_spec_round_trip(spec):
    surface = surface_from_spec(spec)
    text = json.dumps(surface.spec())
    assert json.loads(text) == {k: (list(map(float, v))
                                    if isinstance(v, list) else v)
                                for k, v in spec.items()}
    again = surface_from_spec(text)
    assert again.spec() == surface.spec()
    assert len(repr(surface)) < 200 and type(surface).__name__ in repr(surface)


BAD = [
    ([1, 2], "surface spec: need a dict"),
    ("{not json", "surface spec: not valid JSON"),
    ({"kind": "cone"}, "surface kind: unknown 'cone'"),
    ({"kind": ["plane"]}, "surface kind: unknown"),
    ({"kind": "sphere", "center": [0, 0, 0]}, "surface radius: missing"),
    ({"kind": "sphere", "center": [0, 0, 0], "radius": 1, "radus": 1},
     "surface radus: unknown field"),
    ({"kind": "sphere", "center": [0, 0, np.nan], "radius": 1},
     "surface center: need 3 finite numbers"),
    ({"kind": "sphere", "center": [0, 0], "radius": 1},
     "surface center: need 3 finite numbers"),
    ({"kind": "sphere", "center": [0, 0, 0], "radius": 0},
     "surface radius: must be > 0"),
    ({"kind": "sphere", "center": [0, 0, 0], "radius": "big"},
     "surface radius: need a finite number"),
    ({"kind": "plane", "point": [0, 0, 0], "normal": [0, 0, 0]},
     "surface normal: must be non-zero"),
    ({"kind": "plane", "point": [0, 0, np.inf], "normal": [0, 0, 1]},
     "surface point: need 3 finite numbers"),
    ({"kind": "graph", "z": "x +"}, "surface z: 'x +': syntax error"),
    ({"kind": "graph", "z": "s*t"}, "surface z: 's*t': unknown name 's'"),
    ({"kind": "graph", "z": "__import__('os')"}, "surface z:"),
    (dict(PARABOLOID_ST, z="t**2"), None),  # fine: x = s, y = t
    (dict(PARABOLOID_ST, x="1", y="2", z="s"),
     "does not depend on t"),
    (dict(PARABOLOID_ST, s_range=[1, 1]), "surface s_range: need finite"),
    (dict(PARABOLOID_ST, t_range=[0, np.inf]), "surface t_range: need"),
    (dict(PARABOLOID_ST, t_range="ab"), "surface t_range: need two"),
]


@pytest.mark.parametrize("spec, fragment", BAD)
def test_bad_specs_give_one_line_problem_errors(spec, fragment):
    if fragment is None:
        surface_from_spec(spec)
        return
    with pytest.raises(ProblemError) as info:
        surface_from_spec(spec)
    message = str(info.value)
    assert fragment in message and "\n" not in message


def test_newton_failure_is_a_solver_error_naming_the_count(monkeypatch):
    monkeypatch.setattr(surface_search, "_MAX_ITER", 1)
    points = _cap_points(50, seed=7)
    with pytest.raises(SolverError, match=r"did not converge for \d+ of 50 "
                       "contact nodes"):
        surface_from_spec(SPHERE_ST).gap_along_obstacle_normal(points)


def test_misses_and_edges_are_gap_errors():
    points = np.array([[0.0, 0.0, 1.0], [4.0, 0.0, 5.0]])
    up = np.tile([0.0, 0.0, 1.0], (2, 1))
    with pytest.raises(GapError, match="rays miss the sphere .* for 2 of 2"):
        surface_from_spec(SPHERE).gap_along_rays(points + [10, 0, 0], up)
    with pytest.raises(GapError, match="parallel to the plane"):
        surface_from_spec({"kind": "plane", "point": [0, 0, 0],
                           "normal": [0, 0, 1]}).gap_along_rays(
            points, [1.0, 0.0, 0.0])
    small = dict(PARABOLOID_ST, s_range=[-1, 1], t_range=[-1, 1])
    with pytest.raises(GapError, match="edge of s_range .* for 1 of 2"):
        surface_from_spec(small).gap_along_obstacle_normal(points)
    with pytest.raises(GapError, match="rays miss the obstacle surface"):
        surface_from_spec(small).gap_along_rays(points, -up)
    with pytest.raises(GapError, match="centre"):
        surface_from_spec(SPHERE).gap_along_obstacle_normal(
            [SPHERE["center"]])


def test_no_points_and_broadcast_direction():
    surface = surface_from_spec(PARABOLOID_ST)
    gap, nu, foot = surface.gap_along_obstacle_normal(np.zeros((0, 3)))
    assert gap.shape == (0,) and nu.shape == foot.shape == (0, 3)
    tau, _ = surface.gap_along_rays([[0.5, 0.5, 2.0]], [0, 0, -2.0])
    assert tau[0] == pytest.approx(2.0 - 0.5 / (2 * R), abs=1e-14)


def test_module_example_runs():
    import doctest

    import solver.geometry.surfaces as module

    assert doctest.testmod(module).failed == 0


def test_spherical_cap_as_a_graph_matches_the_sphere():
    rng = np.random.default_rng(8)
    polar, azimuth = rng.uniform(0, 0.8, 500), rng.uniform(-np.pi, np.pi, 500)
    points = rng.uniform(1.7, 2.6, 500)[:, None] * np.c_[
        np.sin(polar) * np.cos(azimuth), np.sin(polar) * np.sin(azimuth),
        np.cos(polar)]
    cap = surface_from_spec({"kind": "graph", "z": "sqrt(4 - x**2 - y**2)"})
    ball = surface_from_spec({"kind": "sphere", "center": [0, 0, 0],
                              "radius": 2})
    for got, expected in zip(cap.gap_along_obstacle_normal(points),
                             ball.gap_along_obstacle_normal(points)):
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-11)
    inward = -points / np.linalg.norm(points, axis=1)[:, None]
    np.testing.assert_allclose(cap.gap_along_rays(points, inward)[0],
                               ball.gap_along_rays(points, inward)[0],
                               rtol=0, atol=1e-12)
