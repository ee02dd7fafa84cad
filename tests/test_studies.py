"""solver.studies: the thesis's numbers are transcribed right, and our rows
are computed by the solvers (not typed in)."""

import re

import pytest

from conftest import ROOT
from solver.problem import load_problem
from solver.studies import THESIS_TABLE1, THESIS_TABLE2, table1, table2

DIGEST = ROOT.parent / "shared" / "THESIS.md"


@pytest.mark.skipif(not DIGEST.exists(), reason="shared/ is beside the "
                    "checkout in CI and in sessions; absent in a bare clone")
def test_transcription_matches_the_digest():
    text = DIGEST.read_text()
    table1 = {(("fb" if m == "FB" else "min"), int(e)): (int(j), int(f))
              for m, e, j, f in re.findall(
                  r"\| φ_(FB|min) \| (\d+) \| (\d+) \| (\d+) \|", text)}
    assert table1 == THESIS_TABLE1
    table2 = {float(c): (int(j), int(f)) for c, j, f in re.findall(
        r"\| (0\.05|0\.3|10) \| (\d+) \| (\d+) \|", text)}
    assert table2 == THESIS_TABLE2


def test_rows_come_from_the_solvers(exported):
    problem = load_problem(exported(118)[0])
    rows = table1({118: problem}, gaps=("obstacle",))
    assert [r["method"] for r in rows] == ["fb", "min"]
    assert all(r["converged"] for r in rows)
    assert rows[0]["thesis_J"] == 18 and rows[1]["thesis_J"] == 6
    friction = table2(problem, frictions=(0.3,), steps=10,
                      variants=(("projection", "lagged", "fb"),))
    assert friction[0]["converged"] and friction[0]["J"] >= 10
