"""φ_min against φ_FB on the shipped friction problems, by measurement.

Usage (after exporting the problems, commands in benchmarks/README.md)::

    python benchmarks/friction_methods.py [--workdir output] [--rounds 3]
        [--methods min,fb] [--cases block_454,...] [--log FILE.jsonl]

Every (case, method) runs ``--rounds`` times, each in a fresh process
(``--one``), the methods alternating within a round, so that both meet
the same machine load. Each run calls :func:`solver.solve_friction` with
every argument at its default but the method (projection formulation,
lagged bound, condensed system, fastest backend) and the case's f_c (load
steps: 100, or the problem's load path). Printed per case and method: the
Jacobian and residual evaluations (deterministic), Jacobians per load step
(all steps; steps without contact take none), the best wall time of the
rounds (``solve_friction``'s own ``time``: factorisation, condensation,
every step, verification) and the paired ratio fb/min (median and range
over the rounds, each run against the other method's in its round).
"""

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: name -> (file in the workdir, f_c, steps): the shipped friction problems
#: (README, sfepy_problems/*.py usage), their documented coefficients.
CASES = {
    "block_454 f_c 0.05": ("block_454.npz", 0.05, 100),
    "block_454 f_c 0.3": ("block_454.npz", 0.3, 100),
    "block_454 f_c 10": ("block_454.npz", 10.0, 100),
    "block_1878 f_c 0.05": ("block_1878.npz", 0.05, 100),
    "block_1878 f_c 0.3": ("block_1878.npz", 0.3, 100),
    "block_1878 f_c 10": ("block_1878.npz", 10.0, 100),
    "cattaneo_mindlin (2D)": ("cm.npz", 0.5, None),
    "cattaneo_mindlin_sphere (3D)": ("cm_sphere.npz", 0.5, None),
    "two_body_patch slide": ("patch_slide.npz", 0.3, 100),
    "two_cylinders cattaneo": ("two_cylinders_cm.npz", 0.5, None),
}


def one(path, friction, steps, method):
    """One run in this process: one JSON line."""
    sys.path.insert(0, str(ROOT))
    import solver

    problem = solver.load_problem(path)
    steps = None if problem.load_path is not None else steps
    r = solver.solve(problem, friction=friction, steps=steps, method=method)
    print(json.dumps({"J": int(r.njev), "F": int(r.nfev),
                      "steps": int(r.steps), "success": bool(r.success),
                      "time": float(r.time)}))


def measure(path, friction, steps, method):
    argv = [sys.executable, __file__, "--one", str(path), str(friction),
            str(steps or 0), method]
    done = subprocess.run(argv, capture_output=True, text=True, check=False)
    if done.returncode:
        raise SystemExit(f"{' '.join(argv[2:])} failed: "
                         f"{done.stderr.strip().splitlines()[-1:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", default=str(ROOT / "output"))
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--methods", default="min,fb")
    parser.add_argument("--cases", help="comma-separated prefixes of "
                        "the case names (default: all)")
    parser.add_argument("--log", help="append every measurement as JSON")
    parser.add_argument("--one", nargs=4, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        path, friction, steps, method = args.one
        return one(path, float(friction), int(steps) or None, method)
    methods = args.methods.split(",")
    cases = {name: case for name, case in CASES.items()
             if not args.cases or any(name.startswith(p) for p in
                                      args.cases.split(","))}
    print("| case | method | J | F | J per step | best time s | "
          "time / min's (median, range) |")
    print("|---|---|---|---|---|---|---|")
    for name, (file, friction, steps) in cases.items():
        path = Path(args.workdir) / file
        runs = {m: [] for m in methods}
        for r in range(args.rounds):
            order = methods if r % 2 == 0 else methods[::-1]
            for method in order:
                out = measure(path, friction, steps, method)
                runs[method].append(out)
                if args.log:
                    with open(args.log, "a") as stream:
                        stream.write(json.dumps(dict(out, case=name,
                                                     method=method,
                                                     round=r)) + "\n")
        for method in methods:
            outs = runs[method]
            first = outs[0]
            paired = [o["time"] / b["time"] for o, b in
                      zip(outs, runs[methods[0]])]
            ratio = "" if method == methods[0] else \
                (f"{statistics.median(paired):.2f} "
                 f"({min(paired):.2f}-{max(paired):.2f})")
            status = "" if first["success"] else " (failed)"
            print(f"| {name} | {method} | {first['J']}{status} | "
                  f"{first['F']} | {first['J'] / first['steps']:.2f} | "
                  f"{min(o['time'] for o in outs):.2f} | {ratio} |",
                  flush=True)


if __name__ == "__main__":
    sys.exit(main())
