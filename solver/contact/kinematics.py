r"""The kinematic assumptions of the contact model, checked on an answer.

The model is geometrically linear (thesis §1–§2): small strain, gaps s
and normals ν computed once, in the reference configuration, and the
non-penetration condition u·ν ≤ s linearised there. That is exact for a
node sliding along a flat obstacle, whatever the distance, and accurate
on a curved one while the sliding stays small against the surface's
features. This module measures two breaches and says them in words:

- *large sliding*: a free node of Γc moves tangentially (u − (u·ν)ν) by
  more than one element of Γc against an obstacle that is not flat (its
  normals at the nodes of Γc differ): its reference gap then describes
  another part of the obstacle;
- *large initial overlap*: the obstacle penetrates the undeformed body by
  more than a tenth of the body's size (the diagonal of its bounding
  box): the contact forces must then undo a deformation that is not small.

Two bodies (:mod:`.two_body`): the dual mortar coupling (D, M, the
normals and weighted gaps) is integrated once in the reference
configuration too, so a slave node whose displacement relative to the
master (v_j = u_j − Σ_k P_jk u_k, its tangential part) exceeds one element
of the slave surface faces another part of the master than the coupling
assumes (:func:`relative_sliding`); flat interfaces included, since the
coupling's pairing of the meshes moves with the sliding.

Both are warnings (:class:`~solver.errors.KinematicsWarning`), not errors:
the answer solves the linearised problem it was given."""

import numpy as np

from ..geometry.mesh import chain_pieces
from .geometry import node_displacement

__all__ = ["SLIDING_ELEMENTS", "OVERLAP_FRACTION", "FLAT_COSINE",
           "element_size", "sliding", "kinematic_breaches",
           "relative_sliding"]

#: Sliding beyond this many elements of Γc breaks "small sliding".
SLIDING_ELEMENTS = 1.0
#: Initial overlap beyond this fraction of the body's size is "large".
OVERLAP_FRACTION = 0.1
#: Normals whose cosines to their mean all exceed this: a flat obstacle.
FLAT_COSINE = 1.0 - 1e-12


def element_size(problem):
    """The median edge length of Γc: consecutive contact nodes of one
    piece in 2D, the edges of ``contact_faces`` in 3D (NaN without them:
    not checked)."""
    x = problem.nodes
    if problem.dim == 2:  # each piece of Γc (several: not their joins)
        chain = problem.contact_nodes
        edges = np.concatenate([
            np.column_stack([chain[lo:hi - 1], chain[lo + 1:hi]])
            for lo, hi in chain_pieces(chain, problem.cells)])
    elif problem.contact_faces is None:  # built without its faces
        return np.nan
    else:
        faces = np.asarray(problem.contact_faces)  # triangles or quads
        if faces.ndim != 2:
            return np.nan
        edges = np.stack([faces, np.roll(faces, -1, axis=1)],
                         axis=-1).reshape(-1, 2)
    if not len(edges):
        return np.nan
    return float(np.median(np.linalg.norm(x[edges[:, 1]] - x[edges[:, 0]],
                                          axis=1)))


def sliding(problem, geometry, u):
    """|u − (u·ν)ν| at the free contact nodes (geometry order) for the
    reduced displacement u."""
    moved = node_displacement(problem, u, geometry.index)
    normal = np.asarray(geometry.normal, float)
    along = np.einsum("ij,ij->i", moved, normal)
    return np.linalg.norm(moved - along[:, None] * normal, axis=1)


def _flat(normal):
    """Whether the unit normals ``normal`` (k, d) are one direction."""
    if len(normal) < 2:
        return True
    mean = normal.mean(axis=0)
    size = np.linalg.norm(mean)
    return size > 0 and bool(np.all(normal @ (mean / size) >= FLAT_COSINE))


def kinematic_breaches(problem, geometry, u):
    """Messages (a list of str, empty if none) naming the breaches of the
    module docstring for the answer u (reduced, the last step's) of a
    rigid-obstacle mesh problem."""
    if problem.kind != "mesh" or not len(geometry.index):
        return []
    found = []
    normal = np.asarray(geometry.normal, float)
    h = element_size(problem)
    if u is not None and np.isfinite(h) and not _flat(normal):
        slip = sliding(problem, geometry, u)
        worst = int(np.argmax(slip))
        if slip[worst] > SLIDING_ELEMENTS * h:
            node = int(problem.contact_nodes[geometry.index[worst]])
            found.append(
                f"node {node} slides {slip[worst]:.3g} along a curved "
                f"obstacle, {slip[worst] / h:.3g} elements of Γc (h = "
                f"{h:.3g}): gaps and normals are taken in the reference "
                "configuration (small sliding), so the answer may be "
                "inaccurate there")
    x = problem.nodes
    size = float(np.linalg.norm(x.max(axis=0) - x.min(axis=0)))
    depth = float(np.max(-np.asarray(geometry.gap, float), initial=0.0))
    if depth > OVERLAP_FRACTION * size:
        found.append(
            f"the obstacle overlaps the undeformed body by {depth:.3g}, "
            f"{depth / size:.2f} of its size ({size:.3g}): the model "
            "assumes small deformations (small strain, reference "
            "configuration)")
    return found


def relative_sliding(slip, h, node_ids):
    """Messages (a list of at most one str) for two bodies: ``slip`` the
    tangential displacement of each slave node relative to the master, ``h``
    the local slave element size there, ``node_ids`` their mesh nodes."""
    slip, h = np.asarray(slip, float), np.asarray(h, float)
    ratio = np.where(h > 0, slip / np.where(h > 0, h, 1.0), 0.0)
    if not len(ratio) or not np.isfinite(ratio).all():
        return []
    worst = int(np.argmax(ratio))
    if ratio[worst] <= SLIDING_ELEMENTS:
        return []
    return [f"slave node {int(node_ids[worst])} slides {slip[worst]:.3g} "
            f"relative to the master, {ratio[worst]:.3g} elements of the "
            f"slave surface (h = {h[worst]:.3g}): the mortar coupling is "
            "computed in the reference configuration (small sliding), so "
            "the answer may be inaccurate there"]
