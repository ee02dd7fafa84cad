r"""Checks and messages of the gap search (thesis §2.1): the node arrays,
the normals (normalised as in (7)), the one-line :class:`GapError` and
the initial-penetration warning."""

import warnings

import numpy as np

from ..errors import GeometryError, InitialPenetrationWarning, ProblemError

__all__ = ["GapError", "warn_penetration", "COORDINATE_LIMIT",
           "RESOLUTION", "Misses", "check_obstacle_list"]

#: Largest accepted |coordinate| of the body's nodes and of the numbers
#: that place an obstacle: beyond it gaps, squared distances and the forces
#: k·s overflow or underflow double precision.
COORDINATE_LIMIT = 1e30

#: Smallest accepted ratio of the body's size to its largest |coordinate|
#: (below it the node positions keep fewer than 8 significant digits), and
#: of the body's size to a sphere obstacle's radius (its gaps |x − c| − R
#: carry an error of about ε·R).
RESOLUTION = 1e-8


class GapError(GeometryError):
    """No sensible gap for a contact node (input error): its normal line
    misses the obstacle, meets it at a grazing angle, or ends at an end of
    it. One line naming the node and its coordinates."""



def as_floats(values, name):
    try:
        return np.asarray(values, dtype=float)
    except (TypeError, ValueError) as exc:
        raise GapError(f"{name} must be real numbers ({exc})") from None


def as_plane_points(points):
    points = as_floats(points, "points")
    if points.ndim != 2 or points.shape[1] != 2:
        raise GapError(f"points must have shape (n, 2), got {points.shape}")
    if not np.isfinite(points).all():
        raise GapError("points must be finite")
    return points


def unit_normals(normals, n):
    """Normalise body normals (7), broadcast to (n, 2)."""
    normals = as_floats(normals, "normals")
    if normals.shape not in ((2,), (n, 2)):
        raise GapError(
            f"normals must have shape (2,) or ({n}, 2), got {normals.shape}")
    normals = np.broadcast_to(normals, (n, 2))
    length = np.hypot(normals[:, 0], normals[:, 1])[:, None]
    if not (np.isfinite(length) & (length > 0)).all():
        raise GapError("normals must be finite and non-zero")
    return normals / length


def normal_line_misses(bad, points, node_ids, reason):
    """Raise GapError about the first node flagged in ``bad``."""
    where = np.flatnonzero(bad)
    i = int(where[0])
    label = i if node_ids is None else node_ids[i]
    x, y = points[i]
    more = f" (and {len(where) - 1} more nodes)" if len(where) > 1 else ""
    raise GapError(
        f"the normal line of contact node {label} at ({x:g}, {y:g}) misses "
        f"the obstacle: {reason(i)}{more}")


def check_obstacle_list(items, name, what, limit):
    """The specs of several obstacles (2D curves, 3D surfaces): a non-empty
    list or tuple of at most ``limit``; ProblemError ``"{name}: ..."``."""
    if not isinstance(items, (list, tuple)) or not items:
        raise ProblemError(f"{name}: need a non-empty list of {what} specs")
    if len(items) > limit:
        raise ProblemError(f"{name}: at most {limit} obstacles, got "
                           f"{len(items)}")


class Misses:
    """Where the normal lines of n nodes miss the obstacle: each call with
    a mask ``bad`` raises :class:`GapError` about its first node
    (:func:`normal_line_misses`), or, ``tolerant``, only marks the nodes in
    ``mask``: a node a bounded obstacle of several does not reach is out of
    its reach, not an input error (:mod:`solver.geometry.curves.several`)."""

    def __init__(self, n, tolerant=False):
        self.mask = np.zeros(n, bool)
        self.tolerant = bool(tolerant)

    def __call__(self, bad, points, node_ids, reason):
        bad = np.asarray(bad, bool) & ~self.mask
        if not bad.any():
            return
        if not self.tolerant:
            normal_line_misses(bad, points, node_ids, reason)
        self.mask |= bad


def warn_penetration(gap, points, node_ids=None,
                     what="the obstacle penetrates the undeformed body",
                     floor=0.0):
    """Warn (:class:`~solver.errors.InitialPenetrationWarning`) if the
    obstacle penetrates the undeformed body (``what`` happens): gaps s < 0
    beyond round-off (1e-12 of the coordinates' magnitude, or ``floor``, a
    length or one per node, where the gaps carry more: the mortar's
    integrated ones),
    naming the first nodes, their count and the deepest penetration."""
    if not len(gap):
        return
    scale = float(np.abs(points).max(initial=0.0))
    deep = gap < -np.maximum(1e-12 * max(scale, float(np.ptp(
        points, axis=0).max(initial=0.0)), 1e-300), floor)
    if not deep.any():
        return
    where = np.flatnonzero(deep)
    labels = where if node_ids is None else np.asarray(node_ids)[where]
    worst = int(where[np.argmin(gap[where])])
    label = worst if node_ids is None else node_ids[worst]
    names = ", ".join(str(v) for v in labels[:5]) \
        + (", ..." if len(where) > 5 else "")
    warnings.warn(
        f"{what} at {len(where)} contact node"
        f"{'s' if len(where) > 1 else ''} ({names}); deepest "
        f"{-gap[worst]:.3g} at node {label} ("
        + ", ".join(f"{x:g}" for x in points[worst]) + "): initial gaps "
        "s < 0, the contact conditions will push these nodes out",
        InitialPenetrationWarning, stacklevel=3)
