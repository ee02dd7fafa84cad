"""Coulomb friction on the partitioned path (issue 33, point 4;
solver/mpi/partitioned_friction.py): ``mpiexec -n N python -m solver DIR
--engine petsc --friction 0.3 --steps 3`` on 1, 2 and 4 (oversubscribed)
ranks, 2D (this file) and 3D (test_mpi_distributed_friction3d.py).

Reference: the serial engine's ``solver.solve(problem, friction=0.3,
steps=3)`` on the ``.npz`` (scipy's factorisation of the whole K, the
serial condensation and the serial recovery of u): every step's u to 1e-8
(read as ParaView reads the pieces, VTK's own ``.pvtu`` reader), the
friction and contact forces to 1e-8, the same stick and slip sets and the
same Jacobians per step (the same driver runs on rank 0). The
verification on every node (the Coulomb bound included) is in the summary
and the printed line."""

import json

import numpy as np
import pytest

from solver import load_problem, save_problem, solve
from test_mpi import REASON, mpirun
from test_mpi_distributed import read_pvtu

pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))

RTOL = 1e-8
FRICTION, STEPS = 0.3, 3
STICKY = 1.0  # f_c at which some nodes stick


def run_friction(folder, out, ranks, *options, friction=FRICTION):
    """The command line on ``ranks``: (summary, stdout)."""
    code, stdout, err = mpirun(ranks, [
        "-m", "solver", folder, "--engine", "petsc", "--friction",
        str(friction), "--steps", str(STEPS), "-o", out, *options])
    assert code == 0, err[-2000:]
    return json.loads((out / "summary.json").read_text()), stdout


def assert_same_as_serial(problem, reference, out, summary, stdout):
    """Every step of the partitioned run ``out`` against the serial
    ``reference`` (module docstring)."""
    assert summary["converged"] and summary["status"] == "converged"
    assert summary["steps_completed"] == STEPS
    assert [r["njev"] for r in summary["records"]] == \
        [r["njev"] for r in reference.records]
    assert_steps_as_serial(problem, reference, out)
    v = summary["verification"]
    assert v["passed"] and v["friction_bound_violation"] <= 1e-8
    assert v["interior_equilibrium"] <= 1e-8 and v["equilibrium"] <= 1e-8
    assert "friction bound violation" in stdout
    # rank 0 held nothing larger than Γc's Schur complement
    m = summary["n_contact_dofs"]
    assert summary["engine"]["rank0_arrays"]["largest_entries"] <= m * m
    assert m < summary["engine"]["n"] // 4


def assert_steps_as_serial(problem, reference, out):
    """Every step's u of the partitioned run ``out`` (VTK's reader of the
    pieces), its friction and contact forces to 1e-8 and its stick, slip
    and contact sets against the serial ``reference``; also used by the
    Krylov path's tests (test_mpi_krylov_friction.py)."""
    n_nodes, dim = problem.nodes.shape
    ref = np.asarray(reference["displacement"])
    for k in range(STEPS):
        u, cells = read_pvtu(out / "steps" / f"step_{k + 1:04d}.pvtu",
                             n_nodes, dim)
        assert np.abs(u - ref[k]).max() <= RTOL * np.abs(ref[k]).max()
    assert cells == len(problem.cells)
    u, _ = read_pvtu(out / "result.pvtu", n_nodes, dim)
    assert np.abs(u - ref[-1]).max() <= RTOL * np.abs(ref[-1]).max()
    assert (out / "result.pvd").read_text().count("<DataSet ") == STEPS
    with np.load(out / "contact.npz") as contact:
        order = np.argsort(problem.contact_nodes)  # not sorted
        position = order[np.searchsorted(problem.contact_nodes,
                                         contact["node"], sorter=order)]
        assert np.array_equal(problem.contact_nodes[position],
                              contact["node"])
        for key in ("friction_traction", "contact_force"):
            mine = contact[f"step_{key}"]
            theirs = np.asarray(reference[key])[:, position]
            assert np.abs(mine - theirs).max() <= RTOL * np.abs(
                theirs).max()
        for key in ("stick", "slip", "in_contact"):
            assert np.array_equal(contact[f"step_{key}"], np.asarray(
                reference[key])[:, position]), key
        # the nodes not taking part (supports) are in neither set
        assert not np.asarray(reference["in_contact"])[:, np.setdiff1d(
            np.arange(problem.n_contact), position)].any()


@pytest.fixture(scope="module")
def block(refined_block, tmp_path_factory):
    """(problem, folder, serial lagged at f_c 0.3, serial implicit at f_c
    1): the 1878 block refined once (7668 DOFs), converted by the command
    line. At f_c 0.3 (thesis §4) every node in contact slips; at f_c 1 the
    last step has nodes that stick and nodes that slip."""
    from solver.cli import main

    root = tmp_path_factory.mktemp("distfric")
    npz = root / "r1.npz"
    save_problem(npz, refined_block(1))
    assert main(["convert", str(npz), str(root / "r1")]) == 0
    problem = load_problem(npz)
    lagged = solve(problem, friction=FRICTION, steps=STEPS)
    implicit = solve(problem, friction=STICKY, steps=STEPS,
                     coulomb="implicit")
    assert lagged.success and implicit.success
    assert np.asarray(lagged["slip"])[-1].any()
    # a case with both sets: nodes that stick and nodes that slip
    assert np.asarray(implicit["stick"])[-1].any()
    assert np.asarray(implicit["slip"])[-1].any()
    return problem, root / "r1", lagged, implicit


@pytest.mark.parametrize("ranks,coulomb", [(1, "lagged"), (2, "lagged"),
                                           (4, "implicit")])
def test_2d_block_same_steps_as_serial(block, tmp_path, ranks, coulomb):
    problem, folder, lagged, implicit = block
    out = tmp_path / "out"
    summary, stdout = run_friction(
        folder, out, ranks, "--coulomb", coulomb,
        friction=FRICTION if coulomb == "lagged" else STICKY)
    assert summary["engine"]["ranks"] == ranks
    assert_same_as_serial(problem, lagged if coulomb == "lagged" else
                          implicit, out, summary, stdout)


def test_a_folder_without_the_mass_matrix_is_refused(block, tmp_path,
                                                     capsys):
    """A folder converted before friction ran here has no mass.npz: the
    front refuses it before any rank works (ProblemError, one line; the
    command line exits 2), frictionless runs still take it."""
    import shutil

    from solver.cli import build_parser
    from solver.cli.run import run
    from solver.errors import ProblemError

    _, folder, _, _ = block
    old = tmp_path / "old"
    shutil.copytree(folder, old)
    (old / "mass.npz").unlink()
    with pytest.raises(ProblemError, match="convert the .npz again"):
        solve(load_problem(old), engine="petsc", friction=0.3)
    args = build_parser().parse_args([str(old), "--engine", "petsc",
                                      "--friction", "0.3", "-o",
                                      str(tmp_path / "out")])
    assert run(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "mass.npz" in err, err
