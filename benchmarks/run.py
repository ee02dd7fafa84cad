"""Scaling benchmark: the thesis block refined, against one linear solve.

Usage::

    python benchmarks/run.py [--max-dofs N] [--max-friction-dofs N]
                             [--max-peer-dofs N] [--max-sfepy-dofs N]
                             [--steps N] [--no-peers]

Sizes: the 1878-element thesis mesh and its uniform refinements (4× the
triangles per level, ``meshes/generate.py --refine``) up to ``--max-dofs``
reduced DOFs; with ``--max-dofs`` ≥ 9e5 also a gmsh mesh of ~10⁶ DOFs
(``--size 0.0225``). Each is exported by ``sfepy-run`` and measured, every
measurement in a fresh process (for its peak memory). One row per size:

* DOFs, Nc (nodes on Γc), the SfePy export time;
* **floor**: one solve of K u = f by the project's fastest linear solver
  (nested dissection ordering + SuperLU factorisation + solve,
  :class:`solver.linalg.Factorization` without the pivot check), and for
  reference SciPy's default ``splu`` (COLAMD) + solve;
* φ_min and φ_FB frictionless solves (``solve_frictionless``, defaults:
  condensed onto Γc, gap from the obstacle, nested start from λ = 0 on the
  coarsest level), time, ratio to the floor, Jacobian/residual evaluations
  of all levels together, the number of levels and the Jacobians on the
  finest level (the full Γc, the ones that cost);
* peers on the same problem (``benchmarks/peers.py``): Clarabel on the QP
  and SfePy's ``nls.semismooth_newton``; a time counts only if the peer's u
  is within 1e-6 (relative, max norm) of ours, else "(differs …)"; up to
  ``--max-peer-dofs`` (SfePy's up to ``--max-sfepy-dofs``: it is slow);
* friction: 100 load steps (``--steps``), f_c = 0.3, projection form,
  φ_min, lagged bound, up to ``--max-friction-dofs``;
* peak resident memory of the floor process, of the frictionless solves
  (the larger of φ_min and φ_FB) and their ratio, and of the friction run
  (which keeps u, the nodal displacement and the contact fields of every
  step).

Ratios are measured in the same run; absolute times are indicative only
(shared, noisy machines).
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

MEASURE = r'''
import json, resource, sys, time
import numpy as np
sys.path.insert(0, sys.argv[4])
from solver import load_problem, solve_frictionless, solve_friction
from solver.contact import contact_geometry

path, what, steps = sys.argv[1], sys.argv[2], int(sys.argv[3])
problem = load_problem(path)
out = {"dofs": problem.n_dofs, "nc": problem.n_contact}
if what == "floor":
    from solver.linalg import Factorization, dof_ordering
    t = time.perf_counter()
    factorization = Factorization(problem.K, dof_ordering(problem),
                                  check=False)
    u = factorization.solve(problem.f)
    out["time"] = time.perf_counter() - t
    out["lu_nnz"] = factorization.nnz
elif what == "colamd":
    import scipy.sparse.linalg as sla
    t = time.perf_counter()
    u = sla.splu(problem.K.tocsc()).solve(problem.f)
    out["time"] = time.perf_counter() - t
elif what in ("min", "fb"):
    t = time.perf_counter()
    r = solve_frictionless(problem, method=what)
    out.update(time=time.perf_counter() - t, J=r.njev, F=r.nfev,
               converged=bool(r.success), contact=r.n_contact,
               levels=len(r.levels), J_finest=r.levels[-1]["njev"])
    np.save(path + f".{what}.npy", r.u)
elif what in ("clarabel", "sfepy"):
    import peers
    geometry = contact_geometry(problem, "obstacle")
    t = time.perf_counter()
    if what == "clarabel":
        u, status = peers.clarabel_qp(problem, geometry)
        out["converged"] = status == "Solved"
    else:
        u, J, converged = peers.sfepy_semismooth_newton(problem, geometry)
        out.update(J=J, converged=bool(converged))
    out["time"] = time.perf_counter() - t
    ours = np.load(path + ".min.npy")
    out["agreement"] = float(np.abs(u - ours).max() / np.abs(ours).max())
elif what == "friction":
    t = time.perf_counter()
    r = solve_friction(problem, 0.3, steps=steps, formulation="projection",
                       method="min")
    out.update(time=time.perf_counter() - t, J=r.njev, F=r.nfev,
               converged=bool(r.success))
out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(json.dumps(out))
'''

COLUMNS = ["DOFs", "Nc", "export [s]", "floor [s]", "L+U nnz",
           "COLAMD [s]", "levels", "min [s]", "min/floor", "min J/F",
           "min J finest", "fb [s]", "fb/floor", "fb J/F", "fb J finest",
           "Clarabel [s]", "Clarabel/min",
           "SfePy SSN [s]", "SfePy/min", "SfePy J", "friction [s]",
           "friction/floor", "friction J/F", "floor RSS [MB]",
           "solve RSS [MB]", "RSS/floor", "friction RSS [MB]"]


def measure(path, what, steps=100):
    """Run one measurement in a fresh process; its JSON line as a dict."""
    env = dict(os.environ, PYTHONWARNINGS="ignore")
    result = subprocess.run(
        [sys.executable, "-c", MEASURE, str(path), what, str(steps),
         str(ROOT / "benchmarks")], capture_output=True, text=True,
        cwd=ROOT, env=env)
    if result.returncode != 0:
        raise RuntimeError(f"{what} failed: {result.stderr[-800:]}")
    return json.loads(result.stdout.strip().splitlines()[-1])


def export(mesh_args, name, folder):
    """Generate a mesh and export it with sfepy-run; (npz, export time)."""
    mesh = Path(folder) / f"{name}.mesh"
    subprocess.run([sys.executable, str(ROOT / "meshes" / "generate.py"),
                    *mesh_args, "-o", str(mesh)], check=True,
                   capture_output=True)
    npz = Path(folder) / f"{name}.npz"
    script = Path(sys.executable).parent / "sfepy-run"
    start = time.perf_counter()
    subprocess.run([str(script) if script.exists() else "sfepy-run",
                    str(ROOT / "sfepy_problems" / "block_obstacle.py"), "-d",
                    f"mesh='{mesh}', output='{npz}'"], check=True,
                   capture_output=True, cwd=folder)
    return npz, time.perf_counter() - start


def sizes(max_dofs):
    """(mesh arguments, name) of each size: refinements of the 1878 mesh
    (DOFs ≈ 1956·4^level), then ~10⁶ DOFs by gmsh if asked for."""
    level = 0
    while 1956 * 4 ** level <= max_dofs * 1.2 or level == 0:
        yield ["--refine", str(level), "--base", "1878"], f"block_r{level}"
        level += 1
    if max_dofs >= 9e5 and 1956 * 4 ** level > 1.3e6:
        yield ["--size", "0.0225", "--algorithm", "6"], "block_1M"


def row(npz, export_time, args):
    """Measure one size; the table row as a dict of strings."""
    floor = measure(npz, "floor")
    t0 = floor["time"]
    cells = {"DOFs": floor["dofs"], "Nc": floor["nc"],
             "export [s]": f"{export_time:.1f}", "floor [s]": f"{t0:.3g}",
             "L+U nnz": f"{floor['lu_nnz']:.3g}",
             "floor RSS [MB]": f"{floor['peak_rss_mb']:.0f}"}
    cells["COLAMD [s]"] = f"{measure(npz, 'colamd')['time']:.3g}"
    peak, times = 0.0, {}
    for method in ("min", "fb"):
        r = measure(npz, method)
        peak = max(peak, r["peak_rss_mb"])
        times[method] = r["time"]
        cells[f"{method} [s]"] = f"{r['time']:.3g}" + \
            ("" if r["converged"] else " (not converged)")
        cells[f"{method}/floor"] = f"{r['time'] / t0:.2f}"
        cells[f"{method} J/F"] = f"{r['J']}/{r['F']}"
        cells[f"{method} J finest"] = str(r["J_finest"])
        cells["levels"] = str(r["levels"])
    if floor["dofs"] <= args.max_peer_dofs:
        for peer, label in (("clarabel", "Clarabel"), ("sfepy", "SfePy")):
            if peer not in args.peers or (
                    peer == "sfepy" and floor["dofs"] > args.max_sfepy_dofs):
                continue
            c = measure(npz, peer)
            ok = c["agreement"] <= 1e-6
            name = "Clarabel [s]" if peer == "clarabel" else "SfePy SSN [s]"
            cells[name] = f"{c['time']:.3g}" + (
                "" if ok else f" (differs {c['agreement']:.0e})")
            cells[f"{label}/min"] = f"{c['time'] / times['min']:.1f}" \
                if ok else "–"
            if peer == "sfepy":
                cells["SfePy J"] = str(c["J"])
    if floor["dofs"] <= args.max_friction_dofs:
        r = measure(npz, "friction", args.steps)
        cells["friction RSS [MB]"] = f"{r['peak_rss_mb']:.0f}"
        cells["friction [s]"] = f"{r['time']:.3g}" + \
            ("" if r["converged"] else " (not converged)")
        cells["friction/floor"] = f"{r['time'] / t0:.1f}"
        cells["friction J/F"] = f"{r['J']}/{r['F']}"
    cells["solve RSS [MB]"] = f"{peak:.0f}"
    cells["RSS/floor"] = f"{peak / floor['peak_rss_mb']:.2f}"
    return cells


def available_peers(no_peers):
    peers = []
    if no_peers:
        return peers
    for module, name in (("clarabel", "clarabel"), ("sfepy", "sfepy")):
        try:
            __import__(module)
            peers.append(name)
        except ImportError:
            print(f"({module} not installed: its column is skipped)",
                  file=sys.stderr)
    return peers


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-dofs", type=float, default=1.3e5)
    parser.add_argument("--max-friction-dofs", type=float, default=1.3e5)
    parser.add_argument("--max-peer-dofs", type=float, default=1.1e6)
    parser.add_argument("--max-sfepy-dofs", type=float,
                        help="default: --max-peer-dofs")
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--no-peers", action="store_true")
    args = parser.parse_args(argv)
    args.peers = available_peers(args.no_peers)
    if args.max_sfepy_dofs is None:
        args.max_sfepy_dofs = args.max_peer_dofs
    print("| " + " | ".join(COLUMNS) + " |")
    print("|" + "---|" * len(COLUMNS), flush=True)
    with tempfile.TemporaryDirectory() as folder:
        for mesh_args, name in sizes(args.max_dofs):
            npz, export_time = export(mesh_args, name, folder)
            cells = row(npz, export_time, args)
            print("| " + " | ".join(str(cells.get(c, "–")) for c in COLUMNS)
                  + " |", flush=True)
            for leftover in Path(folder).glob(name + ".*"):
                leftover.unlink()
    return 0


if __name__ == "__main__":
    sys.exit(main())
