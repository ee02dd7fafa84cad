r"""Closest points and ray intersections on a parametric surface
:math:`c(s, t)`, vectorised over all query points at once.

**Closest point** (3D §2.1.1): minimise :math:`\varphi(u) = \tfrac12
|c(u) - x|^2` over the parameter box :math:`u = (s, t) \in [l, h]`, each
point from its nearest grid sample (restarted from the next nearest,
:data:`CANDIDATES`, if it ends on an edge of the box without a foot
point there), by safeguarded projected Newton (Bertsekas, SIAM J. Control
Optim. 20 (1982) 221-246): :math:`g = J^T r`, :math:`H = J^T J + \sum_k
r_k \nabla^2 c_k` (Gauss-Newton :math:`J^T J` where *H* is not positive
definite); parameters at a bound with the gradient pushing outward held
fixed; the step projected onto the box and halved until :math:`\varphi`
decreases (Armijo, :math:`10^{-4}`); converged when :math:`|g_i| \le
|c_i|\,(10^{-12}|r| + 16\epsilon L)` for the free parameters (a floor at
the rounding level of coordinates of size *L*).

**Ray intersection** (§2.1.2): Newton on :math:`c(s,t) - (x + \tau d) =
0` in :math:`(s, t, \tau)`, damped on :math:`\tfrac12|c - x - \tau d|^2`,
from the closest point, which makes τ the intersection nearest to *x* in
all but contrived cases."""

import numpy as np
from scipy.spatial import cKDTree

from ..checks import COORDINATE_LIMIT
from ..curves import GapError

__all__ = ["DEFAULT_SAMPLES", "grid_start", "local_grid_start",
           "closest_points", "ray_hits"]

#: Samples per parameter of the start grid over a shared parameter box.
DEFAULT_SAMPLES = 65

#: Start samples kept per point, nearest first: a run that ends on an edge
#: of the box without a foot point there (the wrong basin) restarts from
#: the next one farther than two grid spacings away.
CANDIDATES = 12

_EPS = np.finfo(float).eps
_MAX_ITER = 60
_MAX_HALVINGS = 40


def grid_start(surface_map, points, lower, upper, samples=DEFAULT_SAMPLES,
               k=CANDIDATES):
    """The ``k`` grid points of the box [lower, upper] (``samples`` per
    parameter) nearest to each point, nearest first: starts (m, k, 2); no
    start where the surface is not finite or beyond the coordinate limit."""
    s, t = (np.linspace(lower[i], upper[i], samples) for i in (0, 1))
    S, T = (a.ravel() for a in np.meshgrid(s, t, indexing="ij"))
    cloud = surface_map.point(S, T)
    with np.errstate(invalid="ignore"):
        good = (np.abs(cloud) <= COORDINATE_LIMIT).all(axis=1)  # finite too
    if not good.any():
        raise GapError("the obstacle surface is not finite, or out of the "
                       f"supported range |x|, |y|, |z| <= "
                       f"{COORDINATE_LIMIT:g}, at every sample of its "
                       "parameter box")
    _, nearest = cKDTree(cloud[good]).query(points, k=min(k, good.sum()))
    nearest = nearest.reshape(len(points), -1)
    nearest = np.pad(nearest, ((0, 0), (0, k - nearest.shape[1])), "edge")
    return np.stack([S[good][nearest], T[good][nearest]], axis=-1)


def local_grid_start(surface_map, points, lower, upper, samples=5,
                     k=CANDIDATES):
    """As :func:`grid_start` for one box per point (lower, upper: (m, 2))."""
    w = np.linspace(0.0, 1.0, samples)
    a, b = (g.ravel() for g in np.meshgrid(w, w, indexing="ij"))
    S = lower[:, :1] + a * (upper[:, :1] - lower[:, :1])
    T = lower[:, 1:] + b * (upper[:, 1:] - lower[:, 1:])
    d2 = np.sum((surface_map.point(S, T) - points[:, None, :]) ** 2, -1)
    order = np.argsort(np.where(np.isfinite(d2), d2, np.inf), axis=1)[:, :k]
    rows = np.arange(len(points))[:, None]
    return np.stack([S[rows, order], T[rows, order]], axis=-1)


