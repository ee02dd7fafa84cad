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

from mpi_processes import files as listed, rank_pid, ranks_catch_sigterm
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


@pytest.mark.skipif(shutil.which("mpiexec") is None,
                    reason="mpiexec not found")
def test_full_system_without_contact_slices_exit_2(folder, tmp_path):
    """A folder converted before ``contact/`` existed, run on the full
    system by Krylov (solver/mpi/partitioned_full.py, each rank reads its
    contact nodes from there): exit 2, one line saying to convert again."""
    pytest.importorskip("petsc4py")
    copy = damaged(folder, tmp_path, "contact", shutil.rmtree)
    done = subprocess.run(
        ["mpiexec", "--allow-run-as-root", "--oversubscribe", "-n", "2",
         sys.executable, "-m", "solver", str(copy), "--engine", "petsc",
         "--system", "full", "--ksp", "gamg", "-o", str(tmp_path / "out")],
        capture_output=True, text=True, timeout=300,
        env=dict(os.environ, OMP_NUM_THREADS="1"))
    lines = [ln for ln in done.stderr.splitlines()
             if ln.startswith("error")]
    assert done.returncode == 2 and len(lines) == 1, done.stderr
    assert "convert the .npz again" in lines[0]
    assert "Traceback" not in done.stderr


def test_folder_on_the_serial_engine_says_how_to_run_it(folder, capsys):
    from conftest import run_cli

    code, _, err = run_cli([folder], capsys)
    assert code == 2 and err.count("\n") == 1
    assert "--engine petsc" in err and "mpiexec" in err


@pytest.fixture(scope="module")
def larger(refined_block, tmp_path_factory):
    """The 1878 block refined twice (30360 DOFs), converted: a run long
    enough to be stopped."""
    from solver import save_problem
    from solver.mpi.convert import convert

    root = tmp_path_factory.mktemp("partitioned-r2")
    save_problem(root / "r2.npz", refined_block(2))
    convert(root / "r2.npz", root / "r2")
    return root / "r2"


@pytest.mark.skipif(shutil.which("mpiexec") is None,
                    reason="mpiexec not found")
@pytest.mark.parametrize("target", ["rank 0", "rank 1"])
def test_sigterm_leaves_no_complete_looking_result(larger, tmp_path,
                                                   target):
    """SIGTERM to rank 0 (or to a worker) while a partitioned run is on:
    the run ends as every run (solver/cli/run.py): one line "error:
    interrupted by SIGTERM", summary.json "interrupted" listing exactly the
    files there, no temporary file, no result.pvtu of an unfinished run;
    exit 143. (SIGTERM to Open MPI's ``mpiexec`` reaches the ranks one
    second later, after this run has ended: tests/test_mpi_signals.py
    stops a longer run that way.)"""
    pytest.importorskip("petsc4py")
    import signal
    import time

    out = tmp_path / "out"
    proc = subprocess.Popen(
        ["mpiexec", "--allow-run-as-root", "--oversubscribe", "-n", "2",
         sys.executable, "-m", "solver", str(larger), "--engine", "petsc",
         "-o", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
    try:
        deadline = time.monotonic() + 120
        summary = None
        while summary is None:  # the run has opened its folder
            assert time.monotonic() < deadline and proc.poll() is None
            try:
                summary = json.loads((out / "summary.json").read_text())
            except (OSError, ValueError):
                time.sleep(0.01)
        assert summary["status"] == "running"
        while not ranks_catch_sigterm(proc.pid):  # both ranks serve
            assert time.monotonic() < deadline and proc.poll() is None
            time.sleep(0.01)
        os.kill(summary["pid"] if target == "rank 0" else
                rank_pid(proc.pid, 1), signal.SIGTERM)
        _, stderr = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 143, stderr
    assert "Traceback" not in stderr
    assert "error: interrupted by SIGTERM; completed work kept in " \
        f"{out}/" in stderr.splitlines(), stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted" and not summary["converged"]
    files = listed(out)
    assert not [f for f in files if os.path.basename(f).startswith(".")]
    assert sorted(summary["files"]) == files
    assert "result.pvtu" not in files
