"""SfePy's two contact examples: ``sfepy-run``'s penalty solve against the
contact solver's exact solve of the same example, in the same run
(issue 35, point 3).

For each example (``elastic_contact_sphere.py``, ``elastic_contact_planes.py``
on SfePy's ``cube_medium_hexa.mesh``, 3993 DOFs):

* **SfePy**: ``sfepy-run`` on SfePy's own example file, as shipped (penalty
  k = 1e5, its Newton settings), in a subprocess: the Newton iterations
  and the solve time SfePy reports (``solved in ... seconds``: its Newton
  loop with assembly and the direct solves), and the process's wall time.
* **ours**: the problem file of this repository
  (``sfepy_problems/sfepy_contact_*.py``) exported once (not timed), then
  :func:`solver.solve` in-process, the best of ``--repeat`` solves (the
  solve's own time, geometry included) with the default sparse backend
  ("auto": PARDISO where installed) and with CHOLMOD, and the wall time of
  ``python -m solver`` in a subprocess.

``ratio`` is SfePy's solve time over ours; ``wall ratio`` the processes'
(both include Python's and the libraries' start, about 1.5 s).

Usage::

    python benchmarks/sfepy_examples.py [--workdir DIR] [--repeat 3]
"""

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from solver import load_problem, solve  # noqa: E402

EXAMPLES = ("sphere", "planes")
COLUMNS = ("example", "SfePy iter", "SfePy solve s", "SfePy wall s",
           "our iter", "our solve s (auto)", "our solve s (CHOLMOD)",
           "our wall s", "ratio (auto)", "ratio (CHOLMOD)", "wall ratio")


def sfepy_example(name):
    """The path of SfePy's own ``elastic_contact_NAME.py``."""
    import sfepy

    return (Path(sfepy.__file__).parent / "examples" / "linear_elasticity"
            / f"elastic_contact_{name}.py")


def run(argv, cwd):
    """(stdout + stderr, wall seconds) of a subprocess with this
    repository on the path."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    start = time.perf_counter()
    done = subprocess.run(argv, capture_output=True, text=True, cwd=cwd,
                          env=env, check=True)
    return done.stdout + done.stderr, time.perf_counter() - start


def sfepy_run(name, workdir):
    """SfePy's penalty solve of its example: (iterations, solve s, wall s,
    converged)."""
    script = Path(sys.executable).with_name("sfepy-run")
    log, wall = run([str(script), str(sfepy_example(name)), "-o",
                     str(workdir / f"sfepy_{name}")], workdir)
    iters = [int(k) for k in re.findall(r"nls: iter: (\d+)", log)]
    seconds = float(re.search(r"solved in \d+ steps in ([\d.]+) seconds",
                              log).group(1))
    rel = [float(r) for r in re.findall(r"\(rel: ([\d.e+-]+)\)", log)]
    return max(iters), seconds, wall, rel[-1] < 1e-8


def ours(name, workdir, repeat):
    """Export, solve in-process (best of ``repeat``) and as ``python -m
    solver``: (iterations, solve s, wall s)."""
    out = workdir / f"{name}.npz"
    run([sys.executable,
         str(ROOT / "sfepy_problems" / f"sfepy_contact_{name}.py"), "-d",
         f"output='{out}'"], workdir)
    problem = load_problem(out)
    best = {}
    for backend in ("auto", "cholmod"):
        times = []
        for _ in range(repeat):
            result = solve(problem, backend=backend)
            assert result.success, result.message
            times.append(result.time)
        best[backend] = min(times)
    _, wall = run([sys.executable, "-m", "solver", str(out), "-o",
                   str(workdir / f"ours_{name}")], workdir)
    return result.nit, best, wall


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workdir", type=Path, default=None)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--examples", default=",".join(EXAMPLES))
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        workdir = args.workdir or Path(tmp)
        workdir.mkdir(parents=True, exist_ok=True)
        print(" | ".join(COLUMNS))
        print("|".join("---" for _ in COLUMNS))
        for name in args.examples.split(","):
            it, seconds, wall, converged = sfepy_run(name, workdir)
            our_it, our_seconds, our_wall = ours(name, workdir, args.repeat)
            print(" | ".join([
                name, f"{it}" + ("" if converged else " (not converged)"),
                f"{seconds:.2f}", f"{wall:.2f}", f"{our_it}",
                f"{our_seconds['auto']:.3f}", f"{our_seconds['cholmod']:.3f}",
                f"{our_wall:.2f}", f"{seconds / our_seconds['auto']:.0f}",
                f"{seconds / our_seconds['cholmod']:.0f}",
                f"{wall / our_wall:.1f}"]),
                flush=True)


if __name__ == "__main__":
    main()
