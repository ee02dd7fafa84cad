"""Polyline obstacles: geometry, analytic gaps, kinks, and a full solve.

References: point-to-line distances (analytic) and, for the solve, Clarabel
on the same QP (as in test_qp_crosscheck)."""

import numpy as np
import pytest

from conftest import MESHES, solve_block
from solver import solve_frictionless
from solver.contact import contact_geometry
from solver.errors import ProblemError
from solver.geometry.curves import gap_along_normals, gap_from_obstacle
from solver.geometry.curves.polyline import PolylineCurve
from solver.problem import load_problem, save_problem
from test_qp_crosscheck import clarabel_solution

V = [[5.5, -10.0], [5.1, 0.0], [5.5, 10.0]]  # a V opening to the right


def line_distance(p, a, b):
    d = (np.asarray(b) - a) / np.linalg.norm(np.asarray(b) - a)
    r = np.asarray(p) - a
    return abs(r[0] * d[1] - r[1] * d[0])


def test_curve_geometry():
    curve = PolylineCurve(V)
    length = 2 * np.hypot(0.4, 10)
    assert curve.t_range == (0.0, pytest.approx(length))
    np.testing.assert_allclose(curve.point([0, length / 2, length]), V)
    np.testing.assert_allclose(curve.kinks, [length / 2])
    tangent = curve.derivative(length / 4)
    np.testing.assert_allclose(tangent, np.array([-0.4, 10]) / np.hypot(0.4, 10))
    with pytest.raises(ProblemError, match="coincide"):
        PolylineCurve([[0, 0], [0, 0], [1, 1]])
    with pytest.raises(ProblemError, match="n >= 2"):
        PolylineCurve([[0, 0]])


def test_gaps_analytic_and_at_the_kink():
    curve = PolylineCurve(V)
    ys = np.array([-8.0, -3.0, 0.0, 2.5, 7.0])
    points = np.c_[np.full(5, 5.0), ys]
    body = np.tile([1.0, 0.0], (5, 1))
    s, normal, _ = gap_along_normals(points, body[0], curve)
    np.testing.assert_allclose(s, 0.1 + 0.04 * np.abs(ys), atol=1e-14)
    s, normal, _ = gap_from_obstacle(points, curve, body)
    expected = [line_distance(p, V[1], V[0] if p[1] < 0 else V[2])
                for p in points]
    expected[2] = 0.1  # (5, 0): the perpendicular foot lies beyond the
    # vertex on both segments, the nearest point is the vertex (5.1, 0)
    np.testing.assert_allclose(s, expected, atol=1e-13)
    # at the kink (y = 0) the nearest point is the vertex, the normal the
    # direction to it
    np.testing.assert_allclose(normal[2], [1.0, 0.0])
    assert s[2] == pytest.approx(0.1)


def test_round_trip_and_solve(tmp_path):
    path = tmp_path / "v.npz"
    solve_block(MESHES / "block_454.mesh", path, obstacle_points=V)
    problem = load_problem(path)
    assert isinstance(problem.obstacle, PolylineCurve)
    again = load_problem(save_problem(tmp_path / "again.npz", problem))
    np.testing.assert_array_equal(again.obstacle.points, V)
    for gap in ("obstacle", "body"):
        geometry = contact_geometry(problem, gap)
        result = solve_frictionless(problem, method="min", geometry=geometry,
                                    tol=1e-12)
        assert result.success and result.n_contact >= 2
        reference = clarabel_solution(problem, geometry)
        assert np.abs(result.u - reference).max() <= \
            1e-8 * np.abs(reference).max()


def test_polyline_with_expressions_is_refused(tmp_path):
    path = tmp_path / "v.npz"
    solve_block(MESHES / "block_118.mesh", path, obstacle_points=V)
    with np.load(path) as archive:
        arrays = dict(archive)
    arrays["obstacle_x"] = np.array("t")
    np.savez(tmp_path / "bad.npz", **arrays)
    with pytest.raises(ProblemError, match="^obstacle_x: not allowed"):
        load_problem(tmp_path / "bad.npz")
