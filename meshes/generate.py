"""Triangle meshes of the 10 x 20 elastic block, made with gmsh.

The thesis meshes the block ``x in [-5, 5], y in [-10, 10]`` (centred at the
origin) with three linear triangle meshes of 118, 454 and 1878 elements. They
were made there with a commercial pre-processor (VPS), which we do not have.
This script makes meshes with the *same triangle counts* using gmsh; they are
not the same meshes (node positions and connectivity differ).

Settings found by measurement with gmsh 4.15.2 (any other options are the
ones set in ``_set_options``):

=========  ===============  =============================================
triangles  Mesh.Algorithm   sizing
=========  ===============  =============================================
118        5 (Delaunay)     transfinite boundary curves only: 4 segments
                            (5 nodes) on the horizontal edges, 10 segments
                            (11 nodes) on the vertical edges; the surface
                            is not transfinite
454        1 (MeshAdapt)    Mesh.MeshSizeMin = Mesh.MeshSizeMax = 1.08
1878       1 (MeshAdapt)    Mesh.MeshSizeMin = Mesh.MeshSizeMax = 0.52
=========  ===============  =============================================

Sizes 1.06, 1.07, ..., 1.10 all give 454 triangles (1.05: 466, 1.11: 422);
0.515, 0.52, 0.525 give 1878 (0.51: 1908, 0.53: 1680). Another gmsh version may give
other counts; ``thesis_mesh`` checks the count and fails loudly if it differs.

After meshing, the mesh is cleaned (``clean_mesh``): z is dropped, coordinates
closer than 1e-9 to an edge of the block (``SNAP_TOL`` = 1e-10 times its
half-height 10) are put exactly on it, nodes not in any
triangle are removed and the rest are renumbered in gmsh's order, and every
triangle is made counter-clockwise. Files are written in Medit ``.mesh``
format (2D coordinates, triangles only, all reference ids 0) with meshio, and
read with ``sfepy.discrete.fem.Mesh.from_file``. Regions are to be selected by
coordinates, not by ids.

Usage::

    python meshes/generate.py                        # the three thesis meshes
    python meshes/generate.py --size 0.3 -o output/f.mesh   # finer, MeshAdapt
    python meshes/generate.py --size 0.3 --algorithm 6 -o output/f.mesh
    python meshes/generate.py --refine 2 --base 1878 -o output/f.mesh
        # each triangle of the committed 1878 mesh split into 4**2 (no gmsh needed)

gmsh is needed only to generate meshes (``pip install gmsh``); it is imported
when needed. Reading and writing meshes need only numpy and meshio.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

#: The block: x in [-HALF_WIDTH, HALF_WIDTH], y in [-HALF_HEIGHT, HALF_HEIGHT].
HALF_WIDTH = 5.0
HALF_HEIGHT = 10.0

#: Nodes closer to an edge of the block than this times its largest
#: half-size are put exactly on it (relative: round-off scales with size).
SNAP_TOL = 1e-10

#: gmsh 2D algorithms allowed on the command line (all give triangles).
ALGORITHMS = {1: "MeshAdapt", 2: "Automatic", 5: "Delaunay", 6: "Frontal-Delaunay"}

#: Thesis triangle count -> gmsh settings (keyword arguments of ``gmsh_mesh``).
THESIS_SETTINGS = {
    118: {"algorithm": 5, "size": None, "segments": (4, 10)},
    454: {"algorithm": 1, "size": 1.08, "segments": None},
    1878: {"algorithm": 1, "size": 0.52, "segments": None},
}

#: The thesis triangle counts, coarsest first.
THESIS_COUNTS = tuple(sorted(THESIS_SETTINGS))


class GmshMissingError(ImportError):
    """gmsh cannot be imported."""


def mesh_filename(n_triangles: int) -> str:
    """File name of a thesis mesh, e.g. ``block_118.mesh``."""
    return f"block_{n_triangles}.mesh"


def _import_gmsh():
    try:
        import gmsh
    except (ImportError, OSError) as exc:  # OSError: missing shared libraries
        raise GmshMissingError(
            f"gmsh is needed to generate meshes ({exc}); install it with `pip install gmsh`"
        ) from exc
    return gmsh


def _set_options(gmsh, algorithm: int, size: float | None) -> None:
    """Set every option the mesh depends on, so results do not hang on defaults."""
    number = gmsh.option.setNumber
    number("General.Terminal", 0)
    number("General.NumThreads", 1)
    number("Mesh.MaxNumThreads2D", 1)
    number("Mesh.RandomSeed", 1)
    number("Mesh.Algorithm", algorithm)
    number("Mesh.ElementOrder", 1)
    number("Mesh.RecombineAll", 0)
    number("Mesh.Smoothing", 1)
    number("Mesh.MeshSizeFromPoints", 1)
    number("Mesh.MeshSizeFromCurvature", 0)
    number("Mesh.MeshSizeExtendFromBoundary", 1)
    number("Mesh.MeshSizeFactor", 1.0)
    if size is None:
        number("Mesh.MeshSizeMin", 0.0)
        number("Mesh.MeshSizeMax", 1e22)
    else:
        number("Mesh.MeshSizeMin", size)
        number("Mesh.MeshSizeMax", size)


def model_triangles(gmsh):
    """(points (n, 3), triangles (m, 3)) of the current gmsh model's 2D mesh,
    nodes in tag order, triangles as 0-based indices."""
    node_tags, coords, _ = gmsh.model.mesh.getNodes()
    elem_types, _, elem_nodes = gmsh.model.mesh.getElements(dim=2)
    if list(elem_types) != [2]:  # 2 = 3-node triangle
        raise RuntimeError(f"gmsh made 2D elements of types {list(elem_types)}, "
                           "expected only linear triangles (type 2)")
    node_tags = np.asarray(node_tags, dtype=np.int64)
    order = np.argsort(node_tags, kind="stable")
    points = np.asarray(coords, dtype=np.float64).reshape(-1, 3)[order]
    tags = node_tags[order]
    tri_tags = np.asarray(elem_nodes[0], dtype=np.int64).reshape(-1, 3)
    triangles = np.searchsorted(tags, tri_tags)
    if not np.array_equal(tags[triangles], tri_tags):
        raise RuntimeError("gmsh triangles refer to unknown nodes")
    return points, triangles


def gmsh_mesh(
    size: float | None = None,
    algorithm: int = 1,
    segments: tuple[int, int] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Mesh the block with gmsh and return the cleaned mesh.

    size: target element size (sets ``Mesh.MeshSizeMin`` and ``MeshSizeMax``).
    algorithm: ``Mesh.Algorithm``.
    segments: ``(nx, ny)`` makes the horizontal edges transfinite with ``nx``
        segments and the vertical edges with ``ny`` segments (the surface itself
        is not transfinite); then ``size`` may be None.

    Returns ``(points, triangles)`` as ``clean_mesh`` does.
    """
    if size is None and segments is None:
        raise ValueError("give a size, boundary segments, or both")
    if size is not None and not (math.isfinite(size) and size > 0):
        raise ValueError(f"size must be a positive number, got {size}")
    gmsh = _import_gmsh()

    own_session = not gmsh.isInitialized()
    if own_session:
        gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("block")
        geo = gmsh.model.geo
        # Point sizes only matter when ``size`` is None and are then overridden
        # by the transfinite curves; 1.0 keeps them harmless either way.
        corners = [(-HALF_WIDTH, -HALF_HEIGHT), (HALF_WIDTH, -HALF_HEIGHT),
                   (HALF_WIDTH, HALF_HEIGHT), (-HALF_WIDTH, HALF_HEIGHT)]
        pts = [geo.addPoint(x, y, 0.0, 1.0) for x, y in corners]
        # bottom, right, top, left: counter-clockwise, so the normal is +z
        lines = [geo.addLine(pts[i], pts[(i + 1) % 4]) for i in range(4)]
        geo.addPlaneSurface([geo.addCurveLoop(lines)])
        if segments is not None:
            nx, ny = segments
            for line, n in zip(lines, (nx, ny, nx, ny)):
                geo.mesh.setTransfiniteCurve(line, n + 1)
        geo.synchronize()
        _set_options(gmsh, algorithm, size)
        gmsh.model.mesh.generate(2)
        points, triangles = model_triangles(gmsh)
        gmsh.model.remove()
    finally:
        if own_session:
            gmsh.finalize()
    return clean_mesh(points, triangles)


