"""Two unequal spheres in 3D by the dual mortar on both linear paths
(issue 33 point 5): the factorisation (``auto``) against AMG
(``backend="amg"``), mesh by mesh, each solve in a fresh process.

Usage::

    python benchmarks/two_spheres_amg.py [--a-over-h 8,16,24,32]
                                         [--workdir DIR] [--friction]
                                         [--steps N] [--paths auto,amg]

The problem is ``benchmarks/two_spheres3d.py``'s (``sfepy_problems/
two_spheres.py`` on ``meshes/two_spheres.py --a-over-h N``, made and
exported by its ``prepare``, reused from ``--workdir`` when there). For
each mesh and each path, one child process loads the problem file and
runs ``solve(problem)`` (frictionless) or, with ``--friction``,
``solve(problem, friction=0.3, coulomb="lagged", steps=N)`` (the lagged
bound: CG on every Newton system of the AMG path), with ``backend="amg"``
on the AMG path; so the peak RSS (``ru_maxrss`` of the child, loading
included) is the path's own. One Markdown row per path:

* **path**: the one asked for and, in brackets, the linear solver the
  solve reports (``auto`` takes AMG when the factor would not fit);
* **Newton systems / Jacobians**: ``njev`` (summed over the load steps);
* **CG per system (mean, max)**: the AMG path's Krylov iterations per
  Newton system (with friction the mean alone: a load step's record
  keeps its total);
* **CPU s, wall s**: the solve alone (process CPU time, all threads),
  without start-up and loading; **peak RSS**: the whole child;
* **‖Δu‖/‖u‖**: ‖u_amg − u_auto‖₂ / ‖u_auto‖₂ of the final displacement
  (on the AMG row; "(step k)" if a friction run stopped early: the last
  load step both reached);
* **a, p₀ vs Hertz**: :func:`solver.studies3d.hertz_checks`, a from the
  first moment of the nodal forces and p₀ from the fit of (a, p₀) to the
  nodal pressures, relative to Hertz's values for the pair's total force
  (with friction, the dissimilar spheres' tangential coupling is not in
  Hertz's solution);
* **load**: the 1-minute load average before and after the row.

The exit status is 1 if any solve did not converge and pass the
verification.
"""

import argparse
import json
import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(1, str(HERE.parent))

COLUMNS = ["a/h", "contact", "DOFs", "slave nodes", "in contact", "path",
           "Newton systems / Jacobians", "CG per system (mean, max)",
           "CPU [s]", "wall [s]", "peak RSS [MB]", "‖Δu‖/‖u‖",
           "a (moment) vs Hertz", "p₀ (fit) vs Hertz", "load"]


def child(npz, path, friction, steps, out):
    """One solve in this process: its JSON record on stdout, u in
    ``out`` (.npy)."""
    import numpy as np

    from measure import Clock
    from solver import load_problem, solve
    from solver.studies3d import hertz_checks

    problem = load_problem(npz)
    options = {} if path == "auto" else {"backend": path}
    if friction:
        options.update(friction=0.3, coulomb="lagged", steps=steps)
    with Clock() as clock:
        result = solve(problem, **options)
    np.save(out, result.u)
    if friction:
        krylov = []  # a load step's record keeps its total alone
        total = sum(r.get("krylov") or 0 for r in result.records)
    else:
        krylov = list((result.get("history") or {}).get("krylov") or [])
        total = sum(krylov)
    check = hertz_checks(problem, result)
    print(json.dumps({
        "dofs": int(problem.n_dofs), "slave": int(problem.n_contact),
        "a_over_h": check["a_over_h"], "in_contact": check["in_contact"],
        "solver": result.linear_solver, "njev": int(result.njev),
        "krylov": [int(k) for k in krylov], "krylov_total": int(total),
        "ok": bool(result.success and result.verification["passed"]),
        "steps": len(result.records) if friction else 1,
        "message": str(result.message),
        "a_moment": check["a_moment"], "p0_fit": check["p0_fit"],
        **clock.times}))


