r"""Gaps measured from the body, along its outward normals (thesis §2.1.2,
(4)-(6) with the digest's errata; see :mod:`solver.geometry.curves`)."""

import numpy as np

from ..checks import Misses, warn_penetration
from .search import (DEFAULT_SAMPLES, MIN_COSINE, CHUNK,
                         first_per_owner, obstacle_normals, refine_roots,
                         search_setup)

__all__ = ["gap_along_normals"]


def gap_along_normals(points, normals, curve, *, window=None,
                      samples=DEFAULT_SAMPLES, min_cosine=MIN_COSINE,
                      node_ids=None, warn=True, out_of_reach=False):
    r"""Gaps measured from the body, along its outward normals (§2.1.2).

    For every node *B* with unit outward normal ν (7) the intersections of
    the normal line with the obstacle, :math:`B + k\nu = \Gamma_o(t)`
    (4)-(5), are the roots of

    .. math::  h(t) = (\Gamma_o(t) - B) \times \nu
               = (x(t) - b_1)\,\nu_2 - (y(t) - b_2)\,\nu_1,

    with :math:`k = (\Gamma_o(t) - B)\cdot\nu`; the one of smallest
    :math:`|k|` is taken and :math:`s = k` (errata to (6): the distance is
    :math:`|k|\,|\nu|`). ``normals``: the body's outward normals at
    ``points`` (e.g. :func:`~.normals.boundary_normals`, normalised here); the
    other arguments as in :func:`~.closest.gap_from_obstacle`, ``min_cosine``
    bounding :math:`|\nu_o\cdot\nu|`. Returns (gap, normal, t): s, ν (the
    contact direction) and the intersections' parameters. GapError if a
    normal line misses the obstacle inside the window or meets it grazing
    — or, ``out_of_reach``, gap +∞ at those nodes (one bounded obstacle of
    several, :mod:`.several`)."""
    points, nu, (t0, t1), ts, curve_ends = search_setup(
        points, normals, curve, window, samples)
    if not len(points):  # no free contact node: nothing to measure
        return np.zeros(0), np.zeros((0, 2)), np.zeros(0)
    n = len(points)
    misses = Misses(n, out_of_reach)
    with np.errstate(all="ignore"):
        c_pts = curve.point(ts)

    exact_owner, exact_t = [], []
    owners, lowers = [], []
    block = max(1, CHUNK // len(ts))
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

    root, ok = refine_roots(cross, ts[lower], ts[lower + 1],
                       (points[owner, 0], points[owner, 1],
                        nu[owner, 0], nu[owner, 1]))
    owner = np.concatenate([owner[ok]] + exact_owner)
    root = np.concatenate([root[ok]] + exact_t)
    with np.errstate(all="ignore"):
        k = np.sum((curve.point(root) - points[owner]) * nu[owner], axis=1)
    keep = np.isfinite(k)
    owner, root, k = owner[keep], root[keep], k[keep]
    best = first_per_owner(owner, np.abs(k), n)
    if (best < 0).any():
        def reason(i):
            where = "t_range" if all(curve_ends) else "search window"
            hint = "" if all(curve_ends) else \
                "; give a larger search interval (--search-interval)"
            return (f"no intersection for t in the {where} "
                    f"[{t0:g}, {t1:g}]{hint}")
        misses(best < 0, points, node_ids, reason)
    if len(root):
        t = np.where(best < 0, np.nan, root[np.maximum(best, 0)])
        gap = np.where(best < 0, np.inf, k[np.maximum(best, 0)])
    else:  # no intersection at all (only when out_of_reach)
        t, gap = np.full(n, np.nan), np.full(n, np.inf)
    with np.errstate(all="ignore"):
        obstacle_normal, length = obstacle_normals(curve, t)
        cosine = np.sum(obstacle_normal * nu, axis=1)
    bad = ~(np.isfinite(length) & (length > 0))
    if bad.any():
        misses(bad, points, node_ids, lambda i: (
            f"the obstacle has no tangent at the intersection t = {t[i]:g}"))
    grazing = ~(np.abs(cosine) >= min_cosine)
    if grazing.any():
        misses(grazing, points, node_ids, lambda i: (
            f"it meets the obstacle at a grazing angle at t = {t[i]:g} "
            f"(cosine {cosine[i]:.2g} between the normals)"))
    gap[misses.mask] = np.inf
    if warn:  # an obstacle that penetrates the undeformed body
        warn_penetration(gap[~misses.mask], points[~misses.mask],
                         None if node_ids is None
                         else np.asarray(node_ids)[~misses.mask])
    return gap, nu.copy(), t