def clean_mesh(points: np.ndarray, triangles: np.ndarray,
               box: tuple[float, float] | None = (HALF_WIDTH, HALF_HEIGHT),
               ) -> tuple[np.ndarray, np.ndarray]:
    """Return ``(points (N, 2) float64, triangles (M, 3) int64)`` ready to write.

    Drops any z column, puts coordinates within ``SNAP_TOL * max(box)`` of
    the edges x = ±box[0], y = ±box[1] exactly on them (``box`` None: no
    snapping, for other shapes), removes nodes used by no triangle (keeping
    the order of the others), and makes every triangle counter-clockwise.
    """
    points = np.array(points, dtype=np.float64)[:, :2]
    triangles = np.array(triangles, dtype=np.int64).reshape(-1, 3)

    if box is not None:
        tol = SNAP_TOL * max(box)
        for col, half in ((0, box[0]), (1, box[1])):
            for edge in (-half, half):
                near = np.abs(points[:, col] - edge) <= tol
                points[near, col] = edge
    points += 0.0  # turn -0.0 into 0.0 so files never show "-0.0"

    used = np.unique(triangles)
    new_index = np.full(len(points), -1, dtype=np.int64)
    new_index[used] = np.arange(len(used), dtype=np.int64)
    points = points[used]
    triangles = new_index[triangles]

    clockwise = signed_areas(points, triangles) < 0
    triangles[clockwise] = triangles[clockwise][:, ::-1]
    return points, triangles


