r"""Outward normals of the body's contact surface in 3D.

The 3D counterpart of :mod:`solver.geometry.curves.normals` (§2.1.3): the
contact surface is a set of triangles or quadrilaterals
(``contact_faces``), oriented so that the right-hand rule gives the body's
outward normal (inconsistently oriented faces are refused); a
quadrilateral a-b-c-d enters as the triangles a-b-c and a-c-d
(:func:`~solver.geometry.cells.face_triangles`), whose angle weights at a
node sum to the quadrilateral's angle there when it is planar. Three nodal normals:

``"angle"`` (default)
    facet normals weighted by the triangle's angle at the node (Thürmer &
    Wüthrich, J. Graphics Tools 3 (1998) 43-46): independent of how a
    flat region is split into triangles; first order in the mesh size *h*
    on irregular meshes, second on regular ones (Meek & Walton, CAGD 17
    (2000) 521-543).
``"area"``
    facet normals weighted by area.
``"smooth"``
    the counterpart of the thesis's cubic-spline normals: a local cubic
    least-squares fit of the surface over the tangent plane through the
    node and its 2-ring (an osculating jet, Cazals & Pouget, CAGD 22
    (2005) 121-146, :mod:`.jets`), third order in *h*; a quadratic jet, or
    the angle-weighted normal, where the 2-ring is too small or the fit
    ill-conditioned. As the 2D splines end at corners
    (:data:`~solver.geometry.curves.normals.CORNER_ANGLE`), neighbours
    whose angle-weighted normal turns by more than that angle are left out
    of the fit: next to an edge of the body it is one-sided."""

import numpy as np
import scipy.sparse as sp

from ...errors import GeometryError, ProblemError
from ..cells import face_triangles
from .jets import jet_normals

__all__ = ["WEIGHTINGS", "facet_normals", "surface_normals"]

#: The accepted ``weighting`` values.
WEIGHTINGS = ("angle", "area", "smooth")

def _check(nodes, faces, contact_nodes):
    nodes = np.asarray(nodes, dtype=float)
    if nodes.ndim != 2 or nodes.shape[1] != 3 or not np.isfinite(nodes).all():
        raise ProblemError(f"nodes: need finite (n, 3) coordinates, got "
                           f"shape {nodes.shape}")
    faces = np.asarray(faces)
    contact_nodes = np.asarray(contact_nodes)
    for name, a, dims in (("contact_faces", faces, 2),
                          ("contact_nodes", contact_nodes, 1)):
        if a.ndim != dims or (dims == 2 and a.shape[1] not in (3, 4)) or \
                (a.size and a.dtype.kind not in "iu"):
            raise ProblemError(f"{name}: need integer node ids of shape "
                               f"{'(n_f, 3) or (n_f, 4)' if dims == 2 else '(Nc,)'}, got "
                               f"{a.dtype} {a.shape}")
        if a.size and (a.min() < 0 or a.max() >= len(nodes)):
            raise ProblemError(f"{name}: node id out of range [0, "
                               f"{len(nodes)})")
    return (nodes, face_triangles(faces.astype(np.int64)),
            contact_nodes.astype(np.int64))


def facet_normals(nodes, faces):
    r""":math:`(b - a)\times(c - a)` of every face: twice its area times its
    unit normal (right-hand rule)."""
    a, b, c = (nodes[faces[:, k]] for k in range(3))
    return np.cross(b - a, c - a)


def _accumulate(faces, values, n):
    """Sum per-corner (n_f, 3, 3) vectors onto the n nodes."""
    ids = faces.ravel()
    flat = values.reshape(-1, 3)
    return np.stack([np.bincount(ids, flat[:, k], minlength=n)
                     for k in range(3)], axis=1)


def _weighted(nodes, faces, weighting):
    cross = facet_normals(nodes, faces)
    twice_area = np.linalg.norm(cross, axis=1)
    scale = np.abs(nodes).max() if len(nodes) else 1.0
    degenerate = ~(twice_area > 1e-14 * scale ** 2)
    if degenerate.any():
        bad = np.flatnonzero(degenerate)
        raise GeometryError(f"contact_faces: {len(bad)} triangles of zero "
                            f"area (the first: face {bad[0]}, nodes "
                            f"{faces[bad[0]].tolist()})")
    if weighting == "area":
        corner = np.repeat(cross[:, None, :], 3, axis=1)
    else:
        unit = cross / twice_area[:, None]
        p = nodes[faces]                       # (n_f, 3 corners, 3)
        e1 = np.roll(p, -1, axis=1) - p
        e2 = np.roll(p, -2, axis=1) - p
        angle = np.arctan2(np.linalg.norm(np.cross(e1, e2), axis=2),
                           np.sum(e1 * e2, axis=2))
        corner = angle[:, :, None] * unit[:, None, :]
    return _accumulate(faces, corner, len(nodes))


def _check_orientation(faces, n):
    """Every directed edge at most once (consistent orientation)."""
    heads = faces.ravel()
    tails = np.roll(faces, -1, axis=1).ravel()
    count = sp.coo_matrix((np.ones(len(heads)), (heads, tails)),
                          shape=(n, n)).tocsr()
    if count.nnz and count.max() > 1:
        i, j = (a[0] for a in (count > 1).nonzero())
        raise GeometryError(f"contact_faces: inconsistent orientation (edge "
                            f"{i}->{j} is traversed twice in the same "
                            "direction)")


def surface_normals(nodes, faces, contact_nodes, weighting="angle"):
    """Unit outward body normals (Nc, 3) at ``contact_nodes`` of the
    contact-surface triangles ``faces`` (node ids, the right-hand rule
    giving the outward normal), ``weighting`` of the module docstring.
    ProblemError for bad shapes or ids or an unknown weighting;
    GeometryError for zero-area or inconsistently oriented faces, or a
    contact node on no face (or whose facet normals cancel)."""
    if weighting not in WEIGHTINGS:
        raise ProblemError(f"normal weighting: unknown {weighting!r} "
                           f"(known: {', '.join(WEIGHTINGS)})")
    nodes, faces, contact_nodes = _check(nodes, faces, contact_nodes)
    _check_orientation(faces, len(nodes))
    summed = _weighted(nodes, faces, "area" if weighting == "area"
                       else "angle")
    length = np.linalg.norm(summed, axis=1)
    if not (length[contact_nodes] > 0).all():
        bad = contact_nodes[~(length[contact_nodes] > 0)]
        raise GeometryError(f"contact_nodes: {len(bad)} nodes lie on no "
                            f"contact face or their facet normals cancel "
                            f"(the first: node {bad[0]})")
    with np.errstate(invalid="ignore"):
        normals = summed / length[:, None]  # NaN off the faces
    if weighting == "smooth":
        return jet_normals(nodes, faces, contact_nodes, normals)
    return normals[contact_nodes]
