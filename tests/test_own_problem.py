"""docs/own-problem.md as a newcomer uses it (issue 34, point 10).

The guide's example block runs as pasted in a scratch folder that holds a
copy of ``docs/own_problem/``: it copies the three files to
``output/ring/`` (outside ``sfepy_problems/`` and outside the repository)
and runs them with the packages pyproject installs copied into a site
folder (``test_export_installed.install_copy``), so the problem file
imports the installed export helper, not the repository's.

Checks: every command succeeds; the lines the guide shows are printed;
the solve converged and passed its verification; the total contact force
agrees to 1 % with Lamé's thick-walled cylinder (plane strain; Timoshenko
& Goodier, *Theory of Elasticity*), solved here from its boundary
conditions u_r(a) = δ, u_r(b) = g; the numbers of the guide's prose are
ring.py's and ring_mesh.py's defaults and the run's.
"""

import ast
import json
import os
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT, assert_pasteable
from test_export_installed import install_copy

GUIDE = (ROOT / "docs" / "own-problem.md").read_text()
EXAMPLE = ROOT / "docs" / "own_problem"
BLOCKS = re.findall(r"```bash\n(.*?)```", GUIDE, flags=re.S)
RUN = next(b for b in BLOCKS if "mkdir -p output/ring" in b)
FINE = next(b for b in BLOCKS if "ring_fine.mesh" in b)
SHOWN = re.search(r"```text\n(.*?)```", GUIDE, flags=re.S).group(1)


def defaults(filename, function):
    """Keyword defaults of ``function`` in ``filename``, read from its
    source (importing ring.py would need the installed helper)."""
    tree = ast.parse((EXAMPLE / filename).read_text())
    node = next(n for n in ast.walk(tree)
                if isinstance(n, ast.FunctionDef) and n.name == function)
    args = node.args.args[len(node.args.args) - len(node.args.defaults):]
    return {a.arg: ast.literal_eval(d)
            for a, d in zip(args, node.args.defaults)}


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The example block run in a scratch folder; (folder, env, output)."""
    tmp = tmp_path_factory.mktemp("own_problem")
    site = install_copy(tmp / "site")
    folder = tmp / "work"
    shutil.copytree(EXAMPLE, folder / "docs" / "own_problem",
                    ignore=shutil.ignore_patterns("__pycache__"))
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "CONTACT_SSN_VERBOSE")}
    env.update(PATH=f"{os.path.dirname(sys.executable)}:{env['PATH']}",
               PYTHONPATH=str(site), MPLBACKEND="Agg")
    proc = subprocess.run(["bash", "-e", "-c", RUN], cwd=folder, env=env,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    assert "Traceback" not in proc.stderr
    return folder / "output" / "ring", env, proc.stdout, site


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_block_parses_without_placeholders(index):
    assert_pasteable(BLOCKS[index])


def test_problem_file_uses_the_installed_helper(run):
    """ring.py, outside the repository, imports sfepy_problems.export from
    the installed copy."""
    folder, env, _, site = run
    assert not folder.is_relative_to(ROOT)
    where = subprocess.run(
        [sys.executable, "-c", "import ring; print(ring.export.__file__)"],
        cwd=folder, env=env, capture_output=True, text=True, timeout=300)
    assert where.returncode == 0, where.stderr
    assert where.stdout.splitlines()[-1] == str(
        site / "sfepy_problems" / "export.py")


def test_shown_lines_are_printed(run):
    printed = run[2].splitlines()
    for line in SHOWN.splitlines():
        pattern = ".*".join(map(re.escape, line.split("...")))
        assert any(re.fullmatch(pattern, p) for p in printed), (line, printed)


def test_contact_force_is_lames(run):
    """The solve converged with every node of Γc in contact, and the total
    contact force of the quarter is Lamé's pressure times the arc, πb/2."""
    folder = run[0]
    with np.load(folder / "ring.npz") as problem:
        meta = json.loads(str(problem["meta"]))
        assert str(problem["obstacle_x"]) == "2.001*cos(t)"
    summary = json.loads((folder / "ring-solved" / "summary.json").read_text())
    assert summary["status"] == "converged"
    assert summary["verification"]["passed"]
    with np.load(folder / "ring-solved" / "result.npz") as result:
        force = result["contact_force"]
        assert result["in_contact"].all()

    E, nu, a, b = meta["E"], meta["nu"], meta["a"], meta["b"]
    g, delta = meta["gap"], meta["delta"]
    # u_r = A r + B / r with u_r(a) = delta, u_r(b) = g; plane strain
    # Hooke: sigma_rr = (lam + 2 mu) du/dr + lam u/r.
    A, B = np.linalg.solve([[a, 1 / a], [b, 1 / b]], [delta, g])
    mu, lam = E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))
    p = -((lam + 2 * mu) * (A - B / b ** 2) + lam * (A + B / b ** 2))
    assert p > 0
    assert force.sum() == pytest.approx(p * np.pi * b / 2, rel=0.01)


