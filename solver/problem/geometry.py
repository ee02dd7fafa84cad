"""Validation of the mesh keys of a problem file and of its geometry: the
keys common to 2D and 3D, the 2D contact boundary and obstacle curve (3D:
:mod:`solver.problem.geometry3d`; two bodies: :mod:`solver.problem.
two_body`), by the rules of docs/npz-format.md ("Validation"): a geometry
double precision can resolve (:data:`COORDINATE_LIMIT`,
:data:`RESOLUTION`) and on which the thesis's normals (§2.1.3) can be
computed. Failures raise a ProblemError naming the key and the nodes."""

import numpy as np

from ..errors import GeometryError, ProblemError
from ..geometry.checks import COORDINATE_LIMIT, RESOLUTION
from ..geometry.cells import cell_name
from ..geometry.mesh import chain_pieces
from ..geometry.curves.normals import boundary_normals
from ..geometry.curves.parametric import ParametricCurve
from ..geometry.curves.polyline import PolylineCurve
from ..geometry.curves.several import SeveralCurves
from .checks import check_array, check_range, fail
from .meta import parse_json
from .format import ONLY_2D, TWO_BODY
from .geometry3d import (check_quadrilaterals, check_tetrahedra,
                         validate_solid)

__all__ = ["COORDINATE_LIMIT", "RESOLUTION", "validate_mesh"]


def _check_coordinates(nodes):
    """Coordinates double precision can resolve (see the module doc)."""
    if not len(nodes):
        fail("nodes", "the mesh has no nodes")
    size = np.abs(nodes).max(axis=1)
    far = int(np.argmax(size))
    if size[far] > COORDINATE_LIMIT:
        at = ", ".join(f"{c:g}" for c in nodes[far])
        axes = "|x|, |y|" if nodes.shape[1] == 2 else "|x|, |y|, |z|"
        fail("nodes", f"node {far} at ({at}) is out of the supported range "
                      f"{axes} <= {COORDINATE_LIMIT:g} (rescale the units)")
    extent = float(np.ptp(nodes, axis=0).max())
    if extent < max(1 / COORDINATE_LIMIT, RESOLUTION * size[far]):
        fail("nodes", f"the body is {extent:g} across but lies "
                      f"{size[far]:g} from the origin (node {far}): double "
                      "precision cannot resolve it (rescale the units or "
                      "move the body to the origin)")


def validate_mesh(arrays, n, contact_dofs):
    """The mesh keys, the geometry and the obstacle of a ``mesh`` file: the
    fields nodes, cells, dof_map, u_prescribed, contact_nodes, obstacle
    (3D: contact_faces) of a :class:`~solver.problem.ContactProblem`."""
    d = contact_dofs.shape[1]
    nodes = check_array(arrays, "nodes", "float", 2, (None, d))
    n_nodes = len(nodes)
    _check_coordinates(nodes)
    cells = check_array(arrays, "cells", "int", 2)
    if cell_name(d, cells.shape[1]) is None:
        fail("cells", f"expected shape (?, {d + 1}) or (?, {2 ** d}) ("
                      + ("triangles or quadrilaterals" if d == 2 else
                         "tetrahedra or hexahedra")
                      + f"), got {cells.shape}")
    if len(cells) < 1:
        fail("cells", "the mesh has no " + ("triangles" if d == 2
                                              else "tetrahedra"))
    check_range("cells", cells, 0, n_nodes)
    if d == 2 and cells.shape[1] == 4:
        check_quadrilaterals(nodes, cells)
    dof_map = check_array(arrays, "dof_map", "int", 2, (n, 2))
    check_range("dof_map", dof_map[:, 0], 0, n_nodes)
    check_range("dof_map", dof_map[:, 1], 0, d)
    flat = dof_map[:, 0] * d + dof_map[:, 1]
    if len(np.unique(flat)) != n:
        fail("dof_map", "two reduced DOFs map to the same (node, component)")
    u_prescribed = check_array(arrays, "u_prescribed", "float", 2,
                               (n_nodes, d))
    contact_nodes = check_array(arrays, "contact_nodes", "int", 1,
                                (len(contact_dofs),))
    check_range("contact_nodes", contact_nodes, 0, n_nodes)
    if len(np.unique(contact_nodes)) != len(contact_nodes):
        fail("contact_nodes", "a node appears twice")
    fields = dict(nodes=nodes, cells=cells, dof_map=dof_map,
                  u_prescribed=u_prescribed, contact_nodes=contact_nodes)
    if d == 3:
        _check_contact_dofs(flat, n_nodes, contact_nodes, contact_dofs)
        if "mortar_slave" in arrays:  # two bodies: the triangles are
            # checked by solver.problem.two_body
            if cells.shape[1] != 4:
                fail("cells", "a 3D two-body file (mortar_slave) needs "
                              "tetrahedra; hexahedra are not supported "
                              "there (no dual basis of bilinear faces)")
            check_tetrahedra(nodes, cells)
            fields.update(contact_faces=None, obstacle=None)
        else:
            fields.update(validate_solid(arrays, nodes, cells,
                                         contact_nodes))
        return fields
    if any(k in arrays for k in TWO_BODY[1:]):  # two bodies: no obstacle;
        # the segments and the slave chain: solver.problem.two_body
        for key in ONLY_2D:
            if key in arrays:
                fail(key, "not allowed in a two-body file (mortar_slave): "
                          "the contact is with the master body, not an "
                          "obstacle")
        _check_contact_dofs(flat, n_nodes, contact_nodes, contact_dofs)
        fields["obstacle"] = None
        return fields
    if len(contact_nodes) < 2:
        fail("contact_nodes", f"the contact boundary Γc is the single node "
                              f"{contact_nodes[0]}: it needs at least 2 "
                              "nodes joined by a boundary edge")
    pieces = chain_pieces(contact_nodes, cells)
    single = [lo for lo, hi in pieces if hi - lo < 2]
    if single:
        fail("contact_nodes", f"not ordered along the boundary (consecutive "
                              f"contact nodes must share a boundary edge; "
                              f"node {contact_nodes[single[0]]} shares one "
                              "with neither neighbour)")
    _check_contact_dofs(flat, n_nodes, contact_nodes, contact_dofs)
    try:  # the normals of Γc: coincident nodes, zero-area triangles
        boundary_normals(nodes, cells, contact_nodes)
    except GeometryError as exc:
        fail("contact_nodes", str(exc))
    fields["obstacle"] = _obstacle_curve(arrays)
    return fields


