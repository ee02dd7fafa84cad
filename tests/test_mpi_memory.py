"""Memory of the PETSc engine (solver/mpi, MEM20C): the buffer scatter of
K and vectors against the rows of the padded CSR (what the pickled scatter
sent), rank 0 holding no rotated or padded copy of K under MUMPS's factor,
the per-stage and MUMPS memory in the engine summary against MUMPS's own
definitions (INFOG(17) = Σ INFO(15), INFOG(21) = max INFO(22), INFOG(22) =
Σ INFO(22); MUMPS Users' Guide 5.5 §6) and against ``ru_maxrss``, and
glibc giving freed memory back after PETSc is loaded.
"""

import json
import subprocess
import sys

import numpy as np
import pytest

from solver import load_problem
from test_mpi import REASON, mpirun

pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))

SCATTER_DRIVER = """
import sys, numpy as np
from solver import load_problem
from solver.mpi.engine import service, spmd
from solver.mpi.layout import Layout, gather_vector, scatter_vector

def main(path, out):
    p = load_problem(path)
    svc = service()
    layout = Layout(p, svc.size)
    svc.call("layout", layout.ranges())
    svc.call("scatter_matrix", dict(key="K", bsize=layout.dim),
             layout.matrix(p.K))
    blocks = svc.call("local_rows")
    v = np.random.default_rng(2).standard_normal(layout.n)
    back = svc.call("round_trip", None, v)
    arrays = dict(v=v, back=back)
    for r, (a, ptr, ind, val) in enumerate(blocks):
        arrays.update({f"{r}/a": a, f"{r}/ptr": ptr, f"{r}/ind": ind,
                       f"{r}/val": val})
    np.savez(out, **arrays)

from solver.mpi.service import command

@command("local_rows")
def _rows(service, payload, local):
    A = service.objects["K"]["A"]
    ptr, ind, val = A.getValuesCSR()
    return service.comm.gather((A.getOwnershipRange()[0], ptr, ind, val),
                               root=0)

@command("round_trip")
def _trip(service, payload, local):
    vec = service.objects["K"]["x"]
    scatter_vector(service, local, vec)
    vec.scale(1.0)
    return gather_vector(service, vec)

spmd(main, sys.argv[1], sys.argv[2])
"""


@pytest.mark.parametrize("n", [1, 2, 3])
def test_scatter_sends_the_padded_rows(exported, tmp_path, n):
    """Each rank's PETSc rows after the buffer scatter (MPI_Scatterv,
    rank 0's rows in place) are exactly the rows a:b of rank 0's padded
    CSR (Layout.matrix, scipy), which the pickled scatter sent; a vector
    scattered and gathered back is bit for bit the same (1, 2 and 3 ranks,
    3 an uneven split of the 454 block's nodes)."""
    from solver.mpi.layout import Layout

    path = exported(454)[0]
    out = tmp_path / "rows.npz"
    code, _, err = mpirun(n, ["-c", SCATTER_DRIVER, path, out])
    assert code == 0, err[-3000:]
    p = load_problem(path)
    layout = Layout(p, n)
    A = layout.matrix(p.K)
    with np.load(out) as data:
        assert np.array_equal(data["back"], data["v"])
        for r, (a, b) in enumerate(layout.ranges()):
            assert int(data[f"{r}/a"]) == a
            ref = A[a:b]
            ref.sort_indices()
            assert np.array_equal(data[f"{r}/ptr"], ref.indptr)
            assert np.array_equal(data[f"{r}/ind"], ref.indices)
            assert np.array_equal(data[f"{r}/val"], ref.data)


HOLD_DRIVER = """
import gc, json, sys
import scipy.sparse as sp
from solver import load_problem
import functools, solver
solve_frictionless = functools.partial(solver.solve_frictionless, engine="petsc")
from solver.mpi.engine import service, spmd
from solver.mpi.service import HANDLERS

service()  # registers the commands

held = []
factor = HANDLERS["factor"]

def spy(service, payload, local):
    if service.root:  # the n x n sparse matrices alive on rank 0
        held.append(sum(1 for o in gc.get_objects() if sp.issparse(o)
                        and o.shape[0] >= n and o.nnz > 2 * n))
    return factor(service, payload, local)

HANDLERS["factor"] = spy

def main(path, out):
    global n
    p = load_problem(path)
    n = p.n_dofs
    r = solve_frictionless(p, method="min")
    json.dump(dict(held=held, per_rank=r.engine["per_rank"]),
              open(out, "w"))

spmd(main, sys.argv[1], sys.argv[2])
"""


