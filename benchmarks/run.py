"""Scaling benchmark: the thesis block refined, against the fastest floor.

Usage::

    python benchmarks/run.py [--max-dofs N] [--min-dofs N] [--gmsh-size H]
                             [--backends a,b] [--repeat N] [--workdir DIR]
                             [--threads N] [--log FILE]
                             [--max-friction-dofs N] [--max-peer-dofs N]
                             [--max-sfepy-dofs N] [--steps N] [--no-peers]

Sizes: the thesis meshes (118 and 454 triangles, committed), the 1878 mesh
and its uniform refinements (4× the triangles per level, ``meshes/
generate.py --refine``) up to ``--max-dofs`` reduced DOFs; with
``--max-dofs`` ≥ 9e5 also a gmsh mesh of ~9.2·10⁵ DOFs (``--size 0.0225
--algorithm 6``), and one gmsh mesh per ``--gmsh-size`` (the big run).
Each is exported by ``sfepy-run`` (its time and peak memory are columns)
and measured stage by stage, **every measurement in a fresh process**
(``benchmarks/measure.py``; ``python -m solver`` for the output stage).
One table row per size (markdown, printed as each size finishes):

* **floor** ``<backend>``: factorise K and solve K u = f once with each
  installed backend (superlu and cholmod with our nested dissection, the
  ordering timed; pardiso with its own METIS); **fastest** names
  the fastest of them *in this run*, the denominator of every ratio;
* ``min``/``fb`` ``<backend>``: ``solver.solve`` (φ_min, φ_FB; every
  argument but ``backend`` at its default: gap from the obstacle,
  condensed onto Γc, nested start, verification) with each backend, as
  "time (time / fastest floor)";
* levels, and J/F: Jacobian/residual evaluations of all levels (the
  Jacobians on the finest level, the full Γc, in brackets), with the
  fastest backend; a backend whose counts differ is named in the cell;
* **Schur**: the condensation alone (factorisation with Γc last and the
  dense S), fastest backend; **output**: ``python -m solver PROBLEM -o DIR
  --linear-solver <fastest>`` as a whole (start-up, loading, solve, the
  result folder);
* peers on the same problem (``peers.py``): Clarabel on the QP and SfePy's
  ``nls.semismooth_newton``, "time (time / our φ_min)", counted only if
  their u is within 1e-6 (relative, max norm) of ours, else
  "(differs …)"; up to ``--max-peer-dofs`` (SfePy: ``--max-sfepy-dofs``);
* **friction**: 100 load steps (``--steps``), f_c = 0.3, projection form,
  φ_min, lagged bound, fastest backend, up to ``--max-friction-dofs``,
  "time (time / fastest floor)";
* **RSS** (peak resident memory, ``ru_maxrss`` of the stage's process,
  fastest backend): floor, Schur, Newton (the larger of the φ_min and
  φ_FB solves), output; "Newton/floor RSS" is the target's ratio. Every
  process holds the loaded problem (K, M, f, mesh).

``--repeat N`` runs each floor and frictionless solve N times (rounds over
the backends, fresh processes) and keeps the shortest time and the largest
RSS. ``--workdir`` keeps the exported problems there and reuses them (the
export columns then repeat the recorded first export); ``--log`` keeps
every measurement's JSON (wall and CPU time, RSS, counts); ``--threads``
fixes the BLAS/MKL/OpenMP threads. Ratios are measured
in the same run; absolute times are indicative only (shared, noisy
machines).
"""

import argparse
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(1, str(Path(__file__).resolve().parent.parent))

import processes  # noqa: E402
from processes import StageError, export  # noqa: E402
from rows import columns, measure_size  # noqa: E402
from solver.linalg import BACKENDS, available_backends  # noqa: E402

#: Thesis meshes measured as committed: (triangles, reduced DOFs).
THESIS = ((118, 138), (454, 492))
#: Mesh size of the ~9.2·10⁵-DOF gmsh mesh added when --max-dofs ≥ 9e5.
GMSH_1M = 0.0225


