"""The kinematic assumptions are checked on every answer (issue 35,
point 4): sliding of more than one element of Γc along a curved obstacle,
or an initial overlap of more than a tenth of the body, end with a
KinematicsWarning saying which; a flat obstacle, exact under any sliding
in the linear model, stays silent. The reference is the geometry of the
test problems: the sliding prescribed on the block's top (the body moves
rigidly sideways, so every Γc node slides by it) and the lift of the
obstacle into the body."""

import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
from tet_elasticity import mesh_problem, rectangle, stiffness  # noqa: E402

import solver  # noqa: E402
from solver.contact.kinematics import element_size  # noqa: E402
from solver.errors import (InitialPenetrationWarning,  # noqa: E402
                           KinematicsWarning)

N = 24  # elements along Γc: h = 2/24


def block(shift, curvature, lift=0.0, n=N):
    """[−1, 1] × [0, 1] with its top moved by (shift, −0.02) over the
    obstacle y = −κx² − 0.01 + lift."""
    nodes, cells = rectangle((n, 8))
    nodes[:, 0] = 2 * nodes[:, 0] - 1
    x, y = nodes.T
    prescribed = np.full(nodes.shape, np.nan)
    prescribed[np.isclose(y, 1.0)] = [shift, -0.02]
    contact = np.flatnonzero(np.isclose(y, 0.0))
    contact = contact[np.argsort(x[contact])]
    problem = mesh_problem(nodes, cells, stiffness(nodes, cells, 2e5, 0.3),
                           prescribed, contact,
                           np.column_stack([contact[:-1], contact[1:]]))
    problem.obstacle = solver.ParametricCurve(
        "t", f"-{curvature}*t**2 - 0.01 + {lift}")
    problem.meta = {"E": 2e5, "nu": 0.3, "plane": "strain",
                    "mesh": "tests/test_kinematics.py"}
    return problem


def warned(problem, category=KinematicsWarning, **options):
    """The result and the warnings of ``category`` the solve emitted."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = solver.solve(problem, **options)
    assert result.success, result.message
    return result, [w for w in caught if w.category is category]


def test_element_size_is_the_gamma_c_spacing():
    assert element_size(block(0.0, 0.1)) == pytest.approx(2 / N)


@pytest.mark.parametrize("options", [{}, dict(friction=0.1, steps=2)])
def test_large_sliding_on_a_curved_obstacle_warns(options):
    result, caught = warned(block(1.5 * 2 / N, 0.1), **options)
    assert len(caught) == 1
    text = str(caught[0].message)
    assert "slides" in text and "1.51 elements" in text
    assert result.verification["kinematics"] == [text]


@pytest.mark.parametrize("shift, curvature", [
    (0.5 * 2 / N, 0.1),   # half an element on the curve: small sliding
    (10 * 2 / N, 0.0)])   # ten elements on a flat obstacle: still exact
def test_small_sliding_or_a_flat_obstacle_is_silent(shift, curvature):
    result, caught = warned(block(shift, curvature))
    assert not caught and result.verification["kinematics"] == []


def test_a_large_initial_overlap_warns():
    size = np.hypot(2.0, 1.0)  # the block's diagonal
    problem = block(0.0, 0.0, lift=0.15 * size)
    _, caught = warned(problem)
    assert len(caught) == 1 and "overlaps" in str(caught[0].message)
    # the usual warning of any initial penetration comes too
    assert warned(problem, InitialPenetrationWarning)[1]
    # a tenth of the size is the limit: 0.05 of it warns only of penetration
    assert not warned(block(0.0, 0.0, lift=0.05 * size))[1]


@pytest.mark.parametrize("friction", [None, 0.3])
def test_two_bodies_sliding_more_than_a_slave_element_warns(friction):
    """Two stacked blocks, the upper one's top moved sideways by 0.5
    (2.5 slave elements of h = 0.2; the relative slip is the shift less
    the blocks' shear, exactly 0.5 without friction): the mortar coupling
    of the reference configuration no longer pairs the right segments, so
    KinematicsWarning; 0.005 (0.025 elements) stays silent."""
    from tri_elasticity import stacked_blocks

    options = {} if friction is None else dict(friction=friction,
                                               formulation="projection")
    found = {}
    for shift in (5e-3, 0.5):
        problem, _, _ = stacked_blocks(n_upper=(5, 2), n_lower=(7, 2),
                                       materials=((1.0, 0.3), (3.0, 0.2)),
                                       shift=shift)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = solver.solve(problem, **options)
        assert result.success
        found[shift] = [str(w.message) for w in caught
                        if issubclass(w.category, KinematicsWarning)]
        assert found[shift] == result.verification["kinematics"]
    assert found[5e-3] == []
    (message,) = found[0.5]
    assert "relative to the master" in message and "(h = 0.2)" in message
    slid = float(message.split(" slides ")[1].split()[0])
    assert 0.45 < slid <= 0.5 + 1e-12
