"""A body held only by contact on the petsc engine (issue 31) against the
serial engine, in the same run: the Hertz half-cylinder
(``sfepy_problems/hertz_cylinder.py``) on refinements of its mesh,
exported with ``load='displacement'`` (the top edge pressed down by d, K
positive definite) and ``load='force'`` (P = that run's total contact
force: two rigid-body modes held by the contact only), each solved by
``solver.solve`` with each engine's defaults. Prints one Markdown row per
mesh and load: DOFs, the Newton counts (J) and the wall and CPU times
(best of ``--repeat`` after a warm-up; CPU: the process CPU time of every
rank, the serial engine's idle workers included) of both engines, their
ratios, and the largest difference of u relative to max|u|.

    mpiexec -n 2 python benchmarks/floating_mpi.py [--h-contact H ...] [--repeat N]
"""

import argparse
import pathlib
import runpy
import sys
import tempfile
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import solver  # noqa: E402
from solver.mpi.engine import service, spmd  # noqa: E402


def cpu_all_ranks():
    """The process CPU time of every rank so far, summed [s]."""
    return sum(stats["cpu_s"] for stats in service().call("stats"))


def timed(path, engine, repeat):
    """(wall, CPU, result) of the best of ``repeat`` solves after one
    warm-up, the problem read anew each time."""
    best, result = (np.inf, np.inf), None
    for _ in range(repeat + 1):
        problem = solver.load_problem(path)
        cpu, clock = cpu_all_ranks(), time.perf_counter()
        result = solver.solve(problem, engine=engine)
        wall = time.perf_counter() - clock
        best = min(best, (wall, cpu_all_ranks() - cpu))
    assert result.success, result.message
    return best[0], best[1], result


def run(args):
    hertz = runpy.run_path(str(ROOT / "meshes" / "hertz.py"))
    export_only = runpy.run_path(str(ROOT / "sfepy_problems" /
                                     "_export.py"))["export_only"]
    problem_file = ROOT / "sfepy_problems" / "hertz_cylinder.py"
    print(f"ranks: {service().size}")
    print("| DOFs | load | J serial | J petsc | serial [s] | petsc [s] "
          "| petsc / serial | serial CPU [s] | petsc CPU [s] "
          "| CPU petsc / serial | max Δu / max u |")
    print("|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as folder:
        folder = pathlib.Path(folder)
        for h in args.h_contact:
            mesh = folder / f"hertz_{h}.mesh"
            hertz["write_mesh"](mesh, *hertz["hertz_mesh"](h, args.h_far))
            paths = dict(displacement=folder / f"d_{h}.npz",
                         force=folder / f"f_{h}.npz")
            P = None
            for load, path in paths.items():
                extra = {} if P is None else dict(load="force", P=P)
                export_only(problem_file, mesh=str(mesh), output=str(path),
                            **extra)
                ws, cs, rs = timed(path, "serial", args.repeat)
                wp, cp, rp = timed(path, "petsc", args.repeat)
                if P is None:
                    P = float(rs.total_contact_force[1])
                du = np.abs(rp.u - rs.u).max() / np.abs(rs.u).max()
                print(f"| {len(rs.u):,} | {load} | {rs.njev} | {rp.njev} "
                      f"| {ws:.3f} | {wp:.3f} | {wp / ws:.2f} | {cs:.3f} "
                      f"| {cp:.3f} | {cp / cs:.2f} | {du:.1e} |",
                      flush=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--h-contact", type=float, nargs="+",
                        default=[0.002, 0.001])
    parser.add_argument("--h-far", type=float, default=0.02)
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args(argv)
    spmd(run, args)


if __name__ == "__main__":
    sys.exit(main())