def sizes(max_dofs, gmsh_sizes=(), min_dofs=0):
    """(mesh: generate.py arguments or a committed file, name) per size,
    those of about ``min_dofs`` to ``max_dofs`` DOFs (the gmsh ones
    always)."""
    root = Path(__file__).resolve().parent.parent
    for triangles, dofs in THESIS:
        if min_dofs <= dofs * 1.2 and dofs <= max_dofs * 1.2:
            yield root / "meshes" / f"block_{triangles}.mesh", \
                f"block_{triangles}"
    level = 0
    while 1956 * 4 ** level <= max_dofs * 1.2:
        if min_dofs <= 1956 * 4 ** level * 1.2:
            yield ["--refine", str(level), "--base", "1878"], \
                f"block_r{level}"
        level += 1
    extra = list(gmsh_sizes)
    if max_dofs >= 9e5 and 1956 * 4 ** level > 1.3e6 and GMSH_1M not in extra:
        extra.insert(0, GMSH_1M)
    for h in extra:
        yield ["--size", f"{h:g}", "--algorithm", "6"], f"block_h{h:g}"


def installed(names, no_peers):
    """(backends to measure, peers to run); missing ones said on stderr."""
    have = available_backends()
    wanted = BACKENDS if names is None else tuple(names.split(","))
    for name in wanted:
        if name not in BACKENDS:
            raise SystemExit(f"run.py: unknown backend {name!r}")
        if name not in have:
            print(f"({name} not installed: its columns are skipped)",
                  file=sys.stderr)
    peers = []
    for module in () if no_peers else ("clarabel", "sfepy"):
        try:
            __import__(module)
            peers.append(module)
        except ImportError:
            print(f"({module} not installed: its column is skipped)",
                  file=sys.stderr)
    return [b for b in BACKENDS if b in wanted and b in have], peers


def parse(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-dofs", type=float, default=1.3e5)
    parser.add_argument("--min-dofs", type=float, default=0)
    parser.add_argument("--gmsh-size", type=float, action="append",
                        default=[], help="add a gmsh mesh of this size")
    parser.add_argument("--backends", help="comma-separated (default: all "
                        "installed)")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--workdir", help="keep and reuse exports here")
    parser.add_argument("--threads", type=int, help="set MKL_NUM_THREADS, "
                        "OPENBLAS_NUM_THREADS and OMP_NUM_THREADS in every "
                        "measured process (default: untouched)")
    parser.add_argument("--log", help="append every measurement's JSON "
                        "(time, cpu, RSS, counts) to this file")
    parser.add_argument("--max-friction-dofs", type=float, default=1.3e5)
    parser.add_argument("--max-peer-dofs", type=float, default=1.1e6)
    parser.add_argument("--max-sfepy-dofs", type=float,
                        help="default: --max-peer-dofs")
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--no-peers", action="store_true")
    args = parser.parse_args(argv)
    if args.max_sfepy_dofs is None:
        args.max_sfepy_dofs = args.max_peer_dofs
    args.backends, args.peers = installed(args.backends, args.no_peers)
    if args.threads:
        processes.THREADS.update({name: str(args.threads) for name in (
            "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")})
    if args.log:
        processes.LOG[:] = [args.log]
    if not args.backends:
        parser.error("no backend to measure")
    return args


def main(argv=None):
    args = parse(argv)
    names = columns(args.backends)
    print("| " + " | ".join(names) + " |")
    print("|" + "---|" * len(names), flush=True)
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(args.workdir or scratch)
        folder.mkdir(parents=True, exist_ok=True)
        for mesh, name in sizes(args.max_dofs, args.gmsh_size,
                                args.min_dofs):
            try:
                npz, seconds, rss = export(mesh, name, folder)
                cells = measure_size(npz, args, scratch)
            except StageError as exc:
                print(f"{name}: {exc}", file=sys.stderr, flush=True)
                return 1
            cells.update({"export [s]": f"{seconds:.1f}",
                          "export RSS [MB]": f"{rss:.0f}"})
            print("| " + " | ".join(str(cells.get(c, "–")) for c in names)
                  + " |", flush=True)
            if not args.workdir:
                for leftover in folder.glob(name + ".*"):
                    leftover.unlink()
    return 0


if __name__ == "__main__":
    sys.exit(main())
