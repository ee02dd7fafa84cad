"""A force on a body held only by contact against the displacement that
gives the same force (issue 31): the Hertz half-cylinder
(``sfepy_problems/hertz_cylinder.py``) on refinements of its mesh, each
exported twice, ``load='displacement'`` (the top edge pressed down by d,
K positive definite) and ``load='force'`` (P = that run's total contact
force as a traction on the top edge: two rigid-body modes held by the
contact only). Prints one Markdown row per mesh: DOFs, the Newton counts
(J) of both solves, their wall times (best of ``--repeat``, each solve in
this process after one warm-up: the factorisations are made anew every
time, the problem objects rebuilt from the files) and the ratio, and the
relative difference of the two contact pressures (not the same problem:
the top edge straight or uniformly loaded).

    python benchmarks/floating.py [--h-contact H ...] [--repeat N]
"""

import argparse
import importlib.util
import pathlib
import sys
import tempfile
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import solver  # noqa: E402


def _module(name, path):
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


def export_cylinder(folder, h, h_far, name, **options):
    """The Hertz half-cylinder's mesh of contact size ``h`` written to
    ``folder`` and exported by SfePy (``sfepy_problems/hertz_cylinder.py``
    with ``options``, e.g. load='force', P=...) to ``folder/name.npz``;
    returns that path (also of benchmarks/floating_amg.py)."""
    hertz = _module("_contact_ssn_meshes_hertz", ROOT / "meshes" / "hertz.py")
    export = _module("_contact_ssn_sfepy_export",
                     ROOT / "sfepy_problems" / "_export.py")
    mesh = folder / f"hertz_{h}.mesh"
    if not mesh.exists():
        hertz.write_mesh(mesh, *hertz.hertz_mesh(h, h_far))
    path = folder / f"{name}.npz"
    export.export_only(ROOT / "sfepy_problems" / "hertz_cylinder.py",
                       mesh=str(mesh), output=str(path), **options)
    return path


def timed(path, repeat):
    best, result = np.inf, None
    for _ in range(repeat + 1):  # the first run warms up
        problem = solver.load_problem(path)
        clock = time.perf_counter()
        result = solver.solve(problem)
        best = min(best, time.perf_counter() - clock)
    assert result.success, result.message
    return best, result, problem


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--h-contact", type=float, nargs="+",
                        default=[0.004, 0.002, 0.001])
    parser.add_argument("--h-far", type=float, default=0.02)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    print("| DOFs | contact nodes | in contact | J displacement | J force "
          "| displacement [s] | force [s] | force / displacement "
          "| max Δp / p0 |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as folder:
        folder = pathlib.Path(folder)
        for h in args.h_contact:
            moved = export_cylinder(folder, h, args.h_far, f"d_{h}")
            t_d, r_d, p_d = timed(moved, args.repeat)
            P = float(r_d.total_contact_force[1])
            loaded = export_cylinder(folder, h, args.h_far, f"f_{h}",
                                     load="force", P=P)
            t_f, r_f, p_f = timed(loaded, args.repeat)
            p0 = r_d.contact_pressure.max()
            dp = np.abs(r_f.contact_pressure - r_d.contact_pressure).max()
            print(f"| {p_f.n_dofs:,} | {p_f.n_contact} | {r_f.n_contact} "
                  f"| {r_d.njev} | {r_f.njev} | {t_d:.3f} | {t_f:.3f} "
                  f"| {t_f / t_d:.2f} | {dp / p0:.2e} |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
