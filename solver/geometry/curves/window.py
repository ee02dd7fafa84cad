r"""The interval of the obstacle parameter *t* searched for the gaps.

The window must contain every root that matters and be small enough for
the samples to separate the roots: it follows the **geometry**, not the
speed of the parametrisation. With *c* the centre of the contact nodes
:math:`B_i`, ρ their largest distance from *c* and :math:`\Gamma_o(t_j)`
the sampled obstacle point nearest to *c*, the nearest obstacle point of
any :math:`B_i` lies in the disc about *c* of radius :math:`\rho + d`,
:math:`d = \max_i |B_i - \Gamma_o(t_j)|`. The window is grown (×4 at a
time) until both its ends lie outside the disc of twice that radius
(admitting intersections along the body's normals), then shrunk to the
samples inside it and resampled until it no longer shrinks; a curve that
never leaves the disc keeps the starting window."""

import numpy as np

from ...errors import GeometryError

__all__ = ["GROWTH_STEPS", "fit_window", "start_window"]

#: Most growth steps (×4 each, so up to 4**40 times the starting window).
GROWTH_STEPS = 40

#: Most shrinking steps.
_SHRINK_STEPS = 60

#: More separate runs of samples inside the disc than this in a grown
#: window: the curve oscillates (periodic), growing is undone.
_MAX_RUNS = 8


class _Disc:
    """The disc of the body's extent (module docstring)."""

    def __init__(self, points):
        lo, hi = points.min(axis=0), points.max(axis=0)
        self.centre = (lo + hi) / 2
        self.rho = float(np.max(np.hypot(*(points - self.centre).T)))
        self.points = points
        self.radius = np.inf

    def distance(self, curve_points):
        d = curve_points - self.centre
        with np.errstate(all="ignore"):
            r = np.hypot(d[..., 0], d[..., 1])
        return np.where(np.isfinite(r), r, np.inf)

    def update(self, curve_points):
        """Shrink the radius from the sample nearest to the centre."""
        r = self.distance(curve_points)
        j = int(np.argmin(r))
        if np.isfinite(r[j]):
            d = self.points - curve_points[j]
            far = float(np.max(np.hypot(d[:, 0], d[:, 1])))
            self.radius = min(self.radius, 2 * (self.rho + far) + 1e-300)
        return r


def start_window(points, curve):
    """A first window about t = 0: :math:`[-L, L]`,
    :math:`L = 2\\max_i|B_i - \\Gamma_o(0)| + 1` (exact for graphs
    parametrised by a coordinate; :func:`fit_window` corrects it)."""
    origin = curve.point(np.array(0.0))
    if not np.isfinite(origin).all():
        raise GeometryError(
            f"obstacle {curve!r} is not finite at t = 0: give it a t_range "
            "or a search interval (obstacle_search_interval, "
            "--search-interval)")
    d = points - origin
    half = 2.0 * float(np.max(np.hypot(d[:, 0], d[:, 1]))) + 1.0
    return (-half, half)


def _inside(curve, disc, window, samples):
    ts = np.linspace(window[0], window[1], samples)
    with np.errstate(all="ignore"):
        pts = curve.point(ts)
    r = disc.update(pts)
    return ts, r <= disc.radius


def _grow(curve, disc, window, fixed, samples):
    """Grow the free ends while they lie inside the disc."""
    _inside(curve, disc, window, samples)  # a first radius
    a, b = window
    middle = (a + b) / 2
    for _ in range(GROWTH_STEPS):
        ends = np.array([a, b])
        with np.errstate(all="ignore"):
            r = disc.distance(curve.point(ends))
        grow = (r <= disc.radius) & ~np.asarray(fixed)
        if not grow.any():
            return (a, b), True
        if grow[0]:
            a = middle - 4 * (middle - a)
        if grow[1]:
            b = middle + 4 * (b - middle)
        _inside(curve, disc, (a, b), samples)
    return window, False  # never leaves the disc: closed or periodic


def _shrink(curve, disc, window, samples):
    a, b = window
    for _ in range(_SHRINK_STEPS):
        ts, inside = _inside(curve, disc, (a, b), samples)
        where = np.flatnonzero(inside)
        if not len(where):
            break
        lo, hi = ts[max(where[0] - 1, 0)], ts[min(where[-1] + 1, samples - 1)]
        shrunk = (hi - lo) < 0.5 * (b - a)
        a, b = lo, hi
        if not shrunk:
            break
    runs = np.count_nonzero(np.diff(inside.astype(np.int8)) == 1)
    return (a, b), runs


def fit_window(points, curve, window, fixed, samples):
    """(t0, t1): the starting ``window`` (``t_range``, or
    :func:`start_window`) grown and shrunk to the part of the obstacle
    ``curve`` near the contact nodes ``points`` (module docstring), with
    ``samples`` per window; ``fixed`` (bool, bool): the ends that are true
    ends of the obstacle (never grown past)."""
    disc = _Disc(points)
    grown, left = _grow(curve, disc, window, fixed, samples)
    fitted, runs = _shrink(curve, disc, grown, samples)
    if grown != tuple(window) and runs > _MAX_RUNS:  # aliased oscillation
        fitted, runs = _shrink(curve, disc, window, samples)
    return fitted
