"""The full system of a partitioned problem on Krylov (issue 33, point 4;
solver/mpi/partitioned_full.py): ``mpiexec -n N python -m solver DIR
--engine petsc --system full --ksp gamg`` on 1, 2 and 4 (oversubscribed)
ranks, each rank holding only its rows of K and f and the contact nodes
of its own node range.

References: the serial engine's ``solver.solve(problem)`` on the ``.npz``
(another code path: the whole K condensed onto Γc by scipy's
factorisation) for u to 1e-8 and the nodes in contact; VTK's own reader
of the ``.pvtu``. PETSc runs only in the mpiexec subprocesses."""

import json

import numpy as np
import pytest

from solver import load_problem, save_problem, solve
from test_mpi import REASON, mpirun
from test_mpi_distributed import read_pvtu
from test_mpi_forcing import assert_forcing

pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))

RTOL = 1e-8
FULL = ["--engine", "petsc", "--system", "full"]


def converted(problem, root, name):
    """The problem converted by the command line into ``root/name``."""
    from solver.cli import main

    npz = root / f"{name}.npz"
    if problem.source is None or not str(problem.source).endswith(".npz"):
        save_problem(npz, problem)
    else:
        npz = problem.source
    assert main(["convert", str(npz), str(root / name)]) == 0
    return root / name


@pytest.fixture(scope="module")
def block(refined_block, tmp_path_factory):
    """(problem, serial result, folder): the 1878 block refined once
    (7668 DOFs)."""
    problem = refined_block(1)
    result = solve(problem)
    assert result.success
    return problem, result, converted(problem, tmp_path_factory.mktemp(
        "full"), "r1")


@pytest.fixture(scope="module")
def sphere(tmp_path_factory):
    """The a/h 4 quarter Hertz sphere, rollers on x = 0 and y = 0."""
    from test_amg import hertz_sphere

    problem = hertz_sphere(tmp_path_factory, 4)
    result = solve(problem)
    assert result.success
    return problem, result, converted(problem, tmp_path_factory.mktemp(
        "full3d"), "s4")


def run_full(folder, out, ranks, ksp="gamg"):
    code, stdout, err = mpirun(ranks, ["-m", "solver", folder, *FULL,
                                       "--ksp", ksp, "-o", out])
    assert code == 0, err[-2000:]
    assert stdout.startswith("converged")
    return json.loads((out / "summary.json").read_text())


def check_answer(problem, result, out, summary, ranks, folder):
    """u over every node against the serial u (1e-8 of its largest
    entry), the nodes in contact, one piece per rank, the verification
    reduced over the ranks."""
    n_nodes, dim = problem.nodes.shape
    u, cells = read_pvtu(out / "result.pvtu", n_nodes, dim)
    ref = result.displacement
    assert np.abs(u - ref).max() <= RTOL * np.abs(ref).max()
    assert cells == len(problem.cells)
    assert (out / "result.pvtu").read_text().count("<Piece ") == ranks
    with np.load(out / "contact.npz") as contact:
        touching = np.sort(contact["node"][contact["in_contact"]])
        nodes_c = contact["node"]
    assert np.array_equal(touching, np.sort(
        problem.contact_nodes[result.in_contact]))
    v = summary["verification"]
    assert v["passed"] and v["reduced_over_ranks"]
    assert summary["engine"]["system"] == "full"
    # every rank holds the contact nodes of its own node range, no more
    # (the ranges in the folder's numbering: the outputs give the .npz's,
    # node_ids.npy maps the folder's nodes to them)
    ids = np.load(folder / "node_ids.npy")
    inverse = np.empty_like(ids)
    inverse[ids] = np.arange(len(ids))
    nodes_c = inverse[nodes_c]
    per_rank = summary["engine"]["per_rank"]
    starts = np.r_[0, np.cumsum([r["rows"] for r in per_rank])] // dim
    held = [r["contact_nodes"] for r in per_rank]
    assert held == [int(np.count_nonzero((nodes_c >= a) & (nodes_c < b)))
                    for a, b in zip(starts[:-1], starts[1:])]


def test_block_1_2_4_ranks_same_u_and_krylov_counts(block, tmp_path):
    """2D: the same u as the serial engine on 1, 2 and 4 ranks, the same
    Newton count; CG of the systems solved to 10⁻¹² (≈30 each) within
    3 iterations of the 1-rank run's (±10 %; measured 29 / 31 / 32 with
    the smoothers' own eigenvalue estimates), CG per Newton system within
    ±20 % (GAMG's aggregates follow the partition: at 7,668 DOFs, 4
    ranks hold ≈1,900 each, and the inexact systems take 8–13, where one
    iteration is 10 %; the issue's ±10 % on the mean is measured at
    1.2·10⁵ DOFs in benchmarks/README.md)."""
    problem, result, folder = block
    krylov = {}
    for ranks in (1, 2, 4):
        out = tmp_path / f"n{ranks}"
        summary = run_full(folder, out, ranks)
        check_answer(problem, result, out, summary, ranks, folder)
        assert summary["engine"]["ksp_fallbacks"] == 0
        assert_forcing(summary["engine"])  # inexact Newton, same u
        engine = summary["engine"]
        exact = [k for k, eta in zip(engine["ksp_iterations"],
                                     engine["ksp_forcing"]) if eta <= 1e-12]
        krylov[ranks] = (summary["nit"], engine["krylov_per_newton"],
                         sum(exact) / len(exact))
    assert len({nit for nit, _, _ in krylov.values()}) == 1
    _, mean, exact = krylov[1]
    assert all(abs(k - mean) <= 0.2 * mean and abs(e - exact) <= 3
               for _, k, e in krylov.values()), krylov


