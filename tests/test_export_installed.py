"""The export helper after ``pip install .`` (issue 34, point 11).

A problem file outside the repository writes the solver's ``.npz`` with
``from sfepy_problems import export``. That works only if pyproject's
package list installs ``sfepy_problems``; these tests read the list the way
setuptools does (``[tool.setuptools.packages.find]``, namespaces on: the
pyproject default) and install its packages into a scratch folder as pip
installs pure-Python packages (their ``.py`` files, nothing else), then
import the helper from there with the repository out of reach.
"""

import shutil
import subprocess
import sys

import pytest

from conftest import ROOT


def packages():
    """The packages ``pip install .`` installs, found as setuptools finds
    them from pyproject.toml."""
    from setuptools import find_namespace_packages

    tomllib = pytest.importorskip("tomllib", reason="Python >= 3.11")
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    find = config["tool"]["setuptools"]["packages"]["find"]
    return find_namespace_packages(where=str(ROOT), include=find["include"],
                                   exclude=find.get("exclude", ()))


def install_copy(site):
    """Copy the ``.py`` files of :func:`packages` into ``site`` (what a
    wheel of them holds); returns ``site``."""
    for package in packages():
        source = ROOT.joinpath(*package.split("."))
        target = site.joinpath(*package.split("."))
        target.mkdir(parents=True, exist_ok=True)
        for path in source.glob("*.py"):
            shutil.copy2(path, target / path.name)
    return site


def test_pyproject_installs_sfepy_problems():
    found = packages()
    assert "sfepy_problems" in found and "solver" in found
    assert not any(p.split(".")[0] in ("tests", "docs", "meshes", "notebooks",
                                       "benchmarks") for p in found)
    assert (ROOT / "sfepy_problems" / "__init__.py").is_file()
    assert (ROOT / "sfepy_problems" / "export.py").is_file()


def test_installed_helper_imports_outside_the_repository(tmp_path):
    """From a folder outside the repository, with only the installed copy
    on the path: ``sfepy_problems.export`` is the installed file, has the
    helper's public names, and importing it does not import SfePy (that
    happens when an export runs)."""
    site = install_copy(tmp_path / "site")
    work = tmp_path / "elsewhere"
    work.mkdir()
    code = ("import sys; from sfepy_problems import export; "
            "print(export.__file__); print(' '.join(sorted(export.__all__)));"
            " print('sfepy' in sys.modules)")
    result = subprocess.run([sys.executable, "-c", code], cwd=work,
                            env={"PYTHONPATH": str(site), "PATH": ""},
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    where, names, sfepy = result.stdout.splitlines()
    assert where == str(site / "sfepy_problems" / "export.py")
    assert {"export_contact_problem", "obstacle_curve", "set_verbosity",
            "main", "export_only", "NO_SOLVE"} <= set(names.split())
    assert sfepy == "False"
