"""benchmarks/run_two_body.py on the thesis's 1878 block (unrefined) on a
coarse parabola body: both tables complete, every backend converged, the
ratios the quotients of their cells, the Newton counts and the contact
set those of a direct ``solve_two_body`` of the same export (no timing
target here: the 1.2·10⁵-DOF row is in benchmarks/README.md)."""

import subprocess
import sys

import pytest

from conftest import ROOT
from solver import load_problem
from solver.contact.two_body import solve_two_body
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
