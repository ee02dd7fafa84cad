"""Why the default friction formulation is the projection form.

The thesis's split formulation (110)/(111) is singular where p = 0 (thesis
digest, errata); with φ_FB it survives on gradient steps on the 118 and 454
blocks (Table 2), but on the thesis's own finest block (1878 cells) at
f_c = 0.3 it stalls in a load step. The projection form (Alart & Curnier
1991) converges there. References: the thesis's Table 2 setup (f_c = 0.3,
100 load steps, lagged bound) and, for the answer, the thesis formulation on
the 454 block, where both converge and agree to 1e-8
(test_friction.py::test_formulations_agree_where_unique).
"""

import numpy as np

from solver import load_problem, solve_friction


def test_default_is_projection_and_converges_on_the_1878_block(exported):
    problem = load_problem(exported(1878)[0])
    result = solve_friction(problem, 0.3, steps=100)
    assert result.success, result.message
    assert result.formulation == "projection"
    assert result.steps_completed == 100
    assert np.isfinite(result.u).all()


def test_thesis_split_with_fb_stalls_on_the_1878_block(exported):
    """The thesis formulation fails here, and says so in one line."""
    problem = load_problem(exported(1878)[0])
    result = solve_friction(problem, 0.3, steps=100, formulation="thesis")
    assert not result.success
    assert result.failed_step is not None and result.failed_step > 1
    assert result.message.startswith(f"load step {result.failed_step} of "
                                     "100 did not converge")
    assert "\n" not in result.message


def test_default_agrees_with_the_thesis_split_where_both_converge(exported):
    """On the 454 block at f_c = 0.3 (Table 2) both formulations converge:
    same final displacement."""
    problem = load_problem(exported(454)[0])
    a = solve_friction(problem, 0.3, steps=100)
    b = solve_friction(problem, 0.3, steps=100, formulation="thesis")
    assert a.success and b.success
    scale = np.abs(b.u).max()
    assert np.abs(a.u - b.u).max() <= 1e-8 * scale