def test_sphere_with_rollers_2_4_ranks(sphere, tmp_path):
    """3D with rollers on the symmetry planes (a roller's frame has one
    tangent in its free components): u to 1e-8 on 2 and 4 ranks (1 rank
    ran the sphere before the CI budget cut it: the block covers 1)."""
    problem, result, folder = sphere
    for ranks in (2, 4):
        out = tmp_path / f"n{ranks}"
        summary = run_full(folder, out, ranks)
        check_answer(problem, result, out, summary, ranks, folder)


def test_hypre_boomeramg(block, tmp_path):
    """--ksp hypre (BoomerAMG, no near-null space): the same u (one
    rank: the ranks' reductions are the GAMG tests')."""
    problem, result, folder = block
    out = tmp_path / "hypre"
    summary = run_full(folder, out, 1, "hypre")
    check_answer(problem, result, out, summary, 1, folder)
    assert summary["engine"]["ksp"] == "hypre"


def test_gamg_smoothers_estimate_their_own_eigenvalues(block, tmp_path,
                                                        monkeypatch):
    """Every Chebyshev smoother of GAMG's hierarchy bounds its spectrum
    by its own CG estimate times the documented transform (0, 0.2; 0,
    1.5), as ``solver.mpi.full.GAMG_OPTIONS`` says, not by the estimate
    GAMG made for its prolongators (PETSc ≥ 3.17's default, manual page
    PCGAMGSetUseSAEstEig): with that one CG's preconditioner was
    indefinite on 7 of 8 Newton systems of two spheres at 1.3·10⁵ DOFs
    and on a system of the 4.8·10⁵-DOF block at 2 ranks, and MUMPS
    factorised them (benchmarks/README.md, "GAMG's smoothers"). Read
    from PETSc's own view of the Newton KSP ($PETSC_OPTIONS), 2 ranks."""
    problem, result, folder = block
    view = tmp_path / "ksp.txt"
    monkeypatch.setenv("PETSC_OPTIONS", f"-newton_ksp_view ascii:{view}")
    out = tmp_path / "viewed"
    summary = run_full(folder, out, 2)
    check_answer(problem, result, out, summary, 2, folder)
    text = view.read_text()
    smoothers = text.count("type: chebyshev")
    assert smoothers >= 2, text[:2000]  # GAMG made at least two levels
    assert "eigenvalues provided" not in text
    assert text.count("eigenvalues estimated via cg") == smoothers
    assert text.count("estimated using cg with transform: "
                      "[0. 0.2; 0. 1.5]") == smoothers


def test_options_that_do_not_apply_are_refused(block):
    """The full system needs a Krylov ksp, a ksp needs the full system,
    φ_FB is refused: each one line before any collective step (friction,
    both bounds, runs: tests/test_mpi_krylov_friction*.py)."""
    from solver.errors import SolverError

    problem = load_problem(block[2])
    for options, text in (
            (dict(system="full"), "the full system runs by Krylov"),
            (dict(system="full", ksp="mumps"),
             "the full system runs by Krylov"),
            (dict(ksp="gamg"), "ksp='gamg'"),
            (dict(system="full", ksp="gamg", method="fb"), "method='fb'")):
        with pytest.raises(SolverError, match="partitioned") as info:
            solve(problem, engine="petsc", **options)
        assert text in str(info.value)


#: Three solves of one folder in one mpiexec launch (``solver.solve``
#: inside ``spmd``): frictionless, friction, frictionless again.
AGAIN = """
import json, sys
import numpy as np
import solver
from solver.mpi.engine import spmd

def main(folder, out):
    said = []
    for options in ({}, {"friction": 0.3, "steps": 2}, {}):
        r = solver.solve(solver.load_problem(folder), engine="petsc",
                         system="full", ksp="gamg", **options)
        said.append([bool(r.success), r["nit"]])
        np.savez(f"{out}-{len(said)}.npz", **r.contact)
    with open(out + ".json", "w") as stream:
        json.dump(said, stream)

spmd(main, sys.argv[1], sys.argv[2])
"""


def test_solves_again_in_one_process(block, tmp_path):
    """An API user's second and third solve of a folder in the same
    ``mpiexec`` processes: the ranks' objects of the first are replaced,
    not reused (a second solve once failed on every rank: the first
    solve's node frames were taken for PETSc objects), and the third
    equals the first (frictionless, u_n and forces to 1e-12)."""
    _, _, folder = block
    script = tmp_path / "again.py"
    script.write_text(AGAIN)
    out = tmp_path / "again"
    code, _, err = mpirun(2, [script, folder, out])
    assert code == 0, err[-2000:]
    said = json.loads(out.with_suffix(".json").read_text())
    assert all(ok for ok, _ in said), said
    assert said[0][1] == said[2][1]
    first, third = (np.load(f"{out}-{k}.npz") for k in (1, 3))
    for name in ("force", "u_n"):
        scale = np.abs(first[name]).max()
        assert np.abs(first[name] - third[name]).max() <= 1e-12 * scale
    assert np.array_equal(first["in_contact"], third["in_contact"])
