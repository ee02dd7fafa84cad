"""The extrapolated start of a condensed 3D friction step (issue 33 point
2: fewer Jacobians per load step), :func:`solver.contact.friction.start.
extrapolated`.

Within a stretch of equal load increments a step starts from the previous
step's increment, Δu_{κ−1} and g_{κ−1} + (g_{κ−1} − g_{κ−2}), before the
normal correction; elsewhere from the free motion, as before.

Independent references: the run from the free motion
(``start.EXTRAPOLATE = False``, the solver's path before), whose answer
the start must not change (the answer of a converged step does not depend
on where Newton starts: same u, same stick and slip sets), and the
definition of the predictor itself on hand-made states.
"""

from types import SimpleNamespace

import numpy as np

# the a/h = 4 quarter Hertz sphere (a module fixture)
from test_friction_start import sphere_4  # noqa: F401
from solver import solve_friction
from solver.contact.friction import start


def _system(dim=3, formulation="projection"):
    return SimpleNamespace(dim=dim, formulation=formulation)


def test_predictor_on_equal_increments():
    """Equal free motions: the previous increment and the extrapolated
    traction; a different free motion, the first step, 2D or the
    thesis's split: the free motion and the previous traction."""
    free = np.array([1.0, -2.0, 0.5])
    state = SimpleNamespace(free_last=free.copy(), du_last=np.array(
        [0.3, -1.0, 0.1]), g=np.array([2.0, 1.0]), g_last=np.array(
        [1.0, 0.5]))
    du, g = start.extrapolated(_system(), state, free)
    assert np.array_equal(du, [0.3, -1.0, 0.1])
    assert np.array_equal(g, [3.0, 1.5])
    du[0] = 9.0  # a copy: the start does not move the state
    assert state.du_last[0] == 0.3
    other = free * (1 + 1e-9)
    for system, step in ((_system(), other), (_system(dim=2), free),
                         (_system(formulation="thesis"), free)):
        du, g = start.extrapolated(system, state, step)
        assert du is step and g is state.g
    first = SimpleNamespace(g=state.g)  # no step before
    du, g = start.extrapolated(_system(), first, free)
    assert du is free and g is first.g


def same_answer(problem, monkeypatch, module, switch):
    """(ours, before): f_c = 0.3 in 10 steps on ``problem`` as it is and
    with ``module.switch`` False; asserts that both converge, verified on
    every node, to the same u (1e-8, relative) and the same stick, slip
    and contact sets in every step, with both stick and slip at the last
    (the answer of a converged step does not depend on the start or on
    the projection's parameter)."""
    ours = solve_friction(problem, 0.3, steps=10)
    monkeypatch.setattr(module, switch, False)
    before = solve_friction(problem, 0.3, steps=10)
    for run in (ours, before):
        assert run.success and run.verification["passed"]
    assert np.abs(ours.u - before.u).max() <= 1e-8 * np.abs(before.u).max()
    for key in ("stick", "slip", "in_contact"):
        assert np.array_equal(getattr(ours, key), getattr(before, key))
    assert ours.stick[-1].any() and ours.slip[-1].any()
    return ours, before


def test_same_answer_fewer_jacobians(sphere_4, monkeypatch):
    """The quarter Hertz sphere, f_c = 0.3 in 10 steps: the same u (to
    1e-8, relative) and the same stick and slip sets in every step as the
    run from the free motion, verified on every node, with fewer
    Jacobians (measured: 27 against 34, at most 4 in a step against 5;
    with the scalar c_t, ``disc.NODAL_CT = False``, 30 against 38 and 4
    against 6)."""
    ours, before = same_answer(sphere_4, monkeypatch, start, "EXTRAPOLATE")
    assert ours.njev < before.njev
    assert max(r["njev"] for r in ours.records) <= 4
