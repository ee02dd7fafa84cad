r"""Bounded planes and several obstacles in one problem.

A *rectangle* is the plane of a :class:`~.shapes.PlaneSurface` cut to a
rectangle: a node whose foot point (or ray hit) falls outside it has no
obstacle in reach there, gap +∞. *Several* obstacles (``{"kind":
"several", "surfaces": [...]}``) give each node the gap, normal and foot
point of the obstacle with the smallest gap: the one that binds first in
the reference configuration (the gaps are fixed there, small sliding), so
a node touches one obstacle at a time. Where two obstacles meet (an edge
between two planes) a node takes the one it is nearer to in that sense,
and its normal jumps from one to the other across the edge; a node whose
gaps to both are equal takes the first listed. A node no obstacle reaches
(+∞ from every one) takes no part in contact and is reported among the
excluded nodes (:func:`solver.contact.contact_geometry`)."""

import numpy as np

from ...errors import ProblemError
from ..checks import check_obstacle_list
from .base import (Surface, as_directions, as_points, spec_fields,
                   spec_vector)
from .shapes import MIN_COSINE, PlaneSurface

__all__ = ["RectangleSurface", "PolygonSurface", "SeveralSurfaces",
           "MAX_SURFACES", "MAX_VERTICES"]

#: Most obstacles one problem may list.
MAX_SURFACES = 64
#: Most vertices of a polygon's boundary.
MAX_VERTICES = 64
#: A foot point within this distance of a polygon's boundary, relative to
#: the polygon's size, counts as inside (a node on the common edge of two
#: polygons reaches both).
EDGE_TOLERANCE = 1e-9


class RectangleSurface(Surface):
    r"""The plane through ``center`` with outward ``normal`` n (as
    :class:`~.shapes.PlaneSurface`), bounded to |(y − c)·e₁| ≤ a,
    |(y − c)·e₂| ≤ b: e₁ the unit part of ``axis`` normal to n, e₂ = n × e₁,
    (a, b) = ``half_sizes`` > 0."""

    kind = "rectangle"

    def __init__(self, center, normal, axis, half_sizes):
        self.plane = PlaneSurface(center, normal)
        spec = {"axis": axis, "half_sizes": half_sizes}
        given = spec_vector(spec, "axis", limit=None)
        self._axis_given = given
        self.half = spec_vector(spec, "half_sizes", length=2)
        if not (self.half > 0).all():
            raise ProblemError("surface half_sizes: must be > 0")
        n = self.plane.normal
        e1 = given / np.abs(given).max() if np.abs(given).max() > 0 else given
        e1 = e1 - (e1 @ n) * n
        if not np.linalg.norm(e1) > 1e-8:
            raise ProblemError("surface axis: must not be parallel to the "
                               "normal")
        self.e1 = e1 / np.linalg.norm(e1)
        self.e2 = np.cross(n, self.e1)

    @classmethod
    def from_spec(cls, spec):
        spec_fields(spec, cls.kind, ("center", "normal", "axis",
                                     "half_sizes"))
        return cls(spec["center"], spec["normal"], spec["axis"],
                   spec["half_sizes"])

    def spec(self):
        return {"kind": self.kind, "center": self.plane.point.tolist(),
                "normal": self.plane.spec()["normal"],
                "axis": self._axis_given.tolist(),
                "half_sizes": self.half.tolist()}

    def _outside(self, foot):
        """+∞ where the foot points lie outside the rectangle, else 0."""
        rel = foot - self.plane.point
        inside = (np.abs(rel @ self.e1) <= self.half[0]) & \
            (np.abs(rel @ self.e2) <= self.half[1])
        return np.where(inside, 0.0, np.inf)

    def gap_along_obstacle_normal(self, points):
        gap, nu, foot = self.plane.gap_along_obstacle_normal(points)
        return gap + self._outside(foot), nu, foot

    def gap_along_rays(self, points, directions):
        points = as_points(points)
        tau, hit = _rays(self.plane, points,
                         as_directions(directions, len(points)))
        return tau + self._outside(hit), hit


