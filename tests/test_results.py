"""Result objects read well (issue 15.10): a short repr that names what
was solved and how it ended, never an array."""

from solver import solve_friction, solve_frictionless


def test_reprs_are_short(bar_problem):
    frictionless = solve_frictionless(bar_problem, method="min")
    text = repr(frictionless)
    assert text.startswith("<ContactResult min method, converged")
    assert "array" not in text and "\n" not in text and len(text) < 200
    steps = solve_friction(bar_problem, 0.5, steps=20,
                           formulation="projection")
    text = repr(steps)
    assert text.startswith("<ContactResult f_c=0.5, projection")
    assert "20/20 steps, converged" in text and "array" not in text
    assert str(steps) == text and len(text) < 200
    # the data are still there, as in any OptimizeResult
    assert steps.displacement.shape[0] == 20 and "u" in frictionless
