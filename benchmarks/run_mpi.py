"""Benchmark of the PETSc engine (issue 20): 1 and 2 ranks against serial.

``python benchmarks/run_mpi.py [--problems A.npz,B.npz] [--repeat 3]
[--gamg R1.npz,...] [--blas libopenblas.so.0] [--log FILE]`` runs, for each problem, in fresh
processes and ``--repeat`` times each (rounds over the configurations):

- **serial**: ``solve(problem, method="min", candidates=True,
  start="free")`` with the fastest installed backend (the
  iteration the engine runs); with ``--serial-default`` also the serial
  default (nested start);
- **petsc N**: ``mpiexec -n N`` of the engine's condensed φ_min solve
  (MUMPS factorisation in its Schur mode, NCP on rank 0), N = 1, 2; with
  ``--blocked`` / ``--columns`` also (1 rank) the Schur complement from
  KSPMatSolve in blocks of 64 / column by column (before MPI20B);
- **gamg**: CG + GAMG (rigid-body near-null space) solving K u = f once,
  for the iteration counts as the mesh grows (``--gamg``).

Each measurement prints one JSON line: wall time of the solve (problem
loaded before the clock starts), Newton counts, per-rank peak RSS (MB,
``ru_maxrss``), per-rank memory after each stage (``memory_mb``: stage ->
[VmRSS, VmHWM] in MB; rank 0's own stages ``start``, ``geometry``,
``rotate``, ``pad``, ``verify`` and every command), MUMPS's own memory
per rank (``mumps_mb``: INFO(15)/(16)/(22), INFOG(16)/(17)/(21)/(22)),
CPU time and command times, the factorisations and per-round candidates,
and the load average when it ended. ``--log`` appends them to a file. The table of
benchmarks/README.md is made from that log by hand.
"""

import argparse
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
#: Engine mode -> ``schur_block``: MUMPS's Schur mode (the default since
#: MPI20B), KSPMatSolve of 64 sparse right-hand sides, column by column.
SCHUR_MODES = dict(schur=None, blocked=64, columns=1)
#: ``--blas``: a shared BLAS preloaded into the PETSc runs.
BLAS = [None]
MPIEXEC = ["mpiexec", "--allow-run-as-root", "--oversubscribe", "--bind-to",
           "none"]


def _serial(path, mode):
    import resource

    from solver import load_problem, solve

    problem = load_problem(path)
    clock = time.perf_counter()
    options = dict(candidates=True, start="free") if mode == "free" else {}
    result = solve(problem, method="min", **options)
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return dict(time=time.perf_counter() - clock, njev=int(result.njev),
                nit=int(result.nit), backend=result.linear_solver,
                cpu_s=[usage.ru_utime + usage.ru_stime],
                n_dofs=problem.n_dofs, peak_rss_mb=[resource.getrusage(
                    resource.RUSAGE_SELF).ru_maxrss / 1024.0])


def _petsc(path, mode):
    import numpy as np

    from solver import load_problem
    from solver.mpi.engine import service, spmd

    def main():
        problem = load_problem(path)
        clock = time.perf_counter()
        if mode == "gamg":
            return _gamg(problem, clock)
        from solver import solve
        from solver.mpi.engine import PetscEngine

        result = solve(problem, method="min",
                       engine=PetscEngine(schur_block=SCHUR_MODES[mode]))
        seconds = time.perf_counter() - clock
        per_rank = result.engine["per_rank"]
        return dict(time=seconds, njev=int(result.njev), nit=int(result.nit),
                    n_dofs=problem.n_dofs,
                    n_candidates=result.candidates["n_candidates"],
                    peak_rss_mb=[r["peak_rss_mb"] for r in per_rank],
                    memory_mb=[r["memory_mb"] for r in per_rank],
                    mumps_mb=[r.get("mumps_mb") for r in per_rank],
                    cpu_s=[r.get("cpu_s") for r in per_rank],
                    seconds=[r["seconds"] for r in per_rank],
                    cpu_seconds=[r["cpu_seconds"] for r in per_rank],
                    rows=[r["rows"] for r in per_rank],
                    factorizations=result.engine["factorizations"],
                    rounds=[(r["n_candidates"], round(r["factorize_time"], 2))
                            for r in result.candidates["rounds"]])

    def _gamg(problem, clock):
        import scipy.sparse as sp

        from solver.mpi.full import rigid_modes
        from solver.mpi.layout import Layout

        svc = service()
        layout = Layout(problem, svc.size)
        svc.call("layout", layout.ranges())
        eye = sp.identity(problem.n_dofs, format="csr")
        svc.call("newton_setup", dict(ksp="gamg", bsize=layout.dim,
                                      scale=float(problem.K.diagonal().mean())),
                 (layout.matrix(problem.K), rigid_modes(problem, layout,
                                                         eye)))
        setup = time.perf_counter() - clock
        u = svc.call("newton_solve", dict(
            shift_rows=np.zeros(0, np.int64), shift=np.zeros(0),
            fixed_rows=np.zeros(0, np.int64), fixed=np.zeros(0)),
            layout.pad(problem.f))
        its = svc.call("ksp_iterations")
        from solver.linalg import factorize
        error = None
        if problem.n_dofs < 2e5:  # check against a direct solve
            ref = factorize(problem.K).solve(problem.f)
            error = float(np.abs(layout.unpad(u) - ref).max()
                          / np.abs(ref).max())
        stats = svc.call("stats")
        return dict(time=time.perf_counter() - clock, setup=setup,
                    ksp_iterations=its, n_dofs=problem.n_dofs,
                    relative_error=error,
                    peak_rss_mb=[r["peak_rss_mb"] for r in stats])

    return spmd(main)


