"""Package-level properties: the solver never imports SfePy."""

import ast
import subprocess
import sys

from conftest import ROOT


def test_solver_does_not_import_sfepy():
    code = ("import sys, solver, solver.cli, solver.problem, solver.geometry.curves.parametric, "
            "solver.geometry.mesh, solver.examples; "
            "sys.exit(3 if any(m == 'sfepy' or m.startswith('sfepy.') "
            "for m in sys.modules) else 0)")
    result = subprocess.run([sys.executable, "-c", code], cwd=ROOT)
    assert result.returncode == 0


def test_no_sfepy_import_statement_in_solver_sources():
    """Also catches imports inside functions, which the test above misses."""
    for path in (ROOT / "solver").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [node.module or ""]
            else:
                continue
            assert not any(n.split(".")[0] == "sfepy" for n in names), path
