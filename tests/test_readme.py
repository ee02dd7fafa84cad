"""The README as a newcomer uses it (issue 15, items 2, 4 and 11).

- Every ``bash`` block parses (``bash -n``), has no placeholder such as
  ``[a|b]`` or ``<FILE>``, and the blocks made only of export and solver
  commands are run as pasted, in a scratch folder, and must exit 0.
- The first run's numbers that the README quotes are the numbers a run
  prints (the reference is the run itself, through the command line).
- The Python examples run as doctests.
"""

import doctest
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT, assert_pasteable

README = (ROOT / "README.md").read_text()
BLOCKS = re.findall(r"```bash\n(.*?)```", README, flags=re.S)
RUNNABLE = ("sfepy-run ", "python -m solver ", "python sfepy_problems/")


def test_blocks_found():
    assert len(BLOCKS) >= 5
    assert BLOCKS[0].startswith("pip install . && sfepy-run")
    assert BLOCKS[1].strip() == 'pip install ".[test]" && python -m pytest'


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_block_parses_without_placeholders(index):
    assert_pasteable(BLOCKS[index])


def _commands(block):
    """The block's commands (continuation lines joined)."""
    return [line.strip() for line in block.replace("\\\n", " ").splitlines()
            if line.strip() and not line.strip().startswith("#")]


def _runnable():
    return [i for i, block in enumerate(BLOCKS)
            if all(c.startswith(RUNNABLE) for c in _commands(block))]


