"""CPU-time ratios from a ``run.py --log`` file: the same table as run.py's
time columns, but with the CPU time of each stage (all threads, the
shortest of the repeats) instead of its wall time.

Usage::

    python benchmarks/cpu_ratios.py LOG.jsonl

On a shared machine the wall time of a stage is its CPU time plus the time
it waited for a core; the CPU time is what the stage itself did, and its
ratios are much steadier when other jobs load the cores (multi-threaded
MKL/OpenBLAS may add some spinning to it). Ratios are to the fastest
backend's floor by CPU time.
"""

import json
import sys
from collections import defaultdict

METHODS = ("min", "fb")


def table(lines):
    """Markdown rows (list of str) from the JSON lines of one log."""
    best = defaultdict(dict)  # problem -> (stage, backend) -> min CPU
    dofs = {}
    for line in lines:
        r = json.loads(line)
        key = (r["stage"], r["backend"])
        cpu = best[r["problem"]].get(key)
        best[r["problem"]][key] = r["cpu"] if cpu is None \
            else min(cpu, r["cpu"])
        dofs[r["problem"]] = r["dofs"]
    backends = sorted({b for runs in best.values() for s, b in runs
                       if s == "floor"})
    head = (["DOFs"] + [f"floor {b} CPU [s]" for b in backends]
            + ["fastest"] + [f"{m} {b} CPU [s] (/floor)" for m in METHODS
                             for b in backends] + ["Schur CPU [s] (/floor)"])
    rows = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for problem in sorted(best, key=dofs.get):
        runs = best[problem]
        floors = {b: runs[("floor", b)] for b in backends
                  if ("floor", b) in runs}
        fastest = min(floors, key=floors.get)
        t0 = floors[fastest]
        cells = [str(dofs[problem])]
        cells += [f"{floors[b]:.3g}" if b in floors else "–"
                  for b in backends]
        cells.append(fastest)
        for m in METHODS:
            for b in backends:
                t = runs.get((m, b))
                cells.append("–" if t is None else f"{t:.3g} ({t / t0:.2f})")
        schur = [t for (s, _), t in runs.items() if s == "schur"]
        cells.append(f"{schur[0]:.3g} ({schur[0] / t0:.2f})" if schur
                     else "–")
        rows.append("| " + " | ".join(cells) + " |")
    return rows


if __name__ == "__main__":
    with open(sys.argv[1]) as log:
        print("\n".join(table(log)))
