"""Hertz's two cylinders by dual mortar on triangles and on the same mesh
cut into quadrilaterals (issue 35: two bodies on quadrilaterals in 2D).

``meshes/two_body_cylinders.mesh`` (two half-discs, graded triangles) is
exported and solved as it is, then cut into three quadrilaterals per
triangle (``meshes/structured.py quads``: half the element size, the same
grading, each quadrilateral in its triangle's body) and exported and
solved again (``sfepy_problems/two_cylinders.py``, default data: R1 = 1,
R2 = 1.5, plane strain, δ aimed at a = 0.1 R1). Against plane-strain
Hertz (Johnson 1985, §4.3): a = 2√(P R*/(π E*)), p0 = 2P/(πa), with P the
computed interface force (the y component of Σ D t, t the slave
traction); a measured from the pressure's second moment, a² = 4 Σ x² λ D
/ Σ λ D; p0 the largest nodal pressure.

Usage::

    python benchmarks/two_cylinders_quad.py [--workdir DIR]
"""

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

from hertz_sphere_hex import ROOT, export_and_solve, run


def measure(mesh, workdir):
    """One row: DOFs, slave nodes, in contact, a and p0 errors (%), s."""
    problem, result, seconds = export_and_solve("two_cylinders.py", mesh,
                                                workdir)
    D = np.asarray(result.mortar_D)
    D = D if D.ndim == 1 else D.diagonal()
    lam = np.asarray(result.contact_pressure)
    P = abs((D @ np.asarray(result.traction))[1])
    r_star, e_star = problem.meta["R_star"], problem.meta["E_star"]
    a_hertz = 2 * np.sqrt(P * r_star / (np.pi * e_star))
    p0_hertz = 2 * P / (np.pi * a_hertz)
    x = problem.nodes[problem.contact_nodes, 0]
    a = 2 * np.sqrt((D * lam * x ** 2).sum() / (D * lam).sum())
    return [f"{problem.n_dofs}", f"{problem.n_contact}",
            f"{int((lam > 0).sum())}", f"{100 * (a / a_hertz - 1):+.2f}",
            f"{100 * (lam.max() / p0_hertz - 1):+.2f}", f"{seconds:.1f}"]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workdir", type=Path, default=None)
    args = parser.parse_args(argv)
    workdir = args.workdir or Path(tempfile.mkdtemp(prefix="cyl_quad_"))
    workdir.mkdir(parents=True, exist_ok=True)
    triangles = ROOT / "meshes" / "two_body_cylinders.mesh"
    quads = workdir / "two_body_cylinders_quad.mesh"
    run(ROOT / "meshes" / "structured.py", "quads", triangles, "-o", quads)
    print("| cells | DOFs | slave nodes | in contact | a moment err % | "
          "p0 err % | solve s |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, mesh in (("triangles", triangles), ("quadrilaterals", quads)):
        print(f"| {name} | " + " | ".join(measure(mesh, workdir)) + " |",
              flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
