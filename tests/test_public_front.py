"""The notebooks, the benchmarks and docs/make_figures.py solve through the
public front (issue 30, point 5).

A name imported from ``solver`` must be public (``solver.__all__``) and
not one of the compatibility wrappers of :func:`solver.solve`; a module
below ``solver`` may be imported only where :data:`BELOW_THE_FRONT` says
why (none of them solves a contact problem: tables, closed forms and
figures, and what a benchmark measures below the front on purpose).
"""

import ast

import nbformat
import pytest

import solver
from conftest import ROOT

#: The thin wrappers of solver.solve kept for old callers only.
WRAPPERS = {"solve_frictionless", "solve_friction", "solve_two_body"}

#: Modules below the front that these files may import, and why.
BELOW_THE_FRONT = {
    "solver.studies": "the thesis's tables as data and their study loops",
    "solver.studies3d": "the Hertz sphere's table row, the 3D two-body "
                        "checks",
    "solver.verification": "closed forms (Hertz, Cattaneo-Mindlin, Sneddon)",
    "solver.examples": "the bar's closed form (two_dof_bar_closed_form)",
    "solver.output.thesis_figures": "the thesis's figures",
    "solver.output.figures3d": "the 3D pressure plot",
    "solver.output.figures": "the README's figures (make_figures.py)",
    "solver.output.two_body3d": "the 3D two-body figures of docs/figures "
                                "(make_figures.py)",
    "solver.output.friction_figures": "the README's figures (make_figures.py)",
    "solver.linalg": "benchmarks: the floor, one factorisation of K by a "
                     "backend, and the list of backends; the AMG path's "
                     "floor, one AMG-PCG solve of K u = f (measure.py "
                     "amg_floor)",
    "solver.contact.friction.disc": "benchmarks: the whole-LU Newton "
                                    "systems of 3D friction (REDUCED off) "
                                    "against the reduced ones (measure.py "
                                    "friction3d)",
    "solver.contact.strategies.reduction": "benchmarks: the condensation "
                                           "onto Γc alone (measure.py schur)",
    "solver.mpi.engine": "the PETSc engine: spmd, service and PetscEngine "
                         "are how a run under mpiexec starts (docs/mpi.md)",
    "solver.mpi.full": "benchmarks: GAMG's rigid-body modes (run_mpi.py)",
    "solver.mpi.layout": "benchmarks: the row layout of the ranks",
    "solver.mpi.factor": "benchmarks: MUMPS orderings (mumps_ordering/)",
    "solver.mpi.service": "benchmarks: MUMPS orderings (mumps_ordering/)",
    "solver.mpi.schur": "benchmarks: MUMPS orderings (mumps_ordering/)",
    "solver.mpi": "benchmarks: MUMPS orderings (mumps_ordering/)",
}

SCRIPTS = sorted((ROOT / "benchmarks").rglob("*.py")) + [
    ROOT / "docs" / "make_figures.py"]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))


def notebook_code(path):
    cells = nbformat.read(path, as_version=4).cells
    return "\n".join("\n".join(line for line in c.source.splitlines()
                               if not line.lstrip().startswith(("%", "!")))
                     for c in cells if c.cell_type == "code")


def imports(code):
    """(module, [names]) of every import in ``code``."""
    out = []
    for node in ast.walk(ast.parse(code)):
        if isinstance(node, ast.ImportFrom) and node.module:
            out.append((node.module, [a.name for a in node.names]))
        elif isinstance(node, ast.Import):
            out += [(a.name, []) for a in node.names]
    return out


def check(code):
    """The offending imports of ``code`` (empty if it uses the front)."""
    bad = []
    for module, names in imports(code):
        if module == "solver":
            bad += [f"solver.{name}" for name in names
                    if name not in solver.__all__ or name in WRAPPERS]
        elif module.startswith("solver."):
            # "from solver.output import thesis_figures" imports the module
            modules = [f"{module}.{n}" for n in names
                       if f"{module}.{n}" in BELOW_THE_FRONT] or [module]
            bad += [m for m in modules if m not in BELOW_THE_FRONT]
    return bad


@pytest.mark.parametrize("path", SCRIPTS + NOTEBOOKS,
                         ids=lambda p: str(p.relative_to(ROOT)))
def test_public_front_only(path):
    code = notebook_code(path) if path.suffix == ".ipynb" else \
        path.read_text()
    assert check(code) == []


def test_notebooks_import_only_study_and_figure_modules():
    """Notebooks need none of the benchmarks' reasons."""
    allowed = {"solver.studies", "solver.studies3d", "solver.verification",
               "solver.examples", "solver.output.thesis_figures",
               "solver.output.figures3d"}
    readme = (ROOT / "notebooks" / "README.md").read_text()
    for path in NOTEBOOKS:
        for module, names in imports(notebook_code(path)):
            if module.startswith("solver."):
                used = [f"{module}.{n}" for n in names
                        if f"{module}.{n}" in allowed] or [module]
                assert set(used) <= allowed, (path.name, module)
                assert all(f"`{m}" in readme for m in used), used


@pytest.mark.parametrize("code, bad", [
    ("from solver.ncp.newton import DEFAULT_OPTIONS", ["solver.ncp.newton"]),
    ("from solver.contact.two_body import equivalent_problem",
     ["solver.contact.two_body"]),
    ("import solver.ncp.newton as newton_module", ["solver.ncp.newton"]),
    ("from solver import solve_frictionless", ["solver.solve_frictionless"]),
    ("from solver.contact import contact_geometry", ["solver.contact"]),
    ("from solver import DEFAULT_OPTIONS, solve, contact_geometry", []),
    ("from solver.output import thesis_figures as tf", []),
])
def test_the_check_itself(code, bad):
    assert check(code) == bad
