"""A damaged partitioned problem (solver/problem/partitioned.py): a
truncated or missing PETSc binary file, a wrong header, a missing key
gives one ProblemError line naming the file, before any rank reads a row;
on the command line under mpiexec, exit 2 (the table of ``python -m
solver --help``) and one line, on every rank."""

import json
import os
import shutil
import subprocess
import sys

import pytest

from solver.errors import ProblemError
from solver.problem.partitioned import read_partitioned_meta


@pytest.fixture(scope="module")
def folder(exported, tmp_path_factory):
    """The 454 block converted (492 DOFs)."""
    from solver.mpi.convert import convert

    path = tmp_path_factory.mktemp("partitioned") / "b454"
    convert(exported(454)[0], path)
    return path


def damaged(folder, tmp_path, name, change):
    """A copy of ``folder`` with file ``name`` changed by ``change(path)``."""
    copy = tmp_path / "p"
    shutil.copytree(folder, copy)
    change(copy / name)
    return copy


def truncate(path):
    os.truncate(path, os.path.getsize(path) - 8)


def garble(path):
    with open(path, "r+b") as stream:
        stream.write(b"\0\0\0\0")


def drop_key(path):
    meta = json.loads(path.read_text())
    del meta["n"]
    path.write_text(json.dumps(meta))


@pytest.mark.parametrize("name, change, text", [
    ("K.petsc", truncate, "truncated or damaged"),
    ("f.petsc", truncate, "truncated or damaged"),
    ("K.petsc", os.unlink, "missing K.petsc"),
    ("f.petsc", garble, "not a PETSc binary"),
    ("problem.json", drop_key, "missing n"),
    ("contact.npz", os.unlink, "missing contact.npz"),
])
def test_damaged_folder_one_line(folder, tmp_path, name, change, text):
    copy = damaged(folder, tmp_path, name, change)
    with pytest.raises(ProblemError, match=text) as info:
        read_partitioned_meta(copy)
    assert "\n" not in str(info.value)


@pytest.mark.skipif(shutil.which("mpiexec") is None,
                    reason="mpiexec not found")
def test_truncated_matrix_exit_2_on_every_rank(folder, tmp_path):
    pytest.importorskip("petsc4py")
    copy = damaged(folder, tmp_path, "K.petsc", truncate)
    done = subprocess.run(
        ["mpiexec", "--allow-run-as-root", "--oversubscribe", "-n", "2",
         sys.executable, "-m", "solver", str(copy), "--engine", "petsc",
         "-o", str(tmp_path / "out")], capture_output=True, text=True,
        timeout=300, env=dict(os.environ, OMP_NUM_THREADS="1"))
    lines = [ln for ln in done.stderr.splitlines()
             if ln.startswith("error")]
    assert done.returncode == 2 and len(lines) == 1, done.stderr
    assert "truncated" in lines[0] and "Traceback" not in done.stderr


def test_folder_on_the_serial_engine_says_how_to_run_it(folder, capsys):
    from conftest import run_cli

    code, _, err = run_cli([folder], capsys)
    assert code == 2 and err.count("\n") == 1
    assert "--engine petsc" in err and "mpiexec" in err
