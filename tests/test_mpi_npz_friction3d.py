"""Coulomb friction on the full system of a ``.npz`` under mpiexec in 3D
(issue 33; solver/mpi/on_the_fly.py): the a/h 4 quarter Hertz sphere
(2443 DOFs, rollers on its two symmetry planes, kept by the conversion
on the fly), f_c 0.3, 3 load steps, ``--ksp gamg``, the lagged bound on 1
and 2 ranks and the implicit bound (GMRES) on 2.

Reference: the serial engine on the same ``.npz`` with
``candidates=False`` (friction on all of Γc, as the folder runs it; the
semismooth Newton on Γc's Schur complement from scipy's factorisation):
every step's u, friction and contact forces to 1e-8 and the same stick,
slip and contact sets (test_mpi_krylov_friction.assert_same_steps); the
temporary folder is gone after each run. PETSc runs only in the mpiexec
subprocesses."""

import numpy as np
import pytest

from solver import solve
from test_mpi import REASON
from test_mpi_krylov_friction import (FRICTION, STEPS, assert_same_steps,
                                      run_krylov_friction)
from test_mpi_npz_friction import assert_converted, leftovers

pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))


@pytest.fixture(scope="module")
def sphere(tmp_path_factory):
    """The a/h 4 quarter sphere's problem (its ``.npz`` is its source)."""
    from test_amg import hertz_sphere

    return hertz_sphere(tmp_path_factory, 4)


@pytest.mark.parametrize("ranks, coulomb", [(1, "lagged"), (2, "lagged"),
                                            (2, "implicit")])
def test_3d_sphere_with_rollers_from_the_npz(sphere, tmp_path, ranks,
                                             coulomb):
    serial = solve(sphere, friction=FRICTION, steps=STEPS,
                   candidates=False, coulomb=coulomb)
    assert serial.success
    assert np.asarray(serial["slip"])[-1].any()
    out = tmp_path / "out"
    code, summary, stdout, err = run_krylov_friction(
        sphere.source, out, ranks, "gamg", "--coulomb", coulomb)
    assert code == 0, err[-2000:]
    assert summary["engine"]["ranks"] == ranks
    assert summary["coulomb"] == coulomb
    assert summary["n_slip"] > 0
    if coulomb == "lagged":
        assert summary["n_stick"] > 0
    assert_converted(summary, stdout, sphere.source)
    assert_same_steps(sphere, serial, out, summary, stdout)
    assert leftovers(tmp_path) == []
