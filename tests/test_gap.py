"""Signed gaps along normals (thesis §2.1, (1)-(7)).

All reference values are analytic: point-line distances, distances to a
circle (|B - c| - r), intersections of horizontal lines with a circle and a
parabola, and the nearest point of the thesis parabola from the closed-form
root of its foot-point cubic (cross-checked by dense brute force).
"""

import time

import numpy as np
import pytest

from solver.geometry.curves import (GapError, gap_along_normals, gap_from_obstacle,
                        parameter_window)
from solver.errors import InitialPenetrationWarning
from solver.geometry.curves.parametric import ParametricCurve

# Tests whose points lie past the obstacle on purpose say so with
# pytest.warns; any other initial penetration here is an error.
pytestmark = pytest.mark.filterwarnings(
    "error::solver.errors.InitialPenetrationWarning")


def penetrates(node):
    """Expect the warning naming the one penetrating contact node."""
    return pytest.warns(InitialPenetrationWarning,
                        match=rf"at 1 contact node \({node}\)")

# Line x = 6 + 0.3 y, i.e. 6 + 0.3 y - x = 0; its unit normal towards +x
# is (1, -0.3) / sqrt(1.09).
LINE = ParametricCurve("6 + 0.3*t", "t")
LINE_POINTS = np.array([[0.0, 0.0], [5.0, 3.0], [1.0, -2.0], [4.0, 10.0],
                        [7.0, 0.0]])
# Thesis obstacle (§4) right of the block edge x = 5.
PARABOLA = ParametricCurve("5.05 + 0.005*t**2", "t")
# Left half of the circle of radius 2 about (8, 0).
CIRCLE = ParametricCurve("8 + 2*cos(t)", "2*sin(t)",
                         (np.pi / 2, 3 * np.pi / 2))
CENTRE, RADIUS = np.array([8.0, 0.0]), 2.0


def test_line_from_obstacle_is_point_line_distance():
    with penetrates(4):
        gap, normal, t = gap_from_obstacle(LINE_POINTS, LINE, (1.0, 0.0))
    x, y = LINE_POINTS.T
    expected = (6 + 0.3 * y - x) / np.sqrt(1.09)
    assert np.allclose(gap, expected, rtol=0, atol=1e-13)
    assert gap[-1] < 0  # (7, 0) lies past the line
    assert np.allclose(normal, np.array([1.0, -0.3]) / np.sqrt(1.09),
                       atol=1e-15)
    # Foot points: B + s * normal lies on the line at parameter t = y.
    foot = LINE_POINTS + gap[:, None] * normal
    assert np.allclose(foot, LINE.point(t), atol=1e-13)


def test_line_along_horizontal_normals():
    with penetrates(4):
        gap, normal, t = gap_along_normals(LINE_POINTS, (1.0, 0.0), LINE)
    x, y = LINE_POINTS.T
    assert np.allclose(gap, 6 + 0.3 * y - x, rtol=0, atol=1e-13)
    assert np.allclose(t, y, atol=1e-13)
    assert np.array_equal(normal, np.tile([1.0, 0.0], (5, 1)))


def test_normals_are_normalised():
    # Errata (3)/(6): the distance is |k| |nu|, so nu must be unit first.
    with penetrates(4):
        short = gap_along_normals(LINE_POINTS, (1.0, 0.0), LINE)[0]
    with penetrates(4):
        long_ = gap_along_normals(LINE_POINTS, (7.0, 0.0), LINE)[0]
    assert np.allclose(short, long_, atol=1e-13)


def test_circle_from_obstacle():
    angle = np.radians(np.linspace(100, 260, 9))
    distance = np.array([0.5, 1, 2, 3, 0.1, 1.5, 4, 0.25, 2.5])
    points = CENTRE + (RADIUS + distance)[:, None] \
        * np.column_stack([np.cos(angle), np.sin(angle)])
    gap, normal, t = gap_from_obstacle(points, CIRCLE, (1.0, 0.0))
    assert np.allclose(gap, np.linalg.norm(points - CENTRE, axis=1) - RADIUS,
                       rtol=0, atol=1e-13)
    assert np.allclose(t, angle, atol=1e-12)
    # normal points from the body (left) into the circle: towards the centre
    radial = CENTRE - points
    radial /= np.linalg.norm(radial, axis=1, keepdims=True)
    assert np.allclose(normal, radial, atol=1e-12)


def test_circle_along_horizontal_normals():
    y = np.linspace(-1.5, 1.5, 7)
    points = np.column_stack([np.full_like(y, 5.0), y])
    gap, _, t = gap_along_normals(points, (1.0, 0.0), CIRCLE)
    assert np.allclose(gap, 3 - np.sqrt(4 - y ** 2), rtol=0, atol=1e-13)
    assert np.allclose(CIRCLE.point(t), points + gap[:, None] * [1, 0],
                       atol=1e-13)


