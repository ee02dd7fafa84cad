"""A problem file run as a script reports bad input in one line.

``python FILE.py -d "..."`` (the export helper's ``main``) turns an
exception of the export (here SfePy's refusal of a mesh file that does not
exist) into one line on stderr and exit code 1; ``-v`` shows the
traceback, as ``sfepy-run`` always does.
"""

import subprocess
import sys

import pytest

from conftest import BLOCK_PROBLEM


def run(tmp_path, *extra):
    missing = tmp_path / "missing.mesh"
    argv = [sys.executable, str(BLOCK_PROBLEM), *extra, "-d",
            f"mesh='{missing}', output='{tmp_path / 'x.npz'}'"]
    return subprocess.run(argv, cwd=tmp_path, capture_output=True, text=True,
                          timeout=300), missing


def test_missing_mesh_is_one_line(tmp_path):
    result, missing = run(tmp_path)
    assert result.returncode == 1
    line, = result.stderr.splitlines()  # one line, SfePy's words in it
    assert line.startswith("block_obstacle.py: error: ")
    assert str(missing) in line and "not found" in line
    assert line.endswith(" (-v shows the traceback)")
    assert not (tmp_path / "x.npz").exists()


@pytest.mark.parametrize("flag", ["-v", "--verbose"])
def test_verbose_shows_the_traceback(tmp_path, flag):
    result, missing = run(tmp_path, flag)
    assert result.returncode == 1
    assert "Traceback (most recent call last)" in result.stderr
    assert str(missing) in result.stderr