class PolygonSurface(RectangleSurface):
    r"""The plane through ``point`` with outward ``normal`` n (as
    :class:`~.shapes.PlaneSurface`), bounded by the polygon of
    ``vertices`` (≥ 3 points, in order) projected orthogonally onto it: a
    foot point (or ray hit) outside the polygon, by more than
    :data:`EDGE_TOLERANCE` of its size, has no obstacle in reach. SfePy's
    bounded contact plane (``dw_contact_plane``: anchor, normal, boundary
    points ``bs``, whose projections onto the plane bound it) with the
    normal reversed: SfePy's points into the obstacle. Any simple polygon
    (even–odd rule)."""

    kind = "polygon"

    def __init__(self, point, normal, vertices):
        self.plane = PlaneSurface(point, normal)
        n = self.plane.normal
        try:
            corners = np.array(vertices, dtype=float)
        except (TypeError, ValueError, OverflowError):
            corners = None
        if corners is None or corners.ndim != 2 or corners.shape[1] != 3 \
                or not 3 <= len(corners) <= MAX_VERTICES \
                or not np.isfinite(corners).all():
            raise ProblemError(f"surface vertices: need 3 to {MAX_VERTICES} "
                               f"points of 3 finite numbers, got "
                               f"{vertices!r}"[:200])
        for corner in corners:
            spec_vector({"vertices": corner}, "vertices")
        self._vertices = corners
        helper = np.eye(3)[np.argmin(np.abs(n))]
        self.e1 = np.cross(n, helper)
        self.e1 /= np.linalg.norm(self.e1)
        self.e2 = np.cross(n, self.e1)
        rel = corners - self.plane.point
        self.polygon = np.stack([rel @ self.e1, rel @ self.e2], axis=1)
        size = np.ptp(self.polygon, axis=0).max()
        area = 0.5 * abs(np.sum(self.polygon[:, 0] * np.roll(
            self.polygon[:, 1], -1) - np.roll(self.polygon[:, 0], -1)
            * self.polygon[:, 1]))
        if not area > 1e-12 * size ** 2:
            raise ProblemError("surface vertices: the polygon projected onto "
                               "the plane has no area")
        self.tolerance = EDGE_TOLERANCE * size

    @classmethod
    def from_spec(cls, spec):
        spec_fields(spec, cls.kind, ("point", "normal", "vertices"))
        return cls(spec["point"], spec["normal"], spec["vertices"])

    def spec(self):
        return {"kind": self.kind, "point": self.plane.point.tolist(),
                "normal": self.plane.spec()["normal"],
                "vertices": self._vertices.tolist()}

    def _outside(self, foot):
        """+∞ where the foot points lie outside the polygon, else 0: the
        even–odd crossing test, one vectorised pass per edge, and a
        point within the tolerance of an edge is inside."""
        rel = foot - self.plane.point
        x, y = rel @ self.e1, rel @ self.e2
        inside = np.zeros(len(x), dtype=bool)
        near = np.zeros(len(x), dtype=bool)
        a = self.polygon
        b = np.roll(a, -1, axis=0)
        for (xa, ya), (xb, yb) in zip(a, b):
            crosses = (ya > y) != (yb > y)
            with np.errstate(divide="ignore", invalid="ignore"):
                at = xa + (y - ya) * (xb - xa) / (yb - ya)
            inside ^= crosses & (x < at)
            edge = np.array([xb - xa, yb - ya])
            t = np.clip(((x - xa) * edge[0] + (y - ya) * edge[1])
                        / (edge @ edge), 0.0, 1.0)
            near |= np.hypot(x - xa - t * edge[0], y - ya - t * edge[1]) \
                <= self.tolerance
        return np.where(inside | near, 0.0, np.inf)


class SeveralSurfaces(Surface):
    """Several obstacles: each node's gap from the one of smallest gap
    (module docstring); ``surfaces`` the parts (not themselves several)."""

    kind = "several"

    def __init__(self, surfaces):
        check_obstacle_list(surfaces, "surface surfaces", "surface",
                            MAX_SURFACES)
        from . import surface_from_spec

        parts = [s if isinstance(s, Surface) else surface_from_spec(s)
                 for s in surfaces]
        if any(isinstance(p, SeveralSurfaces) for p in parts):
            raise ProblemError("surface surfaces: list the obstacles once, "
                               "not nested")
        self.parts = parts

    @classmethod
    def from_spec(cls, spec):
        spec_fields(spec, cls.kind, ("surfaces",))
        return cls(spec["surfaces"])

    def spec(self):
        return {"kind": self.kind,
                "surfaces": [p.spec() for p in self.parts]}

    @staticmethod
    def _nearest(results, m):
        """Per node, the part of smallest gap: (gap, its part index,
        the chosen rows of each further array of ``results``)."""
        gaps = np.stack([r[0] for r in results])  # (parts, m)
        pick = np.argmin(gaps, axis=0)  # first listed on ties
        rows = np.arange(m)
        chosen = [np.stack([r[k] for r in results])[pick, rows]
                  for k in range(1, len(results[0]))]
        return gaps[pick, rows], pick, chosen

    def gap_along_obstacle_normal(self, points):
        points = as_points(points)
        gap, _, (nu, foot) = self._nearest(
            [p.gap_along_obstacle_normal(points) for p in self.parts],
            len(points))
        return gap, nu, foot

    def gap_along_rays(self, points, directions):
        """Along the rays, from the obstacles the nodes face: a part counts
        at a node when the ray leaves the body towards it (d·ν ≥ 0, ν its
        contact direction at the node's closest point); a plane behind the
        node, which the ray's line meets too, does not."""
        points = as_points(points)
        d = as_directions(directions, len(points))
        results = []
        for part in self.parts:
            _, nu, _ = part.gap_along_obstacle_normal(points)
            tau, hit = _rays(part, points, d)
            facing = np.einsum("ij,ij->i", d, nu) >= 0
            results.append((np.where(facing, tau, np.inf), hit))
        tau, _, (hit,) = self._nearest(results, len(points))
        return tau, hit

    def which(self, points):
        """The index of the obstacle each of ``points`` takes (its gap
        along the obstacle normal)."""
        points = as_points(points)
        return self._nearest(
            [p.gap_along_obstacle_normal(points) for p in self.parts],
            len(points))[1]


def _rays(part, points, d):
    """(τ, hit) of ``part`` along the unit rays d, +∞ where a plane's ray
    runs parallel to it (one obstacle of several need not be hit by every
    ray)."""
    if not isinstance(part, PlaneSurface):
        return part.gap_along_rays(points, d)
    cosine = d @ part.normal
    reach = np.abs(cosine) >= MIN_COSINE
    tau = np.full(len(points), np.inf)
    tau[reach] = -((points[reach] - part.point) @ part.normal) / cosine[reach]
    return tau, points + np.where(reach, tau, 0.0)[:, None] * d
