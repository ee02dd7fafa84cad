"""The PETSc engine under MPI (solver/mpi, issue 20) against the serial
solver, on 1 and 2 ranks (``mpiexec -n 1``, ``-n 2``): the same u to 1e-8
(relative to max|u|) and, for the project's Newton methods, the same
Newton counts, on the thesis blocks 118 and 454 and the 1878 block refined
once (7668 DOFs); PETSc's own SNESVI (reduced-space active-set Newton, an
independent solver) gives the same u as the serial φ_min solve.

The references are the serial engine in this process on the same problem
and the same iteration: condensed, ``candidates=True, start="free"`` (the
iteration the engine runs); full system, ``condense=False``; friction,
``solve_friction(..., formulation="projection")``. Each rank count runs
every case in one ``mpiexec`` launch (:data:`DRIVER`, through the API);
the command line (outputs, one-line errors, exit codes) has its own runs.
Skipped, with the reason naming the ``petsc`` extra, when petsc4py/mpi4py
or mpiexec is missing.
"""

import functools
import json
import os
import shutil
import subprocess
import sys
import time

import numpy as np
import pytest

from solver import load_problem, solve_friction, solve_frictionless
from solver.mpi import missing

REASON = missing() or (None if shutil.which("mpiexec") else
                       "mpiexec not found: apt-get install mpi-default-bin "
                       "(and pip install '.[petsc]', docs/mpi.md)")
pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))

RTOL = 1e-8
MESHES = (118, 454, "r1")
CASES = {  # name -> API call on the engine
    "condensed-min": "solve_frictionless(p, method='min')",
    "condensed-fb": "solve_frictionless(p, method='fb')",
    "full-min-mumps": "solve_frictionless(p, method='min', system='full')",
    "full-fb-mumps": "solve_frictionless(p, method='fb', system='full')",
    "full-min-gamg": "solve_frictionless(p, method='min', system='full', "
                     "ksp='gamg')",
    "full-fb-gamg": "solve_frictionless(p, method='fb', system='full', "
                    "ksp='gamg')",
    "friction": "solve_friction(p, 0.3, steps=10, method='fb')",
}

DRIVER = """
import json, sys, numpy as np
from solver import load_problem
import functools, solver
solve_frictionless = functools.partial(solver.solve_frictionless, engine="petsc")
solve_friction = functools.partial(solver.solve_friction, engine="petsc")
from solver.mpi.engine import spmd
from solver.mpi.snesvi import solve_snesvi

def main(paths, cases, out):
    arrays = {}
    for mesh, path in paths.items():
        p = load_problem(path)
        for name, call in cases.items():
            r = eval(call)
            arrays[f"{mesh}/{name}/u"] = r.displacement
            arrays[f"{mesh}/{name}/njev"] = r.njev
            its = r.engine.get("ksp_iterations", [])
            arrays[f"{mesh}/{name}/its"] = np.array(its, int)
            arrays[f"{mesh}/{name}/ranks"] = r.engine["ranks"]
        arrays[f"{mesh}/snesvi/u"] = solve_snesvi(p)[0]
    np.savez(out, **arrays)

spmd(main, json.loads(sys.argv[1]), json.loads(sys.argv[2]), sys.argv[3])
"""


def mpirun(n, args, timeout=600):
    """``python args`` on n ranks: (exit code, stdout, stderr)."""
    env = dict(os.environ, OMP_NUM_THREADS="1")
    done = subprocess.run(["mpiexec", "--allow-run-as-root",
                           "--oversubscribe", "-n", str(n), sys.executable]
                          + [str(a) for a in args], capture_output=True,
                          text=True, timeout=timeout, env=env)
    return done.returncode, done.stdout, done.stderr


@pytest.fixture(scope="module")
def problems(exported, refined_block, tmp_path_factory):
    from solver import save_problem

    paths = {"118": exported(118)[0], "454": exported(454)[0]}
    paths["r1"] = tmp_path_factory.mktemp("mpi") / "r1.npz"
    save_problem(paths["r1"], refined_block(1))
    return {k: str(v) for k, v in paths.items()}


@pytest.fixture(scope="module", params=[1, 2])
def engine_runs(request, problems, tmp_path_factory):
    """Every case on every mesh, from one launch on ``n`` ranks."""
    out = tmp_path_factory.mktemp("runs") / f"n{request.param}.npz"
    code, _, err = mpirun(request.param, ["-c", DRIVER, json.dumps(problems),
                                          json.dumps(CASES), out])
    assert code == 0, err[-3000:]
    with np.load(out) as data:
        return request.param, dict(data)


