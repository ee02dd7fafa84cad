"""Two unequal spheres in 3D by the dual mortar (issue 32): accuracy
against Hertz and time against the fastest factorisation of K.

Usage::

    python benchmarks/two_spheres3d.py [--a-over-h N] [--workdir DIR]
                                       [--backends a,b] [--mesh FILE]

The problem: ``sfepy_problems/two_spheres.py`` (a quarter model of two
unequal spheres, defaults: R = 1 and 1.5, E = 2e5 and 1e5, ν = 0.3 and
0.25) on ``meshes/two_spheres.py --a-over-h N`` (default 22: about 10⁵
DOFs), exported in-process (SfePy assembles, solves nothing). Then, in
this process:

* **floor** ``<backend>``: factorise K (both bodies, block-diagonal) and
  solve K u = f once (``measure.floor``); **fastest**: the shortest;
* **mortar**: the solve's ``geometry_time``, what :func:`solver.solve`
  does before it iterates: the mortar integration (pair search, clipping,
  D and M on the triangles), the case's check for rigid-body modes, the
  change of variables K̃ = T⁻ᵀKT⁻¹ and the contact geometry (an upper
  bound on the integration alone);
* **solve**: ``solve(problem)``, every argument at its default (the
  backend "auto": PARDISO when installed, whose bordered factorisation of
  K condenses the candidates; mortar coupling, change of variables, the
  condensed Newton on the candidates, verification, mapping back), "time
  (time / fastest floor)", and the mortar integration's share of it. Not
  the backend of the fastest floor: K's floors of PARDISO and CHOLMOD are
  within noise of each other, but CHOLMOD condenses from the glued K̃
  (several times slower);
* Hertz's checks (:func:`solver.studies3d.hertz_checks`): a/h on the
  slave, a from the first moment, (a, p0) fitted, the largest λ_j, where
  it lies (r/a) and the nodes' scatter about Hertz's profile inside 0.9 a
  (RMS and largest, over p0); then the same of the patch-recovered
  pressure p̄_j (``result.contact_pressure_patch``, "p̄" columns).

``--a-over-h 16,22,32`` runs one mesh after the other (a refinement);
``--runs N`` repeats each mesh's measurement N times (floors and solve,
the problem loaded afresh each time). It prints one Markdown table, a row
per run (wall times; CPU times, all threads of the process, in brackets;
"load": the 1-minute load average before and after the row, the
machine's other work that the wall ratios include).
"""

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(1, str(ROOT))


def export(mesh, npz):
    """The two-sphere problem file exported in-process."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "_contact_ssn_sfepy_export", ROOT / "sfepy_problems" / "_export.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    module.export_only(ROOT / "sfepy_problems" / "two_spheres.py",
                       mesh=str(mesh), output=str(npz))


def prepare(mesh, folder):
    """(the exported problem file, seconds taken) of ``mesh``, a
    ``two_spheres_<a/h>.mesh`` in ``folder``: the mesh is made by
    ``meshes/two_spheres.py`` if missing and exported if its ``.npz`` is
    missing (each reused otherwise, then 0 s)."""
    clock = time.perf_counter()
    mesh = Path(mesh)
    if not mesh.exists():
        import subprocess
        a_over_h = mesh.stem.rsplit("_", 1)[-1]
        subprocess.run([sys.executable,
                        str(ROOT / "meshes" / "two_spheres.py"),
                        "--a-over-h", a_over_h, "-o", str(mesh)],
                       check=True)
    npz = Path(folder) / (mesh.stem + ".npz")
    if not npz.exists():
        export(mesh, npz)
    return npz, time.perf_counter() - clock


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--a-over-h", default="22",
                        help="a/h, or several separated by commas")
    parser.add_argument("--workdir")
    parser.add_argument("--mesh", help="an existing two_spheres mesh")
    parser.add_argument("--backends")
    parser.add_argument("--runs", type=int, default=1,
                        help="measurements per mesh")
    args = parser.parse_args(argv)
    from run import installed

    backends, _ = installed(args.backends, True)
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(args.workdir or scratch)
        folder.mkdir(parents=True, exist_ok=True)
        meshes = [Path(args.mesh)] if args.mesh else [
            folder / f"two_spheres_{float(n):g}.mesh"
            for n in args.a_over_h.split(",")]
        for mesh in meshes:
            for _ in range(args.runs):
                rows.append(measure(mesh, folder, backends))
                if len(rows) == 1:
                    print("| " + " | ".join(rows[0][0]) + " |")
                    print("|" + "---|" * len(rows[0][0]))
                print("| " + " | ".join(str(v) for v in
                                        rows[-1][0].values()) + " |",
                      flush=True)
    return 0 if all(ok for _, ok in rows) else 1


def measure(mesh, folder, backends):
    """(the table's cells, converged) of one mesh (made if missing)."""
    from measure import Clock, floor
    from solver import load_problem, solve
    from solver.studies3d import hertz_checks

    load = os.getloadavg()[0]
    npz, prepared = prepare(mesh, folder)
    problem = load_problem(npz)
    floors = {b: floor(problem, b) for b in backends}
    fastest = min(floors, key=lambda b: floors[b]["time"])
    with Clock() as run:
        result = solve(problem)
    check = hertz_checks(problem, result)
    base = floors[fastest]
    cells = {
        "DOFs": problem.n_dofs, "slave nodes": problem.n_contact,
        "a/h": f"{check['a_over_h']:.1f}",
        "mesh + export [s]": f"{prepared:.0f}",
        **{f"floor {b} [s]": f"{t['time']:.2f} ({t['cpu']:.2f})"
           for b, t in floors.items()},
        "mortar [s]": f"{result.geometry_time:.2f} "
                      f"({result.geometry_time / run.times['time']:.1%} of "
                      "the solve)",
        f"solve {result.linear_solver} [s] (/{fastest} floor)":
            f"{run.times['time']:.2f} ({run.times['time'] / base['time']:.2f}"
            f"; CPU {run.times['cpu'] / base['cpu']:.2f})"
            + ("" if result.success else " NOT CONVERGED"),
        "solve CPU [s]": f"{run.times['cpu']:.2f}",
        "load": f"{load:.1f} → {os.getloadavg()[0]:.1f}",
        "J/F": f"{result.njev}/{result.nfev}",
        "in contact": check["in_contact"],
        "a moment": f"{check['a_moment']:+.2%}",
        "a fit": f"{check['a_fit']:+.2%}",
        "p0 fit": f"{check['p0_fit']:+.2%}",
        "max p (at r/a)": f"{check['max_p']:+.2%} ({check['max_p_r']:.2f})",
        "scatter RMS / max": f"{check['nodal_rms']:.2%} / "
                             f"{check['nodal_max']:.2%}",
        "p̄: a fit": f"{check['a_fit_patch']:+.2%}",
        "p̄: p0 fit": f"{check['p0_fit_patch']:+.2%}",
        "p̄: max (at r/a)": f"{check['max_p_patch']:+.2%} "
                            f"({check['max_p_r_patch']:.2f})",
        "p̄: scatter RMS / max": f"{check['nodal_rms_patch']:.2%} / "
                                f"{check['nodal_max_patch']:.2%}",
    }
    return cells, bool(result.success)


if __name__ == "__main__":
    sys.exit(main())
