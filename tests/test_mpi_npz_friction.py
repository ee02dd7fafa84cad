"""Coulomb friction on the full system of a ``.npz`` under mpiexec (issue
33; solver/mpi/on_the_fly.py): ``mpiexec -n N python -m solver X.npz
--engine petsc --system full --ksp gamg --friction 0.3 --steps 3``
converts X.npz on the fly into a temporary folder beside the outputs and
runs the folder's Krylov friction (solver/mpi/krylov_friction.py); the
folder is removed at the end. 2D here (the thesis's §4 block refined
once, 7668 DOFs, f_c 0.3: full slip), 3D in test_mpi_npz_friction3d.py.

Reference: the serial engine's ``solver.solve(problem, friction=0.3,
steps=3)`` on the same ``.npz`` (another method on another system: the
semismooth Newton on Γc's Schur complement from scipy's factorisation of
the whole K): every step's u, friction and contact forces to 1e-8 and the
same stick, slip and contact sets (test_mpi_krylov_friction.
assert_same_steps); and the run of the folder converted beforehand
(``python -m solver convert``), the same fields to 1e-8. The fault
contract (tests/faults, docs/mpi.md): the temporary folder is gone after
success, after a refused option, after SIGTERM to mpiexec and after a
full disk during the conversion (a 256 KiB tmpfs; skipped where mount is
not allowed), each ending in its one line and exit code. PETSc runs only
in the mpiexec subprocesses."""

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from solver import solve
from solver.errors import SolverError
from test_mpi import REASON, mpirun
from test_mpi_krylov_friction import block  # noqa: F401 (fixture)
from test_mpi_krylov_friction import (FRICTION, RTOL, STEPS,
                                      assert_full_slip, assert_same_steps,
                                      run_krylov_friction)

pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))

PATH_LINE = "path: friction on the full system by Krylov"


def leftovers(where):
    """The temporary folders of a conversion on the fly left in
    ``where``."""
    return [name for name in os.listdir(where) if "-converted-" in name]


def assert_converted(summary, stdout, npz):
    """The run said which path ran, and summary.json what it converted."""
    assert PATH_LINE in stdout.splitlines()[0]
    assert summary["problem"] == str(npz)
    converted = summary["converted"]
    assert converted["source"] == str(npz) and converted["removed"]
    assert converted["gap"] == "obstacle" and converted["rollers"]


@pytest.mark.parametrize("ranks", [1, 2])
def test_2d_block_from_the_npz_same_steps_as_serial(block, tmp_path, ranks):
    problem, folder, serial = block
    npz = folder.parent / "r1.npz"
    out = tmp_path / "out"
    code, summary, stdout, err = run_krylov_friction(npz, out, ranks)
    assert code == 0, err[-2000:]
    assert summary["engine"]["ranks"] == ranks
    assert summary["engine"]["ksp"] == "gamg"
    assert_converted(summary, stdout, npz)
    steps = assert_same_steps(problem, serial, out, summary, stdout)
    assert_full_slip(summary, steps, lag=1)
    assert leftovers(tmp_path) == []
    if ranks == 1:  # the folder converted beforehand: the same run
        code, folder_summary, _, err = run_krylov_friction(
            folder, tmp_path / "folder", ranks)
        assert code == 0, err[-2000:]
        with np.load(tmp_path / "folder" / "contact.npz") as theirs:
            for key in ("friction_traction", "contact_force"):
                mine, ref = steps[f"step_{key}"], theirs[f"step_{key}"]
                assert np.abs(mine - ref).max() <= RTOL * np.abs(ref).max()
            for key in ("stick", "slip", "in_contact"):
                assert np.array_equal(steps[f"step_{key}"],
                                      theirs[f"step_{key}"])
        assert summary["njev"] == folder_summary["njev"]


def test_2d_block_implicit_from_the_npz(block, tmp_path):
    """The implicit bound (GMRES) on 2 ranks: the serial implicit run's
    steps; full slip at the step's own normal force."""
    problem, folder, _ = block
    serial = solve(problem, friction=FRICTION,
                                        steps=STEPS, coulomb="implicit")
    assert serial.success
    npz = folder.parent / "r1.npz"
    out = tmp_path / "out"
    code, summary, stdout, err = run_krylov_friction(
        npz, out, 2, "gamg", "--coulomb", "implicit")
    assert code == 0, err[-2000:]
    assert summary["coulomb"] == "implicit"
    assert_converted(summary, stdout, npz)
    steps = assert_same_steps(problem, serial, out, summary, stdout)
    assert_full_slip(summary, steps, lag=0)
    assert leftovers(tmp_path) == []


