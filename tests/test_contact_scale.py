"""The stopping test and the verification measure the contact rows against
the contact forces, however the problem is loaded (issue 34, point 1).

The same physical problem twice: (a) the top of a block moved down by d
onto a rigid parabola (a prescribed displacement: f is the Dirichlet
lifting, 4·10⁴ times the contact forces here), and (b) the top held and
the parabola moved up by d (f = 0, negative gaps). The reference is the
equivalence of the two: the contact forces must agree, and in both the
Coulomb bound, complementarity and penetration must hold to 1e-8 of the
contact forces — before, (a) was held 10⁴ times more loosely than (b)
(its contact forces are 2.3·10⁻⁵·‖f‖ here, below the floor of F_c,
1 % of ‖f‖: the test shows that the answers still meet 1e-8 of the
contact forces there).
"""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
from tet_elasticity import mesh_problem, rectangle, stiffness  # noqa: E402

import solver  # noqa: E402
from solver.contact.verify import contact_scale, force_scale  # noqa: E402
from solver.errors import InitialPenetrationWarning  # noqa: E402

D, KAPPA, REACH = 0.05, 0.25, 0.04999  # top motion, curvature, first touch


def pressed_block(moved, n=24, ny=8):
    """[−1, 1] × [0, 1] over y = −κx² − REACH, brought together by D:
    ``moved`` "top" (u_y = −D on top) or "obstacle" (top held, the
    parabola lifted by D)."""
    nodes, cells = rectangle((n, ny))
    nodes[:, 0] = 2 * nodes[:, 0] - 1
    x, y = nodes.T
    prescribed = np.full(nodes.shape, np.nan)
    top = np.isclose(y, 1.0)
    prescribed[top] = [0.0, -D if moved == "top" else 0.0]
    contact = np.flatnonzero(np.isclose(y, 0.0))
    contact = contact[np.argsort(x[contact])]
    problem = mesh_problem(nodes, cells, stiffness(nodes, cells, 2e5, 0.3),
                           prescribed, contact,
                           np.column_stack([contact[:-1], contact[1:]]))
    lift = D if moved == "obstacle" else 0.0
    problem.obstacle = solver.ParametricCurve(
        "t", f"-{KAPPA}*t**2 - {REACH} + {lift}")
    problem.meta = {"E": 2e5, "nu": 0.3, "plane": "strain",
                    "load": moved, "mesh": "tests/test_contact_scale.py"}
    return problem


@pytest.mark.parametrize("options", [
    dict(method="min"), dict(method="fb"), dict(method="min", system="full"),
    dict(friction=0.3, coulomb="implicit", method="min", steps=1),
    dict(friction=0.3, coulomb="implicit", method="fb", steps=1),
    dict(friction=0.3, coulomb="implicit", method="min", steps=1,
         system="full")])
def test_same_problem_same_strictness(options):
    a, b = pressed_block("top"), pressed_block("obstacle")
    ra = solver.solve(a, **options)
    with pytest.warns(InitialPenetrationWarning):  # (b) on purpose
        rb = solver.solve(b, **options)
    assert ra.success and rb.success, (ra.message, rb.message)
    lam_a = np.atleast_2d(ra.contact_force)[-1]
    lam_b = np.atleast_2d(rb.contact_force)[-1]
    # the lifting is far above the contact forces in (a), absent in (b)
    assert np.linalg.norm(a.f) > 1e4 * np.linalg.norm(lam_a)
    assert not np.any(b.f)
    np.testing.assert_allclose(lam_a, lam_b, rtol=0,
                               atol=1e-9 * np.abs(lam_b).max())
    for problem, result in ((a, ra), (b, rb)):
        v = result.verification
        lam = np.atleast_2d(result.contact_force)[-1]
        contact = np.linalg.norm(np.maximum(lam, 0))
        scale = contact_scale(np.linalg.norm(problem.f), lam)
        if "force_scale" in v:  # frictionless (friction: worst of steps)
            assert v["force_scale"] == pytest.approx(scale)
        for key in ("complementarity", "max_penetration",
                    "friction_bound_violation"):
            if key in v:  # relative to the contact forces themselves
                assert v[key] * scale / contact <= 1e-8, (key, v[key])
        if "friction" in options:  # Coulomb on nodal forces, |t| ≤ f_c λ
            t = np.abs(np.atleast_2d(result.friction_traction)[-1]) * \
                np.asarray(problem.M.sum(axis=1)).ravel()
            excess = np.max(t - 0.3 * np.maximum(lam, 0))
            assert excess <= 1e-9 * contact, excess


def test_scales():
    """F_c is the contact forces' norm (normal and friction), floored at
    1e-2 F (the round-off of λ, computed from forces of size F)."""
    lam = np.array([3.0, 4.0, -1.0])
    assert force_scale(1e6, lam) == 1e6
    assert contact_scale(1e6, lam) == 1e4  # the floor: 1e-2 · 1e6
    assert contact_scale(100.0, lam) == 5.0
    assert contact_scale(100.0, lam, friction_force=[6.0, 8.0]) == 10.0
    assert contact_scale(0.0, np.zeros(3)) == 0.0


class _Stalled:
    """A system whose weighted measure is 100× its plain one."""
    def residual(self, x):
        return np.array([x[0]]), np.array([1.0]), np.array([0.0])

    def error(self, E, A, B, weighted=True):
        return (100.0 if weighted else 1.0) * abs(E[0])

    def scale(self, E, A, B):
        return 1.0


@pytest.mark.parametrize("x, verified, accepted", [
    (5e-11, True, True),    # within tol of the load: floating point's stop
    (5e-11, False, False),  # the answer itself failed: not converged
    (5e-10, True, False)])  # beyond tol even unweighted: a real stall
def test_accept_at_roundoff(x, verified, accepted):
    from scipy.optimize import OptimizeResult
    from solver.contact.verify import accept_at_roundoff
    result = OptimizeResult(status=5, success=False, message="stalled",
                            stopping=dict(relative=100 * x))
    accept_at_roundoff(result, _Stalled(), np.array([x]), 1e-10, verified)
    assert result.success is accepted
    assert result.status == (0 if accepted else 5)
    if accepted:
        assert "round-off" in result.message
