r"""Closed-form contact solutions used to verify the solver.

Hertz line contact (K. L. Johnson, *Contact Mechanics*, 1985, §4.3): an
elastic cylinder of radius R pressed with force P per unit length onto a
rigid flat, plane strain, E* = E/(1 − ν²):

.. math::
    a = 2\sqrt{\frac{P R}{\pi E^*}}, \qquad p_0 = \frac{2P}{\pi a},
    \qquad p(x) = p_0 \sqrt{1 − x^2/a^2}.

Cattaneo–Mindlin partial slip (Johnson §7.1): after the normal load, a
tangential load Q < f_c P leaves a central stick zone of half-width

.. math::  c = a \sqrt{1 − Q/(f_c P)}.

It assumes no coupling between normal and tangential tractions, exact for
ν = 0.5 or identical materials; an elastic body on a rigid obstacle with
ν = 0.3 is coupled, so the stick zone is shifted and its size is close to,
not equal to, c.

Hertz point contact (Johnson §4.2): an elastic sphere of radius R pressed
with force P onto a rigid flat, E* = E/(1 − ν²):

.. math::
    a = \left(\frac{3PR}{4E^*}\right)^{1/3}, \qquad p_0 = \frac{3P}{2\pi a^2},
    \qquad p(r) = p_0 \sqrt{1 − r^2/a^2},

and its Cattaneo–Mindlin stick radius (Johnson §7.2) c = a(1 − Q/(f_c P))^{1/3}.
The first moment of the Hertz pressure, ∫ p r dA / ∫ p dA = 3πa/16, gives
a from the nodal contact forces without a fit
(:func:`contact_radius_from_moment`).
"""

import numpy as np

__all__ = ["hertz_line_contact", "hertz_pressure", "fit_semi_ellipse",
           "cattaneo_mindlin_stick_half_width", "contact_resultants",
           "zone_of", "hertz_point_contact", "cattaneo_mindlin_stick_radius",
           "contact_radius_from_moment", "fit_hertz_profile"]


def hertz_line_contact(P, R, E, nu, plane="strain"):
    """(a, p0) of Hertz's cylinder on a rigid flat."""
    E_star = E / (1 - nu ** 2) if plane == "strain" else E
    a = 2.0 * np.sqrt(P * R / (np.pi * E_star))
    return a, 2.0 * P / (np.pi * a)


def hertz_pressure(x, a, p0):
    """p(x) = p0 sqrt(1 − x²/a²), zero outside |x| < a."""
    return p0 * np.sqrt(np.clip(1.0 - (np.asarray(x) / a) ** 2, 0.0, None))


def fit_semi_ellipse(x, p, guess, drop=1):
    """Least-squares (a, p0, centre) of p(x) = p0 sqrt(1 − (x − x0)²/a²).

    ``x``, ``p``: positions and pressures of the nodes in contact, ordered;
    the ``drop`` outermost on each side are left out (their lumped pressure
    is low: their hat functions reach past the contact edge). ``guess`` =
    (a, p0). Returns (a, p0, x0).
    """
    import warnings

    from scipy.optimize import OptimizeWarning, curve_fit

    x, p = np.asarray(x, float), np.asarray(p, float)
    keep = slice(drop, len(x) - drop) if drop else slice(None)

    def model(x, p0, a, x0):
        return hertz_pressure(x - x0, a, p0)

    with warnings.catch_warnings():  # the covariance is not needed
        warnings.simplefilter("ignore", OptimizeWarning)
        (p0, a, x0), _ = curve_fit(model, x[keep], p[keep],
                                   p0=[guess[1], guess[0], 0.0])
    return abs(a), p0, x0


def cattaneo_mindlin_stick_half_width(a, Q, P, friction):
    """c = a sqrt(1 − Q/(f_c P)) for |Q| < f_c P."""
    ratio = abs(Q) / (friction * P)
    if ratio >= 1:
        raise ValueError(f"Q/(f_c P) = {ratio:.3g} >= 1: full sliding")
    return a * np.sqrt(1.0 - ratio)


def contact_resultants(contact_force, friction_force, normal):
    """Total normal and tangential force on the body from nodal λ, t, ν.

    The obstacle acts on the body with −λν (normal) and t γ (friction along
    the tangent γ = (−ν_y, ν_x)). Returns the (x, y) resultant.
    """
    normal = np.asarray(normal, float)
    tangent = np.c_[-normal[:, 1], normal[:, 0]]
    force = (-np.asarray(contact_force)[:, None] * normal
             + np.asarray(friction_force)[:, None] * tangent)
    return np.nansum(force, axis=0)


def zone_of(x, mask):
    """(half-length, centre) of the interval spanned by ``x[mask]``, widened
    by half a node spacing on each side (the zone ends between nodes)."""
    x = np.asarray(x, float)
    inside = np.flatnonzero(mask)
    if len(inside) == 0:
        return 0.0, np.nan
    lo, hi = inside.min(), inside.max()
    left = x[lo] - 0.5 * (x[lo] - x[lo - 1]) if lo > 0 else x[lo]
    right = x[hi] + 0.5 * (x[hi + 1] - x[hi]) if hi + 1 < len(x) else x[hi]
    return 0.5 * (right - left), 0.5 * (right + left)


def hertz_point_contact(P, R, E, nu):
    """(a, p0) of Hertz's sphere on a rigid flat (Johnson §4.2)."""
    E_star = E / (1 - nu ** 2)
    a = (3.0 * P * R / (4.0 * E_star)) ** (1.0 / 3.0)
    return a, 3.0 * P / (2.0 * np.pi * a ** 2)


def cattaneo_mindlin_stick_radius(a, Q, P, friction):
    """c = a (1 − Q/(f_c P))^(1/3) for |Q| < f_c P (Johnson §7.2)."""
    ratio = abs(Q) / (friction * P)
    if ratio >= 1:
        raise ValueError(f"Q/(f_c P) = {ratio:.3g} >= 1: full sliding")
    return a * (1.0 - ratio) ** (1.0 / 3.0)


def contact_radius_from_moment(radius, force):
    """a = 16/(3π) · Σ F_i r_i / Σ F_i: the contact radius whose Hertz
    pressure has the first moment of the nodal contact forces F_i at
    distances r_i from the axis. A symmetric quarter (or half) model gives
    the same ratio as the whole, so its nodes can be used as they are."""
    radius, force = np.asarray(radius, float), np.asarray(force, float)
    return 16.0 / (3.0 * np.pi) * (force @ radius) / force.sum()


def fit_hertz_profile(radius, p, guess):
    """Least-squares (a, p0) of p(r) = p0 sqrt(1 − r²/a²) through nodal
    pressures ``p`` at distances ``radius`` from the axis, over the nodes
    with p > 0 (``guess`` = (a, p0)). The fit's residual uses every node
    with p > 0 and the model's zero outside r < a."""
    from scipy.optimize import least_squares

    radius, p = np.asarray(radius, float), np.asarray(p, float)
    keep = p > 0

    def residual(x):
        return hertz_pressure(radius[keep], x[0], x[1]) - p[keep]

    fit = least_squares(residual, x0=[guess[0], guess[1]],
                        x_scale=[guess[0], guess[1]])
    return abs(fit.x[0]), fit.x[1]
