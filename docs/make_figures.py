"""Regenerate the key figures of the README into docs/figures/.

Usage (from the repository root, after ``pip install .``)::

    python docs/make_figures.py            # into docs/figures/
    python docs/make_figures.py --out DIR  # elsewhere (tests/test_make_figures.py)

Exports the thesis block on the 454-element mesh with SfePy (``sfepy-run``),
then solves it and the 2-DOF bar with the library and saves PNGs; then the
3D two-body output (``meshes/two_spheres.py`` at a/h 6, the README's
commands): two unequal spheres, the interface pressure against the radius
with Hertz's profile, and two identical spheres pressed then sheared
(Cattaneo–Mindlin), the stick/slip map of the slave surface. Units as
everywhere in the figures (``solver.output.figures.UNITS``): lengths in mm,
forces in N, pressures in MPa, plane strain per mm of thickness.
"""

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from solver import load_problem, solve, two_dof_bar
from solver.examples import two_dof_bar_closed_form
from solver.output import figures, friction_figures

ROOT = Path(__file__).resolve().parent.parent
FIGURES = ROOT / "docs" / "figures"


def export_block(folder, elements=454):
    script = Path(sys.executable).parent / "sfepy-run"
    npz = Path(folder) / f"block_{elements}.npz"
    subprocess.run([str(script) if script.exists() else "sfepy-run",
                    str(ROOT / "sfepy_problems" / "block_obstacle.py"), "-d",
                    f"mesh='{ROOT / 'meshes' / f'block_{elements}.mesh'}', "
                    f"output='{npz}'"], check=True, capture_output=True)
    return load_problem(npz)


def export_spheres(folder, name, mesh_args, **define):
    """meshes/two_spheres.py then sfepy_problems/two_spheres.py, as the
    README's commands."""
    mesh = Path(folder) / f"{name}.mesh"
    npz = Path(folder) / f"{name}.npz"
    subprocess.run([sys.executable, str(ROOT / "meshes" / "two_spheres.py"),
                    *mesh_args, "-o", str(mesh)], check=True,
                   capture_output=True)
    script = Path(sys.executable).parent / "sfepy-run"
    extra = "".join(f", {k}={v!r}" for k, v in define.items())
    subprocess.run([str(script) if script.exists() else "sfepy-run",
                    str(ROOT / "sfepy_problems" / "two_spheres.py"), "-d",
                    f"mesh='{mesh}', output='{npz}'{extra}"], check=True,
                   capture_output=True)
    return load_problem(npz)


def two_body_figures(out):
    """two_spheres_pressure.png and two_spheres_stick_slip.png."""
    from solver.output.two_body3d import (plot_interface3d,
                                          plot_stick_slip_map)

    plt = figures.pyplot()
    with tempfile.TemporaryDirectory() as folder:
        spheres = export_spheres(folder, "spheres", ["--a-over-h", "6"])
        cm = export_spheres(folder, "cm", ["--a-over-h", "6", "--radii",
                                           "1", "1", "--half"],
                            R1=1.0, E1=2e5, nu1=0.3, delta=0.00485,
                            load="cattaneo", shift=1.5e-3)
    r = solve(spheres)
    plt.close(plot_interface3d(spheres, r,
                               out / "two_spheres_pressure.png"))
    r = solve(cm, friction=0.5)
    plt.close(plot_stick_slip_map(cm, r, out / "two_spheres_stick_slip.png"))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=FIGURES,
                        help="folder of the PNG files (default docs/figures)")
    out = parser.parse_args(argv).out
    out.mkdir(parents=True, exist_ok=True)
    plt = figures.pyplot()
    with tempfile.TemporaryDirectory() as folder:
        block = export_block(folder)
    for method in ("fb", "min"):
        # the thesis's full system: the histories that Table 1 compares
        r = solve(block, method=method, system="full")
        plt.close(figures.plot_convergence(
            r, out / f"frictionless_convergence_{method}.png"))
    plt.close(figures.plot_deformed(block, r,
                                    path=out / "frictionless_deformed.png"))
    plt.close(figures.plot_contact_pressure(
        block, r, out / "frictionless_pressure.png"))
    bar = two_dof_bar()
    for fc, name in ((10.0, "10"), (0.5, "0.5")):
        r = solve(bar, friction=fc, steps=100, formulation="thesis")
        exact = np.array([two_dof_bar_closed_form(k, fc)
                          for k in range(1, 101)])
        plt.close(friction_figures.plot_step_history(
            bar, r, reference=exact, path=out / f"bar_fc{name}.png"))
    r = solve(block, friction=0.3, steps=100, formulation="thesis")
    plt.close(friction_figures.plot_friction_along_boundary(
        block, r, path=out / "friction_tractions_fc0.3.png"))
    last = SimpleNamespace(displacement=r.displacement[-1],
                           in_contact=r.in_contact[-1])
    plt.close(figures.plot_deformed(
        block, last, path=out / "friction_deformed_fc0.3.png",
        title=f"after {r.steps_completed} load steps, f_c = 0.3, "
              f"{r.formulation} formulation"))
    two_body_figures(out)
    for path in sorted(out.glob("*.png")):
        print(path)


if __name__ == "__main__":
    main()