def _phi(surface_map, u, x):
    r = surface_map.point(u[:, 0], u[:, 1]) - x
    value = 0.5 * np.sum(r * r, axis=1)
    return np.where(np.isfinite(value), value, np.inf)


def _newton_direction(surface_map, u, x, lower, upper):
    """Projected Newton direction, projected gradient test data."""
    s, t = u[:, 0], u[:, 1]
    c = surface_map.point(s, t)
    cs, ct = surface_map.first(s, t)
    css, cst, ctt = surface_map.second(s, t)
    r = c - x
    dot = lambda a, b: np.sum(a * b, axis=1)  # noqa: E731
    g = np.c_[dot(r, cs), dot(r, ct)]
    G = np.stack([np.c_[dot(cs, cs), dot(cs, ct)],
                  np.c_[dot(cs, ct), dot(ct, ct)]], axis=1)
    H = G + np.stack([np.c_[dot(r, css), dot(r, cst)],
                      np.c_[dot(r, cst), dot(r, ctt)]], axis=1)
    fixed = ((u <= lower) & (g > 0)) | ((u >= upper) & (g < 0))
    pd = (H[:, 0, 0] > 0) & (H[:, 0, 0] * H[:, 1, 1] - H[:, 0, 1] ** 2 > 0)
    one = fixed.any(axis=1)  # 1D: only the diagonal entry matters
    pd |= one & (np.where(fixed[:, 0], H[:, 1, 1], H[:, 0, 0]) > 0)
    M = np.where(pd[:, None, None], H, G)
    M[fixed[:, 0], 0, 1] = M[fixed[:, 0], 1, 0] = 0.0
    M[fixed[:, 1], 0, 1] = M[fixed[:, 1], 1, 0] = 0.0
    M[fixed[:, 0], 0, 0] = M[fixed[:, 1], 1, 1] = 1.0
    rhs = np.where(fixed, 0.0, -g)
    det = M[:, 0, 0] * M[:, 1, 1] - M[:, 0, 1] ** 2
    with np.errstate(all="ignore"):
        d = np.c_[M[:, 1, 1] * rhs[:, 0] - M[:, 0, 1] * rhs[:, 1],
                  M[:, 0, 0] * rhs[:, 1] - M[:, 0, 1] * rhs[:, 0]]
        d /= det[:, None]
    bad = ~np.isfinite(d).all(axis=1)
    d[bad] = rhs[bad]  # singular: steepest descent
    scale = np.maximum(np.abs(x).max(axis=1), np.abs(c).max(axis=1))[:, None]
    r_norm = np.linalg.norm(r, axis=1)[:, None]
    lengths = np.c_[np.linalg.norm(cs, axis=1), np.linalg.norm(ct, axis=1)]
    free_g = np.abs(np.where(fixed, 0.0, g))
    tight = free_g <= lengths * (1e-12 * r_norm + 16 * _EPS * scale)
    loose = free_g <= lengths * np.sqrt(_EPS) * (r_norm + scale)
    return d, g, tight.all(axis=1), loose.all(axis=1)