@pytest.fixture(scope="module")
def scratch(tmp_path_factory):
    """A folder like a checkout: the problem files and meshes linked, the
    venv's scripts first on PATH, and the first command's export made."""
    folder = tmp_path_factory.mktemp("readme")
    for name in ("sfepy_problems", "meshes"):
        os.symlink(ROOT / name, folder / name)
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}:"
               f"{os.environ['PATH']}", PYTHONPATH=str(ROOT))
    first = BLOCKS[0].split("&&", 1)[1].strip()  # without "pip install ."
    first = first.replace("python ", f"{sys.executable} ")
    proc = subprocess.run(first, shell=True, cwd=folder, env=env,
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    return folder, env, proc.stdout


def test_runnable_blocks_exist():
    assert len(_runnable()) >= 3


@pytest.mark.parametrize("index", _runnable())
def test_block_runs_as_pasted(scratch, index):
    folder, env, _ = scratch
    block = BLOCKS[index].replace("python ", f"{sys.executable} ")
    proc = subprocess.run(["bash", "-e", "-c", block], cwd=folder, env=env,
                          capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "Traceback" not in proc.stderr


def test_first_run_numbers_are_what_the_run_prints(scratch):
    """The text block under "What the first command prints" and the
    numbers in the prose around it."""
    folder, env, stdout = scratch
    section = README.split("### What the first command prints", 1)[1]
    section = section.split("\n### ", 1)[0]
    shown = re.search(r"```text\n(.*?)```", section, flags=re.S).group(1)
    for line in shown.splitlines():
        if line != "...":
            assert line in stdout.splitlines(), (line, stdout)
    assert "exported 492 DOFs, 20 contact nodes ->" in section
    assert "exported 492 DOFs, 20 contact nodes ->" in stdout
    levels = re.search(r"J per level \[(\d+), (\d+), (\d+)\]", stdout)
    assert f"{levels[1]} + {levels[2]} + {levels[3]} = 18" in section
    full = subprocess.run(
        [sys.executable, "-m", "solver", "output/block_454.npz", "--method",
         "fb", "--system", "full", "-o", "full"], cwd=folder, env=env,
        capture_output=True, text=True, check=True).stdout
    counts = re.search(r"evaluations +J (\d+), F (\d+)", full)
    assert f"`J {counts[1]}, F {counts[2]}`" in section
    table = README.split("### Table 1 of the thesis", 1)[1]
    assert f"| φ_FB  | 454  | 22 / 117 | {counts[1]} / {counts[2]} |" in table
    assert "4 in contact, of 19 contact nodes that can touch" in stdout


def test_python_examples(scratch, monkeypatch):
    """The doctests of the README, after the export the API section asks
    for (its bash block)."""
    folder, env, _ = scratch
    api = README.split("### Python API", 1)[1].split("\n## ", 1)[0]
    export = re.search(r"```bash\n(.*?)```", api, flags=re.S).group(1)
    subprocess.run(["bash", "-e", "-c", export], cwd=folder, env=env,
                   check=True, capture_output=True)
    monkeypatch.chdir(folder)
    parser = doctest.DocTestParser()
    test = parser.get_doctest(README, {}, "README", "README.md", 0)
    assert len(test.examples) >= 10
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    runner.run(test)
    assert runner.failures == 0


def _table(title):
    """Rows of the README's Markdown table under ``title`` (cells split)."""
    section = README.split(title, 1)[1].split("\n### ", 1)[0]
    rows = [line.strip("|").split("|") for line in section.splitlines()
            if line.startswith("| ") and "---" not in line]
    return [[cell.strip() for cell in row] for row in rows[1:]]


def test_table1_is_what_the_solver_counts(exported):
    """Every count of the README's Table 1 from a run (thesis's system)."""
    from solver import load_problem
    from solver.studies import table1

    problems = {n: load_problem(exported(n)[0]) for n in (118, 454, 1878)}
    got = {(r["method"], r["elements"], r["gap"]): f"{r['J']} / {r['F']}"
           for r in table1(problems)}
    rows = _table("### Table 1 of the thesis, next to ours")
    assert len(rows) == 6
    for method, elements, thesis, obstacle, body in rows:
        key = ("fb" if "FB" in method else "min", int(elements))
        assert obstacle == got[key + ("obstacle",)], (key, obstacle)
        assert body == got[key + ("body",)], (key, body)


def test_table2_is_what_the_solver_counts(exported):
    """Every count of the README's Table 2 from a run (454 block)."""
    from solver import load_problem
    from solver.studies import table2

    rows = _table("### Table 2 of the thesis, next to ours")
    got = table2(load_problem(exported(454)[0]))
    assert len(rows) == 3 and len(got) == 9
    for i, row in enumerate(rows):
        for j, cell in enumerate(row[2:]):
            run = got[3 * i + j]
            assert run["converged"]
            assert cell == f"{run['J']} / {run['F']}", (row[0], j, cell)


def test_condensed_counts_quoted_beside_table1(exported):
    """The prose above Table 1: the default (condensed, nested start) on
    the 1878 mesh, its counts and its agreement with the thesis's system."""
    import numpy as np

    from solver import load_problem, solve_frictionless

    problem = load_problem(exported(1878)[0])
    text = " ".join(README.split("### Table 1 of the thesis", 1)[1]
                    .split("| method |", 1)[0].split())
    finest = []
    for method, name in (("min", "φ_min"), ("fb", "φ_FB")):
        nested = solve_frictionless(problem, method=method)
        full = solve_frictionless(problem, method=method, condense=False)
        assert f"{nested.njev} / {nested.nfev} for {name}" in text
        finest.append(nested.levels[-1]["njev"])
        difference = np.abs(nested.u - full.u).max() / np.abs(full.u).max()
        assert difference <= 1e-12 and "same solution to 1e-12" in text
    assert f"of which {finest[0]} and {finest[1]} Jacobians" in text


def test_support_table_is_the_fronts():
    """The README's "What works where" is what solver.support_table()
    prints: the rules the front applies, not a copy that drifts."""
    from solver import support_table

    section = README.split("### What works where", 1)[1]
    assert support_table() in section


def test_default_friction_counts_quoted_beside_table2(exported):
    """The prose below Table 2: the default friction run (condensed,
    projection, φ_min) and φ_FB on the same system, their counts and their
    agreement with the table's runs (the thesis's system, sparse LU)."""
    import numpy as np

    from solver import load_problem, solve_friction

    problem = load_problem(exported(454)[0])
    text = " ".join(README.split("### Table 2 of the thesis", 1)[1]
                    .split("### Key figures", 1)[0].split())
    counts = {"min": [], "fb": []}
    for fc in (0.05, 0.3, 10.0):
        default = solve_friction(problem, fc, steps=100)
        assert default.method == "min" and default.success
        full = solve_friction(problem, fc, steps=100, method="fb",
                              condense=False)  # the table's column
        scale = np.abs(full.u).max()
        assert np.abs(default.u - full.u).max() <= 1e-10 * scale
        counts["min"].append(f"{default.njev} / {default.nfev}")
        fb = solve_friction(problem, fc, steps=100, method="fb")
        counts["fb"].append(f"{fb.njev} / {fb.nfev}")
    for method, (a, b, c) in counts.items():
        assert f"{a}, {b} and {c}" in text, (method, a, b, c)
    assert "the answer of the table's runs to 1e-10" in text
