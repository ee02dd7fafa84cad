"""Tetrahedral meshes of the thesis block extruded in z (issue 18).

The block [-5, 5] × [-10, 10] of the thesis (``generate.py``, meshes of 118,
454 and 1878 triangles) is extruded to [-5, 5] × [-10, 10] × [0, T] in
``layers`` equal layers; each prism is split into three tetrahedra by the
smallest-index rule (the triangle's vertices a < b < c by node number:
[a, b, c, c'], [a, b, b', c'], [a, a', b', c'], ' = the layer above), which
makes neighbouring prisms agree on the diagonal of their common quadrilateral,
so the mesh is conforming. The cross-section is exactly the 2D thesis mesh,
so that a one-layer slab with u_z = 0 (``sfepy_problems/block3d_obstacle.py
slab=True``) can be compared with the 2D block node for node. No gmsh is
needed; gmsh makes the 2D base mesh if its file is absent.

Usage::

    python meshes/block3d.py --base 454 --layers 5 --thickness 10 \\
        -o meshes/block3d_454x5.mesh
    python meshes/block3d.py --base 118 --layers 1 --thickness 1 \\
        -o meshes/block3d_118_slab.mesh

Written as Medit ``.mesh`` (3D coordinates, tetrahedra only, reference ids
0), all tetrahedra of positive volume.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent


def _load(name, filename):
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, HERE / filename)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


generate = _load("_contact_ssn_meshes_generate", "generate.py")
sphere = _load("_contact_ssn_meshes_hertz_sphere", "hertz_sphere.py")


def extrude(points, triangles, layers: int, thickness: float):
    """Extrude a 2D triangle mesh into tetrahedra; returns (points (N, 3),
    tets (M, 4)) with node ``k * n + i`` = 2D node i at layer height k."""
    if layers < 1 or not (np.isfinite(thickness) and thickness > 0):
        raise ValueError(f"need layers >= 1 and a positive thickness, got "
                         f"{layers} and {thickness}")
    n = len(points)
    z = np.linspace(0.0, thickness, layers + 1)
    nodes = np.column_stack([np.tile(points, (layers + 1, 1)),
                             np.repeat(z, n)])
    a, b, c = np.sort(triangles, axis=1).T
    tets = []
    for k in range(layers):
        lo, hi = k * n, (k + 1) * n
        tets += [np.column_stack([a + lo, b + lo, c + lo, c + hi]),
                 np.column_stack([a + lo, b + lo, b + hi, c + hi]),
                 np.column_stack([a + lo, a + hi, b + hi, c + hi])]
    return nodes, sphere.orient(nodes, np.concatenate(tets))


def main(argv=None) -> int:
    parser = generate.Parser(prog="block3d.py", description=__doc__.split("\n")[0])
    parser.add_argument("--base", type=int, default=454,
                        choices=generate.THESIS_COUNTS,
                        help="the 2D thesis mesh (triangles)")
    parser.add_argument("--layers", type=int, default=5,
                        help="layers in z, at least 1 (default 5)")
    parser.add_argument("--thickness", type=float, default=10.0,
                        help="extent in z, any positive number (default 10)")
    parser.add_argument("-o", "--output", required=True)
    args = parser.parse_args(argv)

    def work():
        points, triangles = generate.base_mesh(args.base)
        nodes, tets = extrude(points, triangles, args.layers, args.thickness)
        sphere.write_mesh(args.output, nodes, tets)
        return nodes, tets

    code, mesh = generate.guarded(parser.prog, work)
    if code:
        return code
    nodes, tets = mesh
    print(f"wrote {args.output}: {len(nodes)} nodes, {len(tets)} "
          "tetrahedra")
    return 0


if __name__ == "__main__":
    sys.exit(main())
