"""Distributed from the file (issue 33, point 4; solver/mpi/distributed.py):
``python -m solver convert X.npz DIR``, then ``mpiexec -n N python -m
solver DIR --engine petsc`` on 1, 2 and 4 (oversubscribed) ranks.

References: the serial engine's ``solver.solve(problem, start="free")``
on the ``.npz`` (another code path: scipy's factorisation of the whole K,
the serial condensation) for u to 1e-8; PETSc's own ``MatLoad`` /
``VecLoad`` for the binary files the converter writes with NumPy. What
ParaView would show is read by VTK's own reader of the ``.pvtu``. What
rank 0 holds is read from the engine's ledger (``rank0_arrays``), each
rank's rows from PETSc's ownership ranges: no array on rank 0 larger
than Γc's Schur complement, no rank with more than its share of K."""

import json

import numpy as np
import pytest
import scipy.sparse as sp

from solver import load_problem, save_problem, solve
from solver.problem.partitioned import write_petsc_matrix, write_petsc_vector
from test_mpi import REASON, mpirun

pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))

RTOL = 1e-8


@pytest.fixture(scope="module")
def converted(refined_block, tmp_path_factory):
    """(npz, folder): the 1878 block refined once (7668 DOFs), converted
    by the command line."""
    from solver.cli import main

    root = tmp_path_factory.mktemp("dist")
    npz = root / "r1.npz"
    save_problem(npz, refined_block(1))
    assert main(["convert", str(npz), str(root / "r1")]) == 0
    return npz, root / "r1"


@pytest.fixture(scope="module")
def reference(converted):
    problem = load_problem(converted[0])
    result = solve(problem, start="free")
    assert result.success
    return problem, result


def read_pvtu(path, n_nodes, dim):
    """u over all nodes and the number of cells of ``path``, read as
    ParaView reads it (VTK's vtkXMLPUnstructuredGridReader: the pieces as
    one grid)."""
    vtk = pytest.importorskip("vtk")
    from vtk.util.numpy_support import vtk_to_numpy

    reader = vtk.vtkXMLPUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    data = grid.GetPointData()
    u = np.full((n_nodes, dim), np.nan)
    u[vtk_to_numpy(data.GetArray("node"))] = vtk_to_numpy(
        data.GetArray("u"))[:, :dim]
    return u, grid.GetNumberOfCells()


#: PETSc's own MatLoad / VecLoad of the two files, in a process of its own
#: (petsc4py initialises MPI; in the test process that would leave Open
#: MPI's singleton environment to every later mpiexec, which then fails).
LOAD = """
import sys
import numpy as np
import scipy.sparse as sp
from petsc4py import PETSc

viewer = PETSc.Viewer().createBinary(sys.argv[1], "r", comm=PETSc.COMM_SELF)
M = PETSc.Mat().create(comm=PETSc.COMM_SELF)
M.setType("aij")
M.load(viewer)
indptr, indices, data = M.getValuesCSR()
viewer = PETSc.Viewer().createBinary(sys.argv[2], "r", comm=PETSc.COMM_SELF)
x = PETSc.Vec().create(comm=PETSc.COMM_SELF)
x.load(viewer)
np.savez(sys.argv[3], indptr=indptr, indices=indices, data=data,
         shape=M.getSize(), v=x.getArray())
"""


