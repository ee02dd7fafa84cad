"""Smoke test of benchmarks/run.py at the smallest size (no timing
assertions: timings live in the benchmark's own output)."""

import subprocess
import sys

from conftest import ROOT


def test_benchmark_prints_a_table_row():
    result = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "run.py"), "--max-dofs",
         "3000", "--steps", "5"],
        capture_output=True, text=True, timeout=600, cwd=ROOT)
    assert result.returncode == 0, result.stderr[-2000:]
    lines = [l for l in result.stdout.splitlines() if l.startswith("|")]
    header, rows = lines[0], lines[2:]
    columns = [c.strip() for c in header.strip("|").split("|")]
    assert len(rows) == 1
    cells = dict(zip(columns, (c.strip() for c in
                               rows[0].strip("|").split("|"))))
    assert cells["DOFs"] == "1956"            # the 1878-element thesis mesh
    assert "not converged" not in rows[0]
    for key in ("min J/F", "fb J/F", "friction J/F"):
        J, F = map(int, cells[key].split("/"))
        assert 0 < J <= F                      # every Jacobian needs Φ
    # the peers (test extras) ran and reached our solution within 1e-6
    for key in ("Clarabel [s]", "SfePy SSN [s]"):
        assert cells[key] != "–" and "differs" not in cells[key], key
    assert float(cells["RSS/floor"]) > 0