def test_inside_circle_gives_negative_gap():
    point = np.array([[7.0, 0.5]])  # inside the disc, past the left arc
    with penetrates(0):
        gap, normal, _ = gap_from_obstacle(point, CIRCLE, (1.0, 0.0))
    assert np.isclose(gap[0], np.hypot(1.0, 0.5) - 2.0, atol=1e-14)
    assert gap[0] < 0 and normal[0, 0] > 0
    with penetrates(0):
        gap, _, _ = gap_along_normals(point, (1.0, 0.0), CIRCLE)
    assert np.isclose(gap[0], 8 - np.sqrt(3.75) - 7, atol=1e-14)


def parabola_foot(y0, a=0.05, c=0.005):
    r"""Nearest point of x = 5 + a + c t^2, y = t from (5, y0), analytic.

    d/dt |Γ(t) - B|^2 = 0 is the cubic 2c^2 t^3 + (1 + 2ac) t - y0 = 0,
    i.e. t^3 + p t + q = 0 with p > 0: one real root, in hyperbolic form
    t = -2 sqrt(p/3) sinh(asinh(3q/(2p) sqrt(3/p)) / 3).
    """
    p = (1 + 2 * a * c) / (2 * c ** 2)
    q = -np.asarray(y0, dtype=float) / (2 * c ** 2)
    t = -2 * np.sqrt(p / 3) * np.sinh(
        np.arcsinh(1.5 * q / p * np.sqrt(3 / p)) / 3)
    return t, np.hypot(a + c * t ** 2, t - y0)


def test_thesis_parabola_both_ways():
    y = np.linspace(-10, 10, 21)
    points = np.column_stack([np.full_like(y, 5.0), y])
    along, normal_b, t_b = gap_along_normals(points, (1.0, 0.0), PARABOLA)
    assert np.allclose(along, 0.05 + 0.005 * y ** 2, rtol=0, atol=1e-14)
    assert np.allclose(t_b, y, atol=1e-14)

    t_ref, d_ref = parabola_foot(y)
    # Independent check of the closed form by dense brute force (spacing
    # 1e-4: the sampled minimum is above the true one by at most
    # h^2/8 * max d'' = 1.25e-9 * 1/0.05, i.e. < 1e-7).
    dense = np.linspace(-12, 12, 240001)
    brute = np.min(np.hypot(0.05 + 0.005 * dense[None, :] ** 2,
                            dense[None, :] - y[:, None]), axis=1)
    assert (brute >= d_ref - 1e-15).all()
    assert np.allclose(brute, d_ref, rtol=0, atol=1e-7)

    nearest, normal_o, t_o = gap_from_obstacle(points, PARABOLA, (1.0, 0.0))
    assert np.allclose(nearest, d_ref, rtol=0, atol=1e-14)
    assert np.allclose(t_o, t_ref, atol=1e-12)
    assert (normal_o[:, 0] > 0.99).all()
    # The two choices of the thesis agree for this flat parabola up to a
    # small difference (largest at the ends, 2.7e-3 of 0.55 at y = +-10);
    # the nearest distance is never larger than one along a line.
    difference = along - nearest
    assert (difference >= 0).all() and difference.max() < 3e-3
    assert difference[10] == 0.0  # y = 0: the normals coincide
    assert np.isclose(difference.max(), 0.55 - d_ref[-1], atol=1e-15)


def test_penetration_of_the_parabola_is_negative():
    point = np.array([[5.1, 0.0]])
    with penetrates(0):
        nearest = gap_from_obstacle(point, PARABOLA, (1, 0))[0][0]
    with penetrates(0):
        along = gap_along_normals(point, (1, 0), PARABOLA)[0][0]
    assert np.isclose(nearest, -0.05, atol=1e-15)
    assert np.isclose(along, -0.05, atol=1e-15)


def test_line_parallel_to_the_normal_is_an_error():
    vertical = ParametricCurve("6", "t")  # x = 6, along the normal (0, 1)
    points = np.array([[5.0, -10.0], [5.0, 0.0]])
    with pytest.raises(GapError, match=r"contact node 0 at \(5, -10\) "
                                       r"misses the obstacle"):
        gap_along_normals(points, (0.0, 1.0), vertical)
    with pytest.raises(GapError, match="nearly perpendicular"):
        gap_from_obstacle(points, vertical, (0.0, 1.0))
    # a line containing the normal line: roots everywhere, all grazing
    with pytest.raises(GapError, match="grazing"):
        gap_along_normals([[6.0, 0.0]], (0.0, 1.0), vertical)


