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


def test_system_comparison_full_against_condensed(exported):
    """Both systems solve (67): the same u; the full system's counts are
    those of table1 (the thesis's setting), computed separately."""
    from solver.studies import system_comparison

    problem = load_problem(exported(118)[0])
    rows = system_comparison({118: problem}, methods=("min",))
    reference = table1({118: problem}, methods=("min",), gaps=("obstacle",))
    assert rows[0]["converged"] and rows[0]["du"] < 1e-8
    assert (rows[0]["full_J"], rows[0]["full_F"]) == \
        (reference[0]["J"], reference[0]["F"])
    assert rows[0]["condensed_start"] == "nested" and rows[0]["levels"] >= 1


def test_tangential_displacement_matches_the_friction_solver(exported):
    """u·γ of a frictionless result equals the friction solver's own u_t
    (R u on the tangential rows) for f_c = 0 in one load step."""
    import numpy as np

    from solver import solve_friction, solve_frictionless
    from solver.studies import tangential_displacement

    problem = load_problem(exported(118)[0])
    frictionless = solve_frictionless(problem, condense=False)
    friction = solve_friction(problem, 0.0, steps=1,
                              formulation="projection")
    ours = tangential_displacement(problem, frictionless)
    theirs = friction.tangential_displacement[-1]
    free = np.isfinite(theirs)
    assert free.sum() == problem.n_contact - 1  # the clamped corner
    assert np.allclose(ours[free], theirs[free], rtol=0,
                       atol=1e-8 * np.abs(theirs[free]).max())


def test_gradient_steps_by_load_step(exported):
    """The per-step counts add up to the run's records; only steps with a
    gradient step are listed. The thesis's split is degenerate where p = 0
    (everywhere on Γc in load step 1): φ_FB takes gradient steps there."""
    from solver import solve_friction
    from solver.studies import gradient_steps_by_load_step

    problem = load_problem(exported(118)[0])
    r = solve_friction(problem, 0.3, steps=5, formulation="thesis")
    steps = gradient_steps_by_load_step(r)
    assert 1 in steps and all(v > 0 for v in steps.values())
    assert sum(steps.values()) == sum(x["gradient_steps"]
                                      for x in r.records)
