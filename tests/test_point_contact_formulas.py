"""The Hertz point-contact helpers of solver.verification against
independent arithmetic: Johnson, *Contact Mechanics* (1985) §4.2 gives
P = (2/3)π a² p0 and a³ = 3PR/(4E*); the first moment is checked by
numerical quadrature of the Hertz pressure, not by the 3πa/16 formula.
Sneddon's exact spherical-profile solution (Int. J. Engng Sci. 3 (1965)
47–57) is checked against Hertz's as a/R → 0 and against quadrature of its
own definitions (the pressure integrates to P; δ is G's zero)."""

import numpy as np
import pytest
from scipy.integrate import quad

from solver.verification import (cattaneo_mindlin_stick_radius,
                                 contact_radius_from_moment,
                                 fit_hertz_profile, hertz_point_contact,
                                 hertz_pressure, sphere_flat_contact,
                                 sphere_flat_pressure)


def test_hertz_point_contact_force_balance():
    a, p0 = hertz_point_contact(P=250.0, R=8.0, E=2.1e5, nu=0.3)
    assert 2.0 / 3.0 * np.pi * a * a * p0 == pytest.approx(250.0, rel=1e-14)
    assert a ** 3 == pytest.approx(3 * 250.0 * 8.0 * (1 - 0.09) / (4 * 2.1e5),
                                   rel=1e-14)


def test_moment_radius_matches_quadrature():
    a, p0 = 0.7, 3.0
    force = quad(lambda r: hertz_pressure(r, a, p0) * 2 * np.pi * r, 0, a)[0]
    moment = quad(lambda r: hertz_pressure(r, a, p0) * 2 * np.pi * r * r,
                  0, a)[0]
    assert contact_radius_from_moment([moment / force], [1.0]) == \
        pytest.approx(a, rel=1e-12)


def test_fit_recovers_exact_profile_and_ignores_zero_pressure():
    a, p0 = 1.3, 42.0
    r = np.linspace(0, 2.0, 57)
    p = hertz_pressure(r, a, p0)
    fa, fp = fit_hertz_profile(r, p, guess=(1.0, 30.0))
    assert (fa, fp) == pytest.approx((a, p0), rel=1e-8)


def test_stick_radius_and_full_sliding():
    assert cattaneo_mindlin_stick_radius(2.0, 0.5, 1.0, 1.0) == \
        pytest.approx(2.0 * 0.5 ** (1 / 3), rel=1e-15)
    with pytest.raises(ValueError, match="full sliding"):
        cattaneo_mindlin_stick_radius(2.0, 1.0, 1.0, 1.0)


def test_sphere_profile_tends_to_hertz():
    """a/a_Hertz − 1 = −(2/15)(a/R)² + O((a/R)⁴): the series of Sneddon's
    P(a) = 4E*a³/(3R) (1 + (2/5)(a/R)²) inverted at fixed P."""
    for P in (1e-3, 1e-1, 35.0):
        a, _ = sphere_flat_contact(P, R=1.0, E=2e5, nu=0.3)
        a_hertz, _ = hertz_point_contact(P, 1.0, 2e5, 0.3)
        e2 = a * a
        assert a / a_hertz - 1 == pytest.approx(-2 / 15 * e2, rel=0.02)


def test_sphere_pressure_integrates_to_force_and_delta_is_edge_condition():
    """∫ p 2πr dr = P by adaptive quadrature (not by Sneddon's closed P);
    δ = t ∫₀ᵗ f'(s)/√(t² − s²) ds at t = a for f' = s/√(R² − s²) (the
    bounded-edge condition G(a) = 0), by quadrature; p vanishes outside a
    and p(0) is within (2/5)(a/R)² of Hertz's p0."""
    R, E, nu, P = 1.0, 2e5, 0.3, 293.0
    a, delta = sphere_flat_contact(P, R, E, nu)
    force = quad(lambda r: sphere_flat_pressure(r, a, R, E, nu)
                 * 2 * np.pi * r, 0, a)[0]
    assert force == pytest.approx(P, rel=1e-10)
    # s = a sin θ removes the end singularity of 1/√(a² − s²).
    edge = a * quad(lambda th: a * np.sin(th)
                    / np.sqrt(R * R - (a * np.sin(th)) ** 2), 0, np.pi / 2)[0]
    assert delta == pytest.approx(edge, rel=1e-12)
    assert sphere_flat_pressure(np.array([a, 1.5 * a]), a, R, E, nu) \
        .tolist() == [0.0, 0.0]
    _, p0 = hertz_point_contact(P, R, E, nu)
    assert 0 < sphere_flat_pressure(0.0, a, R, E, nu) / p0 - 1 < 0.4 * a * a


def test_hertz_fit_on_a_true_sphere_is_off_by_its_model_error():
    """The model error the Hertz-sphere study must stay above: a Hertz
    profile fitted to the exact spherical-profile pressure at a/R ≈ 0.1
    has p0 ≈ +0.22 % and a ≈ −0.12 % off Hertz's values for the same P
    (the a/h 32 target is 0.2 %); at a/R ≈ 0.05 four times less."""
    R, E, nu = 1.0, 2e5, 0.3
    offsets = []
    for P in (293.0, 36.6):
        a, _ = sphere_flat_contact(P, R, E, nu)
        r = a * np.sqrt(np.linspace(0, 1, 2001)[:-1])  # equal areas
        fa, fp = fit_hertz_profile(r, sphere_flat_pressure(r, a, R, E, nu),
                                   hertz_point_contact(P, R, E, nu))
        a_h, p0_h = hertz_point_contact(P, R, E, nu)
        offsets.append((fa / a_h - 1, fp / p0_h - 1))
    (da1, dp1), (da2, dp2) = offsets
    assert 0.0020 < dp1 < 0.0025 and -0.0015 < da1 < -0.0010
    assert dp2 == pytest.approx(dp1 / 4, rel=0.05)
    assert da2 == pytest.approx(da1 / 4, rel=0.05)
