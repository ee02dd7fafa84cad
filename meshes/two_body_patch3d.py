"""Tetrahedral mesh of the 3D contact patch test: two stacked boxes meshed
independently (``sfepy_problems/two_body_patch3d.py``).

Body 0 (cell group 1), the upper box [0, 1]² × [0.5, 1], and body 1 (group
2), the lower box [0, 1]² × [0, 0.5], are meshed by gmsh's Delaunay
(unstructured) with element sizes ``--h`` (default 0.3 above, 0.22 below),
so the interface triangles of the two sides do not match and are
irregular. Reproducible (single thread, fixed seed). The bodies share no
node. Written as Medit ``.mesh`` with the tetrahedra's reference ids 1
and 2 (SfePy's ``cells of group 1`` and ``2``).

Usage::

    python meshes/two_body_patch3d.py -o meshes/two_body_patch3d.mesh
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent

#: Element sizes of the upper and the lower box.
SIZES = (0.3, 0.22)


def _module(name, file):
    key = f"_contact_ssn_meshes_{name}"
    if key not in sys.modules:
        spec = importlib.util.spec_from_file_location(key, HERE / file)
        module = importlib.util.module_from_spec(spec)
        sys.modules[key] = module
        spec.loader.exec_module(module)
    return sys.modules[key]


def box_mesh(z0, height, h):
    """(points, tets) of [0, 1]² × [z0, z0 + height], size h."""
    sphere = _module("hertz_sphere", "hertz_sphere.py")
    gmsh = sphere._load_generate()._import_gmsh()
    own = not gmsh.isInitialized()
    if own:
        gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.model.add("box")
        sphere.set_options(gmsh)
        gmsh.option.setNumber("Mesh.MeshSizeMin", h)
        gmsh.option.setNumber("Mesh.MeshSizeMax", h)
        gmsh.model.occ.addBox(0, 0, z0, 1, 1, height)
        gmsh.model.occ.synchronize()
        gmsh.model.mesh.generate(3)
        points, tets = sphere.tetrahedra(gmsh)
    finally:
        if own:
            gmsh.finalize()
        else:
            gmsh.model.remove()
    planes = ((0, 0.0), (0, 1.0), (1, 0.0), (1, 1.0), (2, z0),
              (2, z0 + height))
    points = sphere.snap(points, planes, 1.0)
    return points, sphere.orient(points, tets)


def patch_mesh(sizes=SIZES):
    """(points, tets, group) of the two boxes."""
    upper = box_mesh(0.5, 0.5, sizes[0])
    lower = box_mesh(0.0, 0.5, sizes[1])
    points = np.concatenate([upper[0], lower[0]])
    tets = np.concatenate([upper[1], lower[1] + len(upper[0])])
    return points, tets, np.repeat([1, 2], [len(upper[1]), len(lower[1])])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="two_body_patch3d.py",
                                     description=__doc__.split("\n")[0])
    parser.add_argument("--h", type=float, nargs=2, default=SIZES,
                        help="element sizes of the upper and lower box")
    parser.add_argument("-o", "--output", required=True)
    args = parser.parse_args(argv)
    points, tets, group = patch_mesh(args.h)
    _module("two_spheres", "two_spheres.py").write_mesh(
        args.output, points, tets, group)
    print(f"wrote {args.output}: {len(points)} nodes, {len(tets)} "
          "tetrahedra")
    return 0


if __name__ == "__main__":
    sys.exit(main())