@pytest.fixture(scope="module")
def held_run(exported, tmp_path_factory):
    out = tmp_path_factory.mktemp("hold") / "held.json"
    code, _, err = mpirun(2, ["-c", HOLD_DRIVER, exported(454)[0], out])
    assert code == 0, err[-3000:]
    return json.loads(out.read_text())


def test_rank0_holds_only_k_under_the_factor(held_run):
    """At every factorisation of the condensed solve on 2 ranks, the only
    stiffness-sized sparse matrix alive on rank 0 is the problem's own K
    (for the verification): no rotated K̂, padded copy or scattered
    block."""
    assert held_run["held"] and all(h == 1 for h in held_run["held"]), \
        held_run["held"]


def test_memory_statistics(held_run):
    """The engine summary's memory: per-stage (VmRSS, VmHWM) with
    VmHWM ≥ VmRSS and the process peak ru_maxrss ≥ every VmHWM seen
    (the same high-water mark, read at the end); rank 0 records its own
    stages; MUMPS's INFOG(17), INFOG(21), INFOG(22) are the sum / max /
    sum over the ranks of INFO(15), INFO(22), INFO(22), and no rank uses
    more than it allocated."""
    per_rank = held_run["per_rank"]
    assert len(per_rank) == 2
    for stats in per_rank:
        stages = stats["memory_mb"]
        assert {"scatter_matrix", "factor"} <= set(stages)
        for rss, hwm in stages.values():
            assert 0 < rss <= hwm <= stats["peak_rss_mb"] + 0.5
        mumps = stats["mumps_mb"]
        assert 0 < mumps["used"] <= mumps["allocated"]
    assert {"rotate", "pad"} <= set(per_rank[0]["memory_mb"])
    mumps = [s["mumps_mb"] for s in per_rank]
    assert mumps[0]["estimate_sum"] == sum(m["estimate"] for m in mumps)
    assert mumps[0]["used_max"] == max(m["used"] for m in mumps)
    assert mumps[0]["used_sum"] == sum(m["used"] for m in mumps)


RELEASE_DRIVER = """
import sys, numpy as np
from solver.mpi import engine
from solver.mpi.service import memory_mb
if sys.argv[1] == "keep":
    engine.restore_malloc = lambda: False
engine.service()
before = memory_mb()[0]
if sys.argv[2] == "one":
    a = np.ones(50_000_000)  # 400 MB, mmapped
    del a
else:  # 50 blocks of 8 MB, below the mmap threshold: on the heap
    blocks = [np.ones(1_000_000) for _ in range(50)]
    del blocks
print(memory_mb()[0] - before)
"""


def test_freed_memory_goes_back_after_petsc_loads():
    """After the engine's PETSc start, a freed 400 MB array leaves the
    resident memory, and so do 50 freed 8 MB arrays from the heap (glibc's
    trim and mmap restored, engine.restore_malloc;
    Debian's libsuperlu_dist switches them off when libpetsc loads, and
    then the array stays resident: checked too where that happens)."""
    if not sys.platform.startswith("linux"):
        pytest.skip("VmRSS is Linux's")

    def grown(mode, size):
        done = subprocess.run([sys.executable, "-c", RELEASE_DRIVER, mode,
                               size], capture_output=True, text=True,
                              timeout=120)
        assert done.returncode == 0, done.stderr[-2000:]
        return float(done.stdout.split()[-1])

    for size in ("one", "many"):  # mmapped, and trimmed from the heap
        kept = grown("keep", size)  # ≈ 400 with Debian's PETSc 3.18
        assert grown("restore", size) < 40.0, \
            f"{size}: without the restore {kept:.0f} MB"