def worker(argv):
    kind, path, mode = argv
    out = _serial(path, mode) if kind == "serial" else _petsc(path, mode)
    if out is not None:
        print("RESULT " + json.dumps(out), flush=True)


def measure(kind, path, mode, ranks=1):
    cmd = [sys.executable, os.path.abspath(__file__), "--worker", kind,
           path, mode]
    env = dict(os.environ, OMP_NUM_THREADS="1", MKL_NUM_THREADS="1",
               OPENBLAS_NUM_THREADS="1")
    if kind == "petsc":
        cmd = MPIEXEC + ["-n", str(ranks)] + cmd
        if BLAS[0]:  # MUMPS's BLAS: Debian links the reference one
            env["LD_PRELOAD"] = BLAS[0]
    done = subprocess.run(cmd, capture_output=True, text=True, env=env)
    lines = [ln for ln in done.stdout.splitlines()
             if ln.startswith("RESULT ")]
    if done.returncode or not lines:
        return dict(kind=kind, problem=path, mode=mode, ranks=ranks,
                    error=done.stderr.strip()[-400:])
    out = json.loads(lines[-1][7:])
    out.update(kind=kind, problem=os.path.basename(path), mode=mode,
               ranks=ranks, loadavg=[round(x, 2) for x in os.getloadavg()])
    return out


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--worker":
        return worker(sys.argv[2:])
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--problems", default="/tmp/bench_wd/block_r4.npz")
    parser.add_argument("--gamg", default="")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--columns", action="store_true")
    parser.add_argument("--blocked", action="store_true")
    parser.add_argument("--no-serial", action="store_true")
    parser.add_argument("--serial-default", action="store_true")
    parser.add_argument("--ranks", default="1,2")
    parser.add_argument("--log")
    parser.add_argument("--blas", help="a BLAS shared library (for "
                        "instance libopenblas.so.0) to LD_PRELOAD into the "
                        "PETSc runs: Debian's petsc-dev links the reference "
                        "BLAS, which makes MUMPS's dense fronts 2-3x slower")
    args = parser.parse_args()
    BLAS[0] = args.blas
    configs = []
    for path in filter(None, args.problems.split(",")):
        if not args.no_serial:
            configs += [("serial", path, "free", 1)]
        if args.serial_default:
            configs += [("serial", path, "default", 1)]
        configs += [("petsc", path, "schur", int(n))
                    for n in args.ranks.split(",")]
        if args.blocked:
            configs += [("petsc", path, "blocked", 1)]
        if args.columns:
            configs += [("petsc", path, "columns", 1)]
    for path in filter(None, args.gamg.split(",")):
        configs += [("petsc", path, "gamg", 1), ("petsc", path, "gamg", 2)]
    for round_ in range(args.repeat):
        for config in configs:
            out = measure(*config)
            out["round"] = round_
            line = json.dumps(out)
            print(line, flush=True)
            if args.log:
                with open(args.log, "a") as stream:
                    stream.write(line + "\n")


if __name__ == "__main__":
    main()
