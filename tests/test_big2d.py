"""``benchmarks/big2d.py``'s grid: the smallest NX x 2NX block whose
reduced DOFs (all nodes but the clamped bottom row, two each) reach the
target, counted here from the mesh the script writes
(``meshes/structured.py``) and checked against the 10⁷-DOF run of
benchmarks/README.md (10,004,568 DOFs)."""

import sys

import pytest

from conftest import ROOT, load_script

sys.path.insert(0, str(ROOT / "benchmarks"))


@pytest.fixture(scope="module")
def big2d():
    return load_script("big2d", ROOT / "benchmarks" / "big2d.py")


def reduced_dofs(nx):
    structured = load_script("structured", ROOT / "meshes" / "structured.py")
    nodes, _ = structured.block(nx, 2 * nx)
    return 2 * int((nodes[:, 1] > -10.0).sum())


@pytest.mark.parametrize("dofs", [2e4, 1e6])
def test_grid_is_the_smallest_that_reaches(big2d, dofs):
    nx = big2d.grid_size(dofs)
    assert reduced_dofs(nx) >= dofs > reduced_dofs(nx - 1)


def test_grid_of_the_recorded_run(big2d):
    nx = big2d.grid_size(1e7)
    assert nx == 1581
    assert 2 * (nx + 1) * (2 * nx + 1) - 2 * (nx + 1) == 10_004_568