@functools.lru_cache(maxsize=None)
def reference(path, name):
    p = load_problem(path)
    if name == "friction":
        r = solve_friction(p, 0.3, steps=10, formulation="projection",
                           method="fb")
    elif name.startswith("condensed"):
        r = solve_frictionless(p, method=name[10:], candidates=True,
                               start="free")
    else:
        r = solve_frictionless(p, method=name.split("-")[1], condense=False)
    return r.displacement, int(r.njev)


def close(u, ref):
    return np.abs(u - ref).max() <= RTOL * np.abs(ref).max()


@pytest.mark.parametrize("mesh", [str(m) for m in MESHES])
@pytest.mark.parametrize("name", list(CASES))
def test_engine_matches_serial(problems, engine_runs, mesh, name):
    n, runs = engine_runs
    u_ref, njev = reference(problems[mesh], name)
    assert close(runs[f"{mesh}/{name}/u"], u_ref)
    assert int(runs[f"{mesh}/{name}/njev"]) == njev
    assert int(runs[f"{mesh}/{name}/ranks"]) == n
    its = runs[f"{mesh}/{name}/its"]
    if name.startswith("full"):  # one KSP solve per Newton system
        assert len(its) == njev
        assert (its == 1).all() if "mumps" in name else (its > 1).all(), its


@pytest.mark.parametrize("mesh", [str(m) for m in MESHES])
def test_snesvi_matches_serial(problems, engine_runs, mesh):
    serial = solve_frictionless(load_problem(problems[mesh]), method="min")
    assert close(engine_runs[1][f"{mesh}/snesvi/u"], serial.u)


def test_command_line_outputs(problems, tmp_path):
    """``mpiexec -n 2 python -m solver X --engine petsc``: the serial run's
    files, its u, per-rank counts in summary.json, printed once."""
    out = tmp_path / "o"
    code, stdout, err = mpirun(2, ["-m", "solver", problems["454"],
                                   "--engine", "petsc", "-o", out])
    assert code == 0, err
    assert stdout.count("verification      passed") == 1
    summary = json.loads((out / "summary.json").read_text())
    assert {"result.npz", "result.vtu", "summary.json"} <= \
        set(summary["files"])
    serial = solve_frictionless(load_problem(problems["454"]),
                                candidates=True, start="free")
    with np.load(out / "result.npz") as data:
        assert close(data["displacement"], serial.displacement)
    per_rank = summary["engine"]["per_rank"]
    assert [r["rank"] for r in per_rank] == [0, 1]
    assert sum(r["contact_nodes_owned"] for r in per_rank) == \
        int(np.isfinite(serial.gap).sum())
    assert sum(r["rows"] for r in per_rank) == 2 * len(
        load_problem(problems["454"]).nodes)
    assert all(r["peak_rss_mb"] > 0 and r["seconds"]["factor"] > 0
               for r in per_rank)


def test_errors_one_line_every_rank(problems, tmp_path):
    """Bad input on 2 ranks: exit 2 on every rank, one line from rank 0,
    no traceback, no hang."""
    for options, text in ((["--ksp", "gamg"], "--system full"),
                          (["--friction", "0.3", "--formulation", "thesis"],
                           "projection")):
        code, _, err = mpirun(2, ["-m", "solver", problems["118"],
                                  "--engine", "petsc", "-o",
                                  tmp_path / "e", *options])
        lines = [ln for ln in err.splitlines() if ln.startswith(
            ("error", "python -m solver"))]
        assert code == 2 and len(lines) == 1 and text in lines[0], err
        assert "Traceback" not in err


SCHUR_DRIVER = """
import sys, numpy as np
from solver import load_problem
from solver.contact.strategies.candidates import NormalCondensation
from solver.contact.geometry import contact_geometry
from solver.mpi.engine import service, spmd
from solver.mpi.factor import PetscFactor
from solver.mpi.layout import Layout

def main(path, out):
    p = load_problem(path)
    svc = service()
    g = contact_geometry(p, "obstacle")
    K = NormalCondensation(p, g, "superlu").K
    c = g.dofs[:, -1]
    layout = Layout(p, svc.size)
    svc.call("layout", layout.ranges())
    b = np.random.default_rng(0).standard_normal(p.n_dofs)
    u_c = np.random.default_rng(1).standard_normal(len(c))
    arrays = {}
    for name, block in (("mumps", None), ("solves", 8)):
        F = PetscFactor(svc, layout, K, c[: len(c) // 2], block=block)
        F.schur(c)  # a second, larger set: refactorised or re-solved
        arrays[name + "/S"] = F.S
        arrays[name + "/x"] = F.solve(b)
        arrays[name + "/u"] = F.back_substitute(b, u_c)
        arrays[name + "/factorizations"] = F.factorizations
    np.savez(out, **arrays)

spmd(main, sys.argv[1], sys.argv[2])
"""


