"""Coulomb friction on the partitioned folder's full system by Krylov in
3D (issue 33, point 1 under mpiexec; solver/mpi/krylov_friction.py): the
a/h 4 quarter Hertz sphere (2443 DOFs, rollers on its two symmetry
planes: a roller's constrained tangent has no row), f_c 0.3, 3 load
steps, CG + GAMG on 1, 2 and 4 (oversubscribed) ranks; the slip springs
across the slip direction are 2 × 2 blocks added to K̂ on the rank that
owns the node.

Reference: the serial engine on the ``.npz`` with ``candidates=False``
(friction on all of Γc, as the folder runs it; the semismooth Newton on
Γc's Schur complement from scipy's factorisation): every step's u,
friction and contact forces to 1e-8, the same stick, slip and contact
sets (test_mpi_krylov_friction.assert_same_steps)."""

import pytest

from solver import solve
from test_mpi import REASON
from test_mpi_forcing import assert_forcing
from test_mpi_krylov_friction import (FRICTION, STEPS, assert_same_steps,
                                      run_krylov_friction)

pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))


@pytest.fixture(scope="module")
def sphere(tmp_path_factory):
    """(problem, folder, serial lagged run)."""
    import numpy as np

    from solver.cli import main
    from test_amg import hertz_sphere

    problem = hertz_sphere(tmp_path_factory, 4)
    folder = tmp_path_factory.mktemp("krylovfric3d") / "s4"
    assert main(["convert", str(problem.source), str(folder)]) == 0
    serial = solve(problem, friction=FRICTION, steps=STEPS,
                   candidates=False)
    assert serial.success
    assert np.asarray(serial["stick"])[-1].any()  # both sets
    assert np.asarray(serial["slip"])[-1].any()
    return problem, folder, serial


@pytest.mark.parametrize("ranks", [1, 2, 4])
def test_3d_sphere_with_rollers_same_steps_as_serial(sphere, tmp_path,
                                                     ranks):
    problem, folder, serial = sphere
    out = tmp_path / "out"
    code, summary, stdout, err = run_krylov_friction(folder, out, ranks)
    assert code == 0, err[-2000:]
    assert summary["engine"]["ranks"] == ranks
    assert summary["n_stick"] > 0 and summary["n_slip"] > 0
    assert_same_steps(problem, serial, out, summary, stdout)
    assert_forcing(summary["engine"])  # inexact Newton, the same steps