def closest_points(surface_map, points, lower, upper, start):
    """Safeguarded projected Newton for the closest points (module
    docstring) of ``points`` (m, 3) on ``surface_map`` from the ``start``
    parameters (m, 2) in the box [``lower``, ``upper``] (shared or per
    point): (u (m, 2), converged (m,) bool)."""
    m = len(points)
    lower = np.broadcast_to(np.asarray(lower, float), (m, 2))
    upper = np.broadcast_to(np.asarray(upper, float), (m, 2))
    u = np.clip(np.asarray(start, float), lower, upper)
    converged = np.zeros(m, bool)
    todo = np.arange(m)
    for _ in range(_MAX_ITER):
        if not len(todo):
            break
        x, lo, hi = points[todo], lower[todo], upper[todo]
        d, g, done, loose = _newton_direction(surface_map, u[todo], x, lo, hi)
        converged[todo[done]] = True
        keep = ~done
        todo, x, lo, hi, d, g, loose = (a[keep] for a in
                                        (todo, x, lo, hi, d, g, loose))
        phi0 = _phi(surface_map, u[todo], x)
        # φ is known to within its rounding, about ε |r| |x|: a step whose
        # predicted decrease is below that (the last Newton steps) passes
        slack = 32 * _EPS * (phi0 + np.sqrt(2 * phi0)
                             * np.abs(x).max(axis=1))
        alpha = np.ones(len(todo))
        searching = np.ones(len(todo), bool)
        new = u[todo].copy()
        for _ in range(_MAX_HALVINGS):
            if not searching.any():
                break
            i = np.flatnonzero(searching)
            trial = np.clip(u[todo[i]] + alpha[i, None] * d[i], lo[i], hi[i])
            decrease = np.sum(g[i] * (trial - u[todo[i]]), axis=1)
            ok = _phi(surface_map, trial, x[i]) \
                <= phi0[i] + 1e-4 * decrease + slack[i]
            ok &= (trial != u[todo[i]]).any(axis=1)
            new[i[ok]] = trial[ok]
            searching[i[ok]] = False
            alpha[i[~ok]] *= 0.5
        # no decrease possible: at the rounding level, accept if nearly
        # stationary; otherwise the node has failed
        stalled = searching
        converged[todo[stalled & loose]] = True
        u[todo[~stalled]] = new[~stalled]
        todo = todo[~stalled]
    return u, converged


def ray_hits(surface_map, points, directions, start, lower, upper,
             min_cosine=1e-3):
    r"""Intersections :math:`c(s,t) = x + \tau d` by damped Newton: (tau,
    u, ok), ``ok`` False where Newton reached no zero or the ray grazes the
    surface (:math:`|n\cdot d| <` ``min_cosine``)."""
    m = len(points)
    lower = np.broadcast_to(np.asarray(lower, float), (m, 2))
    upper = np.broadcast_to(np.asarray(upper, float), (m, 2))
    u = np.clip(np.asarray(start, float), lower, upper)
    tau = np.sum((surface_map.point(u[:, 0], u[:, 1]) - points)
                 * directions, axis=1)

    def residual(u, tau, x, d):
        return surface_map.point(u[:, 0], u[:, 1]) - x - tau[:, None] * d

    scale = np.abs(points).max(axis=1) + np.abs(tau)
    ok = np.zeros(m, bool)
    todo = np.arange(m)
    for _ in range(_MAX_ITER):
        x, d = points[todo], directions[todo]
        R = residual(u[todo], tau[todo], x, d)
        norm = np.linalg.norm(R, axis=1)
        done = norm <= 64 * _EPS * (scale[todo] + np.abs(tau[todo]))
        ok[todo[done]] = True
        todo, x, d, R, norm = (a[~done] for a in (todo, x, d, R, norm))
        if not len(todo):
            break
        cs, ct = surface_map.first(u[todo, 0], u[todo, 1])
        cross = np.cross(ct, -d)
        det = np.sum(cs * cross, axis=1)
        with np.errstate(all="ignore"):  # Cramer's rule for [cs ct -d] y = -R
            step = np.c_[np.sum(-R * cross, axis=1),
                         np.sum(cs * np.cross(-R, -d), axis=1),
                         np.sum(cs * np.cross(ct, -R), axis=1)] / det[:, None]
        alpha = np.ones(len(todo))
        moved = np.zeros(len(todo), bool)
        for _ in range(_MAX_HALVINGS):
            i = np.flatnonzero(~moved & np.isfinite(step).all(axis=1))
            if not len(i):
                break
            uu = np.clip(u[todo[i]] + alpha[i, None] * step[i, :2],
                         lower[todo[i]], upper[todo[i]])
            tt = tau[todo[i]] + alpha[i] * step[i, 2]
            better = np.linalg.norm(residual(uu, tt, x[i], d[i]), axis=1) \
                < (1 - 1e-4 * alpha[i]) * norm[i]
            j = i[better]
            u[todo[j]], tau[todo[j]] = uu[better], tt[better]
            moved[j] = True
            alpha[i[~better]] *= 0.5
        todo = todo[moved]
    normal, _ = surface_map.normal(u[:, 0], u[:, 1])
    with np.errstate(invalid="ignore"):
        ok &= np.abs(np.sum(normal * directions, axis=1)) >= min_cosine
    return tau, u, ok
