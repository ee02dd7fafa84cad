"""3D benchmark (issue 18): the Hertz sphere against the fastest floor.

Usage::

    python benchmarks/run3d.py [--a-over-h 8,16,32] [--workdir DIR]
                               [--backends a,b] [--repeat N] [--steps N]
                               [--max-friction-dofs N] [--bound B]
                               [--method M] [--threads N] [--log FILE]

One row per a/h (``meshes/hertz_sphere.py --a-over-h N``, or the committed
``meshes/hertz_sphere_N.mesh``; exported by ``sfepy-run
sfepy_problems/hertz_sphere.py``; an existing ``hsN.npz`` with its
``hsN.export.json`` in ``--workdir`` is reused). Every measurement runs in
a fresh process (``measure.py``; ``python -m solver`` for the end-to-end
stage; ``processes.py``), which reports wall and CPU time and its peak RSS:

* **floor** ``<backend>``: factorise K and solve K u = f once, each
  installed backend; **fastest**: the shortest floor in this run, the
  denominator of every ratio;
* **solve**: ``solve(problem, method="min", backend=fastest)``, all
  else at its defaults (3D: condensed onto the normal DOFs of candidate
  nodes, :mod:`solver.contact.strategies.candidates`); **N_c in contact** and
  **candidates** (final) from it;
* **python -m solver**: ``python -m solver hsN.npz -o DIR
  --linear-solver fastest`` as a whole (start-up, loading, solve,
  verification, result folder): "end to end from the .npz";
  **imports**: ``python -c "import solver.cli"`` alone (its start-up);
* **friction**: ``solve(problem, friction=0.3, ...)``, ``--steps`` load
  steps (default 10), projection form, ``--method`` and ``--bound``
  (default solve's own: φ_FB, lagged; the lagged bound's stall at a/h 16
  is gone since ROLL18B, benchmarks/README.md), fastest backend (3D
  default: on candidate nodes, rollers included,
  :mod:`solver.contact.strategies.friction_candidates`), up to
  ``--max-friction-dofs``; its final candidates and enlargements;
* **RSS** of each stage's process (``ru_maxrss``; every one holds the
  loaded problem).

A second table gives the same ratios by CPU time (all threads; what a
loaded machine disturbs least; the end-to-end stage has wall time only).
"""

import argparse
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(1, str(Path(__file__).resolve().parent.parent))

import processes  # noqa: E402
from processes import StageError, export, measure, output_stage  # noqa
from rows import _best  # noqa: E402
from run import installed  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent


def columns(backends):
    return (["a/h", "DOFs", "Nc", "export [s]", "export RSS [MB]"]
            + [f"floor {b} [s]" for b in backends]
            + ["fastest", "solve [s] (/floor)",
               "python -m solver [s] (/floor)", "imports [s]", "in contact",
               "candidates",
               "friction [s] (/floor)", "friction J", "friction candidates",
               "RSS floor [MB]", "RSS solve [MB]",
               "RSS python -m solver [MB]", "RSS friction [MB]"])


def cpu_columns(backends):
    return (["a/h", "DOFs"] + [f"floor {b} CPU [s]" for b in backends]
            + ["fastest", "solve CPU [s] (/floor)",
               "friction CPU [s] (/floor)"])


def problem_file(n, folder):
    """The exported Hertz sphere of a/h = n (made if missing; an hsN.npz
    without its export record is used as it is, export columns "–")."""
    npz = Path(folder) / f"hs{n}.npz"
    if npz.exists() and not npz.with_suffix(".export.json").exists():
        return npz, None, None
    committed = ROOT / "meshes" / f"hertz_sphere_{n}.mesh"
    mesh = committed if committed.exists() else ["--a-over-h", str(n)]
    return export(mesh, f"hs{n}", folder, "hertz_sphere.py",
                  "hertz_sphere.py")


def ratio(seconds, floor, digits=2):
    return f"{seconds:.3g} ({seconds / floor:.{digits}f})"


