r"""Signed gaps between contact nodes and the rigid obstacle (thesis §2.1).

Small deformations and small displacements are assumed, so the gap *s* and
the contact normal ν are evaluated **once, on the undeformed body**. For a
contact node *B* the obstacle point is found on a normal line

.. math::  B + k\,\nu = \Gamma_o(t), \qquad (1), (4)

two equations for the unknowns *k* and *t*, with two choices of ν:

* :func:`gap_from_obstacle` -- "measured from the obstacle" (§2.1.1, (1)-(3)):
  ν is the obstacle's normal at *t*, so :math:`\Gamma_o(t)` is a foot point of
  *B*, :math:`(\Gamma_o(t) - B)\cdot\Gamma_o'(t) = 0`; of all foot points the
  nearest one is taken.
* :func:`gap_along_normals` -- "measured from the body" (§2.1.2, (4)-(6)):
  ν is the body's outward normal at *B* (from :mod:`solver.geometry.normals`), and
  *t* is a root of :math:`h(t) = (\Gamma_o(t) - B) \times \nu`; of all roots
  the one with the smallest :math:`|k|` is taken.

In both cases ν is normalised (7) and oriented **from the body towards the
obstacle**, and the gap is the signed distance along it,

.. math::  s = (\Gamma_o(t) - B)\cdot\nu = k \qquad (|\nu| = 1),

positive when the obstacle lies ahead of *B*, negative when *B* already lies
past the obstacle (initial penetration; allowed, the contact conditions then
push the node back, but warned about by :func:`warn_penetration`: it is
rarely what a problem meant). This follows the errata of the thesis digest:
along :math:`B + k\nu` the distance is :math:`|k|\,|\nu|` (the thesis's (3)
and (6) print :math:`|k|/|\nu|`), and the sign rule of §2.1.1 for choosing the
normal from the sign of *k* is replaced by "ν points from the body towards
the obstacle", which makes :math:`s \ge 0` for a node outside the obstacle.

Numerical method
----------------
Both problems are one-dimensional in *t*. The parameter is sampled on a
window (:func:`parameter_window`), a scalar function of *t* is evaluated at
all samples for all nodes at once (vectorised), every sign change between
consecutive samples gives a bracket, all brackets of all nodes are refined
together by Chandrupatla's bracketing root finder
(:func:`scipy.optimize.elementwise.find_root`, to machine precision), and per
node the best root is chosen. Roots closer together than the sample spacing
may be missed (a normal line touching the obstacle tangentially is such a
case; it is rejected anyway, see ``min_cosine``).
"""

import warnings

import numpy as np
from scipy.optimize.elementwise import find_root

from ..errors import (ExpressionError, GeometryError,
                      InitialPenetrationWarning)
from .obstacle import check_interval
from .window import fit_window, start_window

__all__ = ["GapError", "parameter_window", "gap_from_obstacle",
           "gap_along_normals", "warn_penetration", "DEFAULT_SAMPLES",
           "MIN_COSINE"]

#: Default number of samples of the curve parameter in the search window.
DEFAULT_SAMPLES = 2049

#: Smallest accepted :math:`|\nu_o \cdot n|` between the obstacle normal at
#: the found point and the body normal; below it the normal line meets the
#: obstacle at a grazing angle (or runs along it) and the gap is meaningless.
MIN_COSINE = 1e-3

# Values of the searched functions handled per chunk (bounds the memory to
# a few tens of MB whatever the number of nodes).
_CHUNK = 2 ** 20


class GapError(GeometryError):
    """No sensible gap for a contact node (input error).

    Raised when the normal line of a contact node misses the obstacle, meets
    it at a grazing angle, or the nearest obstacle point is an end of the
    obstacle. The message is one line and names the node and its
    coordinates, e.g. ``"the normal line of contact node 3 at (5, -10)
    misses the obstacle: ..."``.
    """


