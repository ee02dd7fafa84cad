"""Scaling benchmark: the thesis block refined, against one linear solve.

Usage::

    python benchmarks/run.py [--max-dofs N] [--max-friction-dofs N]
                             [--steps N] [--no-clarabel]

For each uniform refinement of the 1878-element thesis mesh (4× the
triangles per level) up to ``--max-dofs`` reduced DOFs it prints one row:
DOFs, Nc, the SfePy export time, the *floor* (one SuperLU factorisation and
solve of K u = f, the cost every contact solve pays at least), the
frictionless solve times of φ_min and φ_FB with their ratio to the floor and
their J/F counts, Clarabel on the same QP (if installed; its time counts
only when it reaches our u within 1e-6), and a friction run (``--steps``
steps, f_c = 0.3, projection form, φ_min) up to ``--max-friction-dofs``.
Every measurement of one size runs in a fresh process, whose peak resident
memory is reported. Ratios are measured in the same run; absolute times are
indicative only (shared, noisy machines).
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
import scipy.sparse.linalg as sla
from solver import load_problem, solve_frictionless, solve_friction
from solver.contact import contact_geometry

path, what, steps = sys.argv[1], sys.argv[2], int(sys.argv[3])
problem = load_problem(path)
problem.check_stiffness()
out = {"dofs": problem.n_dofs, "nc": problem.n_contact}
if what == "floor":
    t = time.perf_counter()
    lu = sla.splu(problem.K.tocsc())
    u = lu.solve(problem.f)
    out["floor"] = time.perf_counter() - t
    out["lu_nnz"] = int(lu.L.nnz + lu.U.nnz)
elif what in ("min", "fb"):
    geometry = contact_geometry(problem, "obstacle")
    t = time.perf_counter()
    r = solve_frictionless(problem, method=what, geometry=geometry)
    out.update(time=time.perf_counter() - t, J=r.njev, F=r.nfev,
               converged=bool(r.success), contact=r.n_contact)
    np.save(path + f".{what}.npy", r.u)
elif what == "clarabel":
    import clarabel
    import scipy.sparse as sp
    g = contact_geometry(problem, "obstacle")
    n, m = problem.n_dofs, len(g.gap)
    k = problem.K.diagonal().mean()
    C = sp.csc_matrix((g.normal.ravel(), (np.repeat(np.arange(m), 2),
                       g.dofs.ravel())), shape=(m, n))
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    # defaults (1e-8) stop ~4e-6 from the solution; 1e-10 reaches 5e-8 in u
    settings.tol_gap_abs = settings.tol_gap_rel = settings.tol_feas = 1e-10
    t = time.perf_counter()
    s = clarabel.DefaultSolver(sp.triu(problem.K / k).tocsc(), -problem.f / k,
                               C, g.gap, [clarabel.NonnegativeConeT(m)],
                               settings).solve()
    out["time"] = time.perf_counter() - t
    ours = np.load(path + ".min.npy")
    err = float(np.abs(np.asarray(s.x) - ours).max() / np.abs(ours).max())
    out.update(status=str(s.status), agreement=err)
elif what == "friction":
    t = time.perf_counter()
    r = solve_friction(problem, 0.3, steps=steps, formulation="projection",
                       method="min")
    out.update(time=time.perf_counter() - t, J=r.njev, F=r.nfev,
               converged=bool(r.success))
out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(json.dumps(out))
'''


def measure(path, what, steps=100):
    result = subprocess.run([sys.executable, "-c", MEASURE, str(path), what,
                             str(steps)], capture_output=True, text=True,
                            cwd=ROOT)
    if result.returncode != 0:
        raise RuntimeError(f"{what} failed: {result.stderr[-500:]}")
    return json.loads(result.stdout.strip().splitlines()[-1])


def export(level, folder):
    mesh = Path(folder) / f"block_r{level}.mesh"
    subprocess.run([sys.executable, str(ROOT / "meshes" / "generate.py"),
                    "--refine", str(level), "--base", "1878", "-o",
                    str(mesh)], check=True, capture_output=True)
    npz = Path(folder) / f"block_r{level}.npz"
    script = Path(sys.executable).parent / "sfepy-run"
    start = time.perf_counter()
    subprocess.run([str(script) if script.exists() else "sfepy-run",
                    str(ROOT / "sfepy_problems" / "block_obstacle.py"), "-d",
                    f"mesh='{mesh}', output='{npz}'"], check=True,
                   capture_output=True)
    return npz, time.perf_counter() - start


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-dofs", type=float, default=1.3e5)
    parser.add_argument("--max-friction-dofs", type=float, default=1e4)
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--no-clarabel", action="store_true")
    args = parser.parse_args(argv)
    try:
        import clarabel  # noqa: F401
        use_clarabel = not args.no_clarabel
    except ImportError:
        use_clarabel = False
    columns = ["DOFs", "Nc", "export [s]", "floor [s]", "L+U nnz",
               "min [s]", "min/floor", "min J/F", "fb [s]", "fb/floor",
               "fb J/F", "Clarabel [s]", "Clarabel/floor", "friction [s]",
               "friction/floor", "friction J/F", "peak RSS [MB]"]
    print("| " + " | ".join(columns) + " |")
    print("|" + "---|" * len(columns))
    with tempfile.TemporaryDirectory() as folder:
        level = 0
        while True:
            npz, export_time = export(level, folder)
            floor = measure(npz, "floor")
            if floor["dofs"] > args.max_dofs and level > 0:
                break
            row = {"DOFs": floor["dofs"], "Nc": floor["nc"],
                   "export [s]": f"{export_time:.1f}",
                   "floor [s]": f"{floor['floor']:.3g}",
                   "L+U nnz": f"{floor['lu_nnz']:.3g}"}
            peak = floor["peak_rss_mb"]
            for method in ("min", "fb"):
                r = measure(npz, method)
                peak = max(peak, r["peak_rss_mb"])
                row[f"{method} [s]"] = f"{r['time']:.3g}" + \
                    ("" if r["converged"] else " (not converged)")
                row[f"{method}/floor"] = f"{r['time'] / floor['floor']:.1f}"
                row[f"{method} J/F"] = f"{r['J']}/{r['F']}"
            if use_clarabel:
                c = measure(npz, "clarabel")
                ok = c["agreement"] <= 1e-6
                row["Clarabel [s]"] = f"{c['time']:.3g}" + \
                    ("" if ok else f" (differs {c['agreement']:.0e})")
                row["Clarabel/floor"] = f"{c['time'] / floor['floor']:.1f}" \
                    if ok else "–"
            if floor["dofs"] <= args.max_friction_dofs:
                r = measure(npz, "friction", args.steps)
                peak = max(peak, r["peak_rss_mb"])
                row["friction [s]"] = f"{r['time']:.3g}"
                row["friction/floor"] = f"{r['time'] / floor['floor']:.0f}"
                row["friction J/F"] = f"{r['J']}/{r['F']}"
            row["peak RSS [MB]"] = f"{peak:.0f}"
            print("| " + " | ".join(str(row.get(c, "–")) for c in columns)
                  + " |", flush=True)
            if floor["dofs"] * 4 > args.max_dofs * 1.2:
                break
            level += 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