def signed_areas(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Signed area of each triangle (positive if counter-clockwise)."""
    a, b, c = (points[triangles[:, i]] for i in range(3))
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                  - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def thesis_mesh(n_triangles: int) -> tuple[np.ndarray, np.ndarray]:
    """Generate the mesh with the thesis's triangle count (118, 454 or 1878)."""
    try:
        settings = THESIS_SETTINGS[n_triangles]
    except KeyError:
        raise ValueError(f"the thesis has meshes of {', '.join(map(str, THESIS_COUNTS))} "
                         f"triangles, not {n_triangles}") from None
    points, triangles = gmsh_mesh(**settings)
    if len(triangles) != n_triangles:
        gmsh = _import_gmsh()
        raise RuntimeError(f"settings {settings} gave {len(triangles)} triangles instead of "
                           f"{n_triangles} with gmsh {gmsh.__version__} (measured with 4.15.2)")
    return points, triangles


def base_mesh(n_triangles: int) -> tuple[np.ndarray, np.ndarray]:
    """The committed thesis mesh next to this script, or a generated one if absent."""
    path = Path(__file__).resolve().parent / mesh_filename(n_triangles)
    if path.is_file():
        return read_mesh(path)
    return thesis_mesh(n_triangles)


def refine_uniform(points: np.ndarray, triangles: np.ndarray,
                   levels: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Split every triangle into 4 at its edge midpoints, ``levels`` times.

    Old nodes keep their numbers; new nodes follow. Orientation is kept and
    midpoints of boundary edges lie exactly on the boundary.
    """
    points = np.asarray(points, dtype=np.float64)
    triangles = np.asarray(triangles, dtype=np.int64)
    for _ in range(levels):
        # edges ab, bc, ca of every triangle
        edges = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]],
                                triangles[:, [2, 0]]])
        unique_edges, inverse = np.unique(np.sort(edges, axis=1), axis=0,
                                          return_inverse=True)
        inverse = inverse.reshape(3, -1) + len(points)
        mid = 0.5 * (points[unique_edges[:, 0]] + points[unique_edges[:, 1]])
        points = np.concatenate([points, mid])
        a, b, c = triangles.T
        ab, bc, ca = inverse
        triangles = np.stack([
            np.stack([a, ab, ca], axis=1),
            np.stack([ab, b, bc], axis=1),
            np.stack([ca, bc, c], axis=1),
            np.stack([ab, bc, ca], axis=1),
        ], axis=1).reshape(-1, 3)
    return points, triangles


def write_mesh(path, points: np.ndarray, triangles: np.ndarray) -> None:
    """Write a 2D triangle mesh to a Medit ``.mesh`` file; all reference ids 0.
    Missing folders of ``path`` are made (``-o output/fine.mesh`` in a fresh
    checkout, where git ignores ``output/``)."""
    import meshio

    points = np.ascontiguousarray(points, dtype=np.float64)
    triangles = np.ascontiguousarray(triangles, dtype=np.int64)
    if points.ndim != 2 or points.shape[1] != 2:
        raise ValueError(f"points must have shape (N, 2), got {points.shape}")
    if triangles.ndim != 2 or triangles.shape[1] != 3:
        raise ValueError(f"triangles must have shape (M, 3), got {triangles.shape}")
    mesh = meshio.Mesh(
        points,
        [("triangle", triangles)],
        point_data={"medit:ref": np.zeros(len(points), dtype=np.int64)},
        cell_data={"medit:ref": [np.zeros(len(triangles), dtype=np.int64)]},
    )
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    meshio.write(str(path), mesh, file_format="medit")


def read_mesh(path) -> tuple[np.ndarray, np.ndarray]:
    """Read ``(points (N, 2), triangles (M, 3))`` from a file written by ``write_mesh``."""
    import meshio

    mesh = meshio.read(str(path))
    triangles = np.concatenate([block.data for block in mesh.cells if block.type == "triangle"])
    return np.asarray(mesh.points[:, :2], dtype=np.float64), triangles.astype(np.int64)


def generate(spec, path) -> tuple[np.ndarray, np.ndarray]:
    """Generate a mesh and write it to ``path``; return ``(points, triangles)``.

    spec: a thesis triangle count (int: 118, 454 or 1878) or an element size
    (float, meshed with MeshAdapt).
    """
    if isinstance(spec, (int, np.integer)) and not isinstance(spec, bool):
        points, triangles = thesis_mesh(int(spec))
    else:
        points, triangles = gmsh_mesh(size=float(spec), algorithm=1)
    write_mesh(path, points, triangles)
    return points, triangles


class Parser(argparse.ArgumentParser):
    """The mesh scripts' parser: one error line instead of usage + message
    (exit 2)."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


def guarded(prog, work):
    """(exit code, work()) of a mesh script: 0 and its value, or one error
    line on stderr and 2 (gmsh missing) or 1 (meshing or writing failed)."""
    try:
        return 0, work()
    except GmshMissingError as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        return 2, None
    except (ValueError, RuntimeError, OSError) as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        return 1, None


def positive_float(text: str) -> float:
    """argparse type of the mesh scripts: a finite number > 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a positive number, got {text}")
    return value


def _nonnegative_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be 0 or more, got {text}")
    return value


def _parser() -> argparse.ArgumentParser:
    parser = Parser(
        prog="generate.py",
        description="Write the thesis's triangle meshes of the 10 x 20 block "
                    "(118, 454, 1878 triangles) or a finer mesh.",
    )
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--size", type=positive_float, metavar="H",
                      help="element size of a new gmsh mesh (needs -o)")
    mode.add_argument("--refine", type=_nonnegative_int, metavar="K",
                      help="split each triangle of a thesis mesh into 4**K (needs -o)")
    parser.add_argument("--algorithm", type=int, choices=sorted(ALGORITHMS), metavar="N",
                        help="gmsh Mesh.Algorithm for --size: "
                             + ", ".join(f"{k} {v}" for k, v in ALGORITHMS.items())
                             + " (default 1)")
    parser.add_argument("--base", type=int, choices=THESIS_COUNTS, metavar="N",
                        help="thesis mesh refined by --refine: 118, 454 or 1878 (default 1878)")
    parser.add_argument("-o", "--output", type=Path, metavar="FILE",
                        help="output .mesh file (with --size or --refine)")
    parser.add_argument("--outdir", type=Path, metavar="DIR",
                        help="directory for the thesis meshes (default: this script's)")
    return parser


def main(argv=None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    prog = parser.prog
    custom = args.size is not None or args.refine is not None

    if args.algorithm is not None and args.size is None:
        parser.error("--algorithm needs --size")
    if args.base is not None and args.refine is None:
        parser.error("--base needs --refine")
    if custom and args.output is None:
        parser.error("--size and --refine need -o FILE")
    if not custom and args.output is not None:
        parser.error("-o needs --size or --refine (use --outdir for the thesis meshes)")
    if custom and args.outdir is not None:
        parser.error("--outdir is for the thesis meshes; use -o FILE with --size or --refine")
    if args.output is not None and args.output.suffix != ".mesh":
        parser.error(f"output file must end in .mesh, got {args.output}")

    if custom:
        if args.size is not None:
            jobs = [(args.output, lambda: gmsh_mesh(size=args.size, algorithm=args.algorithm or 1))]
        else:
            base = args.base or THESIS_COUNTS[-1]
            jobs = [(args.output,
                     lambda: refine_uniform(*base_mesh(base), levels=args.refine))]
    else:
        outdir = args.outdir if args.outdir is not None else Path(__file__).resolve().parent
        if not outdir.is_dir():
            parser.error(f"not a directory: {outdir}")
        jobs = [(outdir / mesh_filename(n), lambda n=n: thesis_mesh(n)) for n in THESIS_COUNTS]

    for path, make in jobs:
        try:
            points, triangles = make()
            write_mesh(path, points, triangles)
        except GmshMissingError as exc:
            print(f"{prog}: error: {exc}", file=sys.stderr)
            return 2
        except (RuntimeError, OSError) as exc:
            print(f"{prog}: error: {exc}", file=sys.stderr)
            return 1
        print(f"{path}: {len(triangles)} triangles, {len(points)} nodes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
