r"""Gaps measured from the obstacle: the nearest obstacle point (thesis
§2.1.1, (1)-(3) with the digest's errata; see :mod:`solver.geometry.curves`).
"""

import numpy as np

from ..checks import Misses, warn_penetration
from .search import (DEFAULT_SAMPLES, MIN_COSINE, CHUNK,
                         first_per_owner, obstacle_normals, refine_roots,
                         search_setup)

__all__ = ["gap_from_obstacle", "nearest_obstacle_points", "orient_normals"]


def gap_from_obstacle(points, curve, body_normals, *, window=None,
                      samples=DEFAULT_SAMPLES, min_cosine=MIN_COSINE,
                      node_ids=None, warn=True, out_of_reach=False):
    r"""Gaps measured from the obstacle: nearest obstacle point (§2.1.1).

    For every contact node *B* (``points`` (n, 2), undeformed) the nearest
    point :math:`\Gamma_o(t)` of ``curve`` among the foot points
    :math:`f(t) = (\Gamma_o(t) - B)\cdot\Gamma_o'(t) = 0` (*f* rising: local
    minima of the distance); ν is the obstacle's normal there (1)-(2),
    normalised (7) and oriented from the body towards the obstacle by the
    body's outward ``body_normals``, and :math:`s = (\Gamma_o(t) - B)\cdot\nu`
    (signed |k|, errata to (3)). ``window``: the interval searched (default
    :func:`parameter_window`) with ``samples`` samples; ``min_cosine``: the
    smallest accepted :math:`|\nu\cdot n|`; ``node_ids`` label the nodes in
    messages. Returns (gap, normal, t); GapError where the nearest point is an
    end of the obstacle or of a too small window not perpendicular to it,
    where :math:`|\nu\cdot n| <` ``min_cosine``, or where there is no tangent
    — or, ``out_of_reach``, gap +∞ and ν NaN at those nodes (one bounded
    obstacle of several, :mod:`.several`).
    """
    near = nearest_obstacle_points(points, curve, body_normals,
                                   window=window, samples=samples,
                                   min_cosine=min_cosine, node_ids=node_ids,
                                   out_of_reach=out_of_reach)
    foot_pt, normal, t, cosine, missed = near
    points = np.asarray(points, dtype=float)  # checked by the search
    if not len(t):  # no free contact node: nothing to measure
        return np.zeros(0), np.zeros((0, 2)), np.zeros(0)
    # ν from the body towards the obstacle: the obstacle is rigid and lies
    # on one side of Γo, so one orientation of the curve's normal serves all
    # nodes, the one most body normals agree with (a node past a corner of
    # the body, whose own normal barely faces the obstacle, keeps its sign).
    gap, normal = orient_normals(near, points, np.sign(np.sum(
        cosine[~missed])))
    if warn:  # an obstacle that penetrates the undeformed body
        warn_penetration(gap[~missed], points[~missed],
                         None if node_ids is None
                         else np.asarray(node_ids)[~missed])
    return gap, normal, t


def orient_normals(near, points, side):
    """(gap, ν) from :func:`nearest_obstacle_points`'s ``near`` with the
    curve's normals times ``side`` (±1; 0: each node's own sign of ν·n),
    +∞ and NaN where the node was missed."""
    foot_pt, normal, _, cosine, missed = near
    orient = np.sign(cosine) if side == 0 else np.full(len(cosine), side)
    normal = normal * orient[:, None]
    with np.errstate(all="ignore"):
        gap = np.sum((foot_pt - points) * normal, axis=1)
    gap[missed] = np.inf
    normal[missed] = np.nan
    return gap, normal


