"""Friction between two bodies on the iterative path (issue 33 point 1):
the Hertz cylinders of the tests (``tests/tri_elasticity.py``), squeezed
then shifted, f_c = 0.3, 12 load steps, against the factorisation path.

Usage::

    python benchmarks/amg_friction_two_body.py [--h0 0.002,0.001]
                                               [--coulomb lagged,implicit]

One row per contact mesh size h0 and bound: the factorisation path's
default (condensed onto the slave nodes) and ``backend="amg"`` in this
process, each timed by wall and process CPU time; Newton systems and
Krylov iterations (CG for the lagged bound, GMRES for the implicit) per
system; ‖u_amg − u_direct‖₂ / ‖u_direct‖₂ of the last step. The load
average is printed with each row: the machine is shared, so the CPU
ratio is the fairer one."""

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
sys.path.insert(1, str(Path(__file__).resolve().parent.parent))

from solver import solve  # noqa: E402
from tri_elasticity import two_cylinders  # noqa: E402


def timed(problem, **options):
    """(result, wall seconds, CPU seconds) of one solve."""
    wall, cpu = time.perf_counter(), time.process_time()
    result = solve(problem, friction=0.3, **options)
    return result, time.perf_counter() - wall, time.process_time() - cpu


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--h0", default="0.002,0.001")
    parser.add_argument("--coulomb", default="lagged,implicit")
    args = parser.parse_args(argv)
    print("| h0 | DOFs | bound | direct [s] (CPU) | amg [s] (CPU) | wall "
          "ratio | CPU ratio | Newton systems | Krylov per system"
          " | ‖Δu‖/‖u‖ | load average |")
    print("|---|---:|---|---|---|---:|---:|---:|---|---:|---|")
    for h0 in (float(x) for x in args.h0.split(",")):
        problem = two_cylinders((1.0, 1.5), ((1.0, 0.3), (2.0, 0.25)),
                                h0=h0, squeeze=0.01, shift=0.004)[0]
        for coulomb in args.coulomb.split(","):
            load = os.getloadavg()[0]
            direct, wd, cd = timed(problem, coulomb=coulomb)
            amg, wa, ca = timed(problem, coulomb=coulomb, backend="amg")
            njev = sum(r["njev"] for r in amg.records)
            krylov = sum(r["krylov"] for r in amg.records)
            per = f"{krylov / max(njev, 1):.1f}"
            error = np.linalg.norm(amg.u - direct.u) / np.linalg.norm(
                direct.u)
            ok = amg.success and amg.verification["passed"]
            print(f"| {h0} | {problem.n_dofs:,} | {coulomb} | {wd:.3g} "
                  f"({cd:.3g}) | {wa:.3g} ({ca:.3g}) | {wa / wd:.1f} | "
                  f"{ca / cd:.1f} | {njev} | {per} | {error:.1e}"
                  f"{'' if ok else ' (NOT converged)'} | {load:.1f} → "
                  f"{os.getloadavg()[0]:.1f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
