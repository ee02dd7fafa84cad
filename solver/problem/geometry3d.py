"""Validation of a 3D mesh (format version 3) by the rules of
docs/npz-format.md ("3D"): tetrahedra (none flat, |6V| ≤
:data:`FLAT_RTOL` · L³, one orientation) or hexahedra (the same at each of
their eight corners, :func:`solver.geometry.cells.corner_measures`), the
contact surface (triangles or quadrilaterals, faces of the cells) and the
obstacle surface; and the quadrilaterals of a 2D mesh (counter-clockwise,
no corner flat). Vectorised over the faces; failures raise a one-line
:class:`~solver.errors.ProblemError` naming the key and the element."""

import numpy as np

from ..geometry.cells import cell_faces, corner_measures
from ..geometry.checks import RESOLUTION
from .checks import check_array, check_range, fail
from .surface_spec import obstacle_surface

__all__ = ["FLAT_RTOL", "check_tetrahedra", "check_quadrilaterals",
           "check_hexahedra", "check_contact_faces", "validate_solid"]

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
    _one_orientation(vol6 < 0, cells, "tetrahedron", "tetrahedra")


def _one_orientation(negative, cells, name, names):
    """``cells`` error naming a cell of the smaller orientation group."""
    if negative.any() and not negative.all():
        few = negative if negative.sum() <= len(cells) / 2 else ~negative
        i = int(np.argmax(few))
        fail("cells", f"{name} {i} (nodes {cells[i].tolist()}) is "
                      f"inverted: {int(few.sum())} of {len(cells)} "
                      f"{names} have the other orientation")


def _corners(nodes, cells, name):
    """Corner measures; ``cells`` error for a cell flat at a corner."""
    measure, long2 = corner_measures(nodes, cells)
    scale = long2 ** (nodes.shape[1] / 2)
    flat = (np.abs(measure) <= FLAT_RTOL * scale[:, None]).any(axis=1)
    if flat.any():
        i = int(np.argmax(flat))
        fail("cells", f"{name} {i} (nodes {cells[i].tolist()}) is flat at a "
                      "corner (zero area or volume there)")
    return measure


def check_quadrilaterals(nodes, cells):
    """2D quadrilaterals: counter-clockwise and convex (every corner turns
    left), none flat at a corner."""
    measure = _corners(nodes, cells, "quadrilateral")
    bad = (measure < 0).any(axis=1)
    if bad.any():
        i = int(np.argmax(bad))
        what = ("clockwise" if (measure[i] < 0).all() else
                "not convex or self-intersecting")
        fail("cells", f"quadrilateral {i} (nodes {cells[i].tolist()}) is "
                      f"{what} ({int(bad.sum())} of {len(cells)}): "
                      "quadrilaterals list their nodes counter-clockwise")


def check_hexahedra(nodes, cells):
    """Hexahedra in VTK order: no corner flat, all corners of a cell of one
    sign (not twisted), and all cells of one orientation."""
    measure = _corners(nodes, cells, "hexahedron")
    positive = measure > 0
    mixed = positive.any(axis=1) & ~positive.all(axis=1)
    if mixed.any():
        i = int(np.argmax(mixed))
        fail("cells", f"hexahedron {i} (nodes {cells[i].tolist()}) is "
                      "twisted or not in VTK node order (its corners have "
                      "both orientations)")
    _one_orientation(~positive[:, 0], cells, "hexahedron", "hexahedra")


