"""benchmarks/run_two_body.py on the thesis's 1878 block (unrefined) on a
coarse parabola body: both tables complete, every backend converged, the
ratios the quotients of their cells, the Newton counts and the contact
set those of a direct ``solve_two_body`` of the same export (no timing
target here: the 1.2·10⁵-DOF row is in benchmarks/README.md)."""

import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT
from solver import load_problem
from solver import solve_two_body
from solver.linalg import available_backends

pytest.importorskip("sfepy")
pytest.importorskip("gmsh")


def _cells(table):
    head = [c.strip() for c in table[0].strip("|").split("|")]
    return dict(zip(head, (c.strip() for c in
                           table[2].strip("|").split("|"))))


@pytest.fixture(scope="module")
def tables(tmp_path_factory):
    workdir = tmp_path_factory.mktemp("two_body_bench")
    result = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "run_two_body.py"),
         "--refine", "0", "--h-contact", "0.5", "--workdir", str(workdir)],
        capture_output=True, text=True, timeout=900, cwd=ROOT)
    assert result.returncode == 0, result.stderr[-2000:]
    found, lines = [], []
    for line in result.stdout.splitlines() + [""]:
        if line.startswith("|"):
            lines.append(line)
        elif lines:
            found.append(lines)
            lines = []
    assert len(found) == 2 and all(len(t) == 3 for t in found)
    npz, = workdir.glob("*.npz")
    return _cells(found[0]), _cells(found[1]), load_problem(npz)


def test_tables_are_complete_and_consistent(tables):
    wall, cpu, problem = tables
    assert "–" not in wall.values() and "–" not in cpu.values()
    assert int(wall["DOFs"]) == problem.n_dofs
    assert int(wall["slave"]) == problem.n_contact == 40  # the 1878 block's Γc
    backends = available_backends()
    floors = {b: float(wall[f"floor {b} [s]"]) for b in backends}
    assert wall["fastest"] == min(floors, key=floors.get)
    for cells in (wall, cpu):
        fastest = float(cells[f"floor {wall['fastest']} [s]"])
        for method in ("min", "fb"):
            for b in backends:
                cell = cells[f"{method} {b} [s] (/floor)"]
                assert "not converged" not in cell
                time, ratio = cell.split(" (")
                assert float(ratio.rstrip(")")) == pytest.approx(
                    float(time) / fastest, rel=0.02, abs=0.01)


def test_counts_are_those_of_a_direct_solve(tables):
    wall, _, problem = tables
    for method in ("min", "fb"):
        r = solve_two_body(problem, method=method, backend=wall["fastest"])
        assert wall[f"{method} J/F (finest)"].startswith(
            f"{r.njev}/{r.nfev} ")
        assert int(wall["in contact"]) == r.n_contact


def test_refined_block_mesh(tmp_path):
    """``meshes/two_body.py block --refine 1`` (the benchmark's mesh at one
    level): the block's 118 triangles split into 4 × 118, its base nodes
    first and unmoved (``meshes/block_118.mesh``), each Γc segment halved
    (2 × 10 + 1 nodes on x = 5), the parabola body unchanged."""
    sys.path.insert(0, str(ROOT / "meshes"))
    import generate
    import two_body

    out = tmp_path / "r1.mesh"
    result = subprocess.run(
        [sys.executable, str(ROOT / "meshes" / "two_body.py"), "block",
         "--base", "118", "--refine", "1", "-o", str(out)],
        capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert result.returncode == 0, result.stderr
    points, triangles, body = two_body.read_bodies(out)
    base, base_triangles = generate.read_mesh(ROOT / "meshes" /
                                              "block_118.mesh")
    _, plain_triangles, plain_group = two_body.block_mesh(118)
    assert (body[triangles[:, 0]] == 0).sum() == 4 * len(base_triangles)
    assert np.array_equal(points[:len(base)], base)
    on_edge = (body == 0) & np.isclose(points[:, 0], 5.0)
    assert on_edge.sum() == 2 * 10 + 1
    assert (body == 1).sum() == \
        np.unique(plain_triangles[plain_group == 2]).size
