"""Triangle meshes of two elastic bodies in contact (issue 19).

One Medit ``.mesh`` file per problem, the bodies as **two cell groups**
(reference id 1 = body 0, 2 = body 1; SfePy: ``cells of group 1``) that
share **no node**: where the bodies touch, each has its own nodes (at the
same place where the meshes match, usually elsewhere). The problem files
in ``sfepy_problems/`` (``two_body_patch.py``, ``two_cylinders.py``,
``block_elastic_obstacle.py``) read them.

``patch``
    Contact patch test: the lower block [0, 1] × [0, 0.5] (body 0) and
    the upper block [0, 1] × [0.5, 1] (body 1), non-matching on the
    interface y = 0.5: ``--n-lower`` and ``--n-upper`` segments there
    (default 5 and 8: no interior node of one side is at a node of the
    other), element size ``--h`` elsewhere.
``cylinders``
    Two half-discs touching at the origin: the upper one of radius R1
    centred at (0, R1) (flat side y = R1 on top, body 1), the lower one of
    radius R2 centred at (0, −R2) (flat side y = −R2 at the bottom, body
    0). Each is ``meshes/hertz.py``'s graded half-disc (size ``--h1``,
    ``--h2``, default 0.004 R1 and 0.006 R1, within 0.15 R of the contact
    point, growing to 0.1 R at 0.6 R; symmetric about x = 0), moved (and
    for the lower one mirrored) into place.
``block``
    The thesis block (``meshes/block_454.mesh``, body 0) and an elastic
    obstacle body (body 1) whose left side is the thesis parabola x =
    5.05 + 0.005 y² for |y| <= ``--y-max`` (vertices exactly on it every
    ``--h-contact``), its right side x = ``--x-far``; element size
    ``--h-contact`` at the parabola growing to ``--h-far`` at the far side.
    ``--refine K`` splits the block's triangles into 4, K times (the
    ~10⁵-DOF benchmark, ``benchmarks/run_two_body.py``: ``--base 1878
    --refine 3 --h-contact 0.0625``).

Options are fixed as in ``generate.py`` (one thread, fixed seed), so reruns
with the same gmsh version give identical files (``meshes/README.md`` lists
the committed ones and their sizes).

Usage::

    python meshes/two_body.py patch                # two_body_patch.mesh
    python meshes/two_body.py cylinders            # two_body_cylinders.mesh
    python meshes/two_body.py cylinders --identical \\
        -o meshes/two_body_cylinders_identical.mesh
    python meshes/two_body.py block                # two_body_block_454.mesh

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


def _load(name, filename):
    """A sibling script of this folder as a module (not a package)."""
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, HERE / filename)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


generate = _load("_contact_ssn_meshes_generate", "generate.py")
hertz = _load("_contact_ssn_meshes_hertz", "hertz.py")

#: Default files.
PATCH = HERE / "two_body_patch.mesh"
CYLINDERS = HERE / "two_body_cylinders.mesh"
CYLINDERS_IDENTICAL = HERE / "two_body_cylinders_identical.mesh"
BLOCK = HERE / "two_body_block_454.mesh"

#: The two cylinders (R1 upper, R2 lower) and their element sizes at the
#: contact point over R1: about 50 slave nodes within |x| < 0.1 R1.
R1, R2 = 1.0, 1.5
H1, H2 = 0.004, 0.006


def ccw(points, triangles):
    """Triangles made counter-clockwise."""
    triangles = np.array(triangles, dtype=np.int64)
    cw = generate.signed_areas(points, triangles) < 0
    triangles[cw] = triangles[cw][:, ::-1]
    return triangles


def join(bodies):
    """(points, triangles, group) of bodies [(points, triangles), ...]:
    nodes of body 0 first; group = body id + 1; no node shared."""
    points, triangles, group, offset = [], [], [], 0
    for i, (p, t) in enumerate(bodies):
        points.append(np.asarray(p, dtype=np.float64)[:, :2])
        triangles.append(ccw(points[-1], t) + offset)
        group.append(np.full(len(t), i + 1, dtype=np.int64))
        offset += len(p)
    points = np.concatenate(points) + 0.0  # no "-0.0" in files
    return points, np.concatenate(triangles), np.concatenate(group)


def write_bodies(path, points, triangles, group):
    """Medit ``.mesh``: triangles with reference id = group (body id + 1)."""
    import meshio

    mesh = meshio.Mesh(
        np.ascontiguousarray(points, dtype=np.float64),
        [("triangle", np.ascontiguousarray(triangles, dtype=np.int64))],
        point_data={"medit:ref": np.zeros(len(points), dtype=np.int64)},
        cell_data={"medit:ref": [np.asarray(group, dtype=np.int64)]})
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    meshio.write(str(path), mesh, file_format="medit")


def read_bodies(path):
    """(points (N, 2), triangles (M, 3), body (N,)) of a file written by
    :func:`write_bodies`; body = group − 1 of the triangles of each node."""
    import meshio

    mesh = meshio.read(str(path))
    blocks = [i for i, b in enumerate(mesh.cells) if b.type == "triangle"]
    triangles = np.concatenate([mesh.cells[i].data for i in blocks])
    group = np.concatenate([mesh.cell_data["medit:ref"][i] for i in blocks])
    body = np.full(len(mesh.points), -1, dtype=np.int64)
    body[triangles.ravel()] = np.repeat(group - 1, 3)
    return (np.asarray(mesh.points[:, :2], dtype=np.float64),
            triangles.astype(np.int64), body)


def _polygon(corners, divisions, h, fine=(), h_fine=None, dist=None):
    """gmsh mesh of the polygon ``corners`` (counter-clockwise).

    divisions: {edge index: number of segments} (edge i joins corner i and
    i + 1) made transfinite, i.e. split uniformly; the others are split by
    the size field: ``h``, or with ``fine`` edges ``h_fine`` on those edges
    growing linearly to ``h`` at distance ``dist`` from them.
    Returns (points (N, 2), triangles).
    """
    gmsh = generate._import_gmsh()
    own_session = not gmsh.isInitialized()
    if own_session:
        gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("two_body")
        geo = gmsh.model.geo
        tags = [geo.addPoint(x, y, 0.0) for x, y in corners]
        lines = [geo.addLine(tags[i], tags[(i + 1) % len(tags)])
                 for i in range(len(tags))]
        geo.addPlaneSurface([geo.addCurveLoop(lines)])
        for i, n in divisions.items():
            geo.mesh.setTransfiniteCurve(lines[i], n + 1)
        geo.synchronize()
        field = gmsh.model.mesh.field
        if fine:
            distance = field.add("Distance")
            field.setNumbers(distance, "CurvesList", [lines[i] for i in fine])
            field.setNumber(distance, "Sampling", 20)
            size = field.add("Threshold")
            field.setNumber(size, "InField", distance)
            field.setNumber(size, "SizeMin", h_fine)
            field.setNumber(size, "SizeMax", h)
            field.setNumber(size, "DistMin", 0.0)
            field.setNumber(size, "DistMax", dist)
        else:
            size = field.add("MathEval")
            field.setString(size, "F", repr(float(h)))
        field.setAsBackgroundMesh(size)
        hertz._set_options(gmsh)
        gmsh.model.mesh.generate(2)
        points, triangles = generate.model_triangles(gmsh)
        gmsh.model.remove()
    finally:
        if own_session:
            gmsh.finalize()
    points = points[:, :2].copy()
    # nodes of the straight edges exactly on them (gmsh leaves round-off,
    # ~1e-16 of the coordinates' size): within 1e-12 of the polygon's size
    # or of the edge's coordinate, whichever is larger
    size = np.ptp(np.asarray(corners, dtype=float), axis=0).max()
    for (x0, y0), (x1, y1) in zip(corners, np.roll(corners, -1, axis=0)):
        for col, a, b in ((0, x0, x1), (1, y0, y1)):
            if a == b:
                near = np.abs(points[:, col] - a) <= 1e-12 * max(size, abs(a))
                points[near, col] = a
    for i, n in divisions.items():  # uniform divisions exactly uniform
        a = np.asarray(corners[i], dtype=float)
        b = np.asarray(corners[(i + 1) % len(corners)], dtype=float)
        t = b - a
        s = (points - a) @ t / (t @ t)
        off = np.abs((points - a) @ np.array([-t[1], t[0]])) \
            / np.sqrt(t @ t)
        k = np.round(s * n)
        on = (off <= 1e-9 * np.sqrt(t @ t)) & (np.abs(s * n - k) < 1e-6) \
            & (k >= 0) & (k <= n)
        points[on] = a + (k[on, None] / n) * t
    return points, ccw(points, triangles)


def patch_mesh(n_lower=5, n_upper=8, h=0.2, width=1.0, height=0.5):
    """The patch-test blocks (module doc): (points, triangles, group)."""
    for name, n in (("n_lower", n_lower), ("n_upper", n_upper)):
        if int(n) != n or n < 1:
            raise ValueError(f"{name} must be a positive integer, got {n}")
    lower = _polygon([(0, 0), (width, 0), (width, height), (0, height)],
                     {2: int(n_lower)}, h)
    upper = _polygon([(0, height), (width, height), (width, 2 * height),
                      (0, 2 * height)], {0: int(n_upper)}, h)
    return join([lower, upper])


def cylinders_mesh(r1=R1, r2=R2, h1=None, h2=None):
    """The two half-discs (module doc): (points, triangles, group); the
    sizes at the contact point ``h1``, ``h2`` default to ``H1 * r1``,
    ``H2 * r1`` (any radii > 0 give the default mesh scaled)."""
    h1 = H1 * r1 if h1 is None else h1
    h2 = H2 * r1 if h2 is None else h2
    p1, t1 = hertz.hertz_mesh(h_contact=h1, h_far=0.1 * r1, radius=r1)
    p2, t2 = hertz.hertz_mesh(h_contact=h2, h_far=0.1 * r2, radius=r2)
    upper = p1 + np.array([0.0, r1])
    upper[np.abs(upper[:, 1] - r1) <= 1e-12 * r1, 1] = r1  # the flat side
    lower = p2 * np.array([1.0, -1.0]) - np.array([0.0, r2])
    lower[np.abs(lower[:, 1] + r2) <= 1e-12 * r2, 1] = -r2
    return join([(lower, t2), (upper, t1)])


def parabola(y):
    """The thesis obstacle Γo: x = 5.05 + 0.005 y²."""
    return 5.05 + 0.005 * np.asarray(y, dtype=float) ** 2


def block_mesh(base=454, y_max=11.0, x_far=10.0, h_contact=0.25,
               h_far=1.5, refine=0):
    """The thesis block and the elastic parabola body (module doc); the
    block refined uniformly ``refine`` times (its old nodes first)."""
    block = generate.read_mesh(HERE / generate.mesh_filename(base))
    if refine:
        block = generate.refine_uniform(*block, levels=refine)
    n = int(math.ceil(2 * y_max / h_contact))
    y = np.linspace(y_max, -y_max, n + 1)  # top to bottom: body on the left
    corners = list(zip(parabola(y), y)) + [(x_far, -y_max), (x_far, y_max)]
    obstacle = _polygon(corners, dict.fromkeys(range(n), 1), h_far,
                        fine=range(n), h_fine=h_contact,
                        dist=x_far - parabola(y_max))
    return join([block, obstacle])


def _parser() -> argparse.ArgumentParser:
    parser = generate.Parser(prog="two_body.py",
                     description="Write a two-body triangle mesh (two cell "
                                 "groups, no shared node).")
    sub = parser.add_subparsers(dest="kind", required=True)
    patch = sub.add_parser("patch", help="two stacked blocks, non-matching")
    patch.add_argument("--n-lower", type=int, default=5)
    patch.add_argument("--n-upper", type=int, default=8)
    patch.add_argument("--h", type=generate.positive_float, default=0.2)
    patch.add_argument("-o", "--output", type=Path, default=PATCH)
    cyl = sub.add_parser("cylinders", help="two half-discs touching at 0")
    cyl.add_argument("--r1", type=generate.positive_float, default=R1,
                     help=f"upper radius, any positive number (default {R1:g})")
    cyl.add_argument("--r2", type=generate.positive_float, default=R2,
                     help=f"lower radius (default {R2:g})")
    cyl.add_argument("--h1", type=generate.positive_float, default=None,
                     help=f"upper size at the contact (default {H1} R1)")
    cyl.add_argument("--h2", type=generate.positive_float, default=None,
                     help=f"lower size at the contact (default {H2} R1)")
    cyl.add_argument("--identical", action="store_true",
                     help="R2 = R1 (two identical half-discs; h2 stays)")
    cyl.add_argument("-o", "--output", type=Path, default=None)
    block = sub.add_parser("block", help="thesis block + parabola body")
    block.add_argument("--base", type=int, choices=(118, 454, 1878),
                       default=454)
    block.add_argument("--h-contact", type=generate.positive_float, default=0.25)
    block.add_argument("--h-far", type=generate.positive_float, default=1.5)
    block.add_argument("--refine", type=int, default=0, metavar="K",
                       help="split the block's triangles into 4, K times")
    block.add_argument("-o", "--output", type=Path, default=None)
    return parser


def main(argv=None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)

    def work():
        if args.kind == "patch":
            mesh = patch_mesh(args.n_lower, args.n_upper, args.h)
            output = args.output
        elif args.kind == "cylinders":
            if args.identical:
                args.r2 = args.r1
            mesh = cylinders_mesh(args.r1, args.r2, args.h1, args.h2)
            output = args.output or (CYLINDERS_IDENTICAL if args.identical
                                     else CYLINDERS)
        else:
            if args.refine < 0:
                parser.error(f"--refine must be >= 0, got {args.refine}")
            mesh = block_mesh(args.base, h_contact=args.h_contact,
                              h_far=args.h_far, refine=args.refine)
            suffix = f"_r{args.refine}" if args.refine else ""
            output = args.output or \
                HERE / f"two_body_block_{args.base}{suffix}.mesh"
        if output.suffix != ".mesh":
            parser.error(f"output file must end in .mesh, got {output}")
        write_bodies(output, *mesh)
        return mesh, output

    code, done = generate.guarded(parser.prog, work)
    if code:
        return code
    mesh, output = done
    points, triangles, group = mesh
    counts = np.bincount(group)[1:]
    per_body = ", ".join(map(str, counts))
    print(f"{output}: {len(triangles)} triangles ({per_body} per body), "
          f"{len(points)} nodes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
