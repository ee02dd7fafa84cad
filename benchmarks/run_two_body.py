"""Two-body benchmark (issue 19): the block on the elastic parabola body at
~10⁵ DOFs, against the fastest floor.

Usage::

    python benchmarks/run_two_body.py [--refine K] [--h-contact H]
                                      [--workdir DIR]
                                      [--backends a,b] [--repeat N]
                                      [--threads N] [--log FILE]

The problem: ``sfepy_problems/block_elastic_obstacle.py`` on the mesh
``meshes/two_body.py block --base 1878 --refine K --h-contact H`` (default
K = 3, H = 0.0625: the thesis block's 1878 mesh refined three times, the
1.2·10⁵-DOF size of ``run.py``, on a parabola body meshed at H along the
interface; E of the obstacle 10⁴ × the block's, the problem's default),
exported by ``sfepy-run`` (an existing ``two_body.npz`` with its
``two_body.export.json`` in ``--workdir`` is reused). Every measurement
runs in a fresh process (this script with ``--measure``), which reports
wall and CPU time (all threads) and its peak RSS (``ru_maxrss``; every
process holds the loaded problem):

* **floor** ``<backend>``: factorise the block-diagonal K of both bodies
  and solve K u = f once (``measure.py``'s floor: SuperLU and CHOLMOD with
  our nested dissection, the ordering timed; PARDISO with its METIS);
  **fastest**: the shortest floor in this run, every ratio's denominator;
* **min**, **fb** ``<backend>``: ``solve(problem, method=...,
  backend=...)``, every other argument at its default (mortar coupling,
  change of variables, condensed Newton with the nested start,
  verification, mapping back), "time (time / fastest floor)";
* Newton counts J/F (all levels; the finest level's J in brackets) and
  the slave nodes in contact, fastest backend; the slave and master node
  counts of the interface;
* the same ratios by CPU time (what a loaded machine disturbs least).

``--repeat N`` keeps each stage's shortest time (rounds over the backends)
and its largest RSS.
"""

import argparse
import json
import resource
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(1, str(Path(__file__).resolve().parent.parent))

import processes  # noqa: E402
from processes import StageError, export, run_process  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
METHODS = ("min", "fb")


def measure_stage(path, stage, backend):
    """One stage in this process (``--measure``): a dict for the JSON."""
    from measure import Clock, floor
    from solver import load_problem, solve
    from solver.linalg import get_backend

    problem = load_problem(path)
    out = {"dofs": problem.n_dofs, "slave": int(problem.n_contact),
           "master": int(len(set(problem.mortar_master.ravel().tolist())))}
    if stage == "floor":
        out.update(floor(problem, backend))
    else:
        get_backend(backend)
        with Clock() as clock:
            r = solve(problem, method=stage, backend=backend)
        levels = r.get("levels") or []
        out.update(clock.times, J=r.njev, F=r.nfev, converged=bool(r.success),
                   contact=int(r.n_contact), levels=len(levels),
                   J_finest=levels[-1]["njev"] if levels else r.njev)
    out["peak_rss_mb"] = \
        resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return out


def measure(npz, stage, backend):
    """``measure_stage`` in a fresh process."""
    stdout, _, _ = run_process([sys.executable, Path(__file__).resolve(),
                                "--measure", npz, stage, backend])
    line = json.loads(stdout.strip().splitlines()[-1])
    if processes.LOG:
        with open(processes.LOG[0], "a") as log:
            log.write(json.dumps({"problem": Path(npz).name, "stage": stage,
                                  "backend": backend, **line}) + "\n")
    return line


