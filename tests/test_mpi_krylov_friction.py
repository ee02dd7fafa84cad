"""Coulomb friction on the partitioned folder's full system by Krylov
(issue 33, point 1 under mpiexec; solver/mpi/krylov_friction.py):
``mpiexec -n N python -m solver DIR --engine petsc --system full --ksp
gamg|hypre --friction 0.3 --steps 3`` on 1, 2 and 4 (oversubscribed)
ranks, each rank holding only its rows and its contact nodes; 2D here,
3D with rollers in test_mpi_krylov_friction3d.py.

Reference: the serial engine's ``solver.solve(problem, friction=0.3,
steps=3)`` on the ``.npz`` (another method on another system: the
semismooth Newton on Γc's Schur complement from scipy's factorisation of
the whole K): every step's u (VTK's own reader of the ``.pvtu``), the
friction and contact forces to 1e-8, the same stick, slip and contact
sets; the Jacobians per step are the active set method's, not compared.
Full slip (thesis §4, f_c 0.3): every node in contact slips, its friction
force f_c times the last step's normal force (the lagged bound) to 1e-8.
PETSc runs only in the mpiexec subprocesses."""

import json

import numpy as np
import pytest

from solver import save_problem, solve
from test_mpi import REASON, mpirun
from test_mpi_distributed_friction import assert_steps_as_serial
from test_mpi_forcing import assert_forcing_steps

pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))

RTOL = 1e-8
FRICTION, STEPS = 0.3, 3  # as test_mpi_distributed_friction's


def run_krylov_friction(folder, out, ranks, ksp="gamg", *options):
    """The command line on ``ranks``: (exit code, summary or None, stdout,
    stderr)."""
    code, stdout, err = mpirun(ranks, [
        "-m", "solver", folder, "--engine", "petsc", "--system", "full",
        "--ksp", ksp, "--friction", str(FRICTION), "--steps", str(STEPS),
        "-o", out, *options])
    path = out / "summary.json"
    summary = json.loads(path.read_text()) if path.exists() else None
    return code, summary, stdout, err


def assert_same_steps(problem, reference, out, summary, stdout):
    """Every step of the run ``out`` against the serial ``reference``
    (module docstring; u, forces and sets by test_mpi_distributed_friction.
    assert_steps_as_serial); returns the run's ``step_*`` fields."""
    assert summary["converged"] and summary["steps_completed"] == STEPS
    assert summary["engine"]["system"] == "full"
    assert_steps_as_serial(problem, reference, out)
    v = summary["verification"]
    assert v["passed"] and v["reduced_over_ranks"]
    assert v["friction_bound_violation"] <= 1e-8
    assert v["interior_equilibrium"] <= 1e-8 and v["equilibrium"] <= 1e-8
    assert "friction bound violation" in stdout
    assert [r["step"] for r in summary["records"]] == [1, 2, 3]
    assert all(r["krylov"] > 0 for r in summary["records"])
    with np.load(out / "contact.npz") as contact:
        return {key: contact[key] for key in contact.files
                if key.startswith("step_")}


@pytest.fixture(scope="module")
def block(refined_block, tmp_path_factory):
    """(problem, folder, serial run at f_c 0.3): the 1878 block refined
    once (7668 DOFs), converted by the command line."""
    from solver import load_problem
    from solver.cli import main

    root = tmp_path_factory.mktemp("krylovfric")
    npz = root / "r1.npz"
    save_problem(npz, refined_block(1))
    assert main(["convert", str(npz), str(root / "r1")]) == 0
    problem = load_problem(npz)
    serial = solve(problem, friction=FRICTION, steps=STEPS)
    assert serial.success
    return problem, root / "r1", serial


@pytest.mark.parametrize("ranks,ksp", [(1, "gamg"), (2, "gamg"),
                                       (4, "gamg"), (2, "hypre")])
def test_2d_block_same_steps_as_serial(block, tmp_path, ranks, ksp):
    problem, folder, serial = block
    out = tmp_path / "out"
    code, summary, stdout, err = run_krylov_friction(folder, out, ranks, ksp)
    assert code == 0, err[-2000:]
    assert summary["engine"]["ranks"] == ranks
    assert summary["engine"]["ksp"] == ksp
    steps = assert_same_steps(problem, serial, out, summary, stdout)
    assert_full_slip(summary, steps, lag=1)
    assert_forcing_steps(summary)  # inexact Newton, the same steps


def assert_full_slip(summary, steps, lag):
    """Full slip: every node in contact slips, its friction force D|g| =
    f_c λ of the step ``lag`` steps back (1: the lagged bound's λ_{κ−1},
    0: the implicit bound's own λ_κ) to 1e-8 of the largest λ there."""
    assert summary["n_slip"] == summary["n_in_contact"] > 0
    force = steps["step_contact_force"]
    t = np.abs(steps["step_friction_traction"]) * (
        force / np.where(steps["step_contact_pressure"] > 0,
                         steps["step_contact_pressure"], 1.0))  # D g
    for k in range(lag, STEPS):
        slip = steps["step_slip"][k]
        assert slip.any()
        bound = FRICTION * np.maximum(force[k - lag], 0.0)
        assert np.abs(t[k][slip] - bound[slip]).max() <= \
            RTOL * force[k - lag].max()
