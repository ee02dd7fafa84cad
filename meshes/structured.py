"""Structured quadrilateral and hexahedral meshes (issue 35), and the same
nodes cut into triangles or tetrahedra.

``block``: the thesis's 10 x 20 block (x in [-5, 5], y in [-10, 10]) as
nx x ny square quadrilaterals, counter-clockwise (the quad counterpart of
``generate.py``'s triangle meshes; 10 x 20 gives 200 quads on 231 nodes,
the nearest square mesh to the 454-triangle mesh's 257 nodes). ``box``:
the cube [0, L]^d as n^d quadrilaterals (d = 2) or hexahedra (d = 3) in
VTK / SfePy node order, the patch of ``sfepy_problems/squeezed_block.py``.
``--simplices`` cuts every cell into 2 triangles or 6 tetrahedra (around
the diagonal 0-6) on the same nodes (``solver.geometry.cells.simplices``),
the problem the cells are compared with. ``hexes``: a tetrahedral mesh
cut into hexahedra, four per tetrahedron (a corner, its three edge
midpoints, three face centroids and the centroid), which halves the
element size and keeps the grading: the Hertz sphere's graded tetrahedra
(``hertz_sphere.py``) give a hexahedral sphere; new nodes on the sphere
(``--sphere-radius``, centre (0, 0, R)) are put on it radially. ``quads``:
a triangular mesh cut into quadrilaterals, three per triangle (a corner,
its two edge midpoints and the centroid), counter-clockwise, each keeping
its triangle's cell group (medit reference: the body of a two-body mesh).
Medit ``.mesh`` files, written by meshio, read by
``sfepy.discrete.fem.Mesh.from_file``.

Usage::

    python meshes/structured.py block 10 20 -o meshes/block_quad_200.mesh
    python meshes/structured.py block 10 20 --simplices -o output/block_tri_400.mesh
    python meshes/structured.py box 4 --dim 3 -o meshes/box_hex_4.mesh
    python meshes/structured.py box 4 --dim 3 --simplices -o output/box_tet_4.mesh
    python meshes/structured.py hexes meshes/hertz_sphere_8.mesh --sphere-radius 1 -o output/hertz_sphere_hex_16.mesh
    python meshes/structured.py quads meshes/two_body_patch.mesh -o output/two_body_patch_quad.mesh
"""

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from solver.geometry.cells import simplices  # noqa: E402


def grid(counts, lows, highs):
    """Nodes and cells (quadrilaterals or hexahedra, VTK order) of the
    axis-parallel box [lows, highs] cut into ``counts`` cells per axis; node
    (i, j[, k]) is number i + (nx + 1)(j + (ny + 1) k)."""
    counts = [int(c) for c in counts]
    axes = [np.linspace(lo, hi, c + 1) for c, lo, hi in
            zip(counts, lows, highs)]
    nodes = np.stack(np.meshgrid(*axes, indexing="ij"), -1)
    nodes = nodes.transpose(*range(len(counts))[::-1], len(counts))
    nodes = nodes.reshape(-1, len(counts))
    shape = [c + 1 for c in counts]
    ids = np.arange(np.prod(shape)).reshape(shape[::-1]).T  # ids[i, j, k]
    if len(counts) == 2:
        a = ids[:-1, :-1]
        corners = [a, ids[1:, :-1], ids[1:, 1:], ids[:-1, 1:]]
    else:
        lo = [ids[:-1, :-1, :-1], ids[1:, :-1, :-1], ids[1:, 1:, :-1],
              ids[:-1, 1:, :-1]]
        hi = [ids[:-1, :-1, 1:], ids[1:, :-1, 1:], ids[1:, 1:, 1:],
              ids[:-1, 1:, 1:]]
        corners = lo + hi
    cells = np.stack([c.T.ravel() for c in corners], axis=1)
    return nodes, cells.astype(np.int64)


def block(nx=10, ny=20):
    """The thesis block as nx x ny quadrilaterals."""
    return grid((nx, ny), (-5.0, -10.0), (5.0, 10.0))


def box(n=4, dim=3, length=1.0):
    """[0, length]^dim as n^dim quadrilaterals or hexahedra."""
    return grid((n,) * dim, (0.0,) * dim, (length,) * dim)


