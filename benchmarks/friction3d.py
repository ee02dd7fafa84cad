"""3D friction on a large contact zone (issue 33 point 2): the Hertz sphere
on a mesh graded toward the contact, against the fastest factorisation.

Usage::

    python benchmarks/friction3d.py [--a-over-h 32] [--dist-fine 1.1]
                                    [--dist-coarse 0.2] [--steps 10]
                                    [--backends a,b] [--whole]
                                    [--workdir DIR] [--log FILE]

The mesh: ``meshes/hertz_sphere.py --a-over-h N --dist-fine F
--dist-coarse C`` (the default grading, 1.1 and 0.2, keeps h = a/N over
the contact zone and coarsens within 0.2 R: at a/h 32 about 5·10⁴ DOFs and
10³ nodes in contact), exported by ``sfepy-run
sfepy_problems/hertz_sphere.py`` (reused from ``--workdir`` if there).
Every measurement runs in a fresh process (``measure.py``):

* **floor** ``<backend>``: factorise K and solve K u = f once, each
  installed backend (``--backends``); **fastest**: the shortest, the
  denominator of the ratios (wall and CPU, all threads);
* **friction**: ``solve(problem, friction=0.3, steps=--steps)``, every
  other option at its default (projection form, φ_min, lagged bound, on
  candidate nodes, auto backend), its Newton systems reduced
  (``reduced``, :mod:`solver.contact.friction.disc`); with ``--whole``
  also the LU of the whole Newton system (the path before), and the two
  u compared (max-norm, relative).

Columns: DOFs, nodes in contact at the last step, candidates, steps,
Jacobians (all steps; the most in one step), wall and CPU time, the
fastest floor, the ratios. After the table, one line per run: the floor
and the solve (wall, CPU), both ratios, the Jacobians of every load step
and the load average at the end (what the issue's targets read: ≤ 10×
the fastest factorisation, wall and CPU; ≤ 5 Jacobians in every step).
"""

import argparse
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(1, str(Path(__file__).resolve().parent.parent))

import processes  # noqa: E402
from processes import export, measure  # noqa: E402
from run import installed  # noqa: E402

COLUMNS = ["DOFs", "in contact", "candidates", "steps", "Newton systems",
           "Jacobians (max/step)", "time [s]", "CPU [s]",
           "fastest floor [s] (CPU)", "ratio", "CPU ratio", "u vs whole"]


def parse(argv):
    parser = argparse.ArgumentParser(prog="friction3d.py",
                                     description=__doc__.split("\n")[0])
    parser.add_argument("--a-over-h", default="32")
    parser.add_argument("--dist-fine", default="1.1")
    parser.add_argument("--dist-coarse", default="0.2")
    parser.add_argument("--steps", type=int, default=10)
    parser.add_argument("--backends", default=None,
                        help="comma-separated (default: all installed)")
    parser.add_argument("--whole", action="store_true",
                        help="also the whole Newton systems' LU (slow)")
    parser.add_argument("--workdir", default=None)
    parser.add_argument("--log", default=None,
                        help="append every measurement's JSON line here")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse(argv)
    if args.log:
        processes.LOG.append(args.log)
    backends, _ = installed(args.backends, True)
    folder = Path(args.workdir or tempfile.mkdtemp(prefix="friction3d_"))
    folder.mkdir(parents=True, exist_ok=True)
    name = f"graded{args.a_over_h}_{args.dist_fine}_{args.dist_coarse}"
    npz, _, _ = export(["--a-over-h", args.a_over_h, "--dist-fine",
                        args.dist_fine, "--dist-coarse", args.dist_coarse],
                       name, folder, generator="hertz_sphere.py",
                       problem="hertz_sphere.py")
    floors = {b: measure(npz, "floor", b) for b in backends}
    fastest = min(floors, key=lambda b: floors[b]["time"])
    floor = floors[fastest]
    print("| " + " | ".join(COLUMNS) + " |")
    print("|" + "---|" * len(COLUMNS))
    lines = []
    for newton in ("whole", "reduced") if args.whole else ("reduced",):
        r = measure(npz, "friction3d", "auto", args.steps, newton)
        lines.append(
            f"{newton}: floor {floor['time']:.2f} s wall / "
            f"{floor['cpu']:.2f} s CPU ({fastest}), solve "
            f"{r['time']:.2f} s wall / {r['cpu']:.2f} s CPU, ratio "
            f"{r['time'] / floor['time']:.2f} wall / "
            f"{r['cpu'] / floor['cpu']:.2f} CPU; Jacobians per step "
            f"{r['J_steps']} (max {r['J_max']}); load average "
            f"{r['load_average']:.2f}")
        agreement = r.get("agreement")
        cells = [f"{floor['dofs']:,}", r["contact"], r["candidates"],
                 args.steps, newton, f"{r['J']} ({r['J_max']})",
                 f"{r['time']:.3g}", f"{r['cpu']:.3g}",
                 f"{floor['time']:.3g} ({floor['cpu']:.3g}) {fastest}",
                 f"**{r['time'] / floor['time']:.1f}**",
                 f"{r['cpu'] / floor['cpu']:.1f}",
                 "–" if agreement is None else f"{agreement:.1e}"]
        if not (r["converged"] and r["verified"]):
            cells[4] += " (not converged)"
        print("| " + " | ".join(map(str, cells)) + " |", flush=True)
    print()
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
