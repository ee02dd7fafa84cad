r"""Surfaces from expressions: parametric :math:`c(s, t)` on a parameter
box, and graphs :math:`z = h(x, y)` (the map :math:`(x, y, h(x, y))`).

Closest points and ray hits by the vectorised Newton methods of
:mod:`.search`. The outward normal (out of the obstacle, towards
the body) is :math:`c_s \times c_t / |c_s \times c_t|`; for a graph this is
:math:`(-h_x, -h_y, 1)/\sqrt{1 + h_x^2 + h_y^2}`, upward: the obstacle is
:math:`z \le h(x, y)`."""

import numpy as np

from ...errors import ExpressionError, ProblemError, SolverError
from ..checks import COORDINATE_LIMIT
from ..curves.parametric import check_interval
from .base import (Surface, as_directions, as_points, check_limit, fail,
                   spec_fields)
from .expression import SurfaceMap
from .search import (CANDIDATES, DEFAULT_SAMPLES, closest_points,
                             grid_start, local_grid_start, ray_hits)
from .shapes import MIN_COSINE

__all__ = ["ParametricSurface", "GraphSurface"]


class _MapSurface(Surface):
    """Shared gap computations of the surfaces given by a SurfaceMap."""

    def _box(self, points, k):
        """(lower, upper, starts (m, k, 2)) of the closest-point search."""
        raise NotImplementedError

    def _ray_box(self, points):
        """(lower, upper) of the ray search."""
        raise NotImplementedError

    def _closest(self, points):
        """Closest-point parameters, restarting runs that end off a foot
        point on an edge of the box from farther start candidates."""
        lower, upper, starts = self._box(points, 1)
        m = len(points)
        lower = np.broadcast_to(lower, (m, 2))
        upper = np.broadcast_to(upper, (m, 2))
        u, converged = closest_points(self.map, points, lower, upper,
                                      starts[:, 0])
        bad = ~converged | self._off_edge(u, points, lower, upper)
        if not bad.any():
            return u, lower, upper
        starts = np.zeros((m, CANDIDATES, 2))
        starts[bad] = self._box(points[bad], CANDIDATES)[2]
        width = (upper - lower) / 32
        for j in range(1, starts.shape[1]):
            far = np.abs(starts[:, j] - u) > np.where(np.isfinite(width),
                                                      width, 0)
            retry = np.flatnonzero(bad & far.any(axis=1))
            if not len(retry):
                continue
            v, ok = closest_points(self.map, points[retry], lower[retry],
                                   upper[retry], starts[retry, j])
            ok &= ~self._off_edge(v, points[retry], lower[retry],
                                  upper[retry])
            u[retry[ok]], converged[retry[ok]] = v[ok], True
            bad[retry[ok]] = False
        if not converged.all():
            fail(~converged, points, "the closest-point Newton on the "
                 "obstacle surface did not converge", SolverError)
        return u, lower, upper

    def _off_edge(self, u, points, lower, upper):
        """On an edge of the box but not a foot point there."""
        r = points - self.map.point(u[:, 0], u[:, 1])
        normal, _ = self.map.normal(u[:, 0], u[:, 1])
        distance = np.linalg.norm(r, axis=1)
        on_edge = ((u <= lower) | (u >= upper)).any(axis=1)
        with np.errstate(invalid="ignore"):
            cosine = np.abs(np.sum(r * normal, axis=1)) / np.where(
                distance > 0, distance, 1.0)
        return on_edge & (distance > 0) & ~(cosine >= 1 - 1e-8)

    def _frame(self, u, points):
        normal, length = self.map.normal(u[:, 0], u[:, 1])
        singular = ~(np.isfinite(length) & (length > 0))
        if singular.any():
            fail(singular, points, "the obstacle surface is singular "
                 "(c_s × c_t = 0) at the closest point")
        return normal

    def gap_along_obstacle_normal(self, points):
        points = as_points(points)
        if not len(points):
            return np.zeros(0), np.zeros((0, 3)), np.zeros((0, 3))
        u, lower, upper = self._closest(points)
        foot = self.map.point(u[:, 0], u[:, 1])
        with np.errstate(invalid="ignore"):
            far = ~(np.abs(foot) <= COORDINATE_LIMIT).all(axis=1)
        if far.any():
            fail(far, points, "the nearest obstacle point is not finite or "
                 "out of the supported range |x|, |y|, |z| <= "
                 f"{COORDINATE_LIMIT:g}")
        normal = self._frame(u, points)
        if self._off_edge(u, points, lower, upper).any():
            fail(self._off_edge(u, points, lower, upper), points,
                 "the nearest obstacle point lies on the edge of "
                 "s_range × t_range (not a foot point; enlarge the ranges)")
        return np.sum((points - foot) * normal, axis=1), -normal, foot

    def gap_along_rays(self, points, directions):
        points = as_points(points)
        d = as_directions(directions, len(points))
        if not len(points):
            return np.zeros(0), np.zeros((0, 3))
        u, _, _ = self._closest(points)
        lower, upper = self._ray_box(points)
        tau, _, ok = ray_hits(self.map, points, d, u, lower, upper,
                              MIN_COSINE)
        if not ok.all():  # restart from the grid samples nearest the
            bad = np.flatnonzero(~ok)  # last iterate (another basin)
            guess = points[bad] + tau[bad, None] * d[bad]
            starts = self._box(np.where(np.isfinite(guess), guess,
                                        points[bad]), CANDIDATES)[2]
            for j in range(starts.shape[1]):
                t, _, good = ray_hits(self.map, points[bad], d[bad],
                                      starts[:, j], lower, upper, MIN_COSINE)
                tau[bad[good]], ok[bad[good]] = t[good], True
                starts, bad = starts[~good], bad[~good]
                if not len(bad):
                    break
        if not ok.all():
            fail(~ok, points, "the rays miss the obstacle surface (inside "
                 "its parameter range) or graze it")
        return tau, points + tau[:, None] * d


