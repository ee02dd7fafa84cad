"""Coulomb friction with the implicit bound (``--coulomb implicit``) on
the partitioned folder's full system by Krylov (issue 33, point 1 under
mpiexec; solver/mpi/krylov_friction.py): each Newton system is
nonsymmetric (the slip nodes' tangent rows carry f_c ŵ times their normal
row of K̂, on the rank that owns the node) and is solved by GMRES with the
preconditioner of its symmetric part (GAMG with the rigid modes).

Reference: the serial engine's ``solver.solve(problem, friction=0.3,
steps=3, coulomb="implicit")`` on the ``.npz`` (another method on another
system: the semismooth Newton on Γc's Schur complement from scipy's
factorisation of the whole K): every step's u, friction and contact
forces to 1e-8 and the same stick, slip and contact sets
(test_mpi_krylov_friction.assert_same_steps), on the 2D block of the
thesis's §4 (f_c 0.3, full slip) and the a/h 4 quarter Hertz sphere with
rollers. Full slip with the implicit bound: every node in contact has a
friction force f_c times its normal force of the same step, to 1e-8.
PETSc runs only in the mpiexec subprocesses."""

import numpy as np
import pytest

from solver import solve
from test_mpi import REASON
from test_mpi_forcing import assert_forcing
from test_mpi_krylov_friction import block  # noqa: F401 (fixture)
from test_mpi_krylov_friction import (FRICTION, STEPS, assert_full_slip,
                                      assert_same_steps,
                                      run_krylov_friction)

pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))

IMPLICIT = ("--coulomb", "implicit")


@pytest.fixture(scope="module")
def block_implicit(block):
    """(problem, folder, serial implicit run) of the refined §4 block."""
    problem, folder, _ = block
    serial = solve(problem, friction=FRICTION, steps=STEPS,
                   coulomb="implicit")
    assert serial.success
    return problem, folder, serial


@pytest.mark.parametrize("ranks,ksp", [(1, "gamg"), (2, "gamg")])
def test_2d_block_implicit_same_steps_as_serial(block_implicit, tmp_path,
                                                ranks, ksp):
    problem, folder, serial = block_implicit
    out = tmp_path / "out"
    code, summary, stdout, err = run_krylov_friction(folder, out, ranks,
                                                     ksp, *IMPLICIT)
    assert code == 0, err[-2000:]
    assert summary["coulomb"] == "implicit"
    assert summary["engine"]["ranks"] == ranks
    assert summary["engine"]["ksp"] == ksp
    steps = assert_same_steps(problem, serial, out, summary, stdout)
    assert_forcing(summary["engine"])  # inexact Newton (GMRES)
    # full slip: D|g| = f_c λ_κ at every node in contact (its own step's)
    assert_full_slip(summary, steps, lag=0)


@pytest.fixture(scope="module")
def sphere_implicit(tmp_path_factory):
    """(problem, folder, serial implicit run) of the a/h 4 quarter
    sphere, friction on all of Γc as the folder runs it."""
    from solver.cli import main
    from test_amg import hertz_sphere

    problem = hertz_sphere(tmp_path_factory, 4)
    folder = tmp_path_factory.mktemp("krylovimplicit3d") / "s4"
    assert main(["convert", str(problem.source), str(folder)]) == 0
    serial = solve(problem, friction=FRICTION, steps=STEPS,
                   candidates=False, coulomb="implicit")
    assert serial.success
    assert np.asarray(serial["slip"])[-1].any()
    return problem, folder, serial


@pytest.mark.parametrize("ranks", [1, 2])
def test_3d_sphere_implicit_same_steps_as_serial(sphere_implicit, tmp_path,
                                                 ranks):
    problem, folder, serial = sphere_implicit
    out = tmp_path / "out"
    code, summary, stdout, err = run_krylov_friction(folder, out, ranks,
                                                     "gamg", *IMPLICIT)
    assert code == 0, err[-2000:]
    assert summary["coulomb"] == "implicit"
    assert summary["n_slip"] > 0
    assert_same_steps(problem, serial, out, summary, stdout)
    assert_forcing(summary["engine"])
