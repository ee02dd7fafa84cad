"""3D friction on the iterative path (issue 33: "3D friction, 10 load steps
at a/h 48: ≤ 30× one AMG-PCG solve of K u = f to 1e-8 in the same run"):
the Hertz sphere, f_c = 0.3, lagged bound (``--coulomb implicit``: the
implicit bound, each Newton system by GMRES), ``backend="amg"``.

Usage::

    python benchmarks/amg_friction.py [--a-over-h 16,32] [--steps 10]
                                      [--direct 16] [--workdir DIR]
                                      [--coulomb implicit] [--log FILE]

One row per a/h (the exports of ``run3d.py``: ``hsN.npz`` in
``--workdir``, made if missing). Every measurement runs in a fresh process
(``measure.py``):

* **AMG-PCG**: build the smoothed-aggregation hierarchy of K and solve
  K u = f once by preconditioned CG to 1e-8: the denominator of the ratios
  (wall and CPU, process time);
* **amg friction**: ``solve(problem, friction=0.3, steps=--steps,
  backend="amg")`` (:mod:`solver.contact.friction.active_set`): Newton
  systems and CG iterations per step, stick / slip nodes at the last step;
* **direct** (the a/h listed in ``--direct``): the ``friction3d`` stage,
  the factorisation path's default (condensed onto candidates, reduced
  Newton systems), and ‖u_amg − u_direct‖₂ / ‖u_direct‖₂.

The load average is printed before and after each row (stderr): the
machine is shared, so the CPU ratios are the fairer ones.
"""

import argparse
import os
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(1, str(Path(__file__).resolve().parent.parent))

import processes  # noqa: E402
from processes import measure  # noqa: E402
from run3d import sizes_table  # noqa: E402

COLUMNS = ("a/h", "DOFs", "AMG-PCG K u = f [s] (CPU; CG)",
           "amg friction [s] (CPU)", "wall ratio", "CPU ratio",
           "Newton systems per step", "Krylov per step", "stick / slip (last)",
           "RSS amg [MB]", "direct [s] (CPU)",
           "‖u − u_direct‖ / ‖u_direct‖", "load average")


def measure_case(n, npz, steps, direct, coulomb="lagged"):
    cells = {"a/h": n}
    load = [f"{os.getloadavg()[0]:.1f}"]
    if direct:
        r = measure(npz, "friction3d", "auto", steps, "reduced", coulomb)
        cells["direct [s] (CPU)"] = f"{r['time']:.3g} ({r['cpu']:.3g})"
    r = measure(npz, "amg_floor")
    cells["DOFs"] = f"{r['dofs']:,}"
    pcg, pcg_cpu = r["time"], r["cpu"]
    cells["AMG-PCG K u = f [s] (CPU; CG)"] = \
        f"{pcg:.3g} ({pcg_cpu:.3g}; {r['krylov']})"
    r = measure(npz, "amg_friction", "auto", steps, coulomb)
    load.append(f"{os.getloadavg()[0]:.1f}")
    cells["amg friction [s] (CPU)"] = f"{r['time']:.3g} ({r['cpu']:.3g})"
    cells["wall ratio"] = f"{r['time'] / pcg:.1f}"
    cells["CPU ratio"] = f"{r['cpu'] / pcg_cpu:.1f}"
    cells["Newton systems per step"] = \
        f"{r['J']} ({'/'.join(map(str, r['J_steps']))})"
    cells["Krylov per step"] = \
        f"{sum(r['krylov_steps'])} ({'/'.join(map(str, r['krylov_steps']))})"
    cells["stick / slip (last)"] = f"{r['stick'][-1]} / {r['slip'][-1]}"
    cells["RSS amg [MB]"] = f"{r['peak_rss_mb']:.0f}"
    if "agreement" in r:
        cells["‖u − u_direct‖ / ‖u_direct‖"] = f"{r['agreement']:.1e}"
    cells["load average"] = " → ".join(load)
    if not (r["converged"] and r["verified"]):
        print(f"a/h {n}: amg friction not converged or not verified: "
              f"{r['message']}", file=sys.stderr, flush=True)
    return cells


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--a-over-h", default="16,32")
    parser.add_argument("--steps", type=int, default=10)
    parser.add_argument("--direct", default="16",
                        help="comma-separated a/h also run factorised")
    parser.add_argument("--workdir", help="keep and reuse exports here")
    parser.add_argument("--coulomb", choices=("lagged", "implicit"),
                        default="lagged", help="the bound (implicit: "
                        "GMRES per Newton system)")
    parser.add_argument("--log")
    args = parser.parse_args(argv)
    if args.log:
        processes.LOG[:] = [args.log]
    direct = {int(n) for n in args.direct.split(",") if n}
    folder = args.workdir or tempfile.mkdtemp(prefix="amg-friction-")
    sizes_table((int(x) for x in args.a_over_h.split(",")), folder, COLUMNS,
                lambda n, npz: measure_case(n, npz, args.steps, n in direct,
                                            args.coulomb))
    return 0


if __name__ == "__main__":
    sys.exit(main())