def test_t_range_missed_is_an_error():
    points = np.array([[5.0, 0.0], [5.0, 3.0]])
    with pytest.raises(GapError, match=r"node 7 at \(5, 3\) misses the "
                                       r"obstacle: no intersection .*t_range"):
        gap_along_normals(points, (1.0, 0.0), CIRCLE, node_ids=[6, 7])
    # nearest point of (9, 5) on the left half is its end t = pi/2
    with pytest.raises(GapError, match="end t = 1.5708 of the obstacle"):
        gap_from_obstacle([[9.0, 5.0]], CIRCLE, (0.0, 1.0))
    # ... but an end that is a true foot point is accepted
    gap, _, t = gap_from_obstacle([[8.0, 5.0]], CIRCLE, (0.0, -1.0))
    assert np.isclose(gap[0], 3.0, atol=1e-14) and t[0] == np.pi / 2


def test_default_window_and_explicit_window():
    points = np.array([[5.0, 3.0]])
    # The window follows the body's extent, not the parametrisation: the
    # foot of (5, 3) on x = 6 is t = 3 for y = t and t = 300 for the slow
    # y = t / 100, both found without a window (analytic: gap 1).
    for curve, foot in ((ParametricCurve("6", "t"), 3.0),
                        (ParametricCurve("6", "t/100"), 300.0),
                        (ParametricCurve("6", "1e4*t"), 3e-4)):
        (t0, t1), ends = parameter_window(points, curve)
        assert t0 < foot < t1 and ends == (False, False)
        for result in (gap_from_obstacle(points, curve, (1.0, 0.0)),
                       gap_along_normals(points, (1.0, 0.0), curve)):
            assert np.isclose(result[0][0], 1.0, atol=1e-14)
            assert np.isclose(result[2][0], foot, rtol=1e-12)
    # An explicit window is used as given (and asks for a larger one when
    # the foot lies outside it) ...
    slow = ParametricCurve("6", "t/100")
    with pytest.raises(GapError, match="larger search interval"):
        gap_from_obstacle(points, slow, (1.0, 0.0), window=(-10, 10))
    with pytest.raises(GapError, match="larger search interval"):
        gap_along_normals(points, (1.0, 0.0), slow, window=(-10, 10))
    for result in (gap_from_obstacle(points, slow, (1, 0), window=(-1e3, 1e3)),
                   gap_along_normals(points, (1, 0), slow, window=(0, 1e3))):
        assert np.isclose(result[0][0], 1.0, atol=1e-14)
        assert np.isclose(result[2][0], 300.0, atol=1e-10)
    # ... and so is the curve's own search interval
    slow.search_interval = (-10.0, 10.0)
    with pytest.raises(GapError, match="larger search interval"):
        gap_from_obstacle(points, slow, (1.0, 0.0))
    # an explicit window is clipped to the t_range
    assert parameter_window(points, CIRCLE, (0, 10)) \
        == ((np.pi / 2, 3 * np.pi / 2), (True, True))


def test_nearest_of_several_roots():
    # Circle about (8, 0) without t_range: the horizontal line through
    # (5, 1) meets it twice; the nearer intersection is taken.
    full = ParametricCurve("8 + 2*cos(t)", "2*sin(t)")
    gap, _, t = gap_along_normals([[5.0, 1.0]], (1.0, 0.0), full)
    assert np.isclose(gap[0], 3 - np.sqrt(3), atol=1e-13)
    assert np.isclose(np.cos(t[0]), -np.sqrt(3) / 2, atol=1e-13)
    gap, _, _ = gap_from_obstacle([[5.0, 1.0]], full, (1.0, 0.0))
    assert np.isclose(gap[0], np.sqrt(10) - 2, atol=1e-13)


def test_thousand_points_fast():
    y = np.linspace(-10, 10, 1000)
    points = np.column_stack([np.full_like(y, 5.0), y])
    start = time.perf_counter()
    nearest = gap_from_obstacle(points, PARABOLA, (1.0, 0.0))[0]
    along = gap_along_normals(points, (1.0, 0.0), PARABOLA)[0]
    assert time.perf_counter() - start < 2.0
    assert np.allclose(along, 0.05 + 0.005 * y ** 2, atol=1e-14)
    assert np.allclose(nearest, parabola_foot(y)[1], atol=1e-14)


def test_sine_wave_obstacle_along_the_body_normal():
    """x = 5.2 + 0.05 sin(t), y = t seen along (1, 0) from (5, y): the gap is
    0.2 + 0.05 sin(y) exactly (analytic)."""
    from solver.geometry.curves.parametric import ParametricCurve

    curve = ParametricCurve("5.2 + 0.05*sin(t)", "t")
    ys = np.linspace(-9.5, 9.5, 39)
    points = np.c_[np.full_like(ys, 5.0), ys]
    gap, normal, t = gap_along_normals(points, np.array([1.0, 0.0]), curve)
    np.testing.assert_allclose(gap, 0.2 + 0.05 * np.sin(ys), atol=1e-13)
    np.testing.assert_allclose(t, ys, atol=1e-12)
