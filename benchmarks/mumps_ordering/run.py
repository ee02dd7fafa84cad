"""Experiment: the PETSc engine's Schur factorisation with a METIS ordering.

``python benchmarks/mumps_ordering/run.py PROBLEM.npz [--rounds 3]
[--ranks 1,2]`` compiles ``hook.c`` (gcc, PETSc 3.18.5's and MUMPS's
headers from ``petsc-dev``), then runs in fresh ``mpiexec`` processes,
round by round, the engine's condensed φ_min solve (as
``benchmarks/run_mpi.py``'s "petsc" rows) with MUMPS's own ordering under
the Schur set (AMD: MUMPS 5.5 orders by AMD whatever ICNTL(7) asks once a
Schur set is given) and with a METIS nested dissection of the node graph
(``METIS_NodeND`` of Debian's ``libmetis.so.5``, each node's d DOFs
together, the Schur DOFs last) handed to MUMPS as PERM_IN through the hook.

It prints a table: wall time of the solve (problem loaded before the
clock), the METIS call and its graph (rank 0, serial), the engine's
``factor`` command (MUMPS analysis + factorisation with the Schur set), the
two interior solves, entries in the factors (INFOG(29)), peak RSS per
rank, and the largest difference of u from the first AMD run on 1 rank
(relative to max |u|). Why it is not the engine's default:
``benchmarks/README.md``, "A METIS ordering for MUMPS".
"""

import argparse
import ctypes
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
import scipy.sparse as sp

HERE = os.path.dirname(os.path.abspath(__file__))
MPIEXEC = ["mpiexec", "--allow-run-as-root", "--oversubscribe", "--bind-to",
           "none"]


def build_hook(out_dir):
    """Compile hook.c against the PETSc that petsc4py uses."""
    import petsc4py

    petsc = petsc4py.get_config()["PETSC_DIR"]
    mpi = subprocess.run(["mpicc", "--showme:compile"], capture_output=True,
                         text=True, check=True).stdout.split()
    target = os.path.join(out_dir, "hook.so")
    subprocess.run(["gcc", "-O2", "-shared", "-fPIC", f"-I{petsc}/include",
                    *mpi, os.path.join(HERE, "hook.c"), "-o", target,
                    f"-L{petsc}/lib", "-lpetsc_real"], check=True)
    return target


def node_order(problem, layout):
    """METIS nested dissection of the padded numbering's node graph (from
    K's pattern): the nodes in elimination order."""
    dim, K = layout.dim, problem.K.tocsr()
    nodes = layout.red_to_pad // dim
    n_nodes = layout.n // dim
    P = sp.csr_matrix((np.ones(len(nodes)), (nodes, np.arange(len(nodes)))),
                      shape=(n_nodes, K.shape[0]))
    G = (P @ (abs(K) @ P.T)).tocsr()
    G.setdiag(0)
    G.eliminate_zeros()
    G.sort_indices()
    metis = ctypes.CDLL("libmetis.so.5")
    options = np.full(40, -1, np.int32)  # METIS_NOPTIONS, idx_t = int32
    metis.METIS_SetDefaultOptions(options.ctypes.data_as(ctypes.c_void_p))
    n = np.array([n_nodes], np.int32)
    xadj, adjncy = G.indptr.astype(np.int32), G.indices.astype(np.int32)
    perm, iperm = np.zeros(n_nodes, np.int32), np.zeros(n_nodes, np.int32)
    code = metis.METIS_NodeND(*(a.ctypes.data_as(ctypes.c_void_p) for a in (
        n, xadj, adjncy)), None, options.ctypes.data_as(ctypes.c_void_p),
        perm.ctypes.data_as(ctypes.c_void_p),
        iperm.ctypes.data_as(ctypes.c_void_p))
    if code != 1:  # METIS_OK
        raise RuntimeError(f"METIS_NodeND returned {code}")
    return perm.astype(np.int64)  # perm[k] = the k-th node eliminated


def pivot_positions(order, dim, schur):
    """PERM_IN (1-based pivot position of each padded row): the nodes'
    rows in ``order``, the Schur rows last."""
    rows = (order[:, None] * dim + np.arange(dim)).ravel()
    last = np.zeros(len(rows), bool)
    last[schur] = True
    sequence = np.concatenate([rows[~last[rows]], np.asarray(schur)])
    positions = np.empty(len(sequence), np.int32)
    positions[sequence] = np.arange(1, len(sequence) + 1, dtype=np.int32)
    return positions


