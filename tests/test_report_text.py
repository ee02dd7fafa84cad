"""The command line's summaries (solver/output/report.py, issue 34 point
24): the hint on Table 1's counts only where Table 1 applies (a 2D body
on a rigid obstacle, nested start), "the thesis's" system only there, and
"1 node" in the singular. The summaries are those of real runs (the
2-DOF bar, a 3D block, two bodies, the thesis block) through the command
line."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

from conftest import MESHES, run_cli  # noqa: E402
from test_export_two_body import export  # noqa: E402
from solver import save_problem, two_dof_bar  # noqa: E402
from solver.output.report import (format_friction_result,  # noqa: E402
                                  format_result)

HINT = "Table 1's: --system full"


def evaluations_line(text):
    return next(line for line in text.splitlines()
                if line.startswith("evaluations"))


def summary(folder):
    return json.loads((Path(folder) / "summary.json").read_text())


@pytest.fixture(scope="module")
def bar_npz(tmp_path_factory):
    path = tmp_path_factory.mktemp("bar") / "bar.npz"
    save_problem(path, two_dof_bar())
    return path


def test_thesis_block_nested_start_keeps_the_hint(exported, tmp_path,
                                                  capsys):
    code, out, _ = run_cli([exported(118)[0], "-o", tmp_path / "a"], capsys)
    assert code == 0
    assert evaluations_line(out).endswith(f"(all levels; {HINT})")
    assert "(--system full: the thesis's)" in out
    code, out, _ = run_cli([exported(118)[0], "--system", "full", "-o",
                            tmp_path / "b"], capsys)
    assert code == 0
    assert evaluations_line(out).endswith("(thesis Table 1 metrics)")
    assert "full (the thesis's, in all unknowns)" in out


def test_free_start_has_no_levels_to_count(exported, tmp_path, capsys):
    code, out, _ = run_cli([exported(118)[0], "--start", "free", "-o",
                            tmp_path], capsys)
    assert code == 0
    assert "(" not in evaluations_line(out)


def test_discrete_problem_gets_no_table1_hint(bar_npz, tmp_path, capsys):
    code, out, _ = run_cli([bar_npz, "-o", tmp_path / "a"], capsys)
    assert code == 0
    assert HINT not in out and "the thesis's" not in out
    text = format_result(dict(summary(tmp_path / "a"), system="full"), "x")
    assert "Table 1" not in text and "the thesis's" not in text


@pytest.fixture(scope="module")
def exports(tmp_path_factory):
    """The SfePy exports of a 3D block (the 118 slab) and of the two-body
    patch test, by the problem files (no SfePy solve)."""
    folder = tmp_path_factory.mktemp("exports")
    export(folder, "block3d_obstacle.py", "slab",
           mesh=str(MESHES / "block3d_118_slab.mesh"), slab=True)
    export(folder, "two_body_patch.py", "patch",
           mesh=str(MESHES / "two_body_patch.mesh"))
    return folder


def test_two_bodies_count_levels_without_table1(exports, tmp_path, capsys):
    code, out, _ = run_cli([exports / "patch.npz", "-o", tmp_path], capsys)
    assert code == 0, out
    data = summary(tmp_path)
    assert data["gap"] == "mortar" and data["start"] == "nested"
    assert evaluations_line(out).endswith("(all levels)")
    assert HINT not in out and "the thesis's" not in out


def test_three_dimensional_run_gets_no_table1_hint(exports, tmp_path,
                                                   capsys):
    for system in ("condensed", "full"):
        code, out, _ = run_cli([exports / "slab.npz", "--system", system,
                                "-o", tmp_path / system], capsys)
        assert code == 0, out
        assert summary(tmp_path / system)["dim"] == 3
        assert "Table 1" not in out and "the thesis's" not in out


def test_one_node_in_the_singular(bar_npz, tmp_path, capsys):
    code, out, _ = run_cli([bar_npz, "--friction", "10", "--steps", "100",
                            "-o", tmp_path], capsys)
    assert code == 0
    last = next(line for line in out.splitlines()
                if line.startswith("last step"))
    assert "1 node in contact" in last
    text = format_friction_result(dict(summary(tmp_path),
                                       final_n_contact=4), "x")
    assert "4 nodes in contact" in text
    assert np.isfinite(summary(tmp_path)["final_max_contact_pressure"])
