"""Coulomb friction on the partitioned path in 3D (issue 33, point 4;
solver/mpi/partitioned_friction.py): the a/h 4 quarter Hertz sphere
(2443 DOFs, rollers on its two symmetry planes: a roller's tangential
rows are not all free), f_c 0.3, 3 load steps, on 1, 2 and 4 ranks, the
lagged and the implicit bound.

Reference: the serial engine on the ``.npz`` with ``candidates=False``
(friction on all of Γc, as the partitioned path runs it; the serial
default screens candidates first and agrees to 1e-10 in u, 4e-9 in the
friction forces): every step's u, friction and contact forces to 1e-8,
the same stick and slip sets, the same Jacobians per step
(test_mpi_distributed_friction.assert_same_as_serial)."""

import pytest

from solver import solve
from test_mpi import REASON
from test_mpi_distributed_friction import (FRICTION, STEPS,
                                           assert_same_as_serial,
                                           run_friction)

pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))


@pytest.fixture(scope="module")
def sphere(tmp_path_factory):
    """(problem, folder, {coulomb: serial result})."""
    import numpy as np

    from solver.cli import main
    from test_amg import hertz_sphere

    problem = hertz_sphere(tmp_path_factory, 4)
    folder = tmp_path_factory.mktemp("distfric3d") / "s4"
    assert main(["convert", str(problem.source), str(folder)]) == 0
    serial = {coulomb: solve(problem, friction=FRICTION, steps=STEPS,
                             coulomb=coulomb, candidates=False)
              for coulomb in ("lagged", "implicit")}
    for result in serial.values():
        assert result.success
        assert np.asarray(result["stick"])[-1].any()  # both sets
        assert np.asarray(result["slip"])[-1].any()
    return problem, folder, serial


@pytest.mark.parametrize("ranks,coulomb", [(1, "lagged"), (2, "implicit"),
                                           (4, "lagged")])
def test_3d_sphere_with_rollers_same_steps_as_serial(sphere, tmp_path,
                                                     ranks, coulomb):
    problem, folder, serial = sphere
    out = tmp_path / "out"
    summary, stdout = run_friction(folder, out, ranks, "--coulomb", coulomb)
    assert summary["engine"]["ranks"] == ranks
    assert summary["n_stick"] > 0 and summary["n_slip"] > 0
    assert_same_as_serial(problem, serial[coulomb], out, summary, stdout)
