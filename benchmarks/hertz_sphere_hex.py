"""The Hertz quarter sphere on tetrahedra and on the same meshes cut into
hexahedra (issue 35): a table of the errors against Hertz under
refinement.

Each tetrahedral mesh of ``meshes/hertz_sphere.py`` (nominal a/h 4, 6, 8;
4 and 8 are committed, 6 is made with gmsh) is exported and solved as it
is, then cut into four hexahedra per tetrahedron (``meshes/structured.py
hexes``: half the element size, the same grading, the new nodes of the
sphere put on it) and exported and solved again. The columns are those of
``solver.studies3d.hertz_sphere_row`` (a/h measured on the contact faces,
errors in per cent of Hertz's a and p0 for the computed force), plus the
solve time.

Usage::

    python benchmarks/hertz_sphere_hex.py [--workdir DIR] [--levels 4,6,8]
"""

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from solver import load_problem, solve  # noqa: E402
from solver.studies3d import hertz_sphere_row  # noqa: E402

COLUMNS = ("a/h", "DOFs", "in contact", "a moment err %", "a fit err %",
           "p0 fit err %", "max p err %", "RMS/p0 %")


def run(*argv):
    subprocess.run([sys.executable, *map(str, argv)], check=True,
                   capture_output=True, cwd=ROOT)


def export_and_solve(problem_file, mesh, workdir, **options):
    """Export ``mesh`` with ``sfepy_problems/problem_file`` into
    ``workdir`` and solve it with ``options``: (problem, result, solve
    seconds); the solve must succeed."""
    out = workdir / (Path(mesh).stem + ".npz")
    run(ROOT / "sfepy_problems" / problem_file, "-d",
        f"mesh='{mesh}', output='{out}'")
    problem = load_problem(out)
    start = time.perf_counter()
    result = solve(problem, **options)
    seconds = time.perf_counter() - start
    assert result.success, result.message
    return problem, result, seconds


def measure(mesh, workdir):
    problem, result, seconds = export_and_solve("hertz_sphere.py", mesh,
                                                workdir, method="min")
    row = hertz_sphere_row(problem, result)
    return [f"{row['a/h']:.1f}", f"{row['DOFs']}", f"{row['in contact']}",
            *(f"{row[c]:+.2f}" for c in COLUMNS[3:-1]),
            f"{row['RMS/p0 %']:.2f}", f"{seconds:.1f}"]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workdir", type=Path, default=None)
    parser.add_argument("--levels", default="4,6,8")
    args = parser.parse_args(argv)
    workdir = args.workdir or Path(tempfile.mkdtemp(prefix="hertz_hex_"))
    workdir.mkdir(parents=True, exist_ok=True)
    print("| cells | tet a/h | " + " | ".join(COLUMNS) + " | solve s |")
    print("|---|---:|" + "---:|" * (len(COLUMNS) + 1))
    for level in args.levels.split(","):
        tets = ROOT / "meshes" / f"hertz_sphere_{level}.mesh"
        if not tets.exists():
            tets = workdir / tets.name
            run(ROOT / "meshes" / "hertz_sphere.py", "--a-over-h", level,
                "-o", tets)
        hexes = workdir / f"hertz_sphere_hex_{level}.mesh"
        run(ROOT / "meshes" / "structured.py", "hexes", tets,
            "--sphere-radius", "1", "-o", hexes)
        for name, mesh in (("tetrahedra", tets), ("hexahedra", hexes)):
            print(f"| {name} | {level} | " + " | ".join(
                measure(mesh, workdir)) + " |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
