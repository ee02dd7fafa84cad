"""Faults around a run (issue 16, classes 4-6; issue 15, items 1, 7-9).

Each test runs the command line the way a user or a script would (as a
subprocess where signals, pipes, umask or file-size limits are involved)
and checks what is left on disk with independent readers: ``json``,
``xml.etree`` for the ParaView index, ``meshio`` for every VTU and
``numpy.load`` for result.npz.
"""

import fcntl
import json
import os
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest

from solver.cli import main

SOLVER = [sys.executable, "-m", "solver"]


def listing(folder):
    """Every file below ``folder``, relative, sorted."""
    return sorted(os.path.relpath(os.path.join(d, f), folder)
                  for d, _, files in os.walk(folder) for f in files)


def summary(folder):
    with open(os.path.join(folder, "summary.json")) as stream:
        return json.load(stream)


def read_everything(folder):
    """Read back every file of a run with independent readers; return the
    summary. Fails on a temp file, an unlisted file or an unreadable one."""
    data = summary(folder)
    files = listing(folder)
    assert not [f for f in files if os.path.basename(f).startswith(".")]
    assert sorted(data["files"]) == files
    pvd = os.path.join(folder, "result.pvd")
    if os.path.exists(pvd):
        entries = ET.parse(pvd).getroot().find("Collection")
        times = [float(e.get("timestep")) for e in entries]
        assert times == sorted(times) and 0 < times[0] and times[-1] <= 1
        for entry in entries:
            mesh = meshio.read(os.path.join(folder, entry.get("file")))
            assert mesh.point_data["u"].shape[1] == 3
    for name in files:
        if name.endswith(".vtu"):
            assert len(meshio.read(os.path.join(folder, name)).points)
    if "result.npz" in files:
        with np.load(os.path.join(folder, "result.npz")) as npz:
            for key in npz.files:
                assert np.asarray(npz[key]).size >= 0
    return data


@pytest.fixture(scope="module")
def block(exported):
    return str(exported(118)[0])


def test_friction_outputs_read_back(block, tmp_path):
    """Issue 15.1: the .pvd parses as XML with float timesteps, every VTU it
    names reads with meshio, result.npz has the completed steps."""
    out = tmp_path / "f"
    code = main([block, "--friction", "0.3", "--steps", "7",
                 "--formulation", "projection", "-o", str(out)])
    assert code == 0
    data = read_everything(out)
    assert data["status"] == "converged"
    with np.load(out / "result.npz") as npz:
        assert npz["displacement"].shape[0] == 7 == int(npz["steps_completed"])
        np.testing.assert_allclose(npz["load_factor"], np.arange(1, 8) / 7)
        assert np.isfinite(npz["gap"]).any() and npz["normal"].shape[1] == 2
        assert "contact_pressure_consistent" in npz.files
    text = (out / "result.pvd").read_text()
    assert "np.float64" not in text and 'timestep="0.14285714285714285"' \
        in text


def test_streamed_steps_equal_in_memory_run(block, tmp_path):
    """Steps streamed to disk (bounded memory) are the in-memory run's."""
    from solver import load_problem, solve_friction

    problem = load_problem(block)
    reference = solve_friction(problem, 0.3, steps=40,
                               formulation="projection")
    out = tmp_path / "s"
    assert main([block, "--friction", "0.3", "--steps", "40",
                 "--formulation", "projection", "-o", str(out)]) == 0
    with np.load(out / "result.npz") as npz:
        for key in ("u", "displacement", "contact_force", "slip",
                    "friction_traction", "contact_pressure"):
            np.testing.assert_array_equal(npz[key], reference[key])
    lean = solve_friction(problem, 0.3, steps=40, formulation="projection",
                          keep_steps=False)
    assert "u" not in lean and lean.steps_completed == 40


@pytest.mark.parametrize("umask, mode", [(0o022, 0o644), (0o002, 0o664),
                                         (0o077, 0o600)])
def test_files_respect_umask(block, tmp_path, umask, mode):
    """Issue 15.7: outputs get 0666 & ~umask, as other tools' files."""
    out = tmp_path / "u"
    subprocess.run(SOLVER + [block, "--plots", "-o", str(out)], check=True,
                   capture_output=True, preexec_fn=lambda: os.umask(umask))
    for name in listing(out):
        assert os.stat(out / name).st_mode & 0o777 == mode, name


def test_info_into_closed_pipe(block):
    """Issue 15.8: `--info --json | head -c 100` ends quietly."""
    proc = subprocess.run(
        f"{sys.executable} -m solver {block} --info --json | head -c 100; "
        "echo \" rc=${PIPESTATUS[0]}\"", shell=True, capture_output=True,
        text=True, executable="/bin/bash")
    assert proc.stderr == ""
    assert proc.stdout.endswith(" rc=141\n") or proc.stdout.endswith(
        " rc=0\n")  # head may read everything before it exits


