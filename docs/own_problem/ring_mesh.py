"""Mesh a quarter ring a <= r <= b, x >= 0, y >= 0 with gmsh (the example of
docs/own-problem.md).

The mesh is structured (transfinite): ``n_radial`` elements across the
wall, ``n_arc`` along each arc, every quadrilateral cut into two
triangles. It therefore has exactly (n_radial + 1)(n_arc + 1) nodes and
2 n_radial n_arc triangles with any gmsh version. Written as a Medit
``.mesh`` with 2D coordinates (what SfePy reads), triangles
counter-clockwise.

Usage::

    python ring_mesh.py                        # ring.mesh: a = 1, b = 2, 8 x 48
    python ring_mesh.py --n-arc 96 -o ring_fine.mesh
"""

import argparse
import sys

import numpy as np


def ring_mesh(a=1.0, b=2.0, n_radial=8, n_arc=48):
    """(points (N, 2), triangles (M, 3)) of the quarter ring."""
    import gmsh

    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("ring")
        geo = gmsh.model.geo
        centre = geo.addPoint(0, 0, 0)
        p_a0, p_b0 = geo.addPoint(a, 0, 0), geo.addPoint(b, 0, 0)
        p_b1, p_a1 = geo.addPoint(0, b, 0), geo.addPoint(0, a, 0)
        bottom = geo.addLine(p_a0, p_b0)               # y = 0
        outer = geo.addCircleArc(p_b0, centre, p_b1)   # r = b: the contact
        left = geo.addLine(p_b1, p_a1)                 # x = 0
        inner = geo.addCircleArc(p_a1, centre, p_a0)   # r = a: pushed out
        loop = geo.addCurveLoop([bottom, outer, left, inner])
        surface = geo.addPlaneSurface([loop])
        for curve, n in ((bottom, n_radial), (left, n_radial),
                         (outer, n_arc), (inner, n_arc)):
            geo.mesh.setTransfiniteCurve(curve, n + 1)
        geo.mesh.setTransfiniteSurface(surface)
        geo.synchronize()
        gmsh.model.mesh.generate(2)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        _, _, connectivity = gmsh.model.mesh.getElements(2)
    finally:
        gmsh.finalize()
    # gmsh numbers nodes by tags; keep the nodes of the triangles (not
    # the arcs' centre), numbered from 0.
    triangles = connectivity[0].astype(np.int64).reshape(-1, 3)
    used, triangles = np.unique(triangles, return_inverse=True)
    triangles = triangles.reshape(-1, 3)
    order = np.argsort(tags)
    points = coords.reshape(-1, 3)[order[np.searchsorted(tags[order], used)], :2]
    # Nodes of the straight edges exactly on x = 0 and y = 0, so that the
    # problem file can select them by coordinates.
    points[np.abs(points) < 1e-12 * b] = 0.0
    # Counter-clockwise triangles (positive signed area).
    p0, p1, p2 = (points[triangles[:, i]] for i in range(3))
    area = (p1 - p0)[:, 0] * (p2 - p0)[:, 1] - (p1 - p0)[:, 1] * (p2 - p0)[:, 0]
    triangles[area < 0] = triangles[area < 0][:, ::-1]
    return points, triangles


def write_mesh(path, points, triangles):
    """Medit ``.mesh`` (2D coordinates, triangles, reference ids 0)."""
    import meshio

    meshio.write(str(path), meshio.Mesh(points, [("triangle", triangles)]),
                 file_format="medit")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--a", type=float, default=1.0, help="inner radius")
    parser.add_argument("--b", type=float, default=2.0, help="outer radius")
    parser.add_argument("--n-radial", type=int, default=8)
    parser.add_argument("--n-arc", type=int, default=48)
    parser.add_argument("-o", "--output", default="ring.mesh")
    args = parser.parse_args(argv)
    if not 0 < args.a < args.b or args.n_radial < 1 or args.n_arc < 1:
        parser.exit(2, "ring_mesh.py: error: need 0 < a < b and at least "
                       "one element each way\n")
    try:
        points, triangles = ring_mesh(args.a, args.b, args.n_radial,
                                      args.n_arc)
        write_mesh(args.output, points, triangles)
    except (ImportError, OSError) as exc:  # no gmsh; a folder missing
        parser.exit(1, f"ring_mesh.py: error: {exc}\n")
    print(f"{args.output}: {len(points)} nodes, {len(triangles)} triangles")
    return 0


if __name__ == "__main__":
    sys.exit(main())
