r"""Piecewise linear rigid obstacles given as points: a polyline Γo
through P_0, …, P_n parametrised by arc length t (t = 0 at P_0), with the
interface of :class:`~.parametric.ParametricCurve`, so that the gap
functions of :mod:`solver.geometry.curves` work with it unchanged. At an
inner vertex (a kink) ``derivative`` returns the tangent of the segment
that starts there, and a nearest point on a kink takes the direction from
the node to it as its normal."""

import numpy as np

from ...errors import ExpressionError
from ..checks import COORDINATE_LIMIT
from .parametric import check_interval

__all__ = ["PolylineCurve"]


class PolylineCurve:
    """A polyline obstacle through the vertices ``points`` (n + 1, 2): n ≥ 1
    segments of positive length, coordinates within
    :data:`~solver.geometry.checks.COORDINATE_LIMIT`; ``t_range`` (0, total
    length); ``search_interval`` the interval searched for the gaps (default:
    all of it)."""

    def __init__(self, points, search_interval=None):
        points = np.asarray(points, dtype=float)
        if points.ndim != 2 or points.shape[1] != 2 or len(points) < 2:
            raise ExpressionError(f"obstacle_points: need an (n, 2) array "
                                  f"with n >= 2, got shape {points.shape}")
        if not np.isfinite(points).all():
            raise ExpressionError("obstacle_points: NaN or infinite "
                                  "coordinates")
        far = np.abs(points).max(axis=1)
        if far.max() > COORDINATE_LIMIT:  # segment lengths would overflow
            i = int(np.argmax(far))
            raise ExpressionError(
                f"obstacle_points: point {i} at ({points[i, 0]:g}, "
                f"{points[i, 1]:g}) is out of the supported range |x|, |y| "
                f"<= {COORDINATE_LIMIT:g}, as the nodes (rescale the units)")
        lengths = np.hypot(*np.diff(points, axis=0).T)
        if (lengths <= 0).any():
            i = int(np.argmax(lengths <= 0))
            raise ExpressionError(f"obstacle_points: points {i} and {i + 1} "
                                  "coincide (zero-length segment)")
        self.points = points
        self._t = np.r_[0.0, np.cumsum(lengths)]
        self._tangents = np.diff(points, axis=0) / lengths[:, None]
        self.t_range = (0.0, float(self._t[-1]))
        self.search_interval = None if search_interval is None \
            else check_interval("search interval", search_interval)

    @property
    def kinks(self):
        """Arc-length parameters of the inner vertices."""
        return self._t[1:-1].copy()

    def _segment(self, t):
        t = np.asarray(t, dtype=float)
        index = np.clip(np.searchsorted(self._t, t, side="right") - 1, 0,
                        len(self._tangents) - 1)
        return t, index

    def point(self, t):
        """Γo(t), shape ``t.shape + (2,)`` (linear extrapolation beyond the
        ends, which the gap search never uses: ``t_range`` is finite)."""
        t, i = self._segment(t)
        return self.points[i] + (t - self._t[i])[..., None] * self._tangents[i]

    def derivative(self, t):
        """Unit tangent of the segment containing t."""
        t, i = self._segment(t)
        return self._tangents[i]

    def second_derivative(self, t):
        """Zero (straight segments)."""
        t = np.asarray(t, dtype=float)
        return np.zeros(t.shape + (2,))

    def __repr__(self):
        return f"PolylineCurve({len(self.points)} points, length " \
               f"{self.t_range[1]:g})"
