r"""The plane and the sphere: closest points and ray intersections in
closed form."""

import numpy as np

from ...errors import ProblemError
from .base import (Surface, as_directions, as_points, fail,
                           spec_fields, spec_number, spec_vector)

__all__ = ["PlaneSurface", "SphereSurface", "MIN_COSINE"]

#: Smallest accepted :math:`|n\cdot d|` between the surface normal and a
#: ray (as :data:`solver.geometry.curves.MIN_COSINE` in 2D).
MIN_COSINE = 1e-3


class PlaneSurface(Surface):
    r"""The half-space :math:`(y - p)\cdot n \le 0`; ``point`` *p* within
    :data:`~solver.geometry.checks.COORDINATE_LIMIT`, ``normal`` *n* (out of
    the obstacle) any finite non-zero vector: divided by its largest
    |component| before it is normalised, so that (0, 0, 1e308) and
    (0, 0, 1e-320) are the direction (0, 0, 1)."""

    kind = "plane"

    def __init__(self, point, normal):
        spec = {"point": point, "normal": normal}
        self.point = spec_vector(spec, "point")
        self._normal_given = spec_vector(spec, "normal", limit=None)
        top = np.abs(self._normal_given).max()
        if not top > 0:
            raise ProblemError("surface normal: must be non-zero")
        direction = self._normal_given / top
        self.normal = direction / np.linalg.norm(direction)

    @classmethod
    def from_spec(cls, spec):
        spec_fields(spec, cls.kind, ("point", "normal"))
        return cls(spec["point"], spec["normal"])

    def spec(self):
        return {"kind": self.kind, "point": self.point.tolist(),
                "normal": self._normal_given.tolist()}

    def gap_along_obstacle_normal(self, points):
        points = as_points(points)
        gap = (points - self.point) @ self.normal
        nu = np.broadcast_to(-self.normal, points.shape).copy()
        return gap, nu, points - gap[:, None] * self.normal

    def gap_along_rays(self, points, directions):
        points = as_points(points)
        d = as_directions(directions, len(points))
        cosine = d @ self.normal
        grazing = ~(np.abs(cosine) >= MIN_COSINE)
        if grazing.any():
            fail(grazing, points, "the rays are parallel to the plane")
        tau = -((points - self.point) @ self.normal) / cosine
        return tau, points + tau[:, None] * d


class SphereSurface(Surface):
    """The ball of centre ``center`` and radius ``radius`` > 0, both within
    :data:`~solver.geometry.checks.COORDINATE_LIMIT` (the distances
    :math:`|x - c|` would overflow beyond it)."""

    kind = "sphere"

    def __init__(self, center, radius):
        spec = {"center": center, "radius": radius}
        self.center = spec_vector(spec, "center")
        self.radius = spec_number(spec, "radius")
        if not self.radius > 0:
            raise ProblemError(f"surface radius: must be > 0, got "
                               f"{self.radius:g}")

    @classmethod
    def from_spec(cls, spec):
        spec_fields(spec, cls.kind, ("center", "radius"))
        return cls(spec["center"], spec["radius"])

    def spec(self):
        return {"kind": self.kind, "center": self.center.tolist(),
                "radius": self.radius}

    def gap_along_obstacle_normal(self, points):
        points = as_points(points)
        v = points - self.center
        rho = np.linalg.norm(v, axis=1)
        if not (rho > 0).all():
            fail(~(rho > 0), points, "the closest point is undefined (node "
                 "at the sphere's centre)")
        n = v / rho[:, None]
        return rho - self.radius, -n, self.center + self.radius * n

    def gap_along_rays(self, points, directions):
        r"""Roots of :math:`|x + \tau d - c|^2 = R^2`, the one of smaller
        magnitude, computed without cancellation
        (:math:`\tau_1 = -b - \mathrm{sign}(b)\sqrt{b^2 - q}`,
        :math:`\tau_2 = q/\tau_1`)."""
        points = as_points(points)
        d = as_directions(directions, len(points))
        v = points - self.center
        b = np.sum(d * v, axis=1)
        q = np.sum(v * v, axis=1) - self.radius ** 2
        root = np.sqrt(np.maximum(b * b - q, 0.0))
        # |n·d| at the hit is sqrt(b² - q)/R: reject misses and grazing
        grazing = ~(b * b - q >= (MIN_COSINE * self.radius) ** 2)
        if grazing.any():
            fail(grazing, points, "the rays miss the sphere or graze it")
        big = -b - np.where(b >= 0, 1.0, -1.0) * root
        tau = q / big
        return tau, points + tau[:, None] * d
