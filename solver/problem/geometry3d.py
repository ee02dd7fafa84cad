"""Validation of a 3D mesh (format version 3) by the rules of
docs/npz-format.md ("3D"): tetrahedra (none flat, |6V| ≤
:data:`FLAT_RTOL` · L³, one orientation), the contact surface and the
obstacle surface. Vectorised over the faces; failures raise a one-line
:class:`~solver.errors.ProblemError` naming the key and the element."""

import numpy as np

from ..geometry.checks import RESOLUTION
from .checks import check_array, check_range, fail
from .surface_spec import obstacle_surface

__all__ = ["FLAT_RTOL", "check_tetrahedra", "check_contact_faces",
           "validate_solid"]

#: A tetrahedron (triangle) whose 6·volume (2·area) is below this fraction
#: of L³ (L²) is flat.
FLAT_RTOL = 1e-12


def _edges(p):
    """Edges from the first vertex and the squared longest of them."""
    e = p[:, 1:] - p[:, :1]
    return e, (e ** 2).sum(axis=2).max(axis=1)


def check_tetrahedra(nodes, cells):
    """No flat tetrahedron, one orientation for all."""
    e, long2 = _edges(nodes[cells])
    vol6 = np.einsum("ij,ij->i", e[:, 0], np.cross(e[:, 1], e[:, 2]))
    flat = np.abs(vol6) <= FLAT_RTOL * long2 ** 1.5
    if flat.any():
        i = int(np.argmax(flat))
        fail("cells", f"tetrahedron {i} (nodes {cells[i].tolist()}) has "
                      "zero volume")
    negative = vol6 < 0
    if negative.any() and not negative.all():
        few = negative if negative.sum() <= len(cells) / 2 else ~negative
        i = int(np.argmax(few))
        fail("cells", f"tetrahedron {i} (nodes {cells[i].tolist()}) is "
                      f"inverted: {int(few.sum())} of {len(cells)} "
                      "tetrahedra have the other orientation")


def check_contact_faces(faces, nodes, cells, contact_nodes,
                        key="contact_faces"):
    """The contact triangles (see the module docstring) of the key ``key``
    (also the two bodies' ``mortar_slave`` and ``mortar_master``)."""
    n_nodes = len(nodes)
    if len(faces) < 1:
        fail(key, "no triangles")
    check_range(key, faces, 0, n_nodes)
    on = np.zeros(n_nodes, bool)
    on[contact_nodes] = True
    off = ~on[faces]
    if off.any():
        i, j = np.argwhere(off)[0]
        fail(key, f"triangle {i} has vertex {faces[i, j]}, which is not in "
                  "contact_nodes" if key != "mortar_master" else
                  f"triangle {i} has vertex {faces[i, j]} off the master")
    used = np.zeros(n_nodes, bool)
    used[faces] = True
    lonely = ~used[contact_nodes]
    if lonely.any():
        fail("contact_nodes", f"node {contact_nodes[np.argmax(lonely)]} is "
                              "a vertex of no contact face")
    ordered = np.sort(faces, axis=1)
    same = (ordered[:, :-1] == ordered[:, 1:]).any(axis=1)
    if same.any():
        i = int(np.argmax(same))
        fail(key, f"triangle {i} (nodes {faces[i].tolist()}) repeats a "
                  "vertex")
    e, long2 = _edges(nodes[faces])
    normal = np.cross(e[:, 0], e[:, 1])
    flat = (normal ** 2).sum(axis=1) <= (FLAT_RTOL * long2) ** 2
    if flat.any():
        i = int(np.argmax(flat))
        fail(key, f"triangle {i} (nodes {faces[i].tolist()}) has zero area")
    # The faces of the tetrahedra with three contact vertices, each with
    # the vertex opposite it.
    near = cells[on[cells].sum(axis=1) >= 3]
    skip = np.array([[1, 2, 3, 0], [0, 2, 3, 1], [0, 1, 3, 2],
                     [0, 1, 2, 3]])
    tet_faces = near[:, skip].reshape(-1, 4)
    tet_faces = tet_faces[on[tet_faces[:, :3]].all(axis=1)]
    every = np.concatenate([ordered, np.sort(tet_faces[:, :3], axis=1)])
    unique, inverse = np.unique(every, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    nf = len(faces)
    first = np.unique(inverse[:nf], return_index=True)[1]
    if len(first) < nf:
        i = int(np.setdiff1d(np.arange(nf), first)[0])
        fail(key, f"triangle {i} (nodes {faces[i].tolist()}) appears twice")
    count = np.bincount(inverse[nf:], minlength=len(unique))[inverse[:nf]]
    if (count != 1).any():
        i = int(np.argmax(count != 1))
        what = ("is not a face of any tetrahedron" if count[i] == 0 else
                "is shared by two tetrahedra (an interior face, not on the "
                "surface)")
        fail(key, f"triangle {i} (nodes {faces[i].tolist()}) {what}")
    where = np.empty(len(unique), dtype=np.int64)
    where[inverse[nf:]] = tet_faces[:, 3]  # the opposite vertex, per key
    opposite = nodes[where[inverse[:nf]]]
    inward = np.einsum("ij,ij->i", normal, opposite - nodes[faces[:, 0]]) > 0
    if inward.any():
        i = int(np.argmax(inward))
        fail(key, f"triangle {i} (nodes {faces[i].tolist()}) is oriented "
                  "inwards (its right-hand normal points into the body); "
                  f"{int(inward.sum())} of {nf} are")


def validate_solid(arrays, nodes, cells, contact_nodes):
    """The 3D keys: returns the fields contact_faces and obstacle."""
    check_tetrahedra(nodes, cells)
    faces = check_array(arrays, "contact_faces", "int", 2, (None, 3))
    check_contact_faces(faces, nodes, cells, contact_nodes)
    text = check_array(arrays, "obstacle_surface", "str", 0)
    obstacle = obstacle_surface(text)
    _check_sphere_resolution(obstacle, nodes)
    return dict(contact_faces=faces, obstacle=obstacle)


def _check_sphere_resolution(obstacle, nodes):
    """A sphere whose gaps keep 8 significant digits of the body's size
    (module docstring); a larger one is, to that precision, a plane."""
    if getattr(obstacle, "kind", None) != "sphere":
        return
    size = float(np.ptp(nodes, axis=0).max())
    if obstacle.radius * RESOLUTION > size:
        fail("obstacle_surface", f"the sphere's radius {obstacle.radius:g} "
                                 f"is more than {1 / RESOLUTION:g} times the "
                                 f"body's size {size:g}: its gaps would keep "
                                 "fewer than 8 significant digits (use a "
                                 "plane)")
