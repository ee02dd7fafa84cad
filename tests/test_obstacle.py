"""Obstacle curves from safe expressions; derivatives checked analytically."""

import numpy as np
import pytest
import sympy

from solver.errors import ExpressionError, ProblemError
from solver.geometry.curves.parametric import ParametricCurve, parse_expression


def test_thesis_parabola():
    # Thesis §4: Γo(t) = [5.05 + 0.005 t², t]; Γo' = [0.01 t, 1], Γo'' = [0.01, 0]
    curve = ParametricCurve("5.05 + 0.005*t**2", "t")
    t = np.linspace(-10, 10, 7)
    np.testing.assert_allclose(curve.point(t),
                               np.c_[5.05 + 0.005 * t ** 2, t], rtol=1e-15)
    np.testing.assert_allclose(curve.derivative(t),
                               np.c_[0.01 * t, np.ones_like(t)], rtol=1e-15)
    np.testing.assert_allclose(curve.second_derivative(t),
                               np.c_[np.full_like(t, 0.01), np.zeros_like(t)])
    assert curve.point(0.0).shape == (2,)
    assert curve.point(np.zeros((3, 4))).shape == (3, 4, 2)


def test_circle_and_functions():
    curve = ParametricCurve("2 + 3*cos(t)", "-1 + 3*sin(t)", t_range=(0, np.pi))
    t = np.array([0.0, 0.3, 1.7])
    np.testing.assert_allclose(curve.point(t),
                               np.c_[2 + 3 * np.cos(t), -1 + 3 * np.sin(t)])
    np.testing.assert_allclose(curve.derivative(t),
                               np.c_[-3 * np.sin(t), 3 * np.cos(t)])
    np.testing.assert_allclose(np.linalg.norm(curve.point(t) - [2, -1],
                                              axis=1), 3.0)
    assert curve.t_range == (0.0, np.pi)


def test_every_allowed_function_differentiates_like_finite_differences():
    names = ["sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh",
             "tanh", "exp", "log", "sqrt", "abs", "arcsin", "arccos",
             "arctan"]
    t = np.array([0.2, 0.35, 0.6])
    h = 1e-6
    for name in names:
        curve = ParametricCurve(f"{name}(t) + pi*e", "t")
        fd = (curve.point(t + h) - curve.point(t - h)) / (2 * h)
        np.testing.assert_allclose(curve.derivative(t)[:, 0], fd[:, 0],
                                   rtol=1e-7, err_msg=name)


def test_constant_coordinate_is_a_straight_line():
    curve = ParametricCurve("5.05", "t")
    t = np.linspace(-1, 1, 4)
    np.testing.assert_array_equal(curve.point(t)[:, 0], 5.05)
    np.testing.assert_array_equal(curve.derivative(t), np.c_[0 * t, 1 + 0 * t])


def test_parse_gives_sympy():
    t = sympy.Symbol("t", real=True)
    assert parse_expression("1 + 2*t**2") == 1 + 2 * t ** 2
    assert parse_expression("-t") == -t
    assert parse_expression("pi") == sympy.pi


@pytest.mark.parametrize("text, fragment", [
    ("__import__('os').system('ls')", "__import__"),
    ("open('/etc/passwd')", "open"),
    ("t.__class__", "Attribute"),
    ("(lambda: 1)()", "not allowed"),
    ("lambda: t", "Lambda"),
    ("[t for t in range(3)]", "ListComp"),
    ("t[0]", "Subscript"),
    ("x + 1", "unknown name 'x'"),
    ("sin(t, 2)", "exactly one"),
    ("sin(t=2)", "exactly one"),
    ("sin(*[t])", "exactly one"),
    ("np.sin(t)", "not allowed"),
    ("t^2", "use **"),
    ("t if t else 1", "IfExp"),
    ("t < 1", "Compare"),
    ("'text'", "not a real number"),
    ("True", "not a real number"),
    ("1j*t", "not a real number"),
    ("5 +", "syntax error"),
    ("", "empty"),
    ("1/0 + t", "not finite"),
    ("sqrt(-1)*t", "not real"),
    ("9**9**9**9 + t", "not a finite real number"),
    ("t + " + "1+" * 600 + "1", "longer than"),
    ("t; import os", "syntax error"),
])
def test_unsafe_or_malformed_expressions(text, fragment):
    with pytest.raises(ExpressionError) as exc:
        parse_expression(text)
    assert fragment in str(exc.value)
    assert isinstance(exc.value, ProblemError)  # the format's own error


def test_non_string_and_point_and_range():
    with pytest.raises(ExpressionError, match="string"):
        parse_expression(3.0)
    with pytest.raises(ExpressionError, match="point, not a curve"):
        ParametricCurve("1", "2")
    with pytest.raises(ExpressionError, match="t_range"):
        ParametricCurve("t", "1", t_range=(1.0, 1.0))
    with pytest.raises(ExpressionError, match="t_range"):
        ParametricCurve("t", "1", t_range=(0.0, np.inf))