def row(npz, path, friction, steps, out):
    """(cells, record) of one path on one problem file, in a fresh
    process."""
    from processes import run_measured

    load = os.getloadavg()[0]
    run = run_measured([sys.executable, HERE / "two_spheres_amg.py",
                        "--child", npz, path, str(int(friction)),
                        str(steps), out])
    r = json.loads(run["stdout"].strip().splitlines()[-1])
    systems = r["njev"]
    if r["krylov"]:
        cg = (f"{sum(r['krylov']) / len(r['krylov']):.1f}, "
              f"{max(r['krylov'])}")
    elif r["krylov_total"]:
        cg = f"{r['krylov_total'] / max(systems, 1):.1f}, –"
    else:
        cg = "–"
    cells = {
        "a/h": f"{r['a_over_h']:.1f}",
        "contact": "friction (lagged)" if friction else "frictionless",
        "DOFs": f"{r['dofs']:,}", "slave nodes": f"{r['slave']:,}",
        "in contact": str(r["in_contact"]),
        "path": f"{path} ({r['solver']})",
        "Newton systems / Jacobians": str(systems),
        "CG per system (mean, max)": cg,
        "CPU [s]": f"{r['cpu']:.2f}", "wall [s]": f"{r['time']:.2f}",
        "peak RSS [MB]": f"{run['rss']:.0f}", "‖Δu‖/‖u‖": "–",
        "a (moment) vs Hertz": f"{r['a_moment']:+.2%}",
        "p₀ (fit) vs Hertz": f"{r['p0_fit']:+.2%}",
        "load": f"{load:.1f} → {os.getloadavg()[0]:.1f}"}
    if not r["ok"]:
        cells["path"] += (f" NOT CONVERGED (steps done: {r.get('steps')}; "
                          f"{r.get('message', '')[:60]})")
    return cells, r


def level(a_over_h, folder, paths, friction, steps):
    """The rows of one mesh: every path, then the agreement of each
    later path with the first on its row."""
    import numpy as np

    from processes import run_measured

    mesh = folder / f"two_spheres_{float(a_over_h):g}.mesh"
    npz = folder / (mesh.stem + ".npz")
    if not npz.exists():  # the export in its own process too
        run_measured([sys.executable, HERE / "two_spheres_amg.py",
                      "--prepare", mesh])
    rows, ok = [], True
    tag = "friction" if friction else "frictionless"
    for path in paths:
        out = folder / f"{mesh.stem}.{tag}.{path}.npy"
        cells, record = row(npz, path, friction, steps, out)
        ok &= record["ok"]
        if rows:
            # the last load step's u (a friction run keeps every step's);
            # if a run stopped early, the last step both reached
            u, reference = (np.atleast_2d(np.load(f)) for f in (
                out, folder / f"{mesh.stem}.{tag}.{paths[0]}.npy"))
            step = min(len(u), len(reference))
            error = np.linalg.norm(u[step - 1] - reference[step - 1]) / \
                np.linalg.norm(reference[step - 1])
            cells["‖Δu‖/‖u‖"] = f"{error:.1e}" + (
                "" if len(u) == len(reference) else f" (step {step})")
        rows.append(cells)
    return rows, ok


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--a-over-h", default="8,16,24,32",
                        help="a/h of the meshes, separated by commas")
    parser.add_argument("--workdir", help="keep meshes and exports here")
    parser.add_argument("--paths", default="auto,amg",
                        help="backends, the first the reference of Δu")
    parser.add_argument("--friction", action="store_true",
                        help="f_c = 0.3, the lagged bound, --steps steps")
    parser.add_argument("--steps", type=int, default=5)
    parser.add_argument("--child", nargs=5, help=argparse.SUPPRESS)
    parser.add_argument("--prepare", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        npz, path, friction, steps, out = args.child
        child(npz, path, friction == "1", int(steps), out)
        return 0
    if args.prepare:
        from two_spheres3d import prepare
        prepare(Path(args.prepare), Path(args.prepare).parent)
        return 0
    import tempfile

    ok = True
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(args.workdir or scratch)
        folder.mkdir(parents=True, exist_ok=True)
        print("| " + " | ".join(COLUMNS) + " |")
        print("|" + "---|" * len(COLUMNS), flush=True)
        for n in args.a_over_h.split(","):
            rows, good = level(n, folder, args.paths.split(","),
                               args.friction, args.steps)
            ok &= good
            for cells in rows:
                print("| " + " | ".join(cells[c] for c in COLUMNS) + " |",
                      flush=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
