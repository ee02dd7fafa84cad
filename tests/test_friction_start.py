"""The start of a condensed friction step (issue 34, points 4 and 9).

The condensed load step starts from the free-body predictor with its
normal contact forces corrected (:func:`solver.contact.friction.start.
contact_corrected`).
Independent references: the definition of the normal contact problem
(Signorini's conditions λ ≥ 0, s − u_n ≥ 0, λ(s − u_n) = 0, checked on the
start itself), the Lawson–Hanson non-negative least squares of SciPy on
the same complementarity problem written as a QP, the thesis's system in
all unknowns (``condense=False``: sparse LU, Δu = 0 start, another code
path) for the answers, and φ_min against φ_FB in 3D.
"""

import numpy as np
import pytest
import scipy.linalg as sla
from scipy.optimize import nnls

from conftest import MESHES
from test_export3d import SPHERE, export_module
from solver import solve_friction
from solver.contact.friction import steps
from solver.problem import load_problem


@pytest.fixture(scope="module")
def block_454(exported):
    return load_problem(exported(454)[0])


@pytest.fixture(scope="module")
def sphere_4(tmp_path_factory):
    """The a/h = 4 quarter Hertz sphere (2443 DOFs)."""
    path = tmp_path_factory.mktemp("sphere") / "hertz_sphere_4.npz"
    export_module().export_only(SPHERE, mesh=str(MESHES /
                                                 "hertz_sphere_4.mesh"),
                                output=str(path))
    return load_problem(path)


def _starts(monkeypatch):
    """Record, for every condensed step, the normal forces λ, gaps s − u_n
    and tangential forces r_t of the predictor and of the start (at the
    call: the system moves on from step to step), k̄, F and the normal
    flexibility C_nn = R_n S⁻¹ R_nᵀ (from S by NumPy's solve)."""
    seen = []
    original = steps.contact_corrected

    def state(system, du):
        nr = system.n_rows
        r = system._force(du)
        gap = system.geometry.gap - (system.R @ (system.u_previous
                                                 + du))[nr]
        return -r[nr], gap, r[system.t_rows]

    def recorded(self, du):
        out = original(self, du)
        Rn = self.R[self.n_rows].toarray()
        M = Rn @ np.linalg.solve(self.K.toarray(), Rn.T)
        seen.append(dict(before=state(self, du), after=state(self, out),
                         changed=not np.array_equal(du, out), M=M,
                         k=self.stiffness, F=max(self.load_norm, 1.0)))
        return out

    monkeypatch.setattr(steps, "contact_corrected", recorded)
    return seen


def test_start_satisfies_signorini_and_keeps_tangential_balance(
        block_454, monkeypatch):
    """Every step's start is on the complementarity set of its normal
    pairs (to round-off), its normal forces are the QP's of NNLS, and the
    tangential forces are the predictor's (the correction adds normal
    forces only)."""
    seen = _starts(monkeypatch)
    result = solve_friction(block_454, 0.3, steps=40)
    assert result.success
    assert len(seen) == 40
    for step in seen:
        F, k = step["F"], step["k"]
        lam, gap, rt = step["after"]
        lam0, gap0, rt0 = step["before"]
        assert lam.min() >= -1e-12 * F
        assert gap.min() >= -1e-12 * F / k
        assert np.abs(np.minimum(lam, k * gap)).max() <= 1e-12 * F
        assert np.abs(rt - rt0).max() <= 1e-12 * F
        # the same LCP as a QP: min ½yᵀMy + qᵀy, y ≥ 0 (M = C_nn)
        M = step["M"]
        q = gap0 - M @ lam0
        L = sla.cholesky(M, lower=True)
        y, _ = nnls(L.T, -sla.solve_triangular(L, q, lower=True))
        assert np.abs(y - np.maximum(lam, 0.0)).max() <= 1e-9 * F
    # the predictor penetrates in every step with contact (from step 20)
    assert sum(step["changed"] for step in seen) >= 20


@pytest.mark.parametrize("friction", [0.05, 0.3, 10.0])
def test_fb_condensed_needs_few_jacobians(block_454, friction):
    """Issue 34.4: φ_FB on the condensed system took 431/433/427 Jacobians
    for 100 steps (five per step in contact); the target is ≤ 1.5 per load
    step. The answer is the thesis's system's (all unknowns, sparse LU)."""
    ours = solve_friction(block_454, friction, steps=100, method="fb")
    full = solve_friction(block_454, friction, steps=100, method="fb",
                          condense=False)
    assert ours.success and full.success
    assert ours.njev <= 1.5 * 100
    for key in ("u", "contact_force", "friction_traction"):
        scale = np.abs(full[key]).max()
        assert np.abs(ours[key] - full[key]).max() <= 1e-10 * scale, key
    np.testing.assert_array_equal(ours.in_contact, full.in_contact)
    np.testing.assert_array_equal(ours.stick, full.stick)


@pytest.mark.parametrize("steps", [3, 8])
def test_3d_huge_friction_implicit_bound_converges(sphere_4, steps):
    """Issue 34.9: f_c = 10⁶ with the implicit bound on the Hertz sphere;
    φ_FB stalled ("no progress") in load step 2 of 3 and 3 of 8 (a/h 4). It
    converges, is verified against K and f, and agrees with φ_min (another
    NCP function and damping) and φ_min's stick/slip flags."""
    fb = solve_friction(sphere_4, 1e6, steps=steps, coulomb="implicit",
                        method="fb")
    assert fb.success, fb.message
    assert fb.verification["passed"]
    ref = solve_friction(sphere_4, 1e6, steps=steps, coulomb="implicit",
                         method="min")
    assert ref.success, ref.message
    for key in ("u", "contact_force"):
        scale = np.abs(ref[key]).max()
        assert np.abs(fb[key] - ref[key]).max() <= 1e-8 * scale, key
    np.testing.assert_array_equal(fb.in_contact[-1], ref.in_contact[-1])


def test_default_method_follows_the_formulation(exported):
    """Issue 34.4: φ_min by default with the projection formulation (the
    fewest Jacobians, benchmarks/README.md), the thesis's φ_FB with the
    thesis's split (φ_min's Jacobian is singular there where p = 0:
    tests/test_friction.py::test_thesis_split_is_singular_for_min)."""
    block_118 = load_problem(exported(118)[0])
    projection = solve_friction(block_118, 0.3, steps=25)
    thesis = solve_friction(block_118, 0.3, steps=25, formulation="thesis")
    assert projection.success and thesis.success
    assert projection.method == "min" and thesis.method == "fb"
    assert thesis.njev == solve_friction(block_118, 0.3, steps=25,
                                         formulation="thesis",
                                         method="fb").njev