def parameter_window(points, curve, window=None, samples=DEFAULT_SAMPLES):
    r"""The interval of the obstacle parameter *t* that is searched.

    Parameters
    ----------
    points : (n, 2) array
        The contact nodes.
    curve : ParametricCurve or PolylineCurve
        The obstacle.
    window : (float, float), optional
        Explicit interval ``(t0, t1)``; default ``curve.search_interval``
        (set by the problem file's ``obstacle_search_interval`` or
        ``--search-interval``). Intersected with ``curve.t_range`` if the
        curve has one.
    samples : int
        Samples per window while fitting it.

    Returns
    -------
    (t0, t1) : (float, float)
        The window.
    ends : (bool, bool)
        Whether ``t0`` / ``t1`` are true ends of the obstacle (ends of
        ``curve.t_range``) rather than ends of an artificial window.

    Notes
    -----
    Without an explicit interval the window is fitted to the body's extent
    (:func:`solver.geometry.window.fit_window`), starting from ``t_range`` or, for
    an unbounded curve, from :math:`[-L, L]`,
    :math:`L = 2 \max_i |B_i - \Gamma_o(0)| + 1`: it does not depend on how
    fast the parametrisation runs. When a normal line of the body meets the
    obstacle far from the body, pass an interval.
    """
    points = np.asarray(points, dtype=float)
    t_range = curve.t_range
    if window is None:
        window = getattr(curve, "search_interval", None)
    if window is None:
        if t_range is not None:
            start, fixed = t_range, (True, True)
        else:
            start, fixed = start_window(points, curve), (False, False)
        if not len(points):
            return tuple(start), fixed
        t0, t1 = fit_window(points, curve, tuple(start), fixed,
                            len(_samples(start, samples)))
        ends = (False, False) if t_range is None else \
            (t0 <= t_range[0], t1 >= t_range[1])
        return (float(t0), float(t1)), ends
    try:
        t0, t1 = check_interval("search interval", window)
    except ExpressionError as exc:  # the same check, as a gap error
        raise GapError(str(exc)) from None
    ends = (False, False)
    if t_range is not None:
        ends = (t0 <= t_range[0], t1 >= t_range[1])
        t0, t1 = max(t0, t_range[0]), min(t1, t_range[1])
        if t0 >= t1:
            raise GapError(
                f"search interval {tuple(window)} does not overlap the "
                f"obstacle's t_range {t_range}")
    return (t0, t1), ends


def _as_floats(values, name):
    try:
        return np.asarray(values, dtype=float)
    except (TypeError, ValueError) as exc:
        raise GapError(f"{name} must be real numbers ({exc})") from None


def _as_points(points):
    points = _as_floats(points, "points")
    if points.ndim != 2 or points.shape[1] != 2:
        raise GapError(f"points must have shape (n, 2), got {points.shape}")
    if not np.isfinite(points).all():
        raise GapError("points must be finite")
    return points


def _as_unit(normals, n):
    """Normalise body normals (7), broadcast to (n, 2)."""
    normals = _as_floats(normals, "normals")
    if normals.shape not in ((2,), (n, 2)):
        raise GapError(
            f"normals must have shape (2,) or ({n}, 2), got {normals.shape}")
    normals = np.broadcast_to(normals, (n, 2))
    length = np.hypot(normals[:, 0], normals[:, 1])[:, None]
    if not (np.isfinite(length) & (length > 0)).all():
        raise GapError("normals must be finite and non-zero")
    return normals / length


def _fail(bad, points, node_ids, reason):
    """Raise GapError about the first node flagged in ``bad``."""
    where = np.flatnonzero(bad)
    i = int(where[0])
    label = i if node_ids is None else node_ids[i]
    x, y = points[i]
    more = f" (and {len(where) - 1} more nodes)" if len(where) > 1 else ""
    raise GapError(
        f"the normal line of contact node {label} at ({x:g}, {y:g}) misses "
        f"the obstacle: {reason(i)}{more}")


