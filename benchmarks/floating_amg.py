"""A body held only by contact on the AMG path against the factorisation
path (issue 33 point 1): the Hertz half-cylinder under a force
(``sfepy_problems/hertz_cylinder.py``, ``load='force'``: two rigid-body
modes held by the contact only, K singular) on refinements of its mesh,
solved frictionless by ``backend='auto'`` (the factorisation: PARDISO or
CHOLMOD, K⁺ and the modes' amplitudes, the nested start) and by
``backend='amg'`` (the active set method from the rigid placement, CG
with smoothed aggregation, pseudo-inverse on the coarsest level) in the
same process. Prints one Markdown row per mesh: DOFs, contact nodes in
contact, the Newton systems (J) of both, CG iterations per Newton system
(mean and largest), wall and process CPU seconds of ``solver.solve``
(best of ``--repeat`` after one warm-up, the problem reloaded each time),
AMG / factorisation ratios, max |Δu| / max |u| and whether the contact
sets agree; then the load average.

    python benchmarks/floating_amg.py [--h-contact H ...] [--repeat N]
"""

import argparse
import os
import pathlib
import sys
import tempfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import solver  # noqa: E402
from floating import export_cylinder  # noqa: E402 (benchmarks/floating.py)
from floating_full import timed  # noqa: E402 (best wall and CPU)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--h-contact", type=float, nargs="+",
                        default=[0.004, 0.002, 0.001])
    parser.add_argument("--h-far", type=float, default=0.02)
    parser.add_argument("--P", type=float, default=1739.6)
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args(argv)
    print("| DOFs | in contact | J direct | J AMG | CG / system (max) "
          "| direct wall [s] | AMG wall [s] | direct CPU [s] | AMG CPU [s] "
          "| wall AMG / direct | CPU AMG / direct | max Δu / max u "
          "| same set |")
    print("|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---|")
    with tempfile.TemporaryDirectory() as folder:
        folder = pathlib.Path(folder)
        for h in args.h_contact:
            path = export_cylinder(folder, h, args.h_far, f"f_{h}",
                                   load="force", P=args.P)
            w_d, c_d, r_d = timed(path, args.repeat, tol=1e-10)
            w_a, c_a, r_a = timed(path, args.repeat, tol=1e-10,
                                  backend="amg")
            krylov = np.asarray(r_a.history["krylov"])
            du = np.abs(r_a.u - r_d.u).max() / np.abs(r_d.u).max()
            same = bool(np.array_equal(r_a.in_contact, r_d.in_contact))
            print(f"| {len(r_d.u):,} | {r_d.n_contact} | {r_d.njev} "
                  f"| {r_a.njev} | {krylov.mean():.1f} ({krylov.max()}) "
                  f"| {w_d:.2f} | {w_a:.2f} | {c_d:.2f} | {c_a:.2f} "
                  f"| {w_a / w_d:.2f} | {c_a / c_d:.2f} | {du:.1e} "
                  f"| {'yes' if same else 'no'} |", flush=True)
    print(f"load average: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    sys.exit(main())
