r"""Outward normals of the contact boundary Γc from a natural cubic spline.

The gap measured "from the body" (thesis §2.1.2) needs the normal of Γc at
every contact node, but the mesh only knows the polygon through the nodes.
The thesis (§2.1.3, (8)-(14)) fits a **natural cubic spline** through them
as a graph :math:`y = P(x)`, which is singular on a vertical edge such as
its own contact edge :math:`x = 5` (errata in the thesis digest). Here the
spline is **parametric**: with the cumulative chord length

.. math::  s_1 = 0, \qquad s_{i+1} = s_i + |X_{i+1} - X_i|

as parameter, ``x(s)`` and ``y(s)`` are each interpolated by a natural
cubic spline (:math:`P''(s_1) = P''(s_{n+1}) = 0` as in (14)), the unit
tangent is :math:`T_i = X'(s_i) / |X'(s_i)|` and the normal *T* turned by
±90°, outward by the mesh (:func:`outward_sign`). Fourth order in the node
spacing away from the ends, exact on a straight chain; the natural end
condition is wrong for a curved boundary, so the two end nodes are first
order (``tests/test_normals.py``).

Corners: one spline through a corner of the body rounds it off, and the
gaps along the tilted normals past it can change sign, so
:func:`boundary_normals` splits Γc where the polygon turns by more than
:data:`CORNER_ANGLE`: every node gets the one-sided normal of its smooth
piece, a corner node the bisector of its two. Degenerate geometry raises
:class:`~solver.errors.GeometryError` naming the nodes."""

import numpy as np
from scipy.interpolate import CubicSpline

from ...errors import GeometryError
from ..cells import simplices
from ..mesh import chain_pieces

__all__ = ["CORNER_ANGLE", "chord_parameters", "spline_tangents",
           "spline_normals", "outward_sign", "corners", "boundary_normals"]

#: Turning angle of the Γc polygon (degrees) above which a node is a corner
#: of the body: the splines end there (one-sided normals).
CORNER_ANGLE = 30.0


def chord_parameters(points):
    """Cumulative chord length along the ordered (n, 2) ``points``: ``s[0]
    = 0``, ``s[i+1] = s[i] + |points[i+1] - points[i]|``. GeometryError if
    two consecutive points coincide (s would not increase strictly)."""
    points = np.asarray(points, dtype=float)
    step = np.diff(points, axis=0)
    chords = np.hypot(step[:, 0], step[:, 1])  # no overflow, no underflow
    if not (chords > 0).all():
        i = int(np.flatnonzero(~(chords > 0))[0])
        raise GeometryError(
            f"points {i} and {i + 1} of the chain coincide at "
            f"({points[i, 0]:g}, {points[i, 1]:g})")
    return np.concatenate([[0.0], np.cumsum(chords)])


def _check_points(points):
    points = np.asarray(points, dtype=float)
    if points.ndim != 2 or points.shape[1] != 2:
        raise GeometryError(
            f"points must have shape (n, 2), got {points.shape}")
    if len(points) < 2:
        raise GeometryError(
            f"a spline needs at least 2 points, got {len(points)}")
    if not np.isfinite(points).all():
        raise GeometryError("points must be finite")
    return points


def spline_tangents(points):
    r"""Unit tangents (n, 2) of the parametric natural cubic spline through
    the ordered ``points`` (n ≥ 2; module docstring), pointing from
    ``points[0]`` towards ``points[-1]``; with two points, the segment."""
    points = _check_points(points)
    s = chord_parameters(points)
    # Scaled to unit length first: coordinates of 1e-300 or 1e300 would
    # underflow or overflow in the spline's squares and cubes.
    scale = s[-1]
    spline = CubicSpline(s / scale, points / scale, axis=0,
                         bc_type="natural")
    tangent = spline(s / scale, 1)
    return tangent / np.hypot(tangent[:, 0], tangent[:, 1])[:, None]


