"""The pair search of the mortar integration, in 2D and 3D: the slave and
master facets (segments or triangles) whose axis-aligned bounding boxes
overlap, by sort and sweep (Yang & Laursen, Comput. Mech. 41 (2008) 189;
Popp, Gee & Wall, IJNME 79 (2009) 1354, §3.1), vectorised, with no
slave × master array."""

import numpy as np

__all__ = ["box_pairs", "candidate_pairs", "default_reach", "facet_reach"]


def box_pairs(lo_s, hi_s, lo_m, hi_m):
    """(I, J): every pair of a slave box (``lo_s``, ``hi_s``: (ns, d)) and
    a master box (``lo_m``, ``hi_m``: (nm, d)) that overlap (touching
    counts), by sort and sweep along the axis over which the master boxes
    spread most: the master boxes sorted by their lower end, each slave
    box's range of them found by bisection, the candidates then checked on
    every axis. The masters are swept in classes of width within a factor
    2 (:func:`_width_classes`), each with its own widest box: a graded
    mesh's few coarse facets at the rim then do not widen every slave's
    range to nearly all masters. Sorted by I, then by the masters' lower
    ends."""
    lo_s, hi_s = np.asarray(lo_s, float), np.asarray(hi_s, float)
    lo_m, hi_m = np.asarray(lo_m, float), np.asarray(hi_m, float)
    if not len(lo_s) or not len(lo_m):
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    axis = int(np.argmax(np.ptp(np.r_[lo_m, hi_m], axis=0)))
    order = np.argsort(lo_m[:, axis], kind="stable")
    start = lo_m[order, axis]
    width = (hi_m - lo_m)[order, axis]
    found = [_sweep(lo_s, hi_s, lo_m, hi_m, axis, order[members],
                    start[members], float(width[members].max()))
             + (members,) for members in _width_classes(width)]
    I = np.concatenate([f[0] for f in found])
    J = np.concatenate([f[1] for f in found])
    rank = np.concatenate([members[position] for _, _, position, members
                           in found])          # in the sorted masters
    keep = np.lexsort((rank, I))
    return I[keep], J[keep]


def _width_classes(width):
    """Positions of the sorted master boxes grouped by width along the
    sweep axis, within a factor 2 in each group (by the binary exponent;
    zero widths with the smallest)."""
    positive = width[width > 0]
    floor = positive.min() if len(positive) else 1.0
    exponent = np.frexp(np.maximum(width, floor))[1]
    return [np.flatnonzero(exponent == e) for e in np.unique(exponent)]


def _sweep(lo_s, hi_s, lo_m, hi_m, axis, order, start, widest):
    """(I, J, positions in ``order``) of the overlapping pairs of the
    slave boxes and the master boxes ``order`` (sorted by their lower end
    ``start`` along ``axis``, none wider than ``widest`` there)."""
    first = np.searchsorted(start, lo_s[:, axis] - widest, side="left")
    last = np.searchsorted(start, hi_s[:, axis], side="right")
    count = np.maximum(last - first, 0)
    I = np.repeat(np.arange(len(lo_s)), count)
    offset = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count,
                                                count)
    position = np.repeat(first, count) + offset
    J = order[position]
    overlap = ((lo_s[I] <= hi_m[J]) & (lo_m[J] <= hi_s[I])).all(axis=1)
    return I[overlap], J[overlap], position[overlap]


def candidate_pairs(nodes, slave, master, reach):
    """(I, J): the slave and master facets (rows of node ids, 2 or 3 per
    facet) whose bounding boxes overlap, the slave's enlarged by ``reach``
    (a length; one per slave facet, :func:`facet_reach`; or one per facet
    and axis; :func:`box_pairs`)."""
    ps, pm = nodes[np.asarray(slave)], nodes[np.asarray(master)]
    reach = np.asarray(reach, float)
    if reach.ndim < 2:  # one length for all facets, or one per facet
        reach = np.reshape(reach, (-1, 1))
    return box_pairs(ps.min(axis=1) - reach, ps.max(axis=1) + reach,
                     pm.min(axis=1), pm.max(axis=1))


def default_reach(nodes, slave, master):
    """The screening's reach: twice the largest distance from a slave node
    to its nearest master node plus the longest edge of each side (a
    search distance of the order of the gap and the element size: Yang &
    Laursen 2008; Popp, Gee & Wall 2009, §3.1)."""
    from scipy.spatial import cKDTree

    master_nodes = np.unique(master)
    distance, _ = cKDTree(nodes[master_nodes]).query(nodes[np.unique(slave)])
    return 2 * float(distance.max()) + sum(_longest_edge(nodes, f)
                                           for f in (slave, master))


def _longest_edge(nodes, facets):
    p = nodes[np.asarray(facets)]
    return float(np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2).max())


def facet_reach(nodes, slave, master, tilt=1.5):
    """A reach per slave facet that finds every master facet overlapping it
    along a normal: the distance g from a point of the facet to the master
    surface along a normal is at most ``tilt`` (1/cos of the angle between
    that normal and the master's, 48° for 1.5) times its distance to the
    master surface, itself at most the largest distance from the facet's
    vertices to their nearest master node plus the facet's longest edge;
    so the slave box enlarged by g meets the master facet's box. Local:
    coarse, distant facets at the rim of an interface do not enlarge the
    search in the contact zone (as :func:`default_reach`, one length for
    all, would)."""
    from scipy.spatial import cKDTree

    slave = np.asarray(slave)
    distance, _ = cKDTree(nodes[np.unique(master)]).query(
        nodes[slave.ravel()])
    p = nodes[slave]
    edge = np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2).max(axis=1)
    return tilt * (distance.reshape(slave.shape).max(axis=1) + edge)
