"""Hertz and Cattaneo–Mindlin for two cylinders (issue 19), on half-disks
meshed and assembled here (tests/tri_elasticity.py, no SfePy), against
the closed forms of plane-strain Hertz contact (Johnson, *Contact
Mechanics*, 1985, §4.3 and §7.1):

    a = 2√(P R*/(π E*)),  p₀ = 2P/(πa),  1/R* = 1/R₁ + 1/R₂,
    1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂,  c = a√(1 − Q/(f_c P)).

P is the applied force, the y reaction of the slave body's prescribed top
edge (per unit length). a is measured from the pressure's second moment,
a² = 4 Σ x_j² λ_j D_jj / Σ λ_j D_jj (Hertz's p ∝ √(1 − x²/a²) has
∫x²p / ∫p = a²/4); c likewise from the stick part of the traction,
q* = f_c λ − |g_t| (Cattaneo: q* ∝ √(1 − x²/c²) on |x| < c, 0 outside).
"""

import numpy as np

from solver import solve_two_body
from tri_elasticity import hertz_cylinders, top_reaction, two_cylinders


def second_moment_half_width(x, weight, D):
    return 2 * np.sqrt((D * weight * x ** 2).sum() / (D * weight).sum())


def test_hertz_two_cylinders():
    """R = 1, 1.5; E = 1, 2; ν = 0.3, 0.25: a within 1 %, p₀ within 3 %,
    ≥ 40 slave nodes in contact (measured: 0.6 %, 1.7 %, 57)."""
    R, materials = (1.0, 1.5), ((1.0, 0.3), (2.0, 0.25))
    problem, K, prescribed = two_cylinders(R, materials, squeeze=0.01)
    result = solve_two_body(problem, tol=1e-10)
    assert result.success
    P = -top_reaction(K, problem, result.u, prescribed)
    a_hertz, p0_hertz = hertz_cylinders(P, R, materials)
    x = problem.nodes[problem.contact_nodes, 0]
    a = second_moment_half_width(x, result.contact_pressure, result.mortar_D)
    assert result.n_contact >= 40
    assert abs(a / a_hertz - 1) <= 0.01
    assert abs(result.contact_pressure.max() / p0_hertz - 1) <= 0.03


def test_cattaneo_mindlin_identical_cylinders():
    """Two identical cylinders (Dundurs β = 0): squeeze, then shift the
    top (projection form, lagged bound, f_c = 0.3): c within 3 % of
    a√(1 − Q/(f_c P)), with Q, P the totals of the last step and a
    measured (measured: 0.2 %, Q/(f_c P) ≈ 0.41)."""
    fc, materials = 0.3, ((1.0, 0.3), (1.0, 0.3))
    problem, _, _ = two_cylinders((1.0, 1.0), materials, squeeze=0.01,
                                  shift=0.002)
    result = solve_two_body(problem, friction=fc, formulation="projection",
                            coulomb="lagged", method="fb", tol=1e-10)
    assert result.success, result.message
    D = result.mortar_D
    lam, g = result.contact_pressure[-1], result.friction_traction[-1]
    P, Q = D @ lam, abs(D @ g)
    assert 0.2 < Q / (fc * P) < 0.8
    x = problem.nodes[problem.contact_nodes, 0]
    a = second_moment_half_width(x, lam, D)
    c = second_moment_half_width(x, fc * lam - np.abs(g), D)
    c_exact = a * np.sqrt(1 - Q / (fc * P))
    assert abs(c / c_exact - 1) <= 0.03
    # and the stick zone's nodes lie within c (to a mesh size, 0.002)
    stick = x[result.stick[-1]]
    assert abs(stick.max() - c_exact) < 0.004 and \
        abs(-stick.min() - c_exact) < 0.004