def measure_case(npz, args, scratch):
    """(wall cells, CPU cells) of one problem file."""
    runs = {}
    for _ in range(args.repeat):
        for b in args.backends:
            runs.setdefault(("floor", b), []).append(measure(npz, "floor",
                                                             b))
    best = {key: _best(value) for key, value in runs.items()}
    fastest = min(args.backends, key=lambda b: best["floor", b]["time"])
    floor = best["floor", fastest]
    solve = _best([measure(npz, "min", fastest)
                   for _ in range(args.repeat)])
    seconds, rss = output_stage(npz, fastest, scratch)
    imports = processes.run_process([sys.executable, "-c",
                                     "import solver.cli"])[1]
    wall = {"DOFs": floor["dofs"], "Nc": floor["nc"], "fastest": fastest,
            "solve [s] (/floor)": ratio(solve["time"], floor["time"]) + (
                "" if solve["converged"] else " not converged"),
            "python -m solver [s] (/floor)": ratio(seconds, floor["time"]),
            "imports [s]": f"{imports:.3g}",
            "in contact": solve["contact"],
            "candidates": solve["candidates"],
            "RSS floor [MB]": f"{floor['peak_rss_mb']:.0f}",
            "RSS solve [MB]": f"{solve['peak_rss_mb']:.0f}",
            "RSS python -m solver [MB]": f"{rss:.0f}"}
    fastest_cpu = min(args.backends, key=lambda b: best["floor", b]["cpu"])
    cpu0 = best["floor", fastest_cpu]["cpu"]
    cpu = {"DOFs": floor["dofs"], "fastest": fastest_cpu,
           "solve CPU [s] (/floor)": ratio(solve["cpu"], cpu0)}
    for b in args.backends:
        wall[f"floor {b} [s]"] = f"{best['floor', b]['time']:.3g}"
        cpu[f"floor {b} CPU [s]"] = f"{best['floor', b]['cpu']:.3g}"
    if floor["dofs"] <= args.max_friction_dofs:
        r = measure(npz, "friction", fastest, args.steps, args.bound,
                    args.method)
        wall.update({
            "friction [s] (/floor)": ratio(r["time"], floor["time"], 1) + (
                "" if r["converged"] else " not converged"),
            "friction J": r["J"],
            "friction candidates": f"{r['candidates']}"
            + (f" ({r['enlarged']} enlarged)" if r["enlarged"] else ""),
            "RSS friction [MB]": f"{r['peak_rss_mb']:.0f}"})
        cpu["friction CPU [s] (/floor)"] = ratio(r["cpu"], cpu0, 1)
        if not r["converged"]:
            print(f"friction: {r['message']}", file=sys.stderr, flush=True)
    return wall, cpu


def row(cells, names):
    return "| " + " | ".join(str(cells.get(c, "–")) for c in names) + " |"


def sizes_table(sizes, folder, names, measure_one):
    """Print a Markdown table with columns ``names``: one row per a/h in
    ``sizes``, ``measure_one(n, npz)`` the row's cells for the Hertz sphere
    at that a/h (made and exported into ``folder`` unless there). A stage
    that fails names its a/h on stderr and the table goes on; the load
    average before and after each row goes to stderr (the machine is
    shared)."""
    import os

    print(row({c: c for c in names}, names))
    print("|" + "---|" * len(names), flush=True)
    for n in sizes:
        npz, _, _ = problem_file(n, folder)
        print(f"a/h {n}: load average {os.getloadavg()[0]:.1f} before",
              file=sys.stderr, flush=True)
        try:
            print(row(measure_one(n, npz), names), flush=True)
        except StageError as error:
            print(f"a/h {n}: {error}", file=sys.stderr, flush=True)
        print(f"a/h {n}: load average {os.getloadavg()[0]:.1f} after",
              file=sys.stderr, flush=True)


def parse(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--a-over-h", default="8,16,32",
                        help="comma-separated a/h of the rows")
    parser.add_argument("--workdir", help="keep and reuse exports here")
    parser.add_argument("--backends", help="comma-separated (default: all "
                        "installed)")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--steps", type=int, default=10)
    parser.add_argument("--max-friction-dofs", type=float, default=1.5e5)
    parser.add_argument("--bound", choices=("implicit", "lagged"),
                        default="lagged", help="the friction rows' "
                        "Coulomb bound (default lagged, solve's)")
    parser.add_argument("--method", choices=("fb", "min"), default="fb",
                        help="the friction rows' NCP method (default fb, "
                        "solve's)")
    parser.add_argument("--threads", type=int)
    parser.add_argument("--log")
    args = parser.parse_args(argv)
    args.backends, _ = installed(args.backends, True)
    args.a_over_h = [int(n) for n in args.a_over_h.split(",")]
    if args.threads:
        processes.THREADS.update({name: str(args.threads) for name in (
            "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")})
    if args.log:
        processes.LOG[:] = [args.log]
    return args


def main(argv=None):
    args = parse(argv)
    names, cpu_names = columns(args.backends), cpu_columns(args.backends)
    print(row({c: c for c in names}, names))
    print("|" + "---|" * len(names), flush=True)
    cpu_rows = []
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(args.workdir or scratch)
        folder.mkdir(parents=True, exist_ok=True)
        for n in args.a_over_h:
            try:
                npz, seconds, rss = problem_file(n, folder)
                wall, cpu = measure_case(npz, args, scratch)
            except StageError as exc:
                print(f"a/h {n}: {exc}", file=sys.stderr, flush=True)
                return 1
            if seconds is not None:
                wall.update({"export [s]": f"{seconds:.1f}",
                             "export RSS [MB]": f"{rss:.0f}"})
            wall["a/h"] = n
            cpu["a/h"] = n
            print(row(wall, names), flush=True)
            cpu_rows.append(row(cpu, cpu_names))
    print("\nBy CPU time:\n")
    print(row({c: c for c in cpu_names}, cpu_names))
    print("|" + "---|" * len(cpu_names))
    print("\n".join(cpu_rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