def test_body_held_only_by_contact_is_refused(run, tmp_path):
    """The guide's warning: without the mandrel and the y symmetry the
    quarter ring can slide along y, held only by the bore, and nothing
    (the mandrel was the load) presses it there: the solver refuses the
    file in one line, exit code 2 (issue 31)."""
    folder, env, _, _ = run
    source = (folder / "ring.py").read_text()
    floating = "".join(line for line in source.splitlines(keepends=True)
                       if "'mandrel': (" not in line
                       and "'symmetry_y': (" not in line)
    assert len(floating.splitlines()) == len(source.splitlines()) - 2
    (tmp_path / "floating.py").write_text(floating)
    subprocess.run([sys.executable, "floating.py", "-d",
                    f"mesh='{folder / 'ring.mesh'}', output='floating.npz'"],
                   cwd=tmp_path, env=env, check=True, capture_output=True,
                   timeout=300)
    proc = subprocess.run([sys.executable, "-m", "solver", "floating.npz"],
                          cwd=tmp_path, env=env, capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 2
    line, = proc.stderr.splitlines()
    assert "held by contact only" in line and "no resultant" in line
    assert "no load towards the obstacle at all is refused" in " ".join(
        GUIDE.split())


def _force_error(printed):
    """The relative difference check_ring.py prints, in %."""
    return float(re.search(r"p × quarter arc [\d.]+: ([+-][\d.]+) %",
                           printed)[1])


def test_finer_mesh_is_closer(run):
    """The guide's refinement block (run where the first block ended, in
    output/ring/): twice the elements each way, and the difference of the
    total force falls to about a quarter (linear elements: O(h²))."""
    folder, env, printed, _ = run
    mesh = defaults("ring_mesh.py", "ring_mesh")
    assert f"--n-radial {2 * mesh['n_radial']} --n-arc {2 * mesh['n_arc']}" \
        in FINE
    proc = subprocess.run(["bash", "-e", "-c", FINE], cwd=folder, env=env,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    ratio = _force_error(proc.stdout) / _force_error(printed)
    assert 0.2 < ratio < 0.33
    assert "twice the elements each way, the difference in the total force " \
        "falls to about a quarter" in " ".join(GUIDE.split())


def test_prose_numbers(run):
    """The example's parameters are ring.py's defaults; the counts are
    computed from ring_mesh.py's defaults as the prose does; the quoted
    agreement is the run's."""
    ring = defaults("ring.py", "define")
    mesh = defaults("ring_mesh.py", "ring_mesh")
    example = GUIDE.split("## The example", 1)[1].split("\n## ", 1)[0]
    example = " ".join(example.split())
    for text in (f"a = {ring['a']:g}", f"b = {ring['b']:g}",
                 f"E = {ring['E']:g}", f"ν = {ring['nu']:g}",
                 f"g = {ring['gap']:g}", f"δ = {ring['delta']:g}"):
        assert text in example
    assert (mesh["a"], mesh["b"]) == (ring["a"], ring["b"])

    n_r, n_arc = mesh["n_radial"], mesh["n_arc"]
    nodes, triangles = (n_r + 1) * (n_arc + 1), 2 * n_r * n_arc
    arc, lines = 2 * (n_arc + 1), 2 * n_r
    dofs = 2 * nodes - arc - lines
    prose = " ".join(GUIDE.split("```text", 1)[1].split("## The mesh")[0]
                     .split("```", 1)[1].split())
    assert f"{n_r} elements across the wall and {n_arc} along each arc" \
        in prose
    assert f"({n_r} + 1)({n_arc} + 1) = {nodes} nodes" in prose
    assert f"2 · {n_r} · {n_arc} = {triangles} triangles" in prose
    assert f"2 · {nodes} = {2 * nodes} displacement components" in prose
    assert f"2 · {n_arc + 1} on the inner arc and {n_r} + {n_r}" in prose
    assert f"{2 * nodes} − {arc} − {lines} = {dofs} unknowns" in prose
    assert f"the outer arc, {n_arc + 1} nodes" in prose
    printed = run[2]
    assert f"exported {dofs} DOFs, {n_arc + 1} contact nodes ->" in printed
    assert f"Lamé's pressure to {abs(_force_error(printed)):.2f} %" in prose