def test_stdout_full(block, tmp_path):
    """stdout on /dev/full: outputs complete, exit 4, one line on stderr."""
    out = tmp_path / "full"
    with open("/dev/full", "w") as full:
        proc = subprocess.run(SOLVER + [block, "-o", str(out)], stdout=full,
                              stderr=subprocess.PIPE, text=True)
    assert proc.returncode == 4
    assert proc.stderr.splitlines() == [
        "error: cannot write to standard output: no space left on device"] \
        or proc.stderr.startswith("error: cannot write to standard output")
    assert len(proc.stderr.splitlines()) == 1
    assert read_everything(out)["status"] == "converged"


def test_file_size_limit(exported, tmp_path):
    """A full disk (ulimit -f): exit 4, no temp file, no result file that
    looks complete; summary.json says failed (it is small enough). On the
    454 block result.npz and result.vtu exceed 10 KiB, summary.json not."""
    out, block = tmp_path / "small", exported(454)[0]
    proc = subprocess.run(
        f"ulimit -f 10; exec {sys.executable} -m solver {block} -o {out}",
        shell=True, capture_output=True, text=True, executable="/bin/bash")
    assert proc.returncode == 4, proc.stderr
    assert "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    data = read_everything(out)
    assert data["status"] == "failed" and data["converged"] is False
    assert "result.vtu" not in data["files"]


@pytest.mark.parametrize("signum, code", [(signal.SIGINT, 130),
                                          (signal.SIGTERM, 143)])
