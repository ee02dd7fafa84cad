"""What the deformed-body figure draws besides the body: the obstacle over
the body's extent, and moved with the magnified boundary so that a
magnified drawing keeps the gaps (:func:`moved_obstacle`). Plain
geometry on arrays; :mod:`.figures` draws it."""

import numpy as np

from ..geometry.mesh import chain_pieces

__all__ = ["obstacle_in_box", "closest_on_polyline", "moved_obstacle",
           "piece_joins", "with_breaks"]


def piece_joins(problem):
    """The indices j of the steps contact_nodes[j] → [j + 1] that join two
    separate pieces of a 2D Γc (:func:`~solver.geometry.mesh.
    chain_pieces`): no boundary edge, nothing to draw or project onto."""
    pieces = chain_pieces(problem.contact_nodes, problem.cells)
    return np.array([hi - 1 for _, hi in pieces[:-1]], dtype=np.int64)


def with_breaks(points, joins):
    """``points`` (n, 2) with a NaN row after each of ``joins`` (matplotlib
    leaves the line open there)."""
    return np.insert(np.asarray(points, float), np.asarray(joins) + 1,
                     np.nan, axis=0)


def obstacle_in_box(curve, low, high, samples=1201):
    """Points of a 2D obstacle curve inside the box [low, high], NaN rows
    where it leaves the box: the parameter window (``t_range``, or as
    :func:`solver.geometry.curves.window.start_window`) doubled until the
    curve leaves the box at both ends, then narrowed to the samples inside;
    a polyline's vertices always among the samples; several curves
    (``parts``) one after the other, a NaN row between them."""
    low, high = np.asarray(low, float), np.asarray(high, float)
    parts = getattr(curve, "parts", None)
    if parts is not None:
        gap = np.full((1, 2), np.nan)
        return np.concatenate([row for part in parts for row in (
            obstacle_in_box(part, low, high, samples), gap)])

    def inside(points):
        return np.all((points >= low) & (points <= high), axis=-1)

    if curve.t_range is not None:
        t0, t1 = curve.t_range
    else:
        corners = np.array([low, high, [low[0], high[1]], [high[0], low[1]]])
        origin = curve.point(np.array(0.0))
        half = 2.0 * np.linalg.norm(corners - origin, axis=1).max() + 1.0
        t0, t1 = -half, half
        for _ in range(30):  # widen until both ends are outside the box
            ends = inside(curve.point(np.array([t0, t1])))
            if not ends.any():
                break
            t0, t1 = (2 * t0 if ends[0] else t0), (2 * t1 if ends[1] else t1)
    for _ in range(3):  # narrow to the part inside, one sample beyond it
        t = np.linspace(t0, t1, samples)
        hits = np.flatnonzero(inside(curve.point(t)))
        if not len(hits):
            return np.empty((0, 2))
        t0 = t[max(hits[0] - 1, 0)]
        t1 = t[min(hits[-1] + 1, samples - 1)]
    t = np.linspace(t0, t1, samples)
    kinks = getattr(curve, "kinks", None)
    if kinks is not None:
        t = np.union1d(t, kinks[(kinks > t0) & (kinks < t1)])
    points = curve.point(t).astype(float)
    points[~inside(points)] = np.nan
    return points


def closest_on_polyline(points, chain, chunk=512, skip=None):
    """For each point, the closest point of the polyline through ``chain``
    ((n, 2), n ≥ 2): the segment index j and the fraction τ ∈ [0, 1] along
    it (closest point chain[j] + τ (chain[j + 1] − chain[j])), never one of
    the segments ``skip`` (indices: the joins between separate pieces). NaN
    points get j = 0, τ = 0. Vectorised over points × segments, in chunks."""
    points = np.asarray(points, float)
    a, d = chain[:-1], np.diff(chain, axis=0)
    length2 = np.maximum(np.einsum("ij,ij->i", d, d), np.finfo(float).tiny)
    segment = np.zeros(len(points), int)
    tau = np.zeros(len(points))
    finite = np.flatnonzero(np.isfinite(points).all(axis=1))
    for start in range(0, len(finite), chunk):
        rows = finite[start:start + chunk]
        rel = points[rows, None, :] - a[None]                 # (m, s, 2)
        frac = np.clip(np.einsum("msk,sk->ms", rel, d) / length2, 0.0, 1.0)
        gap = rel - frac[..., None] * d[None]
        d2 = np.einsum("msk,msk->ms", gap, gap)
        if skip is not None:
            d2[:, skip] = np.inf
        best = np.argmin(d2, axis=1)
        segment[rows] = best
        tau[rows] = frac[np.arange(len(rows)), best]
    return segment, tau


def moved_obstacle(problem, displacement, scale, points):
    """The obstacle points moved with the magnified boundary: each point O by
    (scale − 1) ũ(O), ũ the displacement of the closest point of the deformed
    Γc. With the body drawn at X + scale·u each gap keeps its true length
    and direction (the node X + scale·u, its obstacle point O + (scale − 1)·u),
    so nodes in contact lie on the moved obstacle and no node crosses it."""
    u = np.asarray(displacement, float)
    gc = problem.contact_nodes
    chain = problem.nodes[gc] + u[gc]
    segment, tau = closest_on_polyline(points, chain,
                                       skip=piece_joins(problem))
    along = ((1 - tau)[:, None] * u[gc][segment]
             + tau[:, None] * u[gc][segment + 1])
    return points + (scale - 1.0) * along
