r"""First-order cells of the format (docs/npz-format.md, "Cells"): triangles
and quadrilaterals in 2D, tetrahedra and hexahedra in 3D, told apart by
their number of nodes and the dimension; the contact faces of a 3D body
are triangles or quadrilaterals.

A quadrilateral lists its nodes counter-clockwise, a hexahedron in VTK's
(and SfePy's ``3_8``) order: the bottom face 0-1-2-3 counter-clockwise seen
from the top face 4-5-6-7, node k + 4 above node k. The geometry of the
contact (boundary chains and their outward side, nodal normals) only needs
the surface of the body, which does not depend on how a cell is cut into
simplices: :func:`simplices` cuts each quadrilateral into two triangles
and each hexahedron into six tetrahedra around its diagonal 0-6 (Dompierre
et al., "How to subdivide pyramids, prisms and hexahedra into tetrahedra",
IMR 1999), the cut boundary edges and faces being those of the cells.
:func:`corner_measures` gives the signed area (volume) spanned at each
corner of a cell by its edges there: all positive for a valid cell in the
orientation above (the Jacobian of the bilinear / trilinear map at the
corners; Knupp, "Achieving finite element mesh quality via optimization
of the Jacobian matrix norm", IJNME 48 (2000))."""

import numpy as np

__all__ = ["CELL_NAMES", "cell_name", "simplices", "face_triangles",
           "cell_edges", "cell_faces", "corner_measures"]

#: Name of a cell by (dimension, nodes per cell).
CELL_NAMES = {(2, 3): "triangle", (2, 4): "quadrilateral",
              (3, 4): "tetrahedron", (3, 8): "hexahedron"}

_QUAD_TRIANGLES = np.array([[0, 1, 2], [0, 2, 3]])
_HEX_TETRAHEDRA = np.array([[0, 1, 2, 6], [0, 2, 3, 6], [0, 3, 7, 6],
                            [0, 7, 4, 6], [0, 4, 5, 6], [0, 5, 1, 6]])
#: Local faces of each 3D cell, outward by the right-hand rule.
_FACES = {4: np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]),
          8: np.array([[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4],
                       [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]])}
#: Each corner with its neighbours along the cell's local axes.
_CORNERS = {(2, 3): np.array([[0, 1, 2], [1, 2, 0], [2, 0, 1]]),
            (2, 4): np.array([[0, 1, 3], [1, 2, 0], [2, 3, 1], [3, 0, 2]]),
            (3, 4): np.array([[0, 1, 2, 3]]),
            (3, 8): np.array([[0, 1, 3, 4], [1, 2, 0, 5], [2, 3, 1, 6],
                              [3, 0, 2, 7], [4, 7, 5, 0], [5, 4, 6, 1],
                              [6, 5, 7, 2], [7, 6, 4, 3]])}


def cell_name(dim, width):
    """"triangle", "quadrilateral", "tetrahedron" or "hexahedron"; None for
    another (dimension, nodes per cell)."""
    return CELL_NAMES.get((int(dim), int(width)))


def simplices(cells, dim=2):
    """``cells`` (n, k) as triangles (2D) or tetrahedra (3D): unchanged if
    they are already, else cut (module docstring), of the cells' own
    orientation."""
    cells = np.asarray(cells, dtype=np.int64)
    if cells.shape[1] == dim + 1:
        return cells
    cut = _QUAD_TRIANGLES if dim == 2 else _HEX_TETRAHEDRA
    return cells[:, cut].reshape(-1, dim + 1)


def face_triangles(faces):
    """Contact faces (n, 3) or (n, 4) as triangles, a quadrilateral a-b-c-d
    cut into a-b-c and a-c-d (same orientation)."""
    faces = np.asarray(faces, dtype=np.int64)
    if faces.ndim != 2 or faces.shape[1] != 4:
        return faces
    return faces[:, _QUAD_TRIANGLES].reshape(-1, 3)


def cell_edges(cells, dim=2):
    """The edges of the cells (n_e, 2), each once, ``a < b``: the sides of
    triangles and quadrilaterals, the 6 edges of a tetrahedron and the 12
    of a hexahedron (not the cuts of :func:`simplices`)."""
    cells = np.asarray(cells, dtype=np.int64)
    k = cells.shape[1]
    if dim == 2 or k == 4 and dim == 3:
        pairs = ([(a, (a + 1) % k) for a in range(k)] if dim == 2 else
                 [(a, b) for a in range(4) for b in range(a + 1, 4)])
    else:
        pairs = [(a, (a + 1) % 4) for a in range(4)] + \
            [(a + 4, (a + 1) % 4 + 4) for a in range(4)] + \
            [(a, a + 4) for a in range(4)]
    edges = np.sort(np.concatenate([cells[:, list(p)] for p in pairs]),
                    axis=1)
    return np.unique(edges, axis=0)


def cell_faces(cells):
    """The faces of 3D cells, outward: (n · f, m) node ids (m = 3 for
    tetrahedra, 4 for hexahedra) and the cell of each face."""
    cells = np.asarray(cells, dtype=np.int64)
    local = _FACES[cells.shape[1]]
    faces = cells[:, local].reshape(-1, local.shape[1])
    return faces, np.repeat(np.arange(len(cells)), len(local))


def corner_measures(nodes, cells):
    """Signed 2·area (2D) or 6·volume (3D) at each corner (n, corners) of
    the cells (module docstring), and the squared longest edge per cell."""
    nodes = np.asarray(nodes, dtype=float)
    cells = np.asarray(cells, dtype=np.int64)
    dim = nodes.shape[1]
    corner = _CORNERS[(dim, cells.shape[1])]
    p = nodes[cells]                                 # (n, k, d)
    e = p[:, corner[:, 1:]] - p[:, corner[:, :1]]    # (n, c, d, d)
    if dim == 2:
        measure = e[..., 0, 0] * e[..., 1, 1] - e[..., 0, 1] * e[..., 1, 0]
    else:
        measure = np.einsum("ncj,ncj->nc", e[..., 0, :],
                            np.cross(e[..., 1, :], e[..., 2, :]))
    long2 = (e ** 2).sum(axis=-1).max(axis=(1, 2))
    return measure, long2