def test_binary_files_load_in_petsc(tmp_path):
    """The converter's NumPy writer against PETSc's MatLoad / VecLoad."""
    import subprocess
    import sys

    pytest.importorskip("petsc4py")
    A = sp.random(7, 7, density=0.4, random_state=3, format="csr") \
        + sp.identity(7)
    v = np.linspace(-1.0, 2.0, 7)
    write_petsc_matrix(tmp_path / "A.petsc", A)
    write_petsc_vector(tmp_path / "v.petsc", v)
    done = subprocess.run(
        [sys.executable, "-c", LOAD, str(tmp_path / "A.petsc"),
         str(tmp_path / "v.petsc"), str(tmp_path / "loaded.npz")],
        capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    with np.load(tmp_path / "loaded.npz") as data:
        loaded = sp.csr_matrix((data["data"], data["indices"],
                                data["indptr"]), shape=tuple(data["shape"]))
        assert abs(loaded - A).max() == 0.0
        assert np.array_equal(data["v"], v)


@pytest.mark.parametrize("ranks", [1, 2, 4])
def test_same_u_as_serial_and_rank0_holds_gamma_c_only(
        converted, reference, tmp_path, ranks):
    npz, folder = converted
    problem, result = reference
    out = tmp_path / "out"
    code, stdout, err = mpirun(ranks, ["-m", "solver", folder, "--engine",
                                       "petsc", "-o", out])
    assert code == 0, err[-2000:]
    assert stdout.startswith("converged")
    summary = json.loads((out / "summary.json").read_text())
    assert summary["converged"] and summary["engine"]["ranks"] == ranks
    n_nodes, dim = problem.nodes.shape
    u, cells = read_pvtu(out / "result.pvtu", n_nodes, dim)
    ref = result.displacement
    assert np.abs(u - ref).max() <= RTOL * np.abs(ref).max()
    assert cells == len(problem.cells)  # each cell in one piece
    pvtu = (out / "result.pvtu").read_text()
    assert pvtu.count("<Piece ") == ranks
    # in contact: the serial result's nodes
    with np.load(out / "contact.npz") as contact:
        in_contact = np.zeros(n_nodes, bool)
        in_contact[contact["node"][contact["in_contact"]]] = True
    assert np.array_equal(np.flatnonzero(in_contact), np.sort(
        problem.contact_nodes[result.in_contact]))
    # rank 0's driver: nothing larger than Γc's Schur complement
    engine = summary["engine"]
    m = summary["n_contact_dofs"]
    n = engine["n"]
    assert m < n // 10
    assert engine["rank0_arrays"]["largest_dimension"] <= m
    assert engine["rank0_arrays"]["largest_entries"] <= m * m
    # the NCP on Γc's normal rows only (NormalSchur: frictionless, no
    # tangential force), as the serial condensation: (m/d)² entries
    shapes = engine["rank0_arrays"]["shapes"]
    nodes_c = shapes["contact.gap"][0]
    assert shapes["S_n"] == [nodes_c, nodes_c] and m > nodes_c
    assert shapes["u_n"] == [nodes_c]
    assert summary["nit"] == result.nit  # the serial free start's Newton
    # each rank read its share of K's rows (MatLoad), rank 0 a smaller one
    rows = [stats["rows"] for stats in engine["per_rank"]]
    assert sum(rows) == n and rows[0] <= n // ranks + dim
    assert max(rows) <= 2 * n // ranks


def test_3d_quarter_sphere_with_rollers(tmp_path_factory, tmp_path):
    """3D, two tangents per node and rollers on the symmetry planes (a
    roller's normal row is its only free DOF in S_n's numbering): the
    a/h 4 quarter Hertz sphere on 2 ranks against the serial engine's
    free start (u to 1e-8, the same Newton count and contact set)."""
    from solver.cli import main
    from test_amg import hertz_sphere

    problem = hertz_sphere(tmp_path_factory, 4)
    result = solve(problem, start="free")
    assert result.success
    folder = tmp_path / "s4"
    assert main(["convert", str(problem.source), str(folder)]) == 0
    out = tmp_path / "out"
    code, stdout, err = mpirun(2, ["-m", "solver", folder, "--engine",
                                   "petsc", "-o", out])
    assert code == 0, err[-2000:]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["converged"] and summary["nit"] == result.nit
    n_nodes, dim = problem.nodes.shape
    u, _ = read_pvtu(out / "result.pvtu", n_nodes, dim)
    ref = result.displacement
    assert np.abs(u - ref).max() <= RTOL * np.abs(ref).max()
    with np.load(out / "contact.npz") as contact:
        touching = np.sort(contact["node"][contact["in_contact"]])
    assert np.array_equal(touching, np.sort(
        problem.contact_nodes[result.in_contact]))
    nodes_c = summary["engine"]["rank0_arrays"]["shapes"]["S_n"][0]
    assert summary["n_contact_dofs"] < dim * nodes_c  # rollers


def test_options_that_do_not_apply_are_refused(converted, capsys,
                                              tmp_path):
    """The thesis's split (or --system full, ...) on a partitioned problem: the
    front's rules refuse it (solver.solve raises SolverError; the command
    line exits 2 with one line), before any collective step or output (so
    in process: every rank then exits with rank 0's code,
    tests/test_mpi.py)."""
    from solver.cli import build_parser
    from solver.cli.run import run
    from solver.errors import SolverError

    problem = load_problem(converted[1])
    assert problem.kind == "partitioned"
    for options, text in ((dict(friction=0.3, formulation="thesis"),
                           "formulation='thesis'"),
                          (dict(on_step=print), "on_step"),
                          (dict(system="full"), "system='full'"),
                          (dict(gap="body"), "gap='body'"),
                          (dict(), "engine='serial'")):
        engine = "serial" if not options else "petsc"
        with pytest.raises(SolverError, match="partitioned") as info:
            solve(problem, engine=engine, **options)
        assert text in str(info.value)
    with pytest.raises(SolverError, match="engine='serial' is not"):
        solve(problem)  # the default engine
    out = tmp_path / "out"
    for options in (["--formulation", "thesis", "--friction", "0.3"],
                    ["--system", "full"],
                    ["--start", "free"], ["--plots"]):
        args = build_parser().parse_args([str(converted[1]), "--engine",
                                          "petsc", "-o", str(out),
                                          *options])
        assert run(args) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and options[0] in err, err
        assert not out.exists()