@pytest.mark.parametrize("options, refused", [
    (dict(), "system='full' without ksp='gamg' or 'hypre'"),
    (dict(ksp="mumps"), "ksp='mumps'"),
    (dict(ksp="gamg", formulation="thesis"), "formulation='thesis'"),
    (dict(ksp="gamg", method="fb"), "method='fb'"),
    (dict(ksp="gamg", rollers=False), "rollers=False"),
    (dict(ksp="gamg", gap_scale=2.0), "gap_scale=2.0"),
    (dict(ksp="gamg", search_interval=(0.0, 1.0)), "search_interval="),
])
def test_what_the_conversion_fixes_is_refused(block, options, refused):
    """By the front's rules, before any rank works (no petsc4py here: the
    rules refuse before the engine is made)."""
    problem = block[0]
    with pytest.raises(SolverError) as info:
        solve(problem, friction=FRICTION, steps=STEPS, engine="petsc",
                system="full", **options)
    assert str(info.value).startswith(refused)


def test_refused_option_leaves_nothing(block, tmp_path):
    """``--ksp mumps``: exit 2, one line in the command line's words, no
    output folder and no temporary folder."""
    npz = block[1].parent / "r1.npz"
    code, summary, _, err = run_krylov_friction(npz, tmp_path / "out", 1,
                                                "mumps")
    assert code == 2 and summary is None
    lines = [line for line in err.splitlines() if line.startswith("error")]
    assert len(lines) == 1  # mpiexec adds its own banner on exit 2
    assert lines[0].startswith("error: --ksp mumps is not supported for "
                               "2D, rigid, friction, petsc engine")
    assert "Traceback" not in err
    assert os.listdir(tmp_path) == []


def test_sigterm_to_mpiexec_removes_the_folder(block, tmp_path):
    """SIGTERM to mpiexec once the steps run (Open MPI forwards it to the
    ranks and kills them a second later): "interrupted", the completed
    steps kept, the temporary folder gone."""
    npz = block[1].parent / "r1.npz"
    out = tmp_path / "run"
    env = dict(os.environ, OMP_NUM_THREADS="1")
    proc = subprocess.Popen(
        ["mpiexec", "--allow-run-as-root", "--oversubscribe", "-n", "2",
         sys.executable, "-m", "solver", str(npz), "--engine", "petsc",
         "--system", "full", "--ksp", "gamg", "--friction",
         str(FRICTION), "--steps", "2000", "-o", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        deadline = time.monotonic() + 120
        while not (out / "steps" / "step_0002.pvtu").exists():
            assert time.monotonic() < deadline and proc.poll() is None
            time.sleep(0.05)
        assert len(leftovers(tmp_path)) == 1  # the run's own
        proc.send_signal(signal.SIGTERM)
        _, stderr = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode != 0
    assert "Traceback" not in stderr
    assert "error: interrupted by SIGTERM" in stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted"
    assert leftovers(tmp_path) == []


@pytest.fixture()
def small_disk(tmp_path):
    """A 256 KiB tmpfs at ``tmp_path / "disk"`` (root and a kernel that
    lets this process mount; skipped otherwise), unmounted after."""
    disk = tmp_path / "disk"
    disk.mkdir()
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k",
                           "tmpfs", str(disk)], capture_output=True)
    if done.returncode != 0:
        pytest.skip("cannot mount a small tmpfs here: "
                    + done.stderr.decode(errors="replace").strip())
    try:
        yield disk
    finally:
        subprocess.run(["umount", str(disk)], check=False)


def test_full_disk_during_the_conversion(block, small_disk):
    """K (≈1 MB padded) does not fit on the 256 KiB disk beside the
    outputs: the disk-full line, exit 4, summary.json "failed", no
    temporary folder."""
    npz = block[1].parent / "r1.npz"
    out = small_disk / "out"
    code, summary, _, err = run_krylov_friction(npz, out, 2)
    assert code == 4, err[-2000:]
    assert "Traceback" not in err
    lines = [line for line in err.splitlines() if line.startswith("error")]
    assert len(lines) == 1, err[-2000:]
    line = lines[0]
    assert line.startswith("error: cannot write ") and \
        line.endswith("No space left on device"), line
    assert summary["status"] == "failed" and not summary["converged"]
    assert leftovers(small_disk) == []
