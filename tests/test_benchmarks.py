"""Smoke test of benchmarks/run.py at the smallest size (no timing
assertions: timings live in the benchmark's own output)."""

import subprocess
import sys

from conftest import ROOT


def test_benchmark_prints_a_table_row():
    result = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "run.py"), "--max-dofs",
         "3000", "--max-friction-dofs", "3000", "--steps", "5"],
        capture_output=True, text=True, timeout=600, cwd=ROOT)
    assert result.returncode == 0, result.stderr[-2000:]
    lines = [l for l in result.stdout.splitlines() if l.startswith("|")]
    header, rows = lines[0], lines[2:]
    assert "floor [s]" in header and "min/floor" in header
    assert len(rows) == 1
    cells = [c.strip() for c in rows[0].strip("|").split("|")]
    assert cells[0] == "1956"                 # the 1878-element mesh
    assert cells[7] == "7/19"                 # φ_min J/F, as in Table 1 rows
    assert "not converged" not in rows[0]
    assert cells[13] != "–"                   # friction ran