class ParametricSurface(_MapSurface):
    """:math:`c(s, t)`, ``s`` in ``s_range``, ``t`` in ``t_range`` (finite,
    within :data:`~solver.geometry.checks.COORDINATE_LIMIT`).

    ``samples`` × ``samples`` grid points of the box give the Newton starts."""

    kind = "parametric"

    def __init__(self, x, y, z, s_range, t_range, samples=DEFAULT_SAMPLES):
        self.texts = (x, y, z)
        self.map = SurfaceMap(self.texts, ("s", "t"), ("x", "y", "z"))
        ranges = []
        for name, value in (("s_range", s_range), ("t_range", t_range)):
            try:
                ranges.append(check_interval(f"surface {name}", value))
            except ExpressionError as exc:
                raise ProblemError(str(exc)) from None
            check_limit(name, max(map(abs, ranges[-1])), COORDINATE_LIMIT)
        self.s_range, self.t_range = ranges
        self.lower = np.array([self.s_range[0], self.t_range[0]])
        self.upper = np.array([self.s_range[1], self.t_range[1]])
        self.samples = int(samples)

    @classmethod
    def from_spec(cls, spec):
        spec_fields(spec, cls.kind, ("x", "y", "z", "s_range", "t_range"))
        return cls(spec["x"], spec["y"], spec["z"], spec["s_range"],
                   spec["t_range"])

    def spec(self):
        x, y, z = self.texts
        return {"kind": self.kind, "x": x, "y": y, "z": z,
                "s_range": list(self.s_range), "t_range": list(self.t_range)}

    def _ray_box(self, points):
        return self.lower, self.upper

    def _box(self, points, k):
        start = grid_start(self.map, points, self.lower, self.upper,
                           self.samples, k)
        return self.lower, self.upper, start


class GraphSurface(_MapSurface):
    r"""The obstacle :math:`z \le h(x, y)`, h given in ``x`` and ``y``.

    The closest point *q* of a point *x* is no farther than the vertical
    foot :math:`(x_1, x_2, h(x_1, x_2))`, so its parameters lie in the square
    of half-width :math:`v = |x_3 - h(x_1, x_2)|` around :math:`(x_1, x_2)`:
    each node searches its own square (5 × 5 start samples); the rays search
    the whole plane."""

    kind = "graph"

    def __init__(self, z):
        self.text = z
        self.map = SurfaceMap(("x", "y", z), ("x", "y"), ("z", "z", "z"))

    @classmethod
    def from_spec(cls, spec):
        spec_fields(spec, cls.kind, ("z",))
        return cls(spec["z"])

    def spec(self):
        return {"kind": self.kind, "z": self.text}

    def _box(self, points, k):
        h = self.map.point(points[:, 0], points[:, 1])[:, 2]
        if not np.isfinite(h).all():
            fail(~np.isfinite(h), points, "the obstacle height h(x, y) is "
                 "not finite below the node")
        if (np.abs(h) > COORDINATE_LIMIT).any():  # squared distances
            fail(np.abs(h) > COORDINATE_LIMIT, points, "the obstacle height "
                 f"h(x, y) below the node is out of the supported range "
                 f"|z| <= {COORDINATE_LIMIT:g}")
        v = np.abs(points[:, 2] - h)
        v = v * (1 + 1e-12) + 1e-300
        lower, upper = points[:, :2] - v[:, None], points[:, :2] + v[:, None]
        return lower, upper, local_grid_start(self.map, points, lower, upper,
                                              k=k)

    def _ray_box(self, points):
        return np.full(2, -np.inf), np.full(2, np.inf)
