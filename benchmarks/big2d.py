"""The thesis's 2D block at a given DOF count, end to end (issue 33).

Usage::

    python benchmarks/big2d.py --dofs 1e6 [--workdir DIR]
                               [--linear-solvers auto,amg,pardiso]
    python benchmarks/big2d.py --dofs 1e7 --workdir DIR \\
        --linear-solvers auto   # ≈ 12 GB peak: nothing else big beside it

Each stage runs in a fresh process (``processes.run_measured``: wall and
CPU time, the child's own peak RSS from ``wait4``):

* **mesh**: ``meshes/structured.py block NX 2NX --simplices``, the block
  [-5, 5] x [-10, 10] as 2·NX·2NX right triangles, NX chosen so that the
  reduced DOFs 2 (NX + 1)(2 NX + 1) − 2 (NX + 1) reach ``--dofs`` (gmsh
  took 23 min for 1.5·10⁶ nodes; this grid is written in minutes); a
  mesh already in the work folder with its ``.mesh.json`` is reused;
* **export**: ``python sfepy_problems/block_obstacle.py -d "mesh=...,
  output=..., solve=False"``: SfePy assembles K, f, M and writes the
  ``.npz`` without solving the unconstrained problem;
* **solve**, once per ``--linear-solvers`` entry: ``python -m solver
  PROBLEM -o DIR --linear-solver X`` as a whole (loading, the solve,
  verification, result folder); the path taken and why
  (``linear_solver``, ``linear_solver_reason``), Newton (J) and Krylov
  counts and the verification on every contact node from its
  ``summary.json``; with two or more paths the largest relative
  difference of u to the first one's (max-norm, relative to max |u|).

A path that would not fit the memory is not forced here: ``auto`` decides
(``solver.linalg.amg.direct_fits``), and an explicit direct backend above
the memory is left to the caller (the machine has no swap).

Prints one Markdown table and writes ``big2d.json`` in the work folder.
"""

import argparse
import json
import math
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from processes import StageError, run_measured  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent

COLUMNS = ["DOFs", "stage", "path", "wall [s]", "CPU [s]", "peak RSS [MB]",
           "J/F", "Krylov (per system)", "in contact", "verified",
           "|Δu|/|u| vs first"]


def grid_size(dofs):
    """NX of the NX x 2NX grid whose reduced DOFs 2 (NX + 1) 2 NX first
    reach ``dofs`` (the bottom row of NX + 1 nodes clamped)."""
    nx = max(1, int(math.sqrt(dofs / 4.0)) - 1)
    while 4 * (nx + 1) * nx < dofs:
        nx += 1
    return nx


def mesh_and_export(dofs, folder):
    """The mesh and the no-solve export of the block: (npz, rows). A mesh
    already in ``folder`` is reused, with the times recorded when it was
    made (``<mesh>.json``); the export always runs."""
    nx = grid_size(dofs)
    mesh, npz = folder / f"block_{nx}.mesh", folder / f"block_{nx}.npz"
    record = mesh.with_suffix(".mesh.json")
    if not (mesh.exists() and record.exists()):
        run = run_measured([sys.executable,
                            ROOT / "meshes" / "structured.py", "block", nx,
                            2 * nx, "--simplices", "-o", mesh])
        record.write_text(json.dumps(_times(run)))
    rows = [dict(stage="mesh", path=f"structured {nx} x {2 * nx}",
                 **json.loads(record.read_text()))]
    run = run_measured([sys.executable,
                        ROOT / "sfepy_problems" / "block_obstacle.py", "-d",
                        f"mesh='{mesh}', output='{npz}', solve=False"],
                       cwd=folder)
    rows.append(dict(stage="export", path="SfePy, no solve", **_times(run)))
    return npz, rows


def _times(run):
    return {"wall [s]": run["wall"], "CPU [s]": run["cpu"],
            "peak RSS [MB]": run["rss"]}


def solve(npz, linear_solver, folder):
    """``python -m solver`` on one path: (row, u)."""
    out = folder / f"out_{linear_solver}"
    run = run_measured([sys.executable, "-m", "solver", npz, "-o", out,
                        "--linear-solver", linear_solver], cwd=folder)
    summary = json.loads((out / "summary.json").read_text())
    with np.load(out / "result.npz") as result:
        u = result["u"]
    krylov = summary.get("krylov_iterations")
    per = summary.get("krylov_per_system")
    verification = summary["verification"]
    row = dict(stage="solve", DOFs=summary["n_dof"],
               path=f"{linear_solver} -> {summary['linear_solver']}",
               reason=summary.get("linear_solver_reason"), **_times(run),
               **{"J/F": f"{summary['n_jacobian']}/{summary['n_residual']}",
                  "Krylov (per system)": "–" if krylov is None else
                  f"{krylov} ({_mean(per)})",
                  "in contact": summary["n_contact_nodes"],
                  "verified": "yes" if verification["passed"] and
                  summary["converged"] else "NO",
                  "complementarity": verification["complementarity"],
                  "max_penetration": verification["max_penetration"],
                  "solve wall [s]": summary["wall_time"]})
    return row, u


def _mean(per):
    if not per:
        return "–"
    return f"{np.mean(per):.1f}"


def table(rows):
    lines = ["| " + " | ".join(COLUMNS) + " |",
             "|" + "---|" * len(COLUMNS)]
    for row in rows:
        cells = []
        for key in COLUMNS:
            value = row.get(key, "")
            if isinstance(value, float):
                value = (f"{value:.2e}" if key.startswith("|Δu|")
                         else f"{value:.1f}" if key != "peak RSS [MB]"
                         else f"{value:.0f}")
            cells.append(str(value))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def parse(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dofs", type=float, default=1e6,
                        help="reduced DOFs to reach (default 1e6)")
    parser.add_argument("--workdir", default=None,
                        help="folder for the mesh, .npz and outputs "
                             "(default: a temporary one, removed)")
    parser.add_argument("--linear-solvers", default="auto,amg",
                        help="comma-separated --linear-solver values of "
                             "python -m solver (default auto,amg)")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse(argv)
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(args.workdir or scratch).resolve()
        folder.mkdir(parents=True, exist_ok=True)
        try:
            npz, rows = mesh_and_export(int(args.dofs), folder)
            first = None
            for name in args.linear_solvers.split(","):
                row, u = solve(npz, name, folder)
                if first is None:
                    first = u
                else:
                    row["|Δu|/|u| vs first"] = float(
                        np.max(np.abs(u - first)) / np.max(np.abs(first)))
                rows.append(row)
                print(f"{row['path']}: {row['reason'] or '–'}", flush=True)
        except StageError as error:
            print(f"big2d.py: error: {error}", file=sys.stderr)
            return 1
        for row in rows:
            row.setdefault("DOFs", rows[-1]["DOFs"])
        load = os.getloadavg()
        print(table(rows))
        print(f"load average {load[0]:.1f} {load[1]:.1f} {load[2]:.1f}")
        (folder / "big2d.json").write_text(json.dumps(
            dict(rows=rows, load=load), indent=1, default=str))
    return 0


if __name__ == "__main__":
    sys.exit(main())