def worker(path, mode, hook):
    from solver import load_problem
    from solver.mpi.engine import service, spmd
    from solver import solve
    from solver.mpi import factor  # noqa: F401 - registers the factor command
    from solver.mpi.layout import Layout
    from solver.mpi.service import HANDLERS, command

    lib = ctypes.CDLL(hook)
    engine_factor = HANDLERS["factor"]

    @command("factor")
    def factor(svc, payload, local):
        """The engine's factor command, with PERM_IN set through the hook
        before the KSP's set-up (which runs the analysis)."""
        if "order" not in payload or payload.get("schur") is None:
            return engine_factor(svc, payload, local)
        from solver.mpi.factor import mumps_ksp
        from solver.mpi.schur import (interior_solves, mumps_memory,
                                      schur_complement, set_schur_is)

        obj = svc.objects[payload["key"]]
        ksp, pc = mumps_ksp(obj, payload["key"])
        pc.setFactorSetUpSolverType()
        F = pc.getFactorMatrix()
        set_schur_is(F, payload["schur"], obj["A"].getComm())
        perm = pivot_positions(payload["order"], payload["dim"],
                               payload["schur"]) if svc.root else \
            np.zeros(0, np.int32)
        if lib.shim_order(ctypes.c_void_p(F.handle),
                          perm.ctypes.data_as(ctypes.c_void_p),
                          ctypes.c_int32(len(perm))):
            raise RuntimeError("hook: shim_order failed")
        ksp.setUp()
        F = pc.getFactorMatrix()
        counts = svc.objects.setdefault("counts", {})
        counts["mumps_mb"] = mumps_memory(F)
        S = schur_complement(F) if svc.root else None
        interior_solves(F)
        return S

    def main():
        problem = load_problem(path)
        clock = time.perf_counter()
        svc = service()
        if mode == "metis":
            layout = Layout(problem, svc.size)
            order = node_order(problem, layout)
            call = svc.call

            def with_order(name, payload=None, local=None):
                if name == "factor" and payload and \
                        payload.get("schur") is not None:
                    payload = dict(payload, order=order, dim=layout.dim)
                return call(name, payload, local)
            svc.call = with_order
        ordering = time.perf_counter() - clock
        result = solve(problem, method="min", engine="petsc")
        seconds = time.perf_counter() - clock
        per_rank = result.engine["per_rank"]
        return dict(time=seconds, ordering=ordering, njev=int(result.njev),
                    seconds=[r["seconds"] for r in per_rank],
                    peak_rss_mb=[r["peak_rss_mb"] for r in per_rank],
                    mumps_mb=[r.get("mumps_mb") for r in per_rank]), result.u

    out = spmd(main)
    if out is not None:
        summary, u = out
        np.save(os.environ["ORDERING_U"], u)
        print("RESULT " + json.dumps(summary), flush=True)


def measure(path, mode, ranks, hook, u_file):
    cmd = MPIEXEC + ["-n", str(ranks), sys.executable,
                     os.path.abspath(__file__), "--worker", path, mode, hook]
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1",
               ORDERING_U=u_file,
               PETSC_OPTIONS="-k_mat_mumps_icntl_4 2")
    done = subprocess.run(cmd, capture_output=True, text=True, env=env)
    lines = [ln for ln in done.stdout.splitlines() if ln.startswith("RESULT ")]
    if done.returncode or not lines:
        raise SystemExit(f"{mode} on {ranks} ranks failed:\n"
                         f"{done.stderr[-2000:]}")
    out = json.loads(lines[-1][7:])
    for line in done.stdout.splitlines():  # MUMPS's own print-out
        if "INFOG(29)" in line:
            out["entries"] = int(line.split("=")[-1])
        if "Ordering given is used" in line:
            out["user_ordering"] = True
    return out


def main():
    if sys.argv[1:2] == ["--worker"]:
        return worker(*sys.argv[2:5])
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("problem")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--ranks", default="1,2")
    parser.add_argument("--log")
    args = parser.parse_args()
    tmp = tempfile.mkdtemp(prefix="mumps_ordering_")
    hook = build_hook(tmp)
    reference = None
    print(f"{'round':>5} {'ordering':>8} {'ranks':>5} {'time s':>7} "
          f"{'METIS s':>7} {'factor s':>8} {'solves s':>8} "
          f"{'entries':>11} {'peak MB per rank':>18} {'|du|/|u|':>9}")
    for round_ in range(args.rounds):
        for mode in ("amd", "metis"):
            for ranks in map(int, args.ranks.split(",")):
                u_file = os.path.join(tmp, "u.npy")
                out = measure(os.path.abspath(args.problem), mode, ranks,
                              hook, u_file)
                u = np.load(u_file)
                if reference is None:
                    reference = u
                diff = float(np.abs(u - reference).max()
                             / np.abs(reference).max())
                rank0 = out["seconds"][0]
                solves = rank0["condensed_rhs"] + rank0["interior_solve"]
                peaks = " / ".join(f"{m:.0f}" for m in out["peak_rss_mb"])
                if mode == "metis" and not out.get("user_ordering"):
                    raise SystemExit("MUMPS did not use the METIS ordering")
                print(f"{round_:>5} {mode:>8} {ranks:>5} {out['time']:7.2f} "
                      f"{out['ordering']:7.2f} {rank0['factor']:8.2f} "
                      f"{solves:8.2f} {out.get('entries', 0):>11,} "
                      f"{peaks:>18} {diff:9.1e}", flush=True)
                if args.log:
                    with open(args.log, "a") as stream:
                        stream.write(json.dumps(dict(
                            out, round=round_, mode=mode, ranks=ranks,
                            difference=diff, problem=args.problem)) + "\n")


if __name__ == "__main__":
    main()