def warn_penetration(gap, points, node_ids=None):
    """Warn (:class:`~solver.errors.InitialPenetrationWarning`) if the
    obstacle penetrates the undeformed body: gaps s < 0 beyond round-off
    (1e-12 of the coordinates' magnitude), naming the first nodes, their
    count and the deepest penetration."""
    scale = float(np.abs(points).max(initial=0.0))
    deep = gap < -1e-12 * max(scale, float(np.ptp(points, axis=0).max(
        initial=0.0)), 1e-300)
    if not deep.any():
        return
    where = np.flatnonzero(deep)
    labels = where if node_ids is None else np.asarray(node_ids)[where]
    worst = int(where[np.argmin(gap[where])])
    label = worst if node_ids is None else node_ids[worst]
    names = ", ".join(str(v) for v in labels[:5]) \
        + (", ..." if len(where) > 5 else "")
    warnings.warn(
        f"the obstacle penetrates the undeformed body at {len(where)} "
        f"contact node{'s' if len(where) > 1 else ''} ({names}); deepest "
        f"{-gap[worst]:.3g} at node {label} ({points[worst, 0]:g}, "
        f"{points[worst, 1]:g}): initial gaps s < 0, the contact "
        "conditions will push these nodes out",
        InitialPenetrationWarning, stacklevel=3)


def _setup(points, vectors, curve, window, samples):
    """Checked points, unit vectors (one per point), the window (t0, t1),
    its parameter samples and whether it reaches the curve's ends."""
    points = _as_points(points)
    vectors = _as_unit(vectors, len(points))
    if not len(points):
        return points, vectors, (None, None), None, None
    window, curve_ends = parameter_window(points, curve, window, samples)
    return points, vectors, window, _samples(window, samples), curve_ends


def _samples(window, samples):
    samples = int(samples)
    if samples < 3:
        raise GapError(f"samples must be at least 3, got {samples}")
    return np.linspace(window[0], window[1], samples)


def _refine(function, lower, upper, args):
    """Roots of ``function(t, *args)`` in the brackets, all at once.

    Returns the roots and a mask of the brackets that converged.
    """
    if len(lower) == 0:
        return lower.copy(), np.ones(0, dtype=bool)
    with np.errstate(all="ignore"):
        result = find_root(function, (lower, upper), args=args)
    return np.asarray(result.x), np.asarray(result.success)


def _first_per_owner(owner, key, n):
    """Index of the candidate with the smallest ``key`` for every owner.

    Returns an (n,) int array, -1 for owners without candidates.
    """
    best = np.full(n, -1, dtype=np.int64)
    if len(owner):
        order = np.lexsort((key, owner))
        sorted_owner = owner[order]
        first = np.r_[True, sorted_owner[1:] != sorted_owner[:-1]]
        best[sorted_owner[first]] = order[first]
    return best


def _obstacle_normals(curve, t):
    """Unit normals of the obstacle at ``t`` (and the tangent lengths)."""
    tangent = curve.derivative(t)
    length = np.linalg.norm(tangent, axis=-1)
    with np.errstate(all="ignore"):
        normal = np.stack([tangent[..., 1], -tangent[..., 0]], axis=-1) \
            / length[..., None]
    return normal, length


