"""Tetrahedral mesh of two spheres touching at the origin, for the 3D
two-body (dual mortar) problems: ``sfepy_problems/two_spheres.py``.

Body 0 (cell group 1, the slave) is the quarter (``--half``: half) of the
lower half-ball of radius R₀ centred at (0, 0, R₀); body 1 (group 2, the
master) the quarter (half) of the upper half-ball of radius R₁ centred at
(0, 0, −R₁), the same construction mirrored in z. Each is meshed by
:func:`hertz_sphere.hertz_sphere_mesh` (gmsh, graded from the contact
point: h = a/N within 1.5 a, growing to 0.15 R; reproducible), with the
same contact radius a to refine for, so the two interface meshes are
independent and do not match. The bodies share no node.

``--box``: body 1 is instead the box [0, R₀]² × [−R₀, 0] (x from −R₀
with ``--half``), graded from the origin like the spheres: an elastic
sphere on an elastic box, whose stiff limit is the sphere on the rigid
plane z = 0 (``sfepy_problems/hertz_sphere.py``, the same sphere mesh).

Usage::

    python meshes/two_spheres.py --a-over-h 6 -o meshes/two_spheres_6.mesh
    python meshes/two_spheres.py --a-over-h 6 --radii 1 1 --half \\
        -o meshes/two_spheres_half_6.mesh
    python meshes/two_spheres.py --a-over-h 4 --box -o sphere_box_4.mesh

Written as Medit ``.mesh`` with the tetrahedra's reference ids 1 and 2
(SfePy's ``cells of group 1`` and ``2``). gmsh is imported only when
called.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent

#: Default radii R₀ (slave, upper) and R₁ (master, lower).
RADII = (1.0, 1.5)

#: Default contact radius refined for: a = 0.05 R₀.
A_TARGET = 0.05


def _hertz_sphere():
    name = "_contact_ssn_meshes_hertz_sphere"
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(
            name, HERE / "hertz_sphere.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


def two_spheres_mesh(a_over_h: float, radii=RADII, a: float | None = None,
                     half: bool = False):
    """(points (N, 3), tets (M, 4), group (M,) 1 or 2) of the two bodies."""
    sphere = _hertz_sphere()
    a = A_TARGET * radii[0] if a is None else a
    upper = sphere.hertz_sphere_mesh(a_over_h, radii[0], a, half)
    points, tets = sphere.hertz_sphere_mesh(a_over_h, radii[1], a, half)
    lower = points * [1.0, 1.0, -1.0], sphere.orient(points * [1, 1, -1],
                                                       tets)
    points = np.concatenate([upper[0], lower[0]])
    tets = np.concatenate([upper[1], lower[1] + len(upper[0])])
    group = np.repeat([1, 2], [len(upper[1]), len(lower[1])])
    return points, tets, group


def box_mesh(a_over_h: float, width: float, depth: float, a: float,
             half: bool = False):
    """(points, tets) of the box [0, W]² × [−D, 0] (``half``: [−W, W] ×
    [0, W] × [−D, 0]) graded from the origin like the spheres: h = a/N
    within 1.5 a, growing to 0.15 W at 0.7 W."""
    sphere = _hertz_sphere()
    gmsh = sphere._load_generate()._import_gmsh()
    own = not gmsh.isInitialized()
    if own:
        gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.model.add("box")
        sphere.set_options(gmsh)
        occ = gmsh.model.occ
        occ.addBox(-width if half else 0.0, 0.0, -depth,
                   (2 if half else 1) * width, width, depth)
        occ.synchronize()
        eps = 1e-9 * width
        tip = gmsh.model.getEntitiesInBoundingBox(-eps, -eps, -eps, eps, eps,
                                                  eps, 0)
        if not tip:  # the half box: the origin is on an edge, add it
            tip = [(0, occ.addPoint(0.0, 0.0, 0.0))]
            occ.synchronize()
        field = gmsh.model.mesh.field
        distance = field.add("Distance")
        field.setNumbers(distance, "PointsList", [tip[0][1]])
        threshold = field.add("Threshold")
        field.setNumber(threshold, "InField", distance)
        field.setNumber(threshold, "SizeMin", a / a_over_h)
        field.setNumber(threshold, "SizeMax", sphere.H_FAR * width)
        field.setNumber(threshold, "DistMin", sphere.DIST_FINE * a)
        field.setNumber(threshold, "DistMax", sphere.DIST_COARSE * width)
        field.setAsBackgroundMesh(threshold)
        gmsh.model.mesh.generate(3)
        points, tets = sphere.tetrahedra(gmsh)
    finally:
        if own:
            gmsh.finalize()
        else:
            gmsh.model.remove()
    planes = ((0, 0.0), (1, 0.0), (2, 0.0), (2, -depth))[half:]
    points = sphere.snap(points, planes, width)
    return points, sphere.orient(points, tets)


def sphere_on_box_mesh(a_over_h: float, radius: float = 1.0,
                       a: float | None = None, half: bool = False):
    """(points, tets, group): the upper sphere as in
    :func:`two_spheres_mesh` (group 1) on the box [0, R]² × [−R, 0]
    (group 2; ``half``: x from −R)."""
    sphere = _hertz_sphere()
    a = A_TARGET * radius if a is None else a
    upper = sphere.hertz_sphere_mesh(a_over_h, radius, a, half)
    lower = box_mesh(a_over_h, radius, radius, a, half)
    points = np.concatenate([upper[0], lower[0]])
    tets = np.concatenate([upper[1], lower[1] + len(upper[0])])
    group = np.repeat([1, 2], [len(upper[1]), len(lower[1])])
    return points, tets, group


def write_mesh(path, points, tets, group) -> None:
    """Medit ``.mesh``, cell reference ids ``group``."""
    import meshio

    mesh = meshio.Mesh(
        np.ascontiguousarray(points, dtype=np.float64),
        [("tetra", np.ascontiguousarray(tets, dtype=np.int64))],
        point_data={"medit:ref": np.zeros(len(points), dtype=np.int64)},
        cell_data={"medit:ref": [np.asarray(group, dtype=np.int64)]})
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    meshio.write(str(path), mesh, file_format="medit")


def main(argv=None) -> int:
    sphere = _hertz_sphere()
    parser = argparse.ArgumentParser(prog="two_spheres.py",
                                     description=__doc__.split("\n")[0])
    parser.add_argument("--a-over-h", type=float, required=True,
                        help="contact radius over the element size there")
    parser.add_argument("--radii", type=float, nargs=2, default=RADII,
                        help="R0 (slave, upper) and R1 (master, lower)")
    parser.add_argument("--a", type=float, default=None,
                        help=f"contact radius refined for (default "
                             f"{A_TARGET} R0)")
    parser.add_argument("--half", action="store_true",
                        help="the halves y >= 0 (default: the quarters)")
    parser.add_argument("--box", action="store_true",
                        help="the master a box [0, R0]^2 x [-R0, 0] (the "
                             "rigid limit), not a sphere")
    parser.add_argument("-o", "--output", required=True)
    args = parser.parse_args(argv)
    try:
        if args.box:
            points, tets, group = sphere_on_box_mesh(
                args.a_over_h, args.radii[0], args.a, args.half)
        else:
            points, tets, group = two_spheres_mesh(
                args.a_over_h, args.radii, args.a, args.half)
        write_mesh(args.output, points, tets, group)
    except (ValueError, RuntimeError, OSError,
            sphere._load_generate().GmshMissingError) as exc:
        print(f"{parser.prog}: error: {exc}", file=sys.stderr)
        return 1
    print(f"wrote {args.output}: {len(points)} nodes, {len(tets)} "
          "tetrahedra")
    return 0


if __name__ == "__main__":
    sys.exit(main())
