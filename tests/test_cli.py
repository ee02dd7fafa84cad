"""``python -m solver``: --info on both thesis examples, errors as one line."""

import json
import subprocess
import sys

import numpy as np
import pytest

from solver.cli import main
from solver.problem import save_problem


def test_info_mesh_problem(exported, capsys):
    path = exported(454)[0]
    assert main([str(path), "--info"]) == 0
    out = capsys.readouterr().out
    assert "reduced DOFs      492" in out  # 2 x (257 nodes - 11 clamped)
    assert "contact nodes Nc  20 (19 free, 1 supported)" in out
    assert "454 triangles, 257 nodes" in out
    assert "x(t) = 5.05 + 0.005*t**2, y(t) = t" in out


def test_info_json(bar_problem, tmp_path, capsys):
    path = save_problem(tmp_path / "bar.npz", bar_problem)
    assert main([str(path), "--info", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["dofs"] == 2 and info["gap"] == [0.005]
    assert info["K_norm_max"] == 9e4  # thesis §6: K = 1e4 diag(9, 9)


@pytest.mark.parametrize("content", [b"garbage", b""])
def test_bad_file_one_line_exit_2(tmp_path, capsys, content):
    path = tmp_path / "bad.npz"
    path.write_bytes(content)
    assert main([str(path), "--info"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.startswith("error: ")
    assert len(captured.err.strip().splitlines()) == 1


def test_malformed_key_named(bar_problem, tmp_path, capsys):
    arrays = bar_problem.to_arrays()
    arrays["gap"] = np.array([np.inf])
    np.savez(tmp_path / "bad.npz", **arrays)
    assert main([str(tmp_path / "bad.npz"), "--info"]) == 2
    assert capsys.readouterr().err.startswith("error: gap: ")


def test_debug_shows_traceback(tmp_path, capsys):
    assert main([str(tmp_path / "missing.npz"), "--info", "--debug"]) == 2
    assert "Traceback" in capsys.readouterr().err


def test_usage_error_exit_2(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--no-such-option"])
    assert exc.value.code == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_module_entry_point(bar_problem, tmp_path):
    path = save_problem(tmp_path / "bar.npz", bar_problem)
    result = subprocess.run([sys.executable, "-m", "solver", str(path),
                             "--info"], capture_output=True, text=True)
    assert result.returncode == 0
    assert "reduced DOFs      2" in result.stdout
    result = subprocess.run([sys.executable, "-m", "solver",
                             str(tmp_path / "nope.npz"), "--info"],
                            capture_output=True, text=True)
    assert result.returncode == 2
    assert result.stderr.strip().count("\n") == 0
    assert "Traceback" not in result.stderr
