r"""Closed-form contact solutions used to verify the solver (K. L. Johnson,
*Contact Mechanics*, 1985; E* = E/(1 − ν²)).

Hertz line contact (§4.3): an elastic cylinder of radius R pressed with
force P per unit length onto a rigid flat, plane strain:

.. math::
    a = 2\sqrt{\frac{P R}{\pi E^*}}, \qquad p_0 = \frac{2P}{\pi a},
    \qquad p(x) = p_0 \sqrt{1 − x^2/a^2}.

Cattaneo–Mindlin partial slip (§7.1): a tangential load Q < f_c P after
the normal load leaves a central stick zone of half-width
c = a √(1 − Q/(f_c P)); it neglects the coupling of normal and tangential
tractions (exact for ν = 0.5 or identical materials), so on a rigid
obstacle with ν = 0.3 the stick zone is shifted and close to c.

Hertz point contact (§4.2): an elastic sphere of radius R on a rigid flat,

.. math::
    a = \left(\frac{3PR}{4E^*}\right)^{1/3}, \qquad p_0 = \frac{3P}{2\pi a^2},
    \qquad p(r) = p_0 \sqrt{1 − r^2/a^2},

its stick radius (§7.2) c = a(1 − Q/(f_c P))^{1/3}; two elastic spheres
(§4.2) by the same formulas with 1/R* = 1/R₁ + 1/R₂ and 1/E* = (1 − ν₁²)/E₁
+ (1 − ν₂²)/E₂ (:func:`hertz_two_spheres`); the first moment
∫ p r dA / ∫ p dA = 3πa/16 gives a from the nodal contact forces without
a fit (:func:`contact_radius_from_moment`).

Hertz replaces the sphere by the paraboloid r²/(2R). The exact half-space
solution for the spherical profile R − √(R² − r²) (I. N. Sneddon, Int. J.
Engng Sci. 3 (1965) 47–57, with G(t) = δ − t ∫₀ᵗ f'(s)/√(t² − s²) ds):

.. math::
    δ = \frac{a}{2}\ln\frac{R + a}{R − a}, \qquad
    P = \frac{E^*}{2}\left[(a^2 + R^2)\ln\frac{R + a}{R − a}
        − 2aR\right] = \frac{4E^* a^3}{3R}\Bigl(1 + \frac{2}{5}
        \frac{a^2}{R^2} + …\Bigr),

    p(r) = \frac{E^*}{π} \int_r^a \frac{h(t)\,dt}{\sqrt{t^2 − r^2}},
    \qquad h(t) = −G'(t) = \frac12\ln\frac{R + t}{R − t}
    + \frac{tR}{R^2 − t^2}

(:func:`sphere_flat_contact`, :func:`sphere_flat_pressure`): for a given P
its contact radius is Hertz's times 1 − (2/15)(a/R)²."""

import functools

import numpy as np

__all__ = ["hertz_line_contact", "hertz_pressure", "fit_semi_ellipse",
           "cattaneo_mindlin_stick_half_width",
           "zone_of", "hertz_point_contact", "hertz_two_spheres",
           "cattaneo_mindlin_stick_radius",
           "contact_radius_from_moment", "fit_hertz_profile",
           "sphere_flat_contact", "sphere_flat_pressure"]


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
    (a, p0). Returns (a, p0, x0)."""
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


def hertz_two_spheres(P, radii, materials):
    """(a, p0) of Hertz's two spheres of ``radii`` (R₁, R₂) and
    ``materials`` ((E₁, ν₁), (E₂, ν₂)) pressed by P (Johnson §4.2)."""
    R = 1.0 / sum(1.0 / float(r) for r in radii)
    E_star = 1.0 / sum((1 - nu ** 2) / E for E, nu in materials)
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


#: Pressures below this fraction of the largest are round-off, not contact
#: (:func:`fit_hertz_profile`).
FIT_FLOOR = 1e-8


def fit_hertz_profile(radius, p, guess):
    """Least-squares (a, p0) of p(r) = p0 sqrt(1 − r²/a²) through nodal
    pressures ``p`` at distances ``radius`` from the axis, over the nodes
    in contact (``guess`` = (a, p0)). The fit's residual uses every such
    node and the model's zero outside r < a. A node counts as in contact
    when its pressure exceeds :data:`FIT_FLOOR` of the largest: a
    pressure recovered from a residual (the mortar's λ = z/D off the
    active set) is zero only to round-off, and round-off of either sign
    must not decide which nodes the fit takes."""
    from scipy.optimize import least_squares

    radius, p = np.asarray(radius, float), np.asarray(p, float)
    keep = p > FIT_FLOOR * p.max()

    def residual(x):
        return hertz_pressure(radius[keep], x[0], x[1]) - p[keep]

    fit = least_squares(residual, x0=[guess[0], guess[1]],
                        x_scale=[guess[0], guess[1]])
    return abs(fit.x[0]), fit.x[1]


def _sphere_force(a, R, E_star):
    """Sneddon's P(a) of a rigid-flat contact of a sphere (module doc)."""
    return 0.5 * E_star * ((a * a + R * R) * np.log((R + a) / (R - a))
                           - 2.0 * a * R)


def sphere_flat_contact(P, R, E, nu):
    """(a, δ) of an elastic half-space with the exact spherical profile
    R − √(R² − r²), not Hertz's paraboloid, pressed with P onto a rigid
    flat (Sneddon 1965; module doc). a is the root of P(a) = P in
    (0, R), bracketed by Hertz's a, which is larger."""
    from scipy.optimize import brentq

    E_star = E / (1 - nu ** 2)
    a_hertz, _ = hertz_point_contact(P, R, E, nu)
    if not 0 < P or not a_hertz < R:
        raise ValueError(f"P = {P:g} gives no contact radius below R")
    a = brentq(lambda x: _sphere_force(x, R, E_star) - P, 0.5 * a_hertz,
               a_hertz, xtol=1e-15 * a_hertz, rtol=4 * np.finfo(float).eps)
    return a, 0.5 * a * np.log((R + a) / (R - a))


@functools.lru_cache(maxsize=4)
def _gauss_legendre(order):
    return np.polynomial.legendre.leggauss(order)


def sphere_flat_pressure(r, a, R, E, nu, order=64):
    """Sneddon's p(r) for the spherical profile at contact radius ``a``
    (module doc), zero for r ≥ a. With t² = r² + s² the integral is
    E*/π ∫₀^√(a² − r²) h(t)/t ds, smooth: Gauss–Legendre of ``order``
    points, vectorised over r."""
    E_star = E / (1 - nu ** 2)
    r = np.asarray(r, float)
    x, w = _gauss_legendre(order)
    top = np.sqrt(np.clip(a * a - r * r, 0.0, None))[..., None]
    s = 0.5 * top * (x + 1.0)
    t = np.sqrt(r[..., None] ** 2 + s * s)
    with np.errstate(divide="ignore", invalid="ignore"):
        h = (0.5 * np.log((R + t) / (R - t)) + t * R / (R * R - t * t)) / t
        h = np.where(t > 0, h, 2.0 / R)  # the limit t → 0
    return E_star / np.pi * 0.5 * top[..., 0] * (h @ w)
