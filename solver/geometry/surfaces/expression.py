r"""A surface map :math:`c(s, t) = (x(s,t), y(s,t), z(s,t))` from three
expressions parsed by :mod:`solver.geometry.expression` (a graph
:math:`z = h(x, y)` is :math:`c(x, y) = (x, y, h(x, y))`), with exact
derivatives: the closest-point Newton (:mod:`.search`) needs
:math:`c, c_s, c_t, c_{ss}, c_{st}, c_{tt}`, differentiated once, here, and
evaluated together for many parameter pairs."""

import numpy as np
import sympy

from ...errors import ExpressionError
from ..curves.parametric import check_derivative
from ..expression import MAX_DERIVATIVE_NODES, expression_size, parse_expression

__all__ = ["SurfaceMap"]


def _lambdify(expr, symbols):
    """A NumPy function of (s, t) that broadcasts constants."""
    function = sympy.lambdify(symbols, expr, modules="numpy")

    def evaluate(s, t):
        with np.errstate(all="ignore"):
            value = np.asarray(function(s, t), dtype=float)
        return np.broadcast_to(value, np.broadcast(s, t).shape)

    return evaluate


class SurfaceMap:
    r"""The map :math:`c(s, t)` and its derivatives up to order two, from
    the three coordinates' expressions ``texts`` in the two ``variables``
    (``("s", "t")`` or ``("x", "y")``). ExpressionError naming the spec
    field (``fields``): a bad expression, a derivative too large, or a map
    that does not depend on both parameters (not a surface)."""

    def __init__(self, texts, variables=("s", "t"), fields=("x", "y", "z")):
        symbols = [sympy.Symbol(v, real=True) for v in variables]
        exprs = []
        for field, text in zip(fields, texts):
            try:
                exprs.append(parse_expression(text, variables))
            except ExpressionError as exc:
                raise ExpressionError(f"surface {field}: {exc}") from None
        free = set().union(*(e.free_symbols for e in exprs))
        for v, sym in zip(variables, symbols):
            if sym not in free:
                raise ExpressionError(
                    f"surface {'/'.join(fields)}: the map does not depend "
                    f"on {v}: it is a curve or a point, not a surface")
        derivatives = {(0, 0): exprs}
        for key, parent, sym in (((1, 0), (0, 0), 0), ((0, 1), (0, 0), 1),
                                 ((2, 0), (1, 0), 0), ((1, 1), (1, 0), 1),
                                 ((0, 2), (0, 1), 1)):
            derivatives[key] = [sympy.diff(e, symbols[sym])
                                for e in derivatives[parent]]
            for field, text, d in zip(fields, texts, derivatives[key]):
                if expression_size(d, MAX_DERIVATIVE_NODES) > MAX_DERIVATIVE_NODES:
                    raise ExpressionError(
                        f"surface {field}: too complex (a derivative has "
                        f"more than {MAX_DERIVATIVE_NODES} terms)")
                try:  # the Newton searches evaluate all of them
                    check_derivative(d, text, symbols[0])
                except ExpressionError as exc:
                    raise ExpressionError(f"surface {field}: {exc}") \
                        from None
        self.variables = tuple(variables)
        self.exprs = exprs
        self._functions = {key: [_lambdify(e, symbols) for e in value]
                           for key, value in derivatives.items()}

    def _stack(self, key, s, t):
        return np.stack([f(s, t) for f in self._functions[key]], axis=-1)

    def point(self, s, t):
        r""":math:`c(s, t)`, shape ``broadcast(s, t).shape + (3,)``."""
        return self._stack((0, 0), s, t)

    def first(self, s, t):
        r""":math:`(c_s, c_t)` (exact), each of shape ``... + (3,)``."""
        return self._stack((1, 0), s, t), self._stack((0, 1), s, t)

    def second(self, s, t):
        r""":math:`(c_{ss}, c_{st}, c_{tt})` (exact)."""
        return (self._stack((2, 0), s, t), self._stack((1, 1), s, t),
                self._stack((0, 2), s, t))

    def normal(self, s, t):
        r"""Unit normal :math:`c_s \times c_t / |c_s \times c_t|` (NaN
        where the map is singular) and :math:`|c_s \times c_t|`."""
        cs, ct = self.first(s, t)
        cross = np.cross(cs, ct)
        length = np.linalg.norm(cross, axis=-1)
        with np.errstate(all="ignore"):
            return cross / length[..., None], length