def check_contact_faces(faces, nodes, cells, contact_nodes,
                        key="contact_faces"):
    """The contact faces (see the module docstring) of the key ``key``
    (also the two bodies' ``mortar_slave`` and ``mortar_master``):
    triangles of tetrahedra or quadrilaterals of hexahedra, each a face of
    exactly one cell, outward by the right-hand rule."""
    shape = "triangle" if faces.shape[1] == 3 else "quadrilateral"
    n_nodes = len(nodes)
    if len(faces) < 1:
        fail(key, f"no {shape}s")
    check_range(key, faces, 0, n_nodes)
    on = np.zeros(n_nodes, bool)
    on[contact_nodes] = True
    off = ~on[faces]
    if off.any():
        i, j = np.argwhere(off)[0]
        fail(key, f"{shape} {i} has vertex {faces[i, j]}, which is not in "
                  "contact_nodes" if key != "mortar_master" else
                  f"{shape} {i} has vertex {faces[i, j]} off the master")
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
        fail(key, f"{shape} {i} (nodes {faces[i].tolist()}) repeats a "
                  "vertex")
    p = nodes[faces]
    if shape == "triangle":
        normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    else:  # twice the area vector of a quadrilateral: its diagonals
        normal = np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 1])
    long2 = ((p - np.roll(p, -1, axis=1)) ** 2).sum(axis=2).max(axis=1)
    flat = (normal ** 2).sum(axis=1) <= (FLAT_RTOL * long2) ** 2
    if flat.any():
        i = int(np.argmax(flat))
        fail(key, f"{shape} {i} (nodes {faces[i].tolist()}) has zero area")
    # The faces of the cells with enough contact vertices, each with the
    # centre of its cell (inside the body).
    width = faces.shape[1]
    near = cells[on[cells].sum(axis=1) >= width]
    cell_face, owner = cell_faces(near)
    if cell_face.shape[1] != width:
        fail(key, f"{width} columns, but the cells are "
                  f"{'tetrahedra' if cells.shape[1] == 4 else 'hexahedra'}, "
                  f"whose faces have {cell_face.shape[1]} nodes")
    keep = on[cell_face].all(axis=1)
    cell_face, owner = cell_face[keep], owner[keep]
    every = np.concatenate([ordered, np.sort(cell_face, axis=1)])
    unique, inverse = np.unique(every, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    nf = len(faces)
    first = np.unique(inverse[:nf], return_index=True)[1]
    if len(first) < nf:
        i = int(np.setdiff1d(np.arange(nf), first)[0])
        fail(key, f"{shape} {i} (nodes {faces[i].tolist()}) appears twice")
    count = np.bincount(inverse[nf:], minlength=len(unique))[inverse[:nf]]
    if (count != 1).any():
        i = int(np.argmax(count != 1))
        solid = "tetrahedr" if cells.shape[1] == 4 else "hexahedr"
        what = (f"is not a face of any {solid}on" if count[i] == 0 else
                f"is shared by two {solid}a (an interior face, not on the "
                "surface)")
        fail(key, f"{shape} {i} (nodes {faces[i].tolist()}) {what}")
    where = np.empty(len(unique), dtype=np.int64)
    where[inverse[nf:]] = owner  # the cell of each face, per key
    centre = nodes[near[where[inverse[:nf]]]].mean(axis=1)
    inward = np.einsum("ij,ij->i", normal, centre - p.mean(axis=1)) > 0
    if inward.any():
        i = int(np.argmax(inward))
        fail(key, f"{shape} {i} (nodes {faces[i].tolist()}) is oriented "
                  "inwards (its right-hand normal points into the body); "
                  f"{int(inward.sum())} of {nf} are")


def validate_solid(arrays, nodes, cells, contact_nodes):
    """The 3D keys: returns the fields contact_faces and obstacle."""
    if cells.shape[1] == 8:
        check_hexahedra(nodes, cells)
    else:
        check_tetrahedra(nodes, cells)
    faces = check_array(arrays, "contact_faces", "int", 2)
    if faces.shape[1] != (4 if cells.shape[1] == 8 else 3):
        fail("contact_faces", f"expected shape (?, "
                              f"{4 if cells.shape[1] == 8 else 3}), got "
                              f"{faces.shape} (the faces of the cells: "
                              "triangles of tetrahedra, quadrilaterals of "
                              "hexahedra)")
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