def row(npz, backends, repeat):
    """(wall-time cells, CPU-time cells) of the table (dicts)."""
    runs = {}
    for _ in range(repeat):
        for b in backends:
            for stage in ("floor",) + METHODS:
                runs.setdefault((stage, b), []).append(measure(npz, stage,
                                                               b))
    best = {}
    for key, values in runs.items():
        best[key] = dict(min(values, key=lambda r: r["time"]))
        best[key]["cpu"] = min(r["cpu"] for r in values)
        best[key]["peak_rss_mb"] = max(r["peak_rss_mb"] for r in values)
    fastest = min(backends, key=lambda b: best["floor", b]["time"])
    floor = best["floor", fastest]
    wall = {"DOFs": floor["dofs"], "slave": floor["slave"],
            "master": floor["master"], "fastest": fastest,
            "RSS floor [MB]": f"{floor['peak_rss_mb']:.0f}"}
    cpu = dict(wall)
    for b in backends:
        wall[f"floor {b} [s]"] = f"{best['floor', b]['time']:.3g}"
        cpu[f"floor {b} [s]"] = f"{best['floor', b]['cpu']:.3g}"
    for m in METHODS:
        for b in backends:
            r = best[m, b]
            flag = "" if r["converged"] else " not converged"
            for cells, key in ((wall, "time"), (cpu, "cpu")):
                cells[f"{m} {b} [s] (/floor)"] = \
                    f"{r[key]:.3g} ({r[key] / floor[key]:.2f}){flag}"
        ours = best[m, fastest]
        wall[f"{m} J/F (finest)"] = cpu[f"{m} J/F (finest)"] = \
            f"{ours['J']}/{ours['F']} ({ours['J_finest']})"
        wall[f"RSS {m} [MB]"] = cpu[f"RSS {m} [MB]"] = \
            f"{ours['peak_rss_mb']:.0f}"
        wall["in contact"] = cpu["in contact"] = ours["contact"]
    return wall, cpu


def columns(backends):
    return (["DOFs", "slave", "master", "export [s]"]
            + [f"floor {b} [s]" for b in backends] + ["fastest"]
            + [f"{m} {b} [s] (/floor)" for m in METHODS for b in backends]
            + ["min J/F (finest)", "fb J/F (finest)", "in contact",
               "RSS floor [MB]", "RSS min [MB]", "RSS fb [MB]"])


def table(names, cells):
    return "\n".join(["| " + " | ".join(names) + " |",
                      "|" + "---|" * len(names),
                      "| " + " | ".join(str(cells.get(c, "–"))
                                        for c in names) + " |"])


def parse(argv):
    from run import installed

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--refine", type=int, default=3)
    parser.add_argument("--h-contact", type=float, default=0.0625)
    parser.add_argument("--backends", help="comma-separated (default: all "
                        "installed)")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--workdir", help="keep and reuse the export here")
    parser.add_argument("--threads", type=int, help="BLAS/MKL/OpenMP "
                        "threads of every measured process")
    parser.add_argument("--log", help="append every measurement's JSON")
    args = parser.parse_args(argv)
    args.backends, _ = installed(args.backends, True)
    if not args.backends:
        parser.error("no backend to measure")
    if args.threads:
        processes.THREADS.update({name: str(args.threads) for name in (
            "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")})
    if args.log:
        processes.LOG[:] = [args.log]
    return args


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["--measure"]:
        print(json.dumps(measure_stage(*argv[1:4])))
        return 0
    args = parse(argv)
    name = f"two_body_r{args.refine}_h{args.h_contact:g}"
    mesh = ["block", "--base", "1878", "--refine", str(args.refine),
            "--h-contact", f"{args.h_contact:g}"]
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(args.workdir or scratch)
        folder.mkdir(parents=True, exist_ok=True)
        try:
            npz, seconds, _ = export(
                mesh, name, folder, generator="two_body.py",
                problem="block_elastic_obstacle.py")
            wall, cpu = row(npz, args.backends, args.repeat)
        except StageError as exc:
            print(f"run_two_body.py: {exc}", file=sys.stderr)
            return 1
    wall["export [s]"] = cpu["export [s]"] = f"{seconds:.1f}"
    names = columns(args.backends)
    print("Wall time:\n" + table(names, wall))
    print("\nCPU time (all threads):\n" + table(names, cpu))
    return 0


if __name__ == "__main__":
    sys.exit(main())