@pytest.mark.parametrize("n", [1, 2])
def test_schur_mode_matches_serial(problems, tmp_path, n):
    """MUMPS's Schur mode (ctypes on libpetsc, solver/mpi/schur.py) on 1
    and 2 ranks: S on the normal rows of every contact node of the 454
    block equals SuperLU's Schur complement (an independent factorisation,
    solver.linalg.superlu) to 1e-10; K⁻¹b and the back-substitution
    u_i = K_ii⁻¹(b_i − K_ic u_c) equal SuperLU's; the old path (S from
    solves of 8 columns) agrees too. The second Schur set costs one new
    factorisation in the Schur mode, none with the solves."""
    from solver.contact.strategies.candidates import NormalCondensation
    from solver.contact.geometry import contact_geometry
    from solver.linalg import factorize

    out = tmp_path / "schur.npz"
    code, _, err = mpirun(n, ["-c", SCHUR_DRIVER, problems["454"], out])
    assert code == 0, err[-3000:]
    p = load_problem(problems["454"])
    g = contact_geometry(p, "obstacle")
    K = NormalCondensation(p, g, "superlu").K
    c = g.dofs[:, -1]
    ref = factorize(K, schur=c, backend="superlu")
    b = np.random.default_rng(0).standard_normal(p.n_dofs)
    u_c = np.random.default_rng(1).standard_normal(len(c))
    with np.load(out) as data:
        for name, refactorised in (("mumps", 2), ("solves", 1)):
            assert np.abs(data[name + "/S"] - ref.S).max() <= \
                1e-10 * np.abs(ref.S).max()
            assert close(data[name + "/x"], ref.solve(b))
            assert close(data[name + "/u"], ref.back_substitute(b, u_c))
            assert int(data[name + "/factorizations"]) == refactorised


IDLE_DRIVER = """
import sys, time
from solver.mpi.engine import service, spmd

def main(out):
    svc = service()
    before = svc.call("stats")[1]["cpu_s"]
    time.sleep(2.0)  # rank 0's serial work: the worker must not spin
    after = svc.call("stats")[1]["cpu_s"]
    open(out, "w").write(str(after - before))

spmd(main, sys.argv[1])
"""


def test_worker_waits_idle(tmp_path):
    """While rank 0 works alone for 2 s, rank 1 waits for the next command
    without spinning (solver/mpi/service.py polls with sleeps; a blocking
    MPI broadcast busy-waits, ≈ 2 s of CPU): under 0.5 s of CPU."""
    out = tmp_path / "cpu.txt"
    code, _, err = mpirun(2, ["-c", IDLE_DRIVER, out])
    assert code == 0, err[-3000:]
    assert float(out.read_text()) < 0.5


HALF_DRIVER = """
import solver.mpi.service as S
S.ABORT_AFTER = 2.0
from solver.mpi.service import command
from solver.mpi.engine import service, spmd

@command("half_fails")
def _half(svc, payload, local):
    if svc.rank == {failing}:
        raise RuntimeError("rank {failing} broke")
    svc.comm.allreduce(1)  # the others wait here for the failed rank

spmd(lambda: service().call("half_fails"))
"""


@pytest.mark.parametrize("failing", [0, 1])
def test_failure_inside_a_collective_aborts_not_hangs(failing):
    """A command that fails on one rank while the other waits in a
    collective call (as inside PETSc) would hang both forever: the failed
    rank aborts every rank after ABORT_AFTER (2 s here) with one line that
    names the command, the rank and the error; no traceback."""
    clock = time.monotonic()
    code, _, err = mpirun(2, ["-c", HALF_DRIVER.replace(
        "{failing}", str(failing))], timeout=120)
    lines = [ln for ln in err.splitlines() if ln.startswith("error")]
    assert code != 0 and time.monotonic() - clock < 60, err
    assert len(lines) == 1 and f"on rank {failing} of 2" in lines[0], err
    assert f"rank {failing} broke" in lines[0] and "Traceback" not in err