def spline_normals(points, sign=1):
    r"""Unit normals (n, 2) of the natural cubic spline through the ordered
    ``points``: ``sign`` 1 turns the tangent clockwise, :math:`(T_y, -T_x)`
    (to the right of the direction of travel), −1 counter-clockwise; for
    outward normals pass :func:`outward_sign` (or use
    :func:`boundary_normals`)."""
    if sign not in (1, -1):
        raise ValueError(f"sign must be 1 or -1, got {sign!r}")
    tangent = spline_tangents(points)
    return sign * np.stack([tangent[:, 1], -tangent[:, 0]], axis=1)


def outward_sign(nodes, cells, chain):
    r"""Which rotation of the chain's tangent points out of the body: 1 if
    the outward normal is the tangent turned clockwise, :math:`(T_y, -T_x)`
    (the body lies left of the direction of travel), −1 if counter-clockwise.
    Every edge (a, b) of the ordered ``chain`` (n ≥ 2) must be a side of
    exactly one of the triangles ``cells`` (quadrilaterals: of their cuts,
    :func:`~solver.geometry.cells.simplices`), whose third vertex *c* lies inside
    the body: :math:`(e_y, -e_x)`, :math:`e = X_b - X_a`, points outward iff
    :math:`(X_c - X_a) \cdot (e_y, -e_x) < 0`. GeometryError naming the nodes
    otherwise, for a zero-area triangle on Γc, or if the edges disagree."""
    nodes = np.asarray(nodes, dtype=float)
    cells = np.asarray(cells, dtype=np.int64)
    if cells.ndim == 2 and cells.shape[1] == 4:  # quadrilaterals
        cells = simplices(cells, 2)
    chain = np.asarray(chain, dtype=np.int64)
    if chain.ndim != 1 or len(chain) < 2:
        only = f" (node {chain.ravel()[0]})" if chain.size == 1 else ""
        raise GeometryError(f"the contact boundary has {chain.size} "
                            f"node{only}: normals need at least 2 nodes "
                            "joined by a boundary edge")
    n = len(nodes)
    if nodes.ndim != 2 or nodes.shape[1:] != (2,) or cells.ndim != 2 \
            or cells.shape[1:] != (3,) or not len(cells):
        raise GeometryError(f"need (n, 2) nodes and (m, 3) triangles, m >= "
                            f"1, got shapes {nodes.shape}, {cells.shape}")
    if chain.min() < 0 or chain.max() >= n or cells.min() < 0 \
            or cells.max() >= n:
        raise GeometryError(f"node index out of range [0, {n})")
    # Only triangles with two vertices on the chain can have a chain edge
    # as a side (and every triangle with that side has both): sorting
    # their sides alone gives the same counts as sorting all of the mesh's.
    on = np.zeros(n, dtype=bool)
    on[chain] = True
    cells = cells[on[cells].sum(axis=1) >= 2]
    # Sorted keys of those triangles' sides, each with its opposite vertex.
    sides = np.concatenate([cells[:, [0, 1]], cells[:, [1, 2]],
                            cells[:, [2, 0]]])
    opposite = np.concatenate([cells[:, 2], cells[:, 0], cells[:, 1]])
    sides.sort(axis=1)
    keys = sides[:, 0] * n + sides[:, 1]
    order = np.argsort(keys, kind="stable")
    keys, opposite = keys[order], opposite[order]

    a, b = chain[:-1], chain[1:]
    wanted = np.minimum(a, b) * n + np.maximum(a, b)
    first = np.searchsorted(keys, wanted, side="left")
    count = np.searchsorted(keys, wanted, side="right") - first
    if (count != 1).any():
        i = int(np.flatnonzero(count != 1)[0])
        raise GeometryError(
            f"chain edge ({a[i]}, {b[i]}) is a side of {count[i]} triangles, "
            "not of exactly one (not a boundary edge)")
    c = opposite[first]
    edge, inward = _unit(nodes[b] - nodes[a]), _unit(nodes[c] - nodes[a])
    side = inward[:, 0] * edge[:, 1] - inward[:, 1] * edge[:, 0]
    flat = ~(np.abs(side) > 1e-12)  # also NaN: coincident nodes
    if flat.any():
        i = int(np.flatnonzero(flat)[0])
        raise GeometryError(
            f"the triangle ({a[i]}, {b[i]}, {c[i]}) on the contact boundary "
            f"edge ({a[i]}, {b[i]}) has zero area"
            + (f" (and {int(flat.sum()) - 1} more)" if flat.sum() > 1 else ""))
    if (side < 0).all():
        return 1
    if (side > 0).all():
        return -1
    raise GeometryError(
        f"the body lies left of {int((side < 0).sum())} and right of "
        f"{int((side > 0).sum())} chain edges: the chain is not ordered "
        "along one piece of boundary")


