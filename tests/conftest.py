"""Shared fixtures: thesis problems exported through the SfePy problem file.

The export runs SfePy in-process (``solve_pde``, as ``sfepy-run`` does), once
per test session and mesh; tests that check the ``sfepy-run`` command itself
run it as a subprocess.
"""

import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
MESHES = ROOT / "meshes"
BLOCK_PROBLEM = ROOT / "sfepy_problems" / "block_obstacle.py"
THESIS_MESHES = (118, 454, 1878)


#: Modules that initialise MPI when imported. In the pytest process they
#: would make Open MPI's singleton environment, which breaks every later
#: ``mpiexec`` launch of the session (exit 1, empty stderr): PETSc runs in
#: a subprocess only.
MPI_MODULES = ("petsc4py.PETSc", "mpi4py.MPI")


@pytest.fixture(autouse=True)
def _no_mpi_in_process(request):
    """Fail the test that imported PETSc or MPI in the pytest process
    (:data:`MPI_MODULES`), where it happened, not in a later file."""
    before = [m for m in MPI_MODULES if m in sys.modules]
    yield
    after = [m for m in MPI_MODULES if m in sys.modules and m not in before]
    if after:
        pytest.fail(f"{request.node.nodeid} imported {after} in the pytest "
                    "process; run PETSc under mpiexec in a subprocess",
                    pytrace=False)


def assert_pasteable(block):
    """A shell block of the docs parses (bash -n) and holds no
    alternatives ``[a|b]`` or placeholders ``<NAME>`` to fill in."""
    subprocess.run(["bash", "-n"], input=block, text=True, check=True)
    code = re.sub(r"#.*", "", block)
    assert not re.search(r"\[[\w-]+\|[\w-]+", code), block
    assert not re.search(r"<[A-Za-z_]+>", code), block


def load_script(name, path):
    """A script of the repository (meshes/*.py, sfepy_problems/_export.py)
    imported once as module ``name`` (the name the scripts use for it)."""
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


def solve_block(mesh, output, **params):
    """Run the block problem file like ``sfepy-run -d ...``.

    Returns SfePy's problem and its solution variables, and writes the
    ``.npz`` through the file's export hook.
    """
    from sfepy.applications import solve_pde
    from sfepy.base.conf import ProblemConf, get_standard_keywords

    required, other = get_standard_keywords()
    conf = ProblemConf.from_file(
        str(BLOCK_PROBLEM), required, other,
        define_args=dict(mesh=str(mesh), output=str(output), **params))
    return solve_pde(conf, save_results=False)


def run_cli(argv, capsys):
    """``main(argv)`` -> (exit code, stdout, stderr); usage errors exit."""
    from solver.cli import main

    try:
        code = main([str(a) for a in argv])
    except SystemExit as exc:
        code = exc.code
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.fixture(scope="session")
def exported(tmp_path_factory):
    """``exported(n)`` -> (npz path, SfePy problem, SfePy variables)."""
    cache = {}
    folder = tmp_path_factory.mktemp("export")

    def get(n_triangles):
        if n_triangles not in cache:
            path = folder / f"block_{n_triangles}.npz"
            pb, variables = solve_block(MESHES / f"block_{n_triangles}.mesh",
                                        path)
            cache[n_triangles] = (path, pb, variables)
        return cache[n_triangles]

    return get


@pytest.fixture()
def bar_problem():
    from solver.examples import two_dof_bar

    return two_dof_bar()


@pytest.fixture(scope="session")
def refined_block(tmp_path_factory):
    """``refined_block(k)`` -> the 1878 block refined k times (4ᵏ× the
    triangles; 7668 DOFs for k = 1, 30360 for k = 2), exported by SfePy."""
    import subprocess
    import sys

    from solver import load_problem

    cache = {}
    folder = tmp_path_factory.mktemp("refined")

    def get(k):
        if k not in cache:
            mesh = folder / f"r{k}.mesh"
            subprocess.run([sys.executable, str(MESHES / "generate.py"),
                            "--refine", str(k), "--base", "1878", "-o",
                            str(mesh)], check=True, capture_output=True,
                           cwd=ROOT)
            solve_block(mesh, folder / f"r{k}.npz")
            cache[k] = load_problem(folder / f"r{k}.npz")
        return cache[k]

    return get
