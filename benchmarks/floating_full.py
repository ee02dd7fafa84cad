"""Bodies held only by contact on the full system (issue 31 point 2):
``system='full'`` against ``system='condensed'`` on the force-loaded
problem files, each solve in this process (best of ``--repeat`` after a
warm-up, the problem reloaded every time). Prints one Markdown row per
problem and method: DOFs, rigid modes, Newton counts (J / F) of both
systems, wall and process CPU times and their ratios (full / condensed,
measured in the same run), and the largest difference of u relative to
the condensed u. For comparison, the displacement-loaded Hertz cylinder
on both systems (``--system full`` from the thesis's u = 0).

    python benchmarks/floating_full.py [--repeat N]
"""

import argparse
import importlib.util
import os
import pathlib
import sys
import tempfile
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import solver  # noqa: E402

#: (name, problem file, define() keywords)
PROBLEMS = [
    ("Hertz cylinder, d (supported)", "hertz_cylinder.py",
     dict(mesh="meshes/hertz.mesh")),
    ("Hertz cylinder, P", "hertz_cylinder.py",
     dict(mesh="meshes/hertz.mesh", load="force", P=1739.6)),
    ("block on the floor, weight", "block_on_floor.py",
     dict(mesh="meshes/block_454.mesh")),
    ("quarter sphere a/h 4, P", "hertz_sphere.py",
     dict(mesh="meshes/hertz_sphere_4.mesh", load="force", P=36.63)),
    ("two cylinders, upper under P", "two_cylinders.py",
     dict(mesh="meshes/two_body_cylinders.mesh", load="force")),
]


def _export_module():
    name = "_contact_ssn_sfepy_export"
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(
            name, ROOT / "sfepy_problems" / "_export.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


def timed(path, repeat, **options):
    """(best wall, best CPU, result) of ``solver.solve`` on the file."""
    wall = cpu = np.inf
    result = None
    for _ in range(repeat + 1):  # the first run warms up
        problem = solver.load_problem(path)
        clock, process = time.perf_counter(), time.process_time()
        result = solver.solve(problem, **options)
        wall = min(wall, time.perf_counter() - clock)
        cpu = min(cpu, time.process_time() - process)
    assert result.success, result.message
    return wall, cpu, result


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args(argv)
    export = _export_module()
    print(f"load average {os.getloadavg()[0]:.1f} (2 cores)")
    print("| problem | method | DOFs | modes | J / F condensed | J / F full "
          "| wall cond. [s] | wall full [s] | wall ratio | CPU ratio "
          "| max Δu / max u |")
    print("|---|---|---:|---:|---|---|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as folder:
        for name, filename, define in PROBLEMS:
            path = pathlib.Path(folder) / f"{len(name)}_{filename}.npz"
            define = dict(define, mesh=str(ROOT / define["mesh"]))
            export.export_only(ROOT / "sfepy_problems" / filename,
                               output=str(path), **define)
            problem = solver.load_problem(path)
            modes = problem.rigid_modes()[0].shape[1]
            for method in ("min", "fb"):
                w_c, c_c, r_c = timed(path, args.repeat, method=method,
                                      system="condensed")
                w_f, c_f, r_f = timed(path, args.repeat, method=method,
                                      system="full")
                du = np.abs(r_f.u - r_c.u).max() / np.abs(r_c.u).max()
                print(f"| {name} | {method} | {problem.n_dofs:,} | {modes} "
                      f"| {r_c.njev} / {r_c.nfev} | {r_f.njev} / "
                      f"{r_f.nfev} | {w_c:.3f} | {w_f:.3f} "
                      f"| {w_f / w_c:.1f} | {c_f / c_c:.1f} | {du:.1e} |",
                      flush=True)


if __name__ == "__main__":
    sys.exit(main())