def tets_to_hexes(points, tets, radius=None):
    """Four hexahedra (VTK order) per tetrahedron (module docstring); with
    ``radius`` the new nodes of the boundary faces on the sphere of centre
    (0, 0, radius) are projected onto it."""
    points = np.asarray(points, float)
    tets = np.asarray(tets, np.int64)
    n, m = len(points), len(tets)
    # Each corner of a tetrahedron with the other three in an even
    # permutation (same orientation).
    turns = np.array([[0, 1, 2, 3], [1, 2, 0, 3], [2, 0, 1, 3],
                      [3, 0, 2, 1]])

    def index(groups):
        keys = np.sort(groups, axis=-1).reshape(-1, groups.shape[-1])
        unique, inverse = np.unique(keys, axis=0, return_inverse=True)
        return unique, inverse.reshape(groups.shape[:-1])

    t = tets[:, turns]                                  # (m, 4, 4)
    edges, edge_id = index(np.stack([t[..., [0, 1]], t[..., [0, 2]],
                                     t[..., [0, 3]]], axis=2))
    faces, face_id = index(np.stack([t[..., [0, 1, 2]], t[..., [0, 1, 3]],
                                     t[..., [0, 2, 3]]], axis=2))
    mids = points[edges].mean(axis=1)
    centroids = points[faces].mean(axis=1)
    centres = points[tets].mean(axis=1)
    if radius is not None:
        centre = np.array([0.0, 0.0, radius])
        on = np.abs(np.linalg.norm(points - centre, axis=1) - radius) \
            < 1e-9 * radius
        count = np.bincount(face_id.ravel(), minlength=len(faces))
        outer = on[faces].all(axis=1) & (count == 3)  # one tetrahedron
        outer_edges = np.zeros(len(edges), bool)
        keys = {tuple(e) for f in faces[outer]
                for e in ((f[0], f[1]), (f[0], f[2]), (f[1], f[2]))}
        outer_edges[[i for i, e in enumerate(map(tuple, edges))
                     if e in keys]] = True

        def project(x):
            d = x - centre
            return centre + radius * d / np.linalg.norm(d, axis=1)[:, None]

        mids[outer_edges] = project(mids[outer_edges])
        centroids[outer] = project(centroids[outer])
    e0 = n + edge_id
    f0 = n + len(edges) + face_id
    c = np.broadcast_to((n + len(edges) + len(faces)
                         + np.arange(m))[:, None], (m, 4))
    hexes = np.stack([t[..., 0], e0[..., 0], f0[..., 0], e0[..., 1],
                      e0[..., 2], f0[..., 1], c, f0[..., 2]], axis=-1)
    nodes = np.concatenate([points, mids, centroids, centres])
    return nodes, hexes.reshape(-1, 8)


def tris_to_quads(points, triangles):
    """Three quadrilaterals per triangle (module docstring): (nodes, quads,
    the triangle of each quadrilateral); the corners' quadrilaterals in the
    order of the triangles, repeated for corners 0, 1, 2."""
    points = np.asarray(points, float)[:, :2]
    tri = np.asarray(triangles, np.int64)
    n, m = len(points), len(tri)
    edges = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]],
                                    tri[:, [2, 0]]]), axis=1)
    unique, inverse = np.unique(edges, axis=0, return_inverse=True)
    mid = n + inverse.ravel().reshape(3, m)  # edges 01, 12, 20
    centre = n + len(unique) + np.arange(m)
    quads = np.concatenate([
        np.c_[tri[:, 0], mid[0], centre, mid[2]],
        np.c_[tri[:, 1], mid[1], centre, mid[0]],
        np.c_[tri[:, 2], mid[2], centre, mid[1]]])
    nodes = np.concatenate([points, points[unique].mean(axis=1),
                            points[tri].mean(axis=1)])
    a, b, c = (nodes[quads[:, k]] for k in range(3))
    clockwise = ((b - a)[:, 0] * (c - a)[:, 1]
                 - (b - a)[:, 1] * (c - a)[:, 0]) < 0
    quads[clockwise] = quads[clockwise][:, ::-1]
    return nodes + 0.0, quads, np.tile(np.arange(m), 3)


def write(path, nodes, cells, cut=False, groups=None):
    """Medit file of the cells (cut into simplices if ``cut``), with their
    cell ``groups`` (medit references) if given."""
    import meshio

    dim = nodes.shape[1]
    if cut:
        cells = simplices(cells, dim)
    kind = {(2, 3): "triangle", (2, 4): "quad", (3, 4): "tetra",
            (3, 8): "hexahedron"}[dim, cells.shape[1]]
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    extra = {} if groups is None else dict(
        point_data={"medit:ref": np.zeros(len(nodes), np.int64)},
        cell_data={"medit:ref": [np.asarray(groups, np.int64)]})
    meshio.write(path, meshio.Mesh(nodes, [(kind, cells)], **extra),
                 file_format="medit")


def read_quads(path):
    """The triangles of a medit file as quadrilaterals (:func:`tris_to_quads`)
    with their triangles' cell groups: (nodes, quads, groups)."""
    import meshio

    mesh = meshio.read(str(path))
    blocks = [i for i, b in enumerate(mesh.cells) if b.type == "triangle"]
    triangles = np.concatenate([mesh.cells[i].data for i in blocks])
    refs = mesh.cell_data.get("medit:ref")
    group = np.concatenate([refs[i] for i in blocks]) if refs else \
        np.zeros(len(triangles), np.int64)
    nodes, quads, parent = tris_to_quads(mesh.points, triangles)
    return nodes, quads, group[parent]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("shape", choices=("block", "box", "hexes", "quads"))
    parser.add_argument("counts", nargs="+",
                        help="block: nx ny; box: n; hexes, quads: a .mesh "
                             "file")
    parser.add_argument("--sphere-radius", type=float, default=None)
    parser.add_argument("--dim", type=int, default=3, choices=(2, 3))
    parser.add_argument("--simplices", action="store_true",
                        help="cut the cells into triangles / tetrahedra")
    parser.add_argument("-o", "--output", required=True)
    args = parser.parse_args(argv)
    groups = None
    if args.shape == "block":
        nodes, cells = block(*map(int, args.counts[:2]))
    elif args.shape == "box":
        nodes, cells = box(int(args.counts[0]), args.dim)
    elif args.shape == "quads":
        nodes, cells, groups = read_quads(args.counts[0])
    else:
        import meshio

        tet = meshio.read(args.counts[0])
        nodes, cells = tets_to_hexes(tet.points, tet.cells_dict["tetra"],
                                     args.sphere_radius)
    write(args.output, nodes, cells, args.simplices, groups)
    print(f"wrote {args.output}: {len(nodes)} nodes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