def _unit(vectors):
    """Rows scaled to unit length (hypot: no overflow or underflow)."""
    with np.errstate(all="ignore"):
        return vectors / np.hypot(vectors[:, 0], vectors[:, 1])[:, None]


def corners(points, angle=CORNER_ANGLE):
    """Positions of the inner points where the polygon turns by more than
    ``angle`` degrees (corners of the body)."""
    step = _unit(np.diff(np.asarray(points, dtype=float), axis=0))
    cosine = np.sum(step[:-1] * step[1:], axis=1)
    return np.flatnonzero(cosine < np.cos(np.radians(angle))) + 1


def boundary_normals(nodes, cells, chain, corner_angle=CORNER_ANGLE):
    r"""Unit outward normals (n, 2) of Γc at ``nodes[chain]`` (thesis
    §2.1.3; ``chain`` ordered along Γc, either direction, on the triangles
    ``cells``): :func:`spline_normals` oriented by :func:`outward_sign`, one
    spline per smooth piece between :func:`corners`, a corner node the
    bisector of its two one-sided normals; a chain of separate parts
    (:func:`~solver.geometry.mesh.chain_pieces`) part by part. GeometryError naming the nodes for
    a chain of one node, coincident nodes, a zero-area triangle on Γc."""
    nodes = np.asarray(nodes, dtype=float)
    chain = np.asarray(chain, dtype=np.int64)
    if chain.ndim == 1 and len(chain) >= 2 and 0 <= chain.min() \
            and chain.max() < len(nodes):
        points = nodes[chain]
        step = np.diff(points, axis=0)
        same = ~(np.hypot(step[:, 0], step[:, 1]) > 0)
        if same.any():
            i = int(np.flatnonzero(same)[0])
            raise GeometryError(
                f"contact nodes {chain[i]} and {chain[i + 1]} coincide at "
                f"({points[i, 0]:g}, {points[i, 1]:g})")
    try:  # malformed cells or chain: one piece, refused by outward_sign
        pieces = chain_pieces(chain, cells) if chain.ndim == 1 \
            and len(chain) and 0 <= chain.min() else [(0, len(chain))]
    except (ValueError, TypeError, IndexError):
        pieces = [(0, len(chain))]
    if len(pieces) > 1:  # Γc of separate parts: each its own normals
        return np.concatenate([
            boundary_normals(nodes, cells, chain[lo:hi], corner_angle)
            for lo, hi in pieces])
    sign = outward_sign(nodes, cells, chain)
    points = nodes[chain]
    cuts = corners(points, corner_angle)
    bounds = np.r_[0, cuts, len(points) - 1]
    normals = np.empty_like(points)
    before = None
    for lo, hi in zip(bounds[:-1], bounds[1:]):  # pieces between corners
        piece = spline_normals(points[lo:hi + 1], sign)
        normals[lo:hi + 1] = piece
        if before is not None:  # lo is a corner: bisect the one-sided normals
            normals[lo] = _unit((before + piece[0])[None])[0]
        before = piece[-1]
    return normals