def _check_contact_dofs(flat, n_nodes, contact_nodes, contact_dofs):
    """contact_dofs must agree with dof_map (``flat`` = node·d + component
    of each reduced DOF)."""
    d = contact_dofs.shape[1]
    lookup = np.full(d * n_nodes, -1, dtype=np.int64)
    lookup[flat] = np.arange(len(flat))
    expected = lookup[(d * contact_nodes[:, None] + np.arange(d)).ravel()]
    if not np.array_equal(expected.reshape(-1, d), contact_dofs):
        fail("contact_dofs", "does not match dof_map and contact_nodes")


def _obstacle_curve(arrays):
    """The 2D obstacle: expressions x(t), y(t), a polyline or several
    curves (``obstacle_curves``)."""
    if "obstacle_curves" in arrays:
        for key in ONLY_2D:
            if key in arrays and key != "obstacle_curves":
                fail(key, "not allowed with obstacle_curves (each curve "
                          "carries its own fields)")
        text = check_array(arrays, "obstacle_curves", "str", 0)
        # the bounded JSON reader of meta takes an object: the list inside
        specs = parse_json('{"curves": ' + str(text) + "\n}",
                           "obstacle_curves").get("curves")
        if not isinstance(specs, list):
            fail("obstacle_curves", "must be a JSON list of curve specs")
        try:
            return SeveralCurves(specs)
        except ProblemError as exc:
            fail("obstacle_curves", " ".join(str(exc).split()))
    search = None
    if "obstacle_search_interval" in arrays:
        search = check_array(arrays, "obstacle_search_interval", "float", 1,
                             (2,))
    if "obstacle_points" in arrays:
        for key in ("obstacle_x", "obstacle_y", "obstacle_t_range"):
            if key in arrays:
                fail(key, "not allowed with obstacle_points (a polyline "
                          "is parametrised by its arc length)")
        points = check_array(arrays, "obstacle_points", "float", 2,
                             (None, 2))
        try:
            obstacle = PolylineCurve(points, search)
        except ProblemError as exc:
            fail("obstacle_points", str(exc).split(": ", 1)[-1])
    else:
        for key in ("obstacle_x", "obstacle_y"):
            if key not in arrays:
                fail(key, "missing (a 'mesh' problem file needs obstacle_x "
                          "and obstacle_y, or obstacle_points)")
        t_range = None
        if "obstacle_t_range" in arrays:
            t_range = check_array(arrays, "obstacle_t_range", "float", 1,
                                  (2,))
        x = check_array(arrays, "obstacle_x", "str", 0)
        y = check_array(arrays, "obstacle_y", "str", 0)
        try:
            obstacle = ParametricCurve(x, y, t_range, search)
        except ProblemError as exc:  # named by the expression it is about
            key = next((k for k, text in (("obstacle_x", x),
                                          ("obstacle_y", y))
                        if str(exc).startswith(repr(text))), "obstacle")
            fail(key, str(exc))
    return obstacle
