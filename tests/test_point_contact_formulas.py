"""The Hertz point-contact helpers of solver.verification against
independent arithmetic: Johnson, *Contact Mechanics* (1985) §4.2 gives
P = (2/3)π a² p0 and a³ = 3PR/(4E*); the first moment is checked by
numerical quadrature of the Hertz pressure, not by the 3πa/16 formula."""

import numpy as np
import pytest
from scipy.integrate import quad

from solver.verification import (cattaneo_mindlin_stick_radius,
                                 contact_radius_from_moment,
                                 fit_hertz_profile, hertz_point_contact,
                                 hertz_pressure)


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
