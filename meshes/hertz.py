"""Triangle mesh of the elastic half-cylinder of the Hertz line contact test.

The body is the lower half of the disk ``x**2 + y**2 <= R**2, y <= 0``
(R = 1 by default, any R > 0 with ``--radius``): a flat top edge on y = 0
and a circular arc below it, touching the rigid flat obstacle y = -R at the
bottom point (0, -R). The contact zone is small (half-width a ~ 0.1 R for
the default load), so the mesh is graded: a fine element size
``h_contact`` (default 0.004 R) within ``DIST_FINE`` = 0.15 R of the bottom
point, growing linearly to the coarse size ``h_far`` (default 0.1 R) at
``DIST_COARSE`` = 0.6 R from it (gmsh Distance + Threshold background
field). Every length and tolerance is relative to R, so a mesh of radius R
is the R = 1 mesh scaled.

The mesh is **symmetric** about x = 0: gmsh meshes the right quarter
(x >= 0) and the left half is its mirror image, so the contact solution of a
symmetric load is symmetric node by node. The geometry has points at

* (0, 0): the centre of the arc and the middle of the top edge (the node
  pinned in x by ``sfepy_problems/hertz_cylinder.py``),
* (±0.6 R, -0.8 R): where Γc (the arc below y = -0.8 R) ends, so that Γc
  is exactly the arc of angle 2 asin(0.6) (|Γc| = 1.2870 R),
* (0, -R): the first contact point.

Boundary nodes lie on the arc to round-off (|r - R| < 1e-15 R) and exactly
on y = 0 and x = 0 (snapped within 1e-12 R, see ``hertz_mesh``). Written as Medit ``.mesh``
(2D coordinates, triangles only, reference ids 0) with ``write_mesh`` of
``meshes/generate.py``; select regions by coordinates.

Options are fixed (single thread, random seed, Frontal-Delaunay) as in
``generate.py``, so reruns with the same gmsh version give identical files.
Measured with gmsh 4.15 (R = 1, h_far = 0.1, default distances), generation
< 1 s each:

=========  =======  =========  =========================  ==========
h_contact  nodes    triangles  arc nodes with |x| < 0.1   file size
=========  =======  =========  =========================  ==========
0.016      601      1120       13                         45 KB
0.008      1293     2480       25                         100 KB
0.004      3574     6998       51                         290 KB
0.002      11796    23362      101                        986 KB
0.001      43044    85702      201                        3.8 MB
=========  =======  =========  =========================  ==========

The default (0.004) is committed as ``meshes/hertz.mesh``; make the others on
demand. For a = 0.1 R, ``h_contact = 0.004`` puts about 50 nodes in the
contact zone.

Usage::

    python meshes/hertz.py                         # meshes/hertz.mesh (h_c = 0.004)
    python meshes/hertz.py --h-contact 0.004 -o meshes/hertz_0.004.mesh
    python meshes/hertz.py --h-contact 0.002 -o /tmp/hertz_0.002.mesh
    python meshes/hertz.py --h-contact 0.004 --refine 2 -o /tmp/h.mesh
        # all sizes (h_contact and h_far) divided by 2
    python meshes/hertz.py --radius 10 -o output/hertz_R10.mesh
        # R = 10, sizes 0.004 R and 0.1 R

gmsh is needed only here (``pip install gmsh``); it is imported when called.
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent

#: Default fine element size at the contact point, over R: about 50 arc
#: nodes in |x| < 0.1 R, the Hertz half-width of the default load.
H_CONTACT = 0.004

#: Default coarse element size away from the contact zone, over R.
H_FAR = 0.1

#: The element size is h_contact within DIST_FINE * R of (0, -R), grows
#: linearly to h_far at DIST_COARSE * R.
DIST_FINE = 0.15
DIST_COARSE = 0.6

#: y / R below which the arc is the contact boundary Γc (the arc is split
#: there, at x = ±0.6 R).
GAMMA_C_Y = -0.8

#: Coordinates within this distance (times R) of x = 0 or y = 0 are put on it.
SNAP_TOL = 1e-12

#: gmsh Mesh.Algorithm (6 = Frontal-Delaunay: well-shaped graded triangles).
ALGORITHM = 6

#: Default output file (the committed mesh).
DEFAULT_OUTPUT = HERE / "hertz.mesh"


def _load_generate():
    """``meshes/generate.py`` as a module (this folder is not a package)."""
    name = "_contact_ssn_meshes_generate"
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, HERE / "generate.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


generate = _load_generate()
write_mesh = generate.write_mesh
read_mesh = generate.read_mesh
GmshMissingError = generate.GmshMissingError


def _set_options(gmsh) -> None:
    """Every option the mesh depends on (sizes come from the field only)."""
    number = gmsh.option.setNumber
    number("General.Terminal", 0)
    number("General.NumThreads", 1)
    number("Mesh.MaxNumThreads2D", 1)
    number("Mesh.RandomSeed", 1)
    number("Mesh.Algorithm", ALGORITHM)
    number("Mesh.ElementOrder", 1)
    number("Mesh.RecombineAll", 0)
    number("Mesh.Smoothing", 1)
    number("Mesh.MeshSizeFromPoints", 0)
    number("Mesh.MeshSizeFromCurvature", 0)
    number("Mesh.MeshSizeExtendFromBoundary", 0)
    number("Mesh.MeshSizeFactor", 1.0)
    number("Mesh.MeshSizeMin", 0.0)
    number("Mesh.MeshSizeMax", 1e22)


def _quarter(h_contact: float, h_far: float, radius: float,
             dist_fine: float, dist_coarse: float):
    """gmsh mesh of the quarter x >= 0; returns raw (points (N, 3), triangles)."""
    gmsh = generate._import_gmsh()
    own_session = not gmsh.isInitialized()
    if own_session:
        gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("hertz_quarter")
        geo = gmsh.model.geo
        R = radius
        s, c = 0.6 * R, -0.8 * R  # end of Γc on the arc: (0.6 R, -0.8 R)
        centre = geo.addPoint(0.0, 0.0, 0.0)
        right = geo.addPoint(R, 0.0, 0.0)
        end_c = geo.addPoint(s, c, 0.0)
        bottom = geo.addPoint(0.0, -R, 0.0)
        # The loop's orientation does not matter: clean_mesh makes every
        # triangle counter-clockwise.
        top = geo.addLine(centre, right)
        arc_upper = geo.addCircleArc(right, centre, end_c)
        arc_lower = geo.addCircleArc(end_c, centre, bottom)
        axis = geo.addLine(bottom, centre)
        loop = geo.addCurveLoop([top, arc_upper, arc_lower, axis])
        geo.addPlaneSurface([loop])
        geo.synchronize()

        field = gmsh.model.mesh.field
        distance = field.add("Distance")
        field.setNumbers(distance, "PointsList", [bottom])
        threshold = field.add("Threshold")
        field.setNumber(threshold, "InField", distance)
        field.setNumber(threshold, "SizeMin", h_contact)
        field.setNumber(threshold, "SizeMax", h_far)
        field.setNumber(threshold, "DistMin", dist_fine * R)
        field.setNumber(threshold, "DistMax", dist_coarse * R)
        field.setAsBackgroundMesh(threshold)

        _set_options(gmsh)
        gmsh.model.mesh.generate(2)
        points, triangles = generate.model_triangles(gmsh)
        gmsh.model.remove()
    finally:
        if own_session:
            gmsh.finalize()
    return points, triangles


def hertz_mesh(h_contact: float | None = None, h_far: float | None = None,
               refine: float = 1.0, radius: float = 1.0,
               dist_fine: float = DIST_FINE, dist_coarse: float = DIST_COARSE):
    """Mesh the half-disk ``x**2 + y**2 <= radius**2, y <= 0`` with gmsh.

    h_contact: element size near the contact point (0, -radius); None:
        ``H_CONTACT * radius``.
    h_far: element size away from it; None: ``H_FAR * radius``.
    refine: both sizes are divided by ``refine`` (uniform refinement factor
        for convergence studies).
    radius: R.
    dist_fine, dist_coarse: the size is h_contact within ``dist_fine * R`` of
        (0, -R) and grows linearly to h_far at ``dist_coarse * R``.

    Returns ``(points (N, 2) float64, triangles (M, 3) int64)``: every
    triangle counter-clockwise, every node in a triangle, the mesh symmetric
    about x = 0 (mirror of gmsh's right quarter; the nodes on x = 0 are
    shared). Node order: the quarter's nodes in gmsh order, then the mirror
    images of those with x > 0.
    """
    if not (math.isfinite(radius) and radius > 0):
        raise ValueError(f"radius must be a positive number, got {radius}")
    h_contact = H_CONTACT * radius if h_contact is None else h_contact
    h_far = H_FAR * radius if h_far is None else h_far
    for name, value in (("h_contact", h_contact), ("h_far", h_far),
                        ("refine", refine),
                        ("dist_fine", dist_fine), ("dist_coarse", dist_coarse)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a positive number, got {value}")
    h_contact, h_far = h_contact / refine, h_far / refine
    if h_contact > h_far:
        raise ValueError(f"h_contact ({h_contact}) must not exceed h_far ({h_far})")
    if dist_fine >= dist_coarse:
        raise ValueError(f"dist_fine ({dist_fine}) must be less than dist_coarse "
                         f"({dist_coarse})")
    points, triangles = _quarter(h_contact, h_far, radius, dist_fine, dist_coarse)
    # clean_mesh drops z, removes unused nodes (the arc centre is a geometry
    # point only if no triangle uses it; here it is the top-edge corner, so
    # it stays) and orients triangles; box=None: no snapping to the block's
    # edges, this shape snaps its own, relative to R, below.
    points, triangles = generate.clean_mesh(points, triangles, box=None)
    for col in (0, 1):  # the symmetry axis x = 0 and the top edge y = 0
        near = np.abs(points[:, col]) <= SNAP_TOL * radius
        points[near, col] = 0.0
    if (points[:, 0] < 0).any() or (points[:, 1] > 0).any():
        raise RuntimeError("gmsh put quarter nodes outside x >= 0, y <= 0")

    # Mirror: x -> -x; nodes on the axis x = 0 are shared.
    off_axis = np.flatnonzero(points[:, 0] > 0)
    image = np.arange(len(points))
    image[off_axis] = len(points) + np.arange(len(off_axis))
    mirrored = points[off_axis] * np.array([-1.0, 1.0])
    points = np.concatenate([points, mirrored])
    triangles = np.concatenate([triangles, image[triangles][:, ::-1]])
    points += 0.0  # no "-0.0" in files
    return generate.clean_mesh(points, triangles, box=None)


def arc_nodes(points: np.ndarray, radius: float = 1.0, tol: float = 1e-9) -> np.ndarray:
    """Indices of the nodes on the arc (|r - radius| <= tol * radius), by x."""
    r = np.hypot(points[:, 0], points[:, 1])
    on = np.flatnonzero(np.abs(r - radius) <= tol * radius)
    return on[np.argsort(points[on, 0], kind="stable")]


def _parser() -> argparse.ArgumentParser:
    parser = generate.Parser(
        prog="hertz.py",
        description="Write a graded triangle mesh of the half-disk "
                    "x^2 + y^2 <= R^2, y <= 0 (Hertz line contact), "
                    "fine near the contact point (0, -R).")
    parser.add_argument("--h-contact", type=generate.positive_float, default=None, metavar="H",
                        help=f"element size near (0, -R) (default {H_CONTACT} R)")
    parser.add_argument("--h-far", type=generate.positive_float, default=None, metavar="H",
                        help=f"element size away from the contact zone (default {H_FAR} R)")
    parser.add_argument("--refine", type=generate.positive_float, default=1.0, metavar="F",
                        help="divide both sizes by F (default 1)")
    parser.add_argument("--radius", type=generate.positive_float, default=1.0, metavar="R",
                        help="radius R, any positive number (default 1)")
    parser.add_argument("--dist-fine", type=generate.positive_float, default=DIST_FINE, metavar="D",
                        help=f"size h_contact within D*R of (0, -R) (default {DIST_FINE})")
    parser.add_argument("--dist-coarse", type=generate.positive_float, default=DIST_COARSE, metavar="D",
                        help=f"size h_far beyond D*R of (0, -R) (default {DIST_COARSE})")
    parser.add_argument("-o", "--output", type=Path, default=DEFAULT_OUTPUT, metavar="FILE",
                        help="output .mesh file (default: meshes/hertz.mesh)")
    return parser


def main(argv=None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    if args.output.suffix != ".mesh":
        parser.error(f"output file must end in .mesh, got {args.output}")

    def work():
        points, triangles = hertz_mesh(args.h_contact, args.h_far, args.refine,
                                       args.radius, args.dist_fine, args.dist_coarse)
        write_mesh(args.output, points, triangles)
        return points, triangles

    code, mesh = generate.guarded(parser.prog, work)
    if code:
        return code
    points, triangles = mesh
    arc = arc_nodes(points, args.radius)
    a = 0.1 * args.radius
    inside = int((np.abs(points[arc, 0]) < a).sum())
    print(f"{args.output}: {len(triangles)} triangles, {len(points)} nodes, "
          f"{inside} arc nodes with |x| < {a:g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
