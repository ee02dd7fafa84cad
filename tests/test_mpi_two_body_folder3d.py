"""Two bodies (dual mortar) on the partitioned folder under mpiexec, 3D:
the stacked boxes with a jittered, non-matching interface (1213 DOFs;
test_mpi_two_body_folder.py has the 2D case and the checks).

References: the serial engine's ``solver.solve(problem)`` on the same
``.npz`` (module docstring of test_mpi_two_body_folder.py): u, the
contact, friction and mortar forces to 1e-8, the same contact, stick and
slip sets. The rank counts 1, 2 and 4 are spread over the runs (the
frictionless one on 1 and 2, friction on 4 and 2) to keep the launches
few. PETSc runs only in the mpiexec subprocesses."""

import pytest

from tet_two_body import stacked_boxes
from test_mpi import REASON
from test_mpi_two_body_folder import converted, friction_on, frictionless_on

pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))


@pytest.fixture(scope="module")
def boxes(tmp_path_factory):
    """The stacked boxes, E 1 on 3, ν 0.3 / 0.2, squeezed."""
    return converted(stacked_boxes(n_upper=(6, 6, 3), n_lower=(7, 7, 3),
                                   slave="upper")[0],
                     tmp_path_factory.mktemp("tb3"))


def test_frictionless_1_2_ranks_as_the_serial_engine(boxes, tmp_path):
    """u, D_jj λ_j, the mortar forces in u and the contact set of the
    serial run to 1e-8 on 1 rank, and on 2 from the folder converted with
    ``--renumber`` (E, the bodies and Γc renumbered with the nodes; the
    outputs in the .npz's numbers; measured ≤ 1.5e-12); CG per Newton
    system within ±10 % on 1 and 2 ranks and no more than GAMG with its
    aggregation threshold gives (a regression guard, measured values in
    the test)."""
    from solver.cli import main

    problem, folder = boxes
    krylov = {}
    frictionless_on(problem, folder, tmp_path / "plain", (1,), krylov)
    renumbered = tmp_path / "renumbered"
    assert main(["convert", str(problem.source), str(renumbered),
                 "--renumber"]) == 0
    frictionless_on(problem, renumbered, tmp_path / "rcm", (2,), krylov)
    # issue 33: Krylov counts independent of the rank count within ±10 %;
    # CG per Newton system measured 15.3 / 14.3 with GAMG's threshold
    # 0.02 (full.GAMG_OPTIONS), 18.3 / 17.3 with PETSc's default 0, whose
    # aggregates made the two-sphere folder's counts grow 1.34x at 2 ranks
    assert max(krylov.values()) <= 1.1 * min(krylov.values()), krylov
    assert max(krylov.values()) <= 16.5, krylov


@pytest.mark.parametrize("coulomb, ranks", [("lagged", 4),
                                            ("implicit", 2)])
def test_friction_as_the_serial_engine(boxes, tmp_path, coulomb, ranks):
    """f_c 0.3 over 3 load steps, either bound: every step's u and forces
    to 1e-8 (measured u ≤ 4e-12, friction forces ≤ 7e-11), the same sets,
    28 stick and 21 slip nodes at the end."""
    friction_on(*boxes, tmp_path, coulomb, ranks)
