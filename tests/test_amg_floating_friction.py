"""Coulomb friction on a body held by contact only, on the iterative path
(``backend='amg'``, issue 33 point 1): the active set method's load steps
(projection formulation, lagged and implicit bound) with K singular, the
first contact from the rigid placement, each Newton system on the modes
that its constraints hold (solver/contact/friction/active_set.py
FloatingIterativeSpace).

Independent reference: the factorisation path (condensed with K⁺ and the
modes' amplitudes, or system='full' with them as unknowns; semismooth
Newton on the whole NCP with LAPACK or SuperLU, another algorithm and
another linear solver) on the floating blocks of tests/
test_floating_friction.py; statics (the normal forces balance the
weight); the same one-line refusal of a load the lagged bound cannot
hold."""

import numpy as np
import pytest

import solver
from solver.linalg import amg
from test_floating_friction import FC, _block3
from tri_elasticity import (floor_block, floor_block_beyond_lagged,
                            two_cylinders)

pytestmark = pytest.mark.skipif(not amg.available(),
                                reason="pyamg not installed (.[amg])")


@pytest.mark.parametrize("make, options, system, weight", [
    (lambda: floor_block(n=(40, 20)), dict(steps=3), "condensed", 2.0),
    (lambda: floor_block(n=(40, 20), load=(0.2, -1.0)),
     dict(coulomb="implicit", steps=3), "condensed", 2.0),
    (lambda: _block3((0.1, 0.05, -1.0)), dict(coulomb="implicit", steps=3),
     "condensed", 1.0),
    (lambda: _block3((0.1, 0.05, -1.0), n=(8, 8, 3)),
     dict(coulomb="implicit", steps=3), "condensed", 1.0),
], ids=["2d weight lagged", "2d sideways implicit", "3d sideways implicit",
        "3d sideways implicit, 8x8x3"])
def test_floating_block_with_friction(make, options, system, weight):
    """The floating block under its weight (lagged: the first step
    frictionless, its slide left to none as the factorisation path
    leaves it, Δα = 0 along it) or pushed sideways within the friction
    cone (implicit): every step converged and verified, the last step's u
    equal to the factorisation's to 1e-8 (measured 5.8e-12, 6.9e-12,
    1.4e-11, 5.6e-11), the
    same contact and stick sets in every step, and the normal forces
    summing to the weight to 1e-10; the larger meshes (2D 40 × 20, 3D
    8 × 8 × 3) on hierarchies of two levels."""
    problem = make()
    direct = solver.solve(problem, friction=FC, system=system, **options)
    iterative = solver.solve(problem, friction=FC, backend="amg", **options)
    for r in (direct, iterative):
        assert r.success, r.message
    assert iterative.linear_solver == "amg"
    assert iterative.engine["levels"] >= (2 if problem.n_dofs > 900 else 1)
    u, v = iterative.u[-1], direct.u[-1]
    assert np.abs(u - v).max() <= 1e-8 * np.abs(v).max(), \
        np.abs(u - v).max() / np.abs(v).max()
    for a, b in zip(iterative.in_contact, direct.in_contact):
        np.testing.assert_array_equal(a, b)
    for a, b in zip(iterative.stick, direct.stick):
        np.testing.assert_array_equal(a, b)
    assert abs(iterative.contact_force[-1].sum() - weight) <= 1e-10


def test_load_beyond_the_lagged_bound_same_line():
    """A load path whose third step pulls harder sideways than the second
    step's pressure can hold under the lagged bound: the run stops there
    with the same one-line reason as the factorisation path (the motion
    named), two steps completed."""
    problem = floor_block_beyond_lagged()
    runs = [solver.solve(problem, friction=FC, coulomb="lagged",
                         backend=backend) for backend in ("auto", "amg")]
    for r in runs:
        assert not r.success and r.failed_step == 3
        assert r.steps_completed == 2
    assert "translation (" in runs[1].message and "\n" not in runs[1].message
    assert runs[1].message == runs[0].message


def test_3d_boxes_upper_floating_with_friction():
    """Two stacked boxes (dual mortar), the upper one held by contact only
    (six modes) under the pressure p, f_c = 0.3, lagged, two steps: every
    step converged and verified, the last step's u equal to the
    factorisation's to 1e-8 (measured 3e-11) with the same sets."""
    from tet_two_body import stacked_boxes

    problem, _, _ = stacked_boxes(pressure=0.01, slave="upper", squeeze=0.0)
    direct = solver.solve(problem, friction=0.3, steps=2)
    iterative = solver.solve(problem, friction=0.3, steps=2, backend="amg")
    for r in (direct, iterative):
        assert r.success, r.message
    u, v = iterative.u[-1], direct.u[-1]
    assert np.abs(u - v).max() <= 1e-8 * np.abs(v).max()
    for a, b in zip(iterative.stick, direct.stick):
        np.testing.assert_array_equal(a, b)
    for a, b in zip(iterative.in_contact, direct.in_contact):
        np.testing.assert_array_equal(a, b)


@pytest.mark.filterwarnings(
    "ignore:the rigid-body motion .* is held by the contact only weakly:"
    "solver.errors.WeaklyHeldWarning")
@pytest.mark.parametrize("load_path", [True, False],
                         ids=["frictionless stage", "lagged first step"])
def test_weakly_held_spin_in_a_step_without_friction_refused(load_path):
    """The two Hertz cylinders of tests/test_floating_two_body.py, the
    upper one's spin seen by the normals at 4.3e-4 of its motion: P in
    frictionless steps then Q with friction, or P with friction under the
    lagged bound (its first step has f_c p_0 = 0): refused before any
    step in one line naming the motion and the way out. Unrefused they
    stalled at relative errors 4.9e-8 (load path, step 2) and 4.0e-8
    (lagged, step 1, 100 Newton systems) above tol = 1e-10, where the
    factorisation path converges (9.9e-13 in 23 Jacobians;
    benchmarks/README.md)."""
    from solver.errors import SolverError
    from test_floating_two_body import (CM_FRICTION, MATERIALS, P, R,
                                        cattaneo_mindlin_cylinders)

    if load_path:
        problem, steps = cattaneo_mindlin_cylinders(), None
    else:
        problem, _, _ = two_cylinders(R, MATERIALS, force=P)
        steps = 2
    with pytest.raises(SolverError, match="only weakly") as refused:
        solver.solve(problem, friction=CM_FRICTION, steps=steps,
                     backend="amg")
    message = str(refused.value)
    assert "\n" not in message and "rotation" in message
    assert "backend='auto'" in message