def test_interrupted_friction_run(block, tmp_path, signum, code):
    """Issue 16.5: Ctrl-C / SIGTERM keep the completed steps, readable, mark
    the run interrupted, leave no temp file, and exit 128 + signal."""
    out = tmp_path / "int"
    proc = subprocess.Popen(
        SOLVER + [block, "--friction", "0.3", "--steps", "20000",
                  "--formulation", "projection", "-o", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300
    # Step 11's file exists, so step 10 has certainly been counted (a
    # step's file appears just before the count that includes it).
    while not (out / "steps" / "step_0011.vtu").exists():
        assert time.monotonic() < deadline and proc.poll() is None
        time.sleep(0.05)
    proc.send_signal(signum)
    stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == code, stderr
    assert "Traceback" not in stderr
    assert stderr.strip().splitlines()[-1].startswith("error: interrupted")
    data = read_everything(out)
    assert data["status"] == "interrupted" and data["converged"] is False
    done = data["steps_completed"]
    assert 10 <= done < 20000
    with np.load(out / "result.npz") as npz:
        assert npz["displacement"].shape[0] == done
        assert not npz["converged"]
    assert len(listing(out / "steps")) == done


def test_input_inside_output_folder_is_never_overwritten(block, tmp_path,
                                                         capsys):
    """Issue 16.6: an input named like an output in the output folder."""
    out = tmp_path / "o"
    out.mkdir()
    for name in ("result.npz", "summary.json", "result.vtu"):
        target = out / name
        target.write_bytes(open(block, "rb").read())
        before = target.read_bytes()
        assert main([str(target), "-o", str(out)]) == 2
        err = capsys.readouterr().err
        assert "would be overwritten" in err and len(err.splitlines()) == 1
        assert target.read_bytes() == before
        target.unlink()


def test_hard_link_to_input_is_detected(block, tmp_path, capsys):
    out = tmp_path / "o"
    out.mkdir()
    os.link(block, out / "result.npz")
    assert main([block, "-o", str(out)]) == 2
    assert "would be overwritten" in capsys.readouterr().err


def test_folder_in_use_is_refused(block, tmp_path, capsys):
    """Two runs into one folder: the second gets a clear error."""
    out = tmp_path / "busy"
    out.mkdir()
    fd = os.open(out, os.O_RDONLY)
    fcntl.flock(fd, fcntl.LOCK_EX)
    try:
        assert main([block, "-o", str(out)]) == 2
    finally:
        os.close(fd)
    err = capsys.readouterr().err
    assert "in use by another run" in err and listing(out) == []
    assert main([block, "-o", str(out)]) == 0  # free again


def test_stale_outputs_are_cleared(block, tmp_path):
    """A frictionless run after a friction run in the same folder: nothing
    of the earlier run is left beside the new one's files."""
    out = tmp_path / "same"
    assert main([block, "--friction", "0.3", "--steps", "5",
                 "--formulation", "projection", "--plots", "-o",
                 str(out)]) == 0
    assert "result.pvd" in listing(out)
    (out / "notes.txt").write_text("mine")  # not ours: kept
    assert main([block, "-o", str(out)]) == 0
    files = listing(out)
    assert "result.pvd" not in files and "history.png" not in files
    assert not [f for f in files if f.startswith("steps")]
    assert "notes.txt" in files
    assert sorted(summary(out)["files"]) == [f for f in files
                                             if f != "notes.txt"]


def test_fifo_input_is_refused(tmp_path):
    fifo = tmp_path / "p.npz"
    os.mkfifo(fifo)
    proc = subprocess.run(SOLVER + [str(fifo)], capture_output=True,
                          text=True, timeout=60)
    assert proc.returncode == 2 and "not a regular file" in proc.stderr


def test_internal_error_is_one_line(block, tmp_path, capsys, monkeypatch):
    """A bug (simulated) gives exit 1, one line, and a marked folder."""
    import solver.contact

    def broken(*args, **kwargs):
        raise RuntimeError("simulated bug")

    monkeypatch.setattr(solver.contact, "run_frictionless", broken)
    out = tmp_path / "bug"
    assert main([block, "-o", str(out)]) == 1
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("error: internal error:")
    assert summary(out)["status"] == "failed"


def test_progress_lines_without_a_terminal(block, tmp_path):
    """Issue 15.9: no tty: a progress line per 10 % of the steps."""
    proc = subprocess.run(
        SOLVER + [block, "--friction", "0.3", "--steps", "20",
                  "--formulation", "projection", "-o", str(tmp_path / "p")],
        capture_output=True, text=True)
    assert proc.returncode == 0
    lines = [line for line in proc.stderr.splitlines()
             if line.startswith("load step ")]
    assert len(lines) == 10
    assert lines[-1].startswith("load step 20/20 (100 %): J ")
    assert "elapsed" in lines[-1] and "stopping measure" in lines[-1]


def test_load_path_with_too_many_steps(block, tmp_path, capsys):
    from solver.contact.friction.stream import MAX_LOAD_STEPS
    from solver.problem import load_problem

    problem = load_problem(block)
    problem.load_path_steps = np.array([2 ** 62, 2 ** 62])  # int64 wraps
    problem.load_path = [problem.f, problem.f]
    from solver import solve

    with pytest.raises(Exception, match=f"at most {MAX_LOAD_STEPS}"):
        solve(problem, friction=0.3, method="min")


def test_a_second_signal_cannot_cut_the_finish_short():
    """The first SIGINT, SIGTERM or SIGHUP stops the run; the ones after it
    are ignored until the run has written its outputs (the handlers the
    caller had come back when it returns). Before, Ctrl-C stayed Python's
    KeyboardInterrupt and any signal during the finish raised again."""
    import importlib
    import warnings
    from types import SimpleNamespace

    run = importlib.import_module("solver.cli.run")
    stops = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
    saved = {s: signal.getsignal(s) for s in stops}
    try:
        for signum in stops:
            with warnings.catch_warnings():
                run._setup(SimpleNamespace(verbose=True))
            with pytest.raises(run.Interrupted) as caught:
                signal.raise_signal(signum)
            assert caught.value.signum == signum
            assert all(signal.getsignal(s) is signal.SIG_IGN for s in stops)
            signal.raise_signal(signal.SIGTERM)  # ignored: nothing raised
    finally:
        for signum, handler in saved.items():
            signal.signal(signum, handler)


def test_temporaries_of_a_killed_run_are_removed(block, tmp_path):
    """A run killed with SIGKILL (``kill -9``, or ``mpiexec`` when its
    grace after SIGTERM ends) leaves its scratch folder and temporary
    files; the next run into the folder (which it holds locked) removes
    them, and keeps files that are not ours."""
    out = tmp_path / "killed"
    (out / ".tmp-steps-x1y2").mkdir(parents=True)
    (out / ".tmp-steps-x1y2" / "u.npy").write_bytes(b"\x93NUMPY")
    (out / ".tmp-abc123.npz").write_bytes(b"PK")
    (out / "steps").mkdir()
    (out / "steps" / ".tmp-def456.vtu").write_text("<VTKFile")
    (out / "notes.txt").write_text("mine")
    (out / "summary.json").write_text(json.dumps({"status": "running"}))
    assert main([block, "--friction", "0.3", "--steps", "3",
                 "--formulation", "projection", "-o", str(out)]) == 0
    files = listing(out)
    assert "notes.txt" in files
    files.remove("notes.txt")
    assert not [f for f in files if "/." in "/" + f], files
    assert sorted(summary(out)["files"]) == files