def nearest_obstacle_points(points, curve, body_normals, *, window=None,
                            samples=DEFAULT_SAMPLES, min_cosine=MIN_COSINE,
                            node_ids=None, out_of_reach=False):
    """The nearest obstacle points of :func:`gap_from_obstacle` before ν is
    oriented: (Γo(t), the curve's own unit normals there, t, their cosines
    with the body normals, the nodes missed (all False unless
    ``out_of_reach``)); arguments as there."""
    points, body, (t0, t1), ts, curve_ends = search_setup(
        points, body_normals, curve, window, samples)
    n = len(points)
    if not n:
        empty = np.zeros((0, 2))
        return empty, empty, np.zeros(0), np.zeros(0), np.zeros(0, bool)
    misses = Misses(n, out_of_reach)
    t, best_d2, end_d2 = _nearest_foot_points(points, curve, ts)
    t = _window_ends(points, curve, t, best_d2, end_d2, (t0, t1),
                     curve_ends, node_ids, misses)
    if np.isnan(t).any():
        misses(np.isnan(t), points, node_ids, lambda i: (
            f"no finite obstacle point for t in [{t0:g}, {t1:g}]"))

    foot_pt, normal, length, cosine = _contact_normals(points, curve, t,
                                                       body)
    if not (np.isfinite(length) & (length > 0)).all():
        bad = ~(np.isfinite(length) & (length > 0))
        misses(bad, points, node_ids, lambda i: (
            f"the obstacle has no tangent at its nearest point t = {t[i]:g}"))
    grazing = ~(np.abs(cosine) >= min_cosine)
    if grazing.any():
        misses(grazing, points, node_ids, lambda i: (
            f"the obstacle normal at its nearest point t = {t[i]:g} is "
            f"nearly perpendicular to the body normal "
            f"(cosine {cosine[i]:.2g})"))
    return foot_pt, normal, t, cosine, misses.mask


def _nearest_foot_points(points, curve, ts):
    """Per node, the nearest foot point Γo(t) among the sampled brackets
    of f(t) = (Γo(t) − B)·Γo'(t) (f < 0 then f ≥ 0: local minima of the
    distance), refined by :func:`refine_roots`: t (NaN where none), its squared
    distance (inf where none) and the squared distances to the window's
    two ends, (n, 2)."""
    n = len(points)
    with np.errstate(all="ignore"):
        c_pts = curve.point(ts)
        c_der = curve.derivative(ts)

    # Brackets of the local minima of |Γo(t) - B|: f < 0 then f >= 0.
    owners, lowers = [], []
    end_d2 = np.empty((n, 2))
    block = max(1, CHUNK // len(ts))
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

    root, ok = refine_roots(slope, ts[lower], ts[lower + 1],
                       (points[owner, 0], points[owner, 1]))
    owner, root = owner[ok], root[ok]
    with np.errstate(all="ignore"):
        d2 = np.sum((curve.point(root) - points[owner]) ** 2, axis=1)
    keep = np.isfinite(d2)
    owner, root, d2 = owner[keep], root[keep], d2[keep]
    best = first_per_owner(owner, d2, n)
    has = best >= 0
    t = np.full(n, np.nan)
    t[has] = root[best[has]]
    best_d2 = np.full(n, np.inf)
    best_d2[has] = d2[best[has]]
    return t, best_d2, end_d2


def _window_ends(points, curve, t, best_d2, end_d2, window, curve_ends,
                 node_ids, misses):
    """t with an end of the window where it is closer than every interior
    foot point; GapError unless that end is itself a foot point (distance
    perpendicular to the obstacle)."""
    t0, t1 = window
    n = len(points)
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
            misses(bad, points, node_ids, reason)
        t = np.where(at_end >= 0, t_end, t)
    return t


def _contact_normals(points, curve, t, body):
    """Γo(t), the obstacle's unit normals there (at a corner, the direction
    from B to that point), the tangent lengths and ν·n with the body's
    normals ``body`` (ν not yet oriented)."""
    with np.errstate(all="ignore"):
        foot_pt = curve.point(t)
        normal, length = obstacle_normals(curve, t)
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
    return foot_pt, normal, length, cosine
