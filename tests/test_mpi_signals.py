"""Stopping a run of the PETSc engine under ``mpiexec`` (solver/mpi/
service.py, docs/mpi.md "Stopping a run"): a signal to ``mpiexec`` or to
any one rank leaves what a serial interrupt leaves, within seconds.

Open MPI 4.1's ``mpiexec``, on SIGTERM or SIGINT, sends the ranks SIGCONT,
SIGTERM one second later and SIGKILL one second after that
(``odls_base_sigkill_timeout``), and kills every rank at once when one of
them dies of a signal. The friction runs here are therefore stopped the
four ways a user or a batch system stops them, and the folder is read
back: ``summary.json`` "interrupted", the completed steps in
``result.npz`` equal to the step files in ``steps/`` and to the entries of
``result.pvd``, no temporary file. The driver test makes the hard case
deterministic: a signal that arrives while the ranks are inside a
collective command (before, rank 0 left the command and the other ranks
waited in it until the 60 s abort).
"""

import json
import os
import shutil
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest

from mpi_processes import files as listed, rank_pid
from solver.mpi import missing

REASON = missing() or (None if shutil.which("mpiexec") else
                       "mpiexec not found: apt-get install mpi-default-bin "
                       "(and pip install '.[petsc]', docs/mpi.md)")
pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))

MPIEXEC = ["mpiexec", "--allow-run-as-root", "--oversubscribe", "-n", "2"]

#: Seconds from the signal to the end of ``mpiexec``: Open MPI's own two
#: seconds of timers and the writing (docs/mpi.md has the measurements),
#: with a margin for a loaded machine; far below the 60 s abort.
WITHIN = 15.0


def _open_mpi():
    """Whether ``mpiexec`` is Open MPI's: after a signal to it, it exits
    with 1 whatever the ranks return."""
    done = subprocess.run(["mpiexec", "--version"], capture_output=True,
                          text=True)
    return "Open MPI" in done.stdout or "OpenRTE" in done.stdout


@pytest.fixture(scope="module")
def block(exported):
    return str(exported(454)[0])


@pytest.mark.parametrize("target, signum", [
    ("mpiexec", signal.SIGTERM), ("mpiexec", signal.SIGINT),
    ("rank 0", signal.SIGTERM), ("rank 1", signal.SIGTERM)])
def test_interrupted_friction_run(block, tmp_path, target, signum):
    """SIGTERM (or Ctrl-C's SIGINT) to ``mpiexec``, or SIGTERM to one rank,
    after the first steps are on disk: every rank stops as a serial run
    does (the ranks get SIGTERM from mpiexec, so the summary says
    SIGTERM), within seconds. ``mpiexec`` exits with 143 when a rank was
    signalled, with its own 1 when it was (Open MPI)."""
    out = tmp_path / "run"
    env = dict(os.environ, OMP_NUM_THREADS="1")
    proc = subprocess.Popen(
        MPIEXEC + [sys.executable, "-m", "solver", block, "--engine",
                   "petsc", "--friction", "0.3", "--steps", "2000", "-o",
                   str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True, env=env)
    try:
        deadline = time.monotonic() + 300
        # step 11's file is there, so step 10 has been counted
        while not (out / "steps" / "step_0011.vtu").exists():
            assert time.monotonic() < deadline and proc.poll() is None
            time.sleep(0.05)
        pid = {"mpiexec": proc.pid, "rank 1": rank_pid(proc.pid, 1),
               "rank 0": json.loads((out / "summary.json").read_text())[
                   "pid"]}[target]
        clock = time.monotonic()
        os.kill(pid, signum)
        _, stderr = proc.communicate(timeout=120)
        seconds = time.monotonic() - clock
    finally:
        if proc.poll() is None:
            proc.kill()
    if target != "mpiexec":
        assert proc.returncode == 143, stderr
    elif _open_mpi():
        assert proc.returncode == 1, stderr
    else:
        assert proc.returncode != 0, stderr
    assert seconds < WITHIN, (seconds, stderr)
    assert "Traceback" not in stderr
    assert f"error: interrupted by SIGTERM; completed work kept in {out}/" \
        in stderr.splitlines(), stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted", summary
    assert summary["message"] == "interrupted by SIGTERM"
    files = listed(out)
    assert not [f for f in files if os.path.basename(f).startswith(".")]
    assert sorted(summary["files"]) == files
    done = summary["steps_completed"]
    assert 10 <= done < 2000
    steps = [f for f in files if f.startswith("steps" + os.sep)]
    assert steps == [os.path.join("steps", f"step_{k:04d}.vtu")
                     for k in range(1, done + 1)]
    entries = ET.parse(out / "result.pvd").getroot().find("Collection")
    assert [e.get("file") for e in entries] == steps
    with np.load(out / "result.npz") as npz:
        assert int(npz["steps_completed"]) == done and not npz["converged"]
        u = npz["displacement"]
        np.testing.assert_allclose(npz["load_factor"],
                                   np.arange(1, done + 1) / 2000)
    assert u.shape[0] == done
    last = meshio.read(out / steps[-1]).point_data["u"]
    np.testing.assert_allclose(last[:, :2], u[-1], rtol=1e-12, atol=0)


DRIVER = """
import os, signal, sys, time
from solver.mpi.service import command
from solver.mpi.engine import service, spmd

class Stopped(Exception):
    pass

def handler(signum, frame):
    raise Stopped(signum)

@command("signalled")
def _signalled(svc, payload, local):
    if svc.rank == payload:
        os.kill(os.getpid(), signal.SIGTERM)
    time.sleep(0.2)  # a pending Python handler runs here
    return svc.comm.allreduce(svc.rank + 1)  # every rank must take part

def main(out, target):
    svc = service()
    signal.signal(signal.SIGTERM, handler)
    try:
        svc.call("signalled", target)
        text = "not stopped"
    except Stopped as exc:
        text = f"stopped by {exc.args[0]}"
    total = svc.call("signalled", -1)  # the workers still serve
    open(out, "w").write(f"{text}, allreduce {total}")

spmd(main, sys.argv[1], int(sys.argv[2]))
"""


@pytest.mark.parametrize("rank", [0, 1])
def test_signal_during_a_command_waits_for_its_end(tmp_path, rank):
    """SIGTERM to rank 0, or to a worker, while every rank is inside a
    command that ends in a collective call: the command completes on every
    rank, then rank 0's own handler gets the signal (a worker's is
    reported to it), and the workers go on serving. Before, rank 0 left
    the command at once and the worker waited in the collective call
    until the 60 s abort (exit 1), or, signalled itself, died and took
    rank 0 with it."""
    out = tmp_path / "said.txt"
    clock = time.monotonic()
    done = subprocess.run(MPIEXEC + [sys.executable, "-c", DRIVER, out,
                                     str(rank)], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-3000:]
    assert out.read_text() == "stopped by 15, allreduce 3"
    assert time.monotonic() - clock < 45  # not ABORT_AFTER (60 s)