def gap_from_obstacle(points, curve, body_normals, *, window=None,
                      samples=DEFAULT_SAMPLES, min_cosine=MIN_COSINE,
                      node_ids=None):
    r"""Gaps measured from the obstacle: nearest obstacle point (§2.1.1).

    For every node *B* the nearest point :math:`\Gamma_o(t)` of the obstacle
    is found among the foot points,
    :math:`f(t) = (\Gamma_o(t) - B)\cdot\Gamma_o'(t) = 0` with *f* rising
    through zero (local minima of the distance); then
    :math:`B + k\nu = \Gamma_o(t)` holds with ν the obstacle's normal (1)-(2).
    ν is normalised (7) and oriented from the body towards the obstacle:
    the rigid obstacle lies on one side of Γo, so one orientation of its
    normal serves every node, the one with :math:`\nu \cdot n > 0` for the
    body's outward normals *n* (summed over the nodes: a node past a corner
    of the body, whose own *n* barely faces the obstacle, keeps the sign of
    its gap), and :math:`s = (\Gamma_o(t) - B)\cdot\nu` (signed |k|,
    errata to (3)).

    Parameters
    ----------
    points : (n, 2) array
        Contact nodes *B* (undeformed).
    curve : ParametricCurve
        The obstacle.
    body_normals : (n, 2) or (2,) array
        Outward normals of the body at the nodes (any length); used only to
        orient ν and to reject grazing configurations.
    window : (float, float), optional
        Parameter interval searched; see :func:`parameter_window` for the
        default.
    samples : int
        Number of samples of *t* in the window; local minima of the distance
        closer together than the sample spacing may be missed.
    min_cosine : float
        Smallest accepted :math:`|\nu\cdot n|`.
    node_ids : sequence, optional
        Labels of the nodes for error messages (default: their index).

    Returns
    -------
    gap : (n,) float array
        Signed gaps *s*; negative for a node past the obstacle.
    normal : (n, 2) float array
        Unit obstacle normals ν at the nearest points, pointing from the body
        towards the obstacle: the contact direction.
    t : (n,) float array
        Parameters of the nearest points.

    Raises
    ------
    GapError
        If for some node the nearest point is an end of the obstacle (its
        ``t_range``) where the distance is not perpendicular to the
        obstacle, or an end of an artificial window (the window is too
        small), or ν is nearly perpendicular to the body normal
        (:math:`|\nu\cdot n| <` ``min_cosine``; e.g. the obstacle runs
        along the body normal), or the obstacle has no tangent there.
    """
    points, body, (t0, t1), ts, curve_ends = _setup(
        points, body_normals, curve, window, samples)
    if not len(points):  # no free contact node: nothing to measure
        return np.zeros(0), np.zeros((0, 2)), np.zeros(0)
    n = len(points)
    with np.errstate(all="ignore"):
        c_pts = curve.point(ts)
        c_der = curve.derivative(ts)

    # Brackets of the local minima of |Γo(t) - B|: f < 0 then f >= 0.
    owners, lowers = [], []
    end_d2 = np.empty((n, 2))
    block = max(1, _CHUNK // len(ts))
    for start in range(0, n, block):  # a few chunks, each vectorised
        stop = min(n, start + block)
        with np.errstate(all="ignore"):
            r = c_pts[None, :, :] - points[start:stop, None, :]
            f = np.einsum("pjk,jk->pj", r, c_der)
            d2 = np.einsum("pjk,pjk->pj", r, r)
        p, j = np.nonzero((f[:, :-1] < 0) & (f[:, 1:] >= 0))
        owners.append(p + start)
        lowers.append(j)
        end_d2[start:stop] = d2[:, [0, -1]]
    owner = np.concatenate(owners)
    lower = np.concatenate(lowers)

    def slope(t, bx, by):
        pt, der = curve.point(t), curve.derivative(t)
        return ((pt[..., 0] - bx) * der[..., 0]
                + (pt[..., 1] - by) * der[..., 1])

    root, ok = _refine(slope, ts[lower], ts[lower + 1],
                       (points[owner, 0], points[owner, 1]))
    owner, root = owner[ok], root[ok]
    with np.errstate(all="ignore"):
        d2 = np.sum((curve.point(root) - points[owner]) ** 2, axis=1)
    keep = np.isfinite(d2)
    owner, root, d2 = owner[keep], root[keep], d2[keep]
    best = _first_per_owner(owner, d2, n)
    has = best >= 0
    t = np.full(n, np.nan)
    t[has] = root[best[has]]
    best_d2 = np.full(n, np.inf)
    best_d2[has] = d2[best[has]]

    # An end of the window closer than every interior foot point wins; it is
    # accepted only if it is itself a foot point (distance perpendicular).
    end_d2 = np.where(np.isfinite(end_d2), end_d2, np.inf)
    at_end = np.full(n, -1)
    for side in (0, 1):
        closer = end_d2[:, side] < best_d2 * (1 - 1e-12)
        closer &= end_d2[:, side] <= end_d2[:, 1 - side]
        at_end[closer] = side
    if (at_end >= 0).any():
        t_end = np.where(at_end == 0, t0, t1)
        with np.errstate(all="ignore"):
            r = curve.point(t_end) - points
            der = curve.derivative(t_end)
            cosine = np.abs(np.sum(r * der, axis=1)) / (
                np.linalg.norm(r, axis=1) * np.linalg.norm(der, axis=1))
        foot = (np.linalg.norm(r, axis=1) == 0) | (cosine <= 1e-10)
        bad = (at_end >= 0) & ~foot
        if bad.any():
            def reason(i):
                end = (t0, t1)[at_end[i]]
                if curve_ends[at_end[i]]:
                    return (f"its nearest obstacle point is the end "
                            f"t = {end:g} of the obstacle's t_range")
                return (f"no obstacle point nearer than the end t = {end:g} "
                        f"of the search window [{t0:g}, {t1:g}]; give a "
                        "larger search interval (--search-interval)")
            _fail(bad, points, node_ids, reason)
        t = np.where(at_end >= 0, t_end, t)
    if np.isnan(t).any():
        _fail(np.isnan(t), points, node_ids, lambda i: (
            f"no finite obstacle point for t in [{t0:g}, {t1:g}]"))

    with np.errstate(all="ignore"):
        foot_pt = curve.point(t)
        normal, length = _obstacle_normals(curve, t)
        # At a kink of a polyline (or any corner) the nearest point is not a
        # foot point: (Γo − B)·Γo' jumps in sign there instead of vanishing.
        # The normal is then the direction from B to that point (the limit
        # of the normals of both sides' nearest points).
        r = foot_pt - points
        distance = np.linalg.norm(r, axis=1)
        tangent = curve.derivative(t)
        off = np.abs(np.sum(r * tangent, axis=1)) > 1e-9 * distance * \
            np.linalg.norm(tangent, axis=1)
        corner = off & (distance > 0)
        toward = r[corner] / distance[corner, None]
        # ... oriented like the curve's own normal there (both sides'
        # normals agree in sign with it), so that ν_o keeps one orientation
        # along the whole obstacle
        flip = np.sign(np.sum(toward * normal[corner], axis=1))
        normal[corner] = toward * np.where(flip == 0, 1.0, flip)[:, None]
        length[corner] = 1.0
        cosine = np.sum(normal * body, axis=1)
    if not (np.isfinite(length) & (length > 0)).all():
        bad = ~(np.isfinite(length) & (length > 0))
        _fail(bad, points, node_ids, lambda i: (
            f"the obstacle has no tangent at its nearest point t = {t[i]:g}"))
    grazing = ~(np.abs(cosine) >= min_cosine)
    if grazing.any():
        _fail(grazing, points, node_ids, lambda i: (
            f"the obstacle normal at its nearest point t = {t[i]:g} is "
            f"nearly perpendicular to the body normal "
            f"(cosine {cosine[i]:.2g})"))
    # ν from the body towards the obstacle: the obstacle is rigid and lies
    # on one side of Γo, so one orientation of the curve's normal serves all
    # nodes, the one most body normals agree with (a node past a corner of
    # the body, whose own normal barely faces the obstacle, keeps the sign
    # of its gap right).
    side = np.sign(np.sum(cosine))
    orient = np.sign(cosine) if side == 0 else np.full(n, side)
    normal *= orient[:, None]
    gap = np.sum((foot_pt - points) * normal, axis=1)
    warn_penetration(gap, points, node_ids)
    return gap, normal, t


def gap_along_normals(points, normals, curve, *, window=None,
                      samples=DEFAULT_SAMPLES, min_cosine=MIN_COSINE,
                      node_ids=None):
    r"""Gaps measured from the body, along its outward normals (§2.1.2).

    For every node *B* with unit outward normal ν (7) the intersections of
    the normal line with the obstacle, :math:`B + k\nu = \Gamma_o(t)`
    (4)-(5), are the roots of

    .. math::  h(t) = (\Gamma_o(t) - B) \times \nu
               = (x(t) - b_1)\,\nu_2 - (y(t) - b_2)\,\nu_1,

    with :math:`k = (\Gamma_o(t) - B)\cdot\nu`. The intersection with the
    smallest :math:`|k|` is taken and :math:`s = k`: positive when the
    obstacle lies ahead along the outward normal, negative when behind
    (errata to (6): the distance is :math:`|k|\,|\nu|`).

    Parameters
    ----------
    points : (n, 2) array
        Contact nodes *B* (undeformed).
    normals : (n, 2) or (2,) array
        Outward normals of the body at the nodes, e.g. from
        :func:`solver.geometry.normals.boundary_normals`; normalised here.
    curve : ParametricCurve
        The obstacle.
    window, samples, min_cosine, node_ids
        As in :func:`gap_from_obstacle`; ``min_cosine`` bounds
        :math:`|\nu_o\cdot\nu|` with :math:`\nu_o` the obstacle's normal at
        the intersection (rejects grazing intersections).

    Returns
    -------
    gap : (n,) float array
        Signed gaps ``s = k``.
    normal : (n, 2) float array
        The unit body normals ν (the contact direction, from the body towards
        the obstacle).
    t : (n,) float array
        Parameters of the intersection points.

    Raises
    ------
    GapError
        If the normal line of some node does not meet the obstacle inside
        the window (changes of sign of *h* between samples), or meets it at a
        grazing angle (:math:`|\nu_o\cdot\nu| <` ``min_cosine``, e.g. an
        obstacle line parallel to the normal).
    """
    points, nu, (t0, t1), ts, curve_ends = _setup(
        points, normals, curve, window, samples)
    if not len(points):  # no free contact node: nothing to measure
        return np.zeros(0), np.zeros((0, 2)), np.zeros(0)
    n = len(points)
    with np.errstate(all="ignore"):
        c_pts = curve.point(ts)

    exact_owner, exact_t = [], []
    owners, lowers = [], []
    block = max(1, _CHUNK // len(ts))
    for start in range(0, n, block):  # a few chunks, each vectorised
        stop = min(n, start + block)
        b, v = points[start:stop, None, :], nu[start:stop, None, :]
        with np.errstate(all="ignore"):
            r = c_pts[None, :, :] - b
            h = r[..., 0] * v[..., 1] - r[..., 1] * v[..., 0]
        p, j = np.nonzero(h == 0)
        exact_owner.append(p + start)
        exact_t.append(ts[j])
        p, j = np.nonzero(h[:, :-1] * h[:, 1:] < 0)
        owners.append(p + start)
        lowers.append(j)
    owner = np.concatenate(owners)
    lower = np.concatenate(lowers)

    def cross(t, bx, by, vx, vy):
        pt = curve.point(t)
        return (pt[..., 0] - bx) * vy - (pt[..., 1] - by) * vx

    root, ok = _refine(cross, ts[lower], ts[lower + 1],
                       (points[owner, 0], points[owner, 1],
                        nu[owner, 0], nu[owner, 1]))
    owner = np.concatenate([owner[ok]] + exact_owner)
    root = np.concatenate([root[ok]] + exact_t)
    with np.errstate(all="ignore"):
        k = np.sum((curve.point(root) - points[owner]) * nu[owner], axis=1)
    keep = np.isfinite(k)
    owner, root, k = owner[keep], root[keep], k[keep]
    best = _first_per_owner(owner, np.abs(k), n)
    if (best < 0).any():
        def reason(i):
            where = "t_range" if all(curve_ends) else "search window"
            hint = "" if all(curve_ends) else \
                "; give a larger search interval (--search-interval)"
            return (f"no intersection for t in the {where} "
                    f"[{t0:g}, {t1:g}]{hint}")
        _fail(best < 0, points, node_ids, reason)
    t, gap = root[best], k[best]
    with np.errstate(all="ignore"):
        obstacle_normal, length = _obstacle_normals(curve, t)
        cosine = np.sum(obstacle_normal * nu, axis=1)
    bad = ~(np.isfinite(length) & (length > 0))
    if bad.any():
        _fail(bad, points, node_ids, lambda i: (
            f"the obstacle has no tangent at the intersection t = {t[i]:g}"))
    grazing = ~(np.abs(cosine) >= min_cosine)
    if grazing.any():
        _fail(grazing, points, node_ids, lambda i: (
            f"it meets the obstacle at a grazing angle at t = {t[i]:g} "
            f"(cosine {cosine[i]:.2g} between the normals)"))
    warn_penetration(gap, points, node_ids)
    return gap, nu.copy(), t
