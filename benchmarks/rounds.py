"""Solve-to-floor ratios measured in interleaved rounds of fresh processes.

Usage::

    python benchmarks/rounds.py PROBLEM.npz [PROBLEM2.npz ...]
        [--rounds 5] [--backends pardiso,cholmod] [--stages min,fb]
        [--friction-steps 100] [--log FILE.jsonl]

Why rounds: on this shared 2-core virtual machine the same factorisation
took 2.8-4.3 s in fresh processes minutes apart (4.8·10⁵ DOFs, PARDISO),
more than the solve's whole overhead over the floor. A round runs, per
problem, every backend's floor and every (stage, backend) once, each in a
fresh ``measure.py`` process, in an order rotated from round to round; so
each stage has a floor measured within seconds of it. Printed per problem
and (stage, backend), wall and CPU:

* ``best``: the shortest of the rounds, and ``best/floor``, its ratio to
  the shortest floor of any backend over all rounds (the measure of
  ``stage_ratios.py``);
* ``paired``: the median over rounds of the stage's time divided by the
  fastest floor *of the same round*, with the lowest and highest of those
  ratios.

Stages: ``min``, ``fb`` (frictionless, every default), ``friction``
(``measure.py``'s: projection formulation, lagged bound, φ_min, f_c = 0.3,
``--friction-steps`` steps: issue 17's benchmark configuration) and
``friction-fb`` (the same with φ_FB), ``friction-read`` (``friction``, then
every step's displacement read from the result: the recovery that waits
for a first read, timed too).
"""

import argparse
import json
import statistics
import subprocess
import sys
from collections import defaultdict
from pathlib import Path

MEASURE = str(Path(__file__).resolve().parent / "measure.py")


def measure(problem, stage, backend, steps):
    argv = [sys.executable, MEASURE, problem, stage, backend]
    if stage.startswith("friction"):
        argv[3] = ("friction_read" if stage == "friction-read"
                   else "friction")
        argv += [str(steps), "lagged", "fb" if stage == "friction-fb"
                 else "min"]
    done = subprocess.run(argv, capture_output=True, text=True, check=False)
    if done.returncode:
        raise SystemExit(f"{' '.join(argv[1:])} failed: "
                         f"{done.stderr.strip().splitlines()[-1:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def run(problems, backends, stages, rounds, steps, log):
    times = defaultdict(list)  # (problem, stage, backend) -> [out per round]
    jobs = [("floor", b) for b in backends] + \
        [(s, b) for s in stages for b in backends]
    for r in range(rounds):
        shift = r % len(jobs)
        for problem in problems:
            for stage, backend in jobs[shift:] + jobs[:shift]:
                out = measure(problem, stage, backend, steps)
                out.update(round=r, problem=problem, stage=stage,
                           backend=backend)
                times[problem, stage, backend].append(out)
                if log:
                    with open(log, "a") as stream:
                        stream.write(json.dumps(out) + "\n")
    return times


def report(times, problems, backends, stages, rounds):
    for problem in problems:
        floors = {b: times[problem, "floor", b] for b in backends}
        dofs = floors[backends[0]][0]["dofs"]
        print(f"\n{problem}: {dofs} DOFs, {rounds} rounds")
        for clock in ("time", "cpu"):
            fastest = min(o[clock] for b in backends for o in floors[b])
            per_round = [min(floors[b][r][clock] for b in backends)
                         for r in range(rounds)]
            name = "wall" if clock == "time" else "CPU"
            print(f"  {name}: fastest floor {fastest:.3f} s; per round "
                  + " ".join(f"{t:.3f}" for t in per_round))
            print(f"  {'stage':9s} {'backend':8s} {'best':>8s} "
                  f"{'best/floor':>10s} {'paired median (min-max)':>24s}")
            for stage in ["floor"] + list(stages):
                for b in backends:
                    outs = times[problem, stage, b]
                    best = min(o[clock] for o in outs)
                    paired = [o[clock] / per_round[o["round"]] for o in outs]
                    print(f"  {stage:9s} {b:8s} {best:8.3f} "
                          f"{best / fastest:10.2f} "
                          f"{statistics.median(paired):10.2f} "
                          f"({min(paired):.2f}-{max(paired):.2f})")
        for stage in stages:
            for b in backends:
                out = times[problem, stage, b][0]
                print(f"  {stage} {b}: J/F {out.get('J')}/{out.get('F')}, "
                      f"converged {out.get('converged')}, peak RSS "
                      f"{max(o['peak_rss_mb'] for o in times[problem, stage, b]):.0f} MB")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("problems", nargs="+")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--backends", default="pardiso,cholmod")
    parser.add_argument("--stages", default="min,fb")
    parser.add_argument("--friction-steps", type=int, default=100)
    parser.add_argument("--log", help="append every measurement as JSON")
    args = parser.parse_args()
    backends = args.backends.split(",")
    stages = args.stages.split(",")
    times = run(args.problems, backends, stages, args.rounds,
                args.friction_steps, args.log)
    report(times, args.problems, backends, stages, args.rounds)


if __name__ == "__main__":
    main()
