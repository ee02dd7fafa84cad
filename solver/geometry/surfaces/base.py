r"""The interface every rigid obstacle surface keeps, and the checks of the
fields of a surface spec (:mod:`solver.geometry.surfaces` is the front).

Conventions (the 3D contract; as in 2D, thesis §2.1 with the errata of the
digest): the obstacle's **outward** normal *n* points out of the obstacle,
towards the body; the contact direction ν returned by the gap functions
points from the body towards the obstacle, :math:`\nu = -n` at the foot
point; a gap is positive while the body point lies outside the obstacle."""

import math

import numpy as np

from ...errors import ProblemError
from ..checks import COORDINATE_LIMIT
from ..curves import GapError

__all__ = ["Surface", "GapError", "spec_fields", "spec_vector",
           "spec_number", "check_limit", "as_points", "as_directions",
           "fail"]


def spec_fields(spec, kind, required, optional=()):
    """Check that ``spec`` has exactly the fields of its kind."""
    known = {"kind", *required, *optional}
    for key in spec:
        if key not in known:
            raise ProblemError(
                f"surface {key}: unknown field for a {kind} (expected: "
                f"{', '.join(sorted(known - {'kind'}))})")
    for key in required:
        if key not in spec:
            raise ProblemError(f"surface {key}: missing (a {kind} needs "
                               f"{', '.join(required)})")


def spec_vector(spec, field, length=3, limit=COORDINATE_LIMIT):
    """``spec[field]`` as a finite float vector of ``length`` entries, each
    of magnitude at most ``limit`` (None: any finite value, e.g. for a
    direction)."""
    value = spec[field]
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        array = None
    if array is None or array.shape != (length,) or \
            not np.isfinite(array).all():
        raise ProblemError(f"surface {field}: need {length} finite numbers, "
                           f"got {value!r}"[:200])
    check_limit(field, np.abs(array).max(), limit)
    return array


def spec_number(spec, field, limit=COORDINATE_LIMIT):
    """``spec[field]`` as a finite float of magnitude at most ``limit``."""
    value = spec[field]
    try:
        number = float(value)
    except (TypeError, ValueError, OverflowError):
        number = math.nan
    if isinstance(value, bool) or not math.isfinite(number):
        raise ProblemError(f"surface {field}: need a finite number, got "
                           f"{value!r}"[:200])
    check_limit(field, abs(number), limit)
    return number


def check_limit(field, magnitude, limit):
    """Coordinates and lengths beyond :data:`COORDINATE_LIMIT` make gaps
    and squared distances overflow (a sphere of radius 1e300 had an
    infinite gap and a zero normal)."""
    if limit is not None and magnitude > limit:
        raise ProblemError(f"surface {field}: {magnitude:g} is out of the "
                           f"supported range (at most {limit:g} in "
                           "magnitude, as the nodes; rescale the units)")


def as_points(points, name="points"):
    """``points`` as a finite (m, 3) float array (GapError otherwise)."""
    points = np.asarray(points, dtype=float)
    if points.ndim != 2 or points.shape[1] != 3:
        raise GapError(f"{name} must have shape (m, 3), got {points.shape}")
    if not np.isfinite(points).all():
        raise GapError(f"{name} must be finite")
    return points


def as_directions(directions, m):
    """Unit (m, 3) directions (GapError for a wrong shape or zero)."""
    d = np.asarray(directions, dtype=float)
    d = np.broadcast_to(as_points(d.reshape(-1, 3) if d.shape == (3,) else d,
                                  "directions"), (m, 3))
    length = np.linalg.norm(d, axis=1)
    if not (length > 0).all():
        raise GapError("directions must be non-zero")
    return d / length[:, None]


def fail(bad, points, what, error=GapError):
    """Raise ``error`` about the nodes flagged in ``bad``: their count and
    the first one's coordinates."""
    bad = np.flatnonzero(bad)
    x, y, z = points[bad[0]]
    raise error(f"{what} for {len(bad)} of {len(points)} contact nodes "
                f"(the first, index {bad[0]}, at ({x:g}, {y:g}, {z:g}))")


class Surface:
    """A rigid obstacle surface in 3D: subclasses set :attr:`kind` and
    implement :meth:`spec`, :meth:`gap_along_obstacle_normal` and
    :meth:`gap_along_rays`."""

    kind = None

    def spec(self):
        """The JSON-serialisable spec this surface was made from."""
        raise NotImplementedError

    def gap_along_obstacle_normal(self, points):
        r"""Gaps measured from the obstacle (3D §2.1.1) at the body
        ``points`` (m, 3): (gap, ν, foot), the signed distance
        :math:`(x - q)\cdot n(q)` to the closest point *q* (positive
        outside the obstacle), the unit contact direction :math:`-n(q)`
        and *q*."""
        raise NotImplementedError

    def gap_along_rays(self, points, directions):
        r"""Gaps measured from the body (3D §2.1.2) along the body's outward
        normals ``directions`` d (normalised here): (τ, the points x + τd on
        the surface), τ of smallest :math:`|\tau|` (graph and parametric
        surfaces: the one Newton reaches from the closest point), τ > 0 when
        the obstacle lies ahead. GapError naming how many rays miss the surface
        or graze it."""
        raise NotImplementedError

    def __repr__(self):
        fields = ", ".join(f"{k}={v!r}" for k, v in self.spec().items()
                           if k != "kind")
        return f"{type(self).__name__}({fields})"
