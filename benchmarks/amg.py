"""The iterative path against the factorisation (issue 33): the Hertz
sphere, frictionless.

Usage::

    python benchmarks/amg.py [--a-over-h 16,32] [--workdir DIR]
                             [--backends a,b] [--no-direct 64]
                             [--threads N] [--log FILE]

One row per a/h (the exports of ``run3d.py``: ``hsN.npz`` in
``--workdir``, made if missing). Every measurement runs in a fresh process
(``measure.py``, ``processes.py``) and reports its wall time and peak RSS:

* **floor** ``<backend>``: factorise K and solve K u = f once, each
  installed backend; **fastest**: the shortest, the direct path's floor;
* **direct**: ``solve(problem, backend=fastest)`` (3D default: condensed
  onto candidate nodes), its Jacobians;
* **AMG-PCG**: build the smoothed-aggregation hierarchy of K and solve
  K u = f once by preconditioned CG to 1e-8: the iterative path's floor;
* **amg**: ``solve(problem, backend="amg")`` (the active set method on the
  full system, :mod:`solver.contact.frictionless.active_set`): Newton
  systems, CG iterations in all and per system (max / mean), CG
  iterations per decade of residual reduction (the systems after the free
  solution: their tolerances differ, so both are printed), its time
  over the fastest floor, over the direct solve and over AMG-PCG, and
  ‖u_amg − u_direct‖₂ / ‖u_direct‖₂; its CPU time over AMG-PCG's (same
  run); Hertz's checks (``solver.studies3d.hertz_sphere_row``): the
  errors of a (first moment of the nodal forces; fitted with p0) and of
  the fitted p0 against Hertz's values for the computed force.

The load average is printed before and after each row (stderr): the
machine is shared, so the CPU ratios are the fairer ones.

``--no-direct`` lists the a/h whose factorisations are not run (they
would not fit the memory): the amg rows alone.
"""

import argparse
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(1, str(Path(__file__).resolve().parent.parent))

import processes  # noqa: E402
from processes import measure  # noqa: E402
from run import installed  # noqa: E402
from run3d import sizes_table  # noqa: E402

COLUMNS = ("a/h", "DOFs", "fastest floor [s] (backend)", "direct [s] "
           "(/floor), J", "RSS direct [MB]", "AMG-PCG K u = f [s] (CG)",
           "amg [s] (/floor, /direct, /AMG-PCG)", "Newton systems",
           "CG total (max / mean per system)",
           "CG per decade (contact systems)", "RSS amg [MB]",
           "in contact", "|u − u_direct| / |u_direct|",
           "CPU amg [s] (/AMG-PCG CPU)", "a err % (moment / fit)",
           "p0 fit err %")


def measure_case(n, npz, backends, direct=True):
    cells = {"a/h": n}
    floors = {}
    if direct:
        for backend in backends:
            r = measure(npz, "floor", backend)
            floors[backend] = r["time"]
            print(f"a/h {n}: floor {backend} wall {r['time']:.3g} s, CPU "
                  f"{r['cpu']:.3g} s", file=sys.stderr, flush=True)
        fastest = min(floors, key=floors.get)
        floor = floors[fastest]
        cells["fastest floor [s] (backend)"] = f"{floor:.3g} ({fastest})"
        r = measure(npz, "min", fastest)
        cells["DOFs"] = f"{r['dofs']:,}"
        direct_time = r["time"]
        print(f"a/h {n}: direct ({fastest}) wall {r['time']:.3g} s, CPU "
              f"{r['cpu']:.3g} s", file=sys.stderr, flush=True)
        cells["direct [s] (/floor), J"] = \
            f"{direct_time:.3g} ({direct_time / floor:.2f}), {r['J']}"
        cells["RSS direct [MB]"] = f"{r['peak_rss_mb']:.0f}"
    else:
        fastest, floor, direct_time = "none", None, None
    r = measure(npz, "amg_floor")
    cells["DOFs"] = f"{r['dofs']:,}"
    pcg, pcg_cpu = r["time"], r["cpu"]
    cells["AMG-PCG K u = f [s] (CG)"] = f"{pcg:.3g} ({r['krylov']})"
    r = measure(npz, "amg", fastest)
    ratios = [f"{r['time'] / x:.2f}" for x in (floor, direct_time, pcg)
              if x is not None]
    cells["amg [s] (/floor, /direct, /AMG-PCG)"] = \
        f"{r['time']:.3g} ({', '.join(ratios)})"
    cells["Newton systems"] = r["J"]
    cells["CG total (max / mean per system)"] = \
        f"{r['krylov']} ({r['krylov_max']} / {r['krylov_mean']:.1f})"
    decades = r.get("krylov_decades")
    if decades:  # CG per decade of residual reduction, after the free one
        its, dec = r["krylov_per_system"][1:], decades[1:]
        if sum(dec) > 0:
            cells["CG per decade (contact systems)"] = \
                f"{sum(its) / sum(dec):.2f}"
    cells["RSS amg [MB]"] = f"{r['peak_rss_mb']:.0f}"
    cells["in contact"] = r["contact"]
    if "agreement" in r:
        cells["|u − u_direct| / |u_direct|"] = f"{r['agreement']:.1e}"
    cells["CPU amg [s] (/AMG-PCG CPU)"] = \
        f"{r['cpu']:.3g} ({r['cpu'] / pcg_cpu:.2f})"
    hertz = r.get("hertz")
    if hertz:
        cells["a err % (moment / fit)"] = \
            f"{hertz['a moment err %']:+.2f} / {hertz['a fit err %']:+.2f}"
        cells["p0 fit err %"] = f"{hertz['p0 fit err %']:+.2f}"
    if not (r["converged"] and r["verified"]):
        print(f"a/h {n}: amg not converged or not verified",
              file=sys.stderr, flush=True)
    print(f"a/h {n}: CG per Newton system {r['krylov_per_system']}, "
          f"active set sizes {r['active']}, AMG {r['amg']}",
          file=sys.stderr, flush=True)
    if decades:
        print(f"a/h {n}: decades of residual reduction per system "
              f"{[round(x, 2) for x in decades]}, eliminated hierarchy "
              f"setup per system [s] "
              f"{[round(x, 3) for x in r['setup_per_system']]}; amg wall "
              f"{r['time']:.3g} s, CPU {r['cpu']:.3g} s; AMG-PCG wall "
              f"{pcg:.3g} s, CPU {pcg_cpu:.3g} s",
              file=sys.stderr, flush=True)
    return cells


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--a-over-h", default="16,32")
    parser.add_argument("--workdir", help="keep and reuse exports here")
    parser.add_argument("--backends", help="comma-separated (default: all "
                        "installed but superlu)")
    parser.add_argument("--no-direct", default="",
                        help="comma-separated a/h without factorisations")
    parser.add_argument("--threads", type=int)
    parser.add_argument("--log")
    args = parser.parse_args(argv)
    backends, _ = installed(args.backends or "pardiso,cholmod", True)
    if args.threads:
        processes.THREADS.update({name: str(args.threads) for name in (
            "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")})
    if args.log:
        processes.LOG[:] = [args.log]
    skip = {int(n) for n in args.no_direct.split(",") if n}
    folder = args.workdir or tempfile.mkdtemp(prefix="amg-bench-")
    sizes_table((int(x) for x in args.a_over_h.split(",")), folder, COLUMNS,
                lambda n, npz: measure_case(n, npz, backends, n not in skip))
    return 0


if __name__ == "__main__":
    sys.exit(main())
