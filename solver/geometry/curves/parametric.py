r"""Rigid parametric obstacles :math:`\Gamma_o(t) = (x(t), y(t))`.

The thesis (§4) describes its obstacle by two expressions in a parameter *t*,

.. math::  \Gamma_o(t) = [\,5.05 + 0.005\,t^2,\; t\,],

and needs the curve and its derivative to compute gaps and normals (§2.1,
(1)-(7)). Here the two expressions are text (they travel inside the
``.npz`` problem file), parsed safely into SymPy expressions with exact
derivatives by :mod:`solver.geometry.expression`.

Example
-------
>>> curve = ParametricCurve("5.05 + 0.005*t**2", "t")
>>> curve.point(0.0)
array([5.05, 0.  ])
>>> curve.derivative(2.0)
array([0.02, 1.  ])"""

import math

import numpy as np
import sympy

from ...errors import ExpressionError
from ..expression import (ALLOWED_CONSTANTS, ALLOWED_FUNCTIONS,  # noqa: F401
                         MAX_DERIVATIVE_NODES, check_constants, numeric_function,
                         expression_size, parse_expression)

__all__ = ["ALLOWED_FUNCTIONS", "ALLOWED_CONSTANTS", "parse_expression",
           "check_interval", "check_derivative", "ParametricCurve"]


def check_interval(name, interval):
    """``(t0, t1)`` as floats with t0 < t1 both finite, else
    :class:`~solver.errors.ExpressionError` naming ``name``."""
    try:
        t0, t1 = (float(v) for v in interval)
    except (TypeError, ValueError, OverflowError):
        raise ExpressionError(f"{name}: need two numbers t0 < t1, got "
                              f"{interval!r}"[:200]) from None
    if not (math.isfinite(t0) and math.isfinite(t1) and t0 < t1):
        raise ExpressionError(f"{name}: need finite t0 < t1, got "
                              f"({t0:g}, {t1:g})")
    return (t0, t1)


def check_derivative(derivative, text, symbol):
    """ExpressionError (naming the expression and its derivative) unless
    the constants of a derivative are finite in double precision, as those
    of the expression are: 1e308*t**2 is finite, its derivative 2e308*t is
    infinite everywhere."""
    try:
        check_constants(derivative, text, symbol)
    except ExpressionError as exc:
        reason = str(exc).split(": ", 1)[-1]
        raise ExpressionError(f"{text!r}: its derivative {derivative} "
                              f"overflows ({reason}; rescale the "
                              "units)") from None


class ParametricCurve:
    r"""A rigid obstacle :math:`\Gamma_o(t) = (x(t), y(t))`, thesis §4, from
    the expressions ``x``, ``y`` in ``t`` (kept in ``x_text``, ``y_text``,
    parsed in ``x_expr``, ``y_expr``), on ``t_range`` (None: the real line),
    the gaps searched on ``search_interval`` (None: from the body's extent,
    :func:`solver.geometry.curves.parameter_window`)."""

    def __init__(self, x, y, t_range=None, search_interval=None):
        self.x_text, self.y_text = x, y
        self.x_expr = parse_expression(x)
        self.y_expr = parse_expression(y)
        if t_range is not None:
            t_range = check_interval("t_range", t_range)
        self.t_range = t_range
        self.search_interval = None if search_interval is None \
            else check_interval("search interval", search_interval)
        symbol = self._symbol = sympy.Symbol("t", real=True)
        # t must appear (SymPy has already cancelled 0*t, t - t); a curve
        # that is constant only after simplification, sin(t)**2 + cos(t)**2,
        # has no tangent, which the gap computation reports. (SymPy's
        # is_constant() would simplify, which can take minutes.)
        if not (self.x_expr.free_symbols or self.y_expr.free_symbols):
            raise ExpressionError(
                f"obstacle ({x!r}, {y!r}) does not depend on t: it is a "
                "point, not a curve")
        first = []
        for text, e in ((x, self.x_expr), (y, self.y_expr)):
            d = sympy.diff(e, symbol)
            if expression_size(d, MAX_DERIVATIVE_NODES) > MAX_DERIVATIVE_NODES:
                raise ExpressionError(
                    f"{text!r}: too complex (its derivative has more than "
                    f"{MAX_DERIVATIVE_NODES} terms)")
            check_derivative(d, text, symbol)
            first.append(d)
        self._derivatives = [[self.x_expr, self.y_expr], first, None]
        self._functions = [[numeric_function(d, symbol) for d in pair]
                           for pair in self._derivatives[:2]] + [None]

    def _evaluate(self, t, order):
        if self._functions[order] is None:  # Γo'' only on demand
            self._derivatives[order] = [sympy.diff(d, self._symbol)
                                        for d in self._derivatives[order - 1]]
            self._functions[order] = [numeric_function(d, self._symbol)
                                      for d in self._derivatives[order]]
        fx, fy = self._functions[order]
        return np.stack([fx(t), fy(t)], axis=-1)

    def point(self, t):
        r""":math:`\Gamma_o(t)`, shape ``t.shape + (2,)``."""
        return self._evaluate(t, 0)

    def derivative(self, t):
        r"""Tangent :math:`\Gamma_o'(t)` (exact), shape ``t.shape + (2,)``."""
        return self._evaluate(t, 1)

    def second_derivative(self, t):
        r""":math:`\Gamma_o''(t)` (exact), shape ``t.shape + (2,)``.

        Differentiated on the first call (the solver does not need it)."""
        return self._evaluate(t, 2)

    def __repr__(self):
        rng = "" if self.t_range is None else f", t_range={self.t_range}"
        if self.search_interval is not None:
            rng += f", search_interval={self.search_interval}"
        return (f"ParametricCurve(x={self.x_text!r}, y={self.y_text!r}"
                f"{rng})")
