"""Fresh processes for the benchmark: the export, each measurement
(``measure.py``) and the output stage (``python -m solver``), each with its
wall time and its own peak resident memory (``ru_maxrss`` from ``wait4``,
i.e. the child alone, not the largest child so far)."""

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

__all__ = ["StageError", "run_process", "run_measured", "measure",
           "output_stage", "export", "THREADS", "LOG"]

#: Environment variables set in every measured process (``--threads``).
THREADS = {}
#: Every measurement's JSON line is appended here if set (``--log``).
LOG = []


class StageError(RuntimeError):
    """A measured process failed."""


def run_measured(command, cwd=ROOT):
    """Run ``command``; a dict of its ``stdout``, ``wall`` time [s],
    ``cpu`` time (user + system of the child, all threads) [s] and ``rss``,
    the child's peak resident memory [MB]. StageError with the tail of its
    stderr if it fails."""
    env = dict(os.environ, PYTHONWARNINGS="ignore", **THREADS)
    with tempfile.TemporaryFile() as errors:
        start = time.perf_counter()
        process = subprocess.Popen([str(c) for c in command], cwd=cwd,
                                   env=env, stdout=subprocess.PIPE,
                                   stderr=errors)
        stdout = process.stdout.read().decode(errors="replace")
        process.stdout.close()
        _, status, usage = os.wait4(process.pid, 0)
        elapsed = time.perf_counter() - start
        process.returncode = code = os.waitstatus_to_exitcode(status)
        if code:
            errors.seek(0)
            tail = errors.read().decode(errors="replace")[-800:]
            raise StageError(f"{Path(str(command[1])).name} "
                             f"{' '.join(map(str, command[2:4]))} failed "
                             f"(exit {code}): {tail}")
    return dict(stdout=stdout, wall=elapsed,
                cpu=usage.ru_utime + usage.ru_stime,
                rss=usage.ru_maxrss / 1024)


def run_process(command, cwd=ROOT):
    """Run ``command``; (stdout, wall time [s], peak RSS [MB] of the
    child). StageError with the tail of its stderr if it fails."""
    run = run_measured(command, cwd)
    return run["stdout"], run["wall"], run["rss"]


def measure(npz, stage, backend="auto", steps=100, *extra):
    """One stage of ``measure.py`` in a fresh process (``extra``: its
    further arguments); its JSON as a dict."""
    stdout, _, _ = run_process([sys.executable,
                                ROOT / "benchmarks" / "measure.py", npz,
                                stage, backend, steps, *extra])
    line = stdout.strip().splitlines()[-1]
    if LOG:
        with open(LOG[0], "a") as log:
            log.write(json.dumps({"problem": Path(npz).name, "stage": stage,
                                  "backend": backend, **json.loads(line)})
                      + "\n")
    return json.loads(line)


def output_stage(npz, backend, folder):
    """``python -m solver PROBLEM -o DIR --linear-solver backend`` as a
    whole (start-up, loading, solve, result folder): (time, RSS MB)."""
    _, elapsed, rss = run_process(
        [sys.executable, "-m", "solver", npz, "-o", Path(folder) / "out",
         "--linear-solver", backend])
    return elapsed, rss


def export(mesh, name, folder, generator="generate.py",
           problem="block_obstacle.py"):
    """Make the mesh (``mesh`` is the arguments of ``meshes/<generator>``
    or a committed mesh file) and export it with sfepy-run of
    ``sfepy_problems/<problem>``; (npz, export time, export RSS MB). With
    a kept folder an earlier export is reused, with the time and memory
    recorded then (the mesh generation is not in the export time)."""
    folder = Path(folder)
    npz, record = folder / f"{name}.npz", folder / f"{name}.export.json"
    if npz.exists() and record.exists():
        saved = json.loads(record.read_text())
        return npz, saved["time"], saved["rss"]
    if isinstance(mesh, (str, Path)):
        mesh_file = Path(mesh)
    else:
        mesh_file = folder / f"{name}.mesh"
        run_process([sys.executable, ROOT / "meshes" / generator, *mesh,
                     "-o", mesh_file])
    script = Path(sys.executable).parent / "sfepy-run"
    _, elapsed, rss = run_process(
        [script if script.exists() else "sfepy-run",
         ROOT / "sfepy_problems" / problem, "-d",
         f"mesh='{mesh_file}', output='{npz}'"], cwd=folder)
    record.write_text(json.dumps({"time": elapsed, "rss": rss}))
    return npz, elapsed, rss
