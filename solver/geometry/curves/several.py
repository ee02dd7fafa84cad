r"""Several rigid obstacle curves in one 2D problem.

The 2D counterpart of :mod:`solver.geometry.surfaces.several`: a list of
curves (parametric, :class:`~.parametric.ParametricCurve`, bounded by a
``t_range`` or not; polylines, :class:`~.polyline.PolylineCurve`; a
straight segment is a polyline of two points), each node's gap and normal
from the obstacle of **smallest gap** in the reference configuration (the
one that binds first; small sliding), so that a node touches one obstacle
at a time.

Every curve is searched for all nodes in its *out-of-reach* mode (the gap
functions' ``out_of_reach``): where a bounded curve ends before a node
(its nearest point is an end that is not a foot point), or its normal
line misses it or meets it grazing, the node is out of that curve's reach
(gap +∞ from it) instead of an input error. A node no curve reaches takes
no part in contact and is reported among the excluded nodes ("no obstacle
in reach", :func:`solver.contact.contact_geometry`).

Orientation. A single curve orients its normal by the body normals of all
nodes (:func:`~.closest.gap_from_obstacle`); of several, each curve by the
body normals of the nodes nearest to it (unsigned distance), so that a
curve on the left of the body points to the left although most nodes,
those on the right, face another one.

Gap modes. ``"obstacle"`` (§2.1.1): s = (Γo(t) − B)·ν, ν the oriented
obstacle normal at the nearest point. ``"body"`` (§2.1.2): s = k along the
body's outward normal n, counted only from the curves the node faces,
n·ν_o ≥ 0 with ν_o the curve's oriented normal at the intersection (as
the 3D rays: a line behind the node, which the normal line meets too,
does not count).

At a corner between two obstacles (or wherever two reach a node) the node
takes the one of smaller gap, and its normal jumps from one to the other
across the bisector; at equal gaps it takes the first listed."""

import numpy as np

from ...errors import ProblemError
from ..checks import check_obstacle_list
from .closest import nearest_obstacle_points, orient_normals
from .parametric import ParametricCurve
from .polyline import PolylineCurve
from .rays import gap_along_normals
from .search import DEFAULT_SAMPLES, MIN_COSINE, obstacle_normals

__all__ = ["SeveralCurves", "curve_from_spec", "curve_spec", "several_gaps",
           "MAX_CURVES"]

#: Most obstacle curves one problem may list (as 3D surfaces).
MAX_CURVES = 64


def curve_from_spec(spec):
    """A curve from its spec dict: ``{"x": "x(t)", "y": "y(t)"}`` (optional
    ``"t_range"``, ``"search_interval"``) a ParametricCurve, ``{"points":
    [[x, y], ...]}`` (optional ``"search_interval"``, in arc length) a
    PolylineCurve; ProblemError naming the keys otherwise."""
    if not isinstance(spec, dict):
        raise ProblemError(f"obstacle curve: need an object, got "
                           f"{type(spec).__name__}")
    keys = set(spec)
    if keys >= {"x", "y"} and keys <= {"x", "y", "t_range",
                                       "search_interval"}:
        return ParametricCurve(spec["x"], spec["y"], spec.get("t_range"),
                               spec.get("search_interval"))
    if keys >= {"points"} and keys <= {"points", "search_interval"}:
        return PolylineCurve(spec["points"], spec.get("search_interval"))
    raise ProblemError(
        'obstacle curve: an obstacle curve is {"x": ..., "y": ...} '
        '(optionally "t_range", "search_interval") or {"points": [...]} '
        f'(optionally "search_interval"), got the keys {sorted(keys)}'[:300])


def curve_spec(curve):
    """The spec dict of ``curve`` (inverse of :func:`curve_from_spec`)."""
    if isinstance(curve, PolylineCurve):
        spec = {"points": curve.points.tolist()}
    else:
        spec = {"x": curve.x_text, "y": curve.y_text}
        if curve.t_range is not None:
            spec["t_range"] = list(curve.t_range)
    if curve.search_interval is not None:
        spec["search_interval"] = list(curve.search_interval)
    return spec


class SeveralCurves:
    """Several obstacle curves (module docstring); ``curves`` curve objects
    or their spec dicts (:func:`curve_from_spec`), 1 to
    :data:`MAX_CURVES`."""

    kind = "several"
    #: No one parameter t: each curve has its own (``search_interval``
    #: per curve, in its spec).
    t_range = None
    search_interval = None

    def __init__(self, curves):
        check_obstacle_list(curves, "obstacle curves", "curve", MAX_CURVES)
        self.parts = [c if isinstance(c, (ParametricCurve, PolylineCurve))
                      else curve_from_spec(c) for c in curves]

    def spec(self):
        """The list of the curves' spec dicts."""
        return [curve_spec(c) for c in self.parts]

    def __repr__(self):
        return f"SeveralCurves({', '.join(map(repr, self.parts))})"


def several_gaps(points, obstacle, body_normals, gap="obstacle", *,
                 samples=DEFAULT_SAMPLES, min_cosine=MIN_COSINE,
                 node_ids=None):
    """(s, ν, foot, which) at the nodes ``points`` (n, 2) with outward
    ``body_normals`` for the :class:`SeveralCurves` ``obstacle``: the gap
    from the curve of smallest gap (module docstring), ν, the foot point
    Γo(t) on it (n, 2) and its index ``which``; +∞, NaN and −1 where no
    curve reaches the node. ``gap``: "obstacle" or "body"."""
    points = np.asarray(points, float)
    body = np.asarray(body_normals, float)
    n = len(points)
    kwargs = dict(samples=samples, min_cosine=min_cosine, node_ids=node_ids,
                  out_of_reach=True)
    near = [nearest_obstacle_points(points, c, body, **kwargs)
            for c in obstacle.parts]
    distance = np.stack([np.where(m, np.inf, np.hypot(*(f - points).T))
                         for f, _, _, _, m in near]) if n else \
        np.zeros((len(near), 0))
    nearest = np.argmin(distance, axis=0) if n else np.zeros(0, int)
    reached = np.isfinite(distance.min(axis=0, initial=np.inf))
    gaps, normals, feet = [], [], []
    for j, (curve, part) in enumerate(zip(obstacle.parts, near)):
        cosine, missed = part[3], part[4]
        voters = (nearest == j) & reached & ~missed
        side = np.sign(np.sum(cosine[voters]))
        if side == 0:  # no node is nearest to it: all that it reaches
            side = np.sign(np.sum(cosine[~missed]))
        if gap == "obstacle":
            s, nu = orient_normals(part, points, side)
            foot = part[0]
        else:
            s, nu, t = gap_along_normals(points, body, curve, warn=False,
                                         **kwargs)
            with np.errstate(all="ignore"):
                foot = curve.point(t)
                facing = np.sum(obstacle_normals(curve, t)[0] * nu, axis=1)
            if side != 0:  # a curve behind the node does not count
                s = np.where(side * facing >= 0, s, np.inf)
        gaps.append(s)
        normals.append(nu)
        feet.append(foot)
    gaps = np.stack(gaps)
    pick = np.argmin(gaps, axis=0)  # the first listed on ties
    rows = np.arange(n)
    s = gaps[pick, rows]
    nu = np.stack(normals)[pick, rows]
    foot = np.stack(feet)[pick, rows]
    out = ~np.isfinite(s)
    nu[out], foot[out] = np.nan, np.nan
    return s, nu, foot, np.where(out, -1, pick)
