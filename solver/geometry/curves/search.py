r"""The vectorised one-dimensional search behind the gaps (thesis §2.1).

Both gap problems of :mod:`solver.geometry.curves` are one-dimensional in
the obstacle parameter *t*: a scalar function of *t* is evaluated at the
samples of a window (:func:`parameter_window`) for all nodes at once,
every sign change between consecutive samples gives a bracket, all
brackets are refined together by Chandrupatla's root finder
(:func:`scipy.optimize.elementwise.find_root`, to machine precision), and
per node the best root is chosen (:func:`first_per_owner`). Roots closer
together than the sample spacing may be missed (a tangential touch, which
:data:`MIN_COSINE` rejects anyway)."""

import numpy as np
from scipy.optimize.elementwise import find_root

from ...errors import ExpressionError
from ..checks import GapError, as_plane_points, unit_normals
from .parametric import check_interval
from .window import fit_window, start_window

__all__ = ["parameter_window", "DEFAULT_SAMPLES", "MIN_COSINE"]

#: Default number of samples of the curve parameter in the search window.
DEFAULT_SAMPLES = 2049

#: Smallest accepted :math:`|\nu_o \cdot n|` between the obstacle normal at
#: the found point and the body normal; below it the normal line meets the
#: obstacle at a grazing angle (or runs along it) and the gap is meaningless.
MIN_COSINE = 1e-3

# Values of the searched functions handled per chunk (bounds the memory to
# a few tens of MB whatever the number of nodes).
CHUNK = 2 ** 20


def parameter_window(points, curve, window=None, samples=DEFAULT_SAMPLES):
    r"""The interval of the obstacle parameter *t* searched at the contact
    nodes ``points``: ((t0, t1), ends), ``ends`` saying whether t0 / t1 are
    ends of ``curve.t_range``. ``window`` defaults to ``curve.search_interval``
    (the problem file's or ``--search-interval``), intersected with
    ``t_range``; without one it is fitted to the body's extent
    (:func:`~.window.fit_window`). Pass one when a normal line of the body
    meets the obstacle far from the body."""
    points = np.asarray(points, dtype=float)
    t_range = curve.t_range
    if window is None:
        window = getattr(curve, "search_interval", None)
    if window is None:
        if t_range is not None:
            start, fixed = t_range, (True, True)
        else:
            start, fixed = start_window(points, curve), (False, False)
        if not len(points):
            return tuple(start), fixed
        t0, t1 = fit_window(points, curve, tuple(start), fixed,
                            len(_samples(start, samples)))
        ends = (False, False) if t_range is None else \
            (t0 <= t_range[0], t1 >= t_range[1])
        return (float(t0), float(t1)), ends
    try:
        t0, t1 = check_interval("search interval", window)
    except ExpressionError as exc:  # the same check, as a gap error
        raise GapError(str(exc)) from None
    ends = (False, False)
    if t_range is not None:
        ends = (t0 <= t_range[0], t1 >= t_range[1])
        t0, t1 = max(t0, t_range[0]), min(t1, t_range[1])
        if t0 >= t1:
            raise GapError(
                f"search interval {tuple(window)} does not overlap the "
                f"obstacle's t_range {t_range}")
    return (t0, t1), ends


def search_setup(points, vectors, curve, window, samples):
    """Checked points, unit vectors (one per point), the window (t0, t1),
    its parameter samples and whether it reaches the curve's ends."""
    points = as_plane_points(points)
    vectors = unit_normals(vectors, len(points))
    if not len(points):
        return points, vectors, (None, None), None, None
    window, curve_ends = parameter_window(points, curve, window, samples)
    return points, vectors, window, _samples(window, samples), curve_ends


def _samples(window, samples):
    samples = int(samples)
    if samples < 3:
        raise GapError(f"samples must be at least 3, got {samples}")
    return np.linspace(window[0], window[1], samples)


def refine_roots(function, lower, upper, args):
    """Roots of ``function(t, *args)`` in the brackets, all at once.

    Returns the roots and a mask of the brackets that converged."""
    if len(lower) == 0:
        return lower.copy(), np.ones(0, dtype=bool)
    with np.errstate(all="ignore"):
        result = find_root(function, (lower, upper), args=args)
    return np.asarray(result.x), np.asarray(result.success)


def first_per_owner(owner, key, n):
    """Index of the candidate with the smallest ``key`` for every owner.

    Returns an (n,) int array, -1 for owners without candidates."""
    best = np.full(n, -1, dtype=np.int64)
    if len(owner):
        order = np.lexsort((key, owner))
        sorted_owner = owner[order]
        first = np.r_[True, sorted_owner[1:] != sorted_owner[:-1]]
        best[sorted_owner[first]] = order[first]
    return best


def obstacle_normals(curve, t):
    """Unit normals of the obstacle at ``t`` (and the tangent lengths; by
    hypot where the plain norm overflows or underflows, so that a fast
    parametrisation, y = 1e300·t, has a tangent, and the others keep the
    norm's last bit, on which the thesis's degenerate split depends)."""
    tangent = curve.derivative(t)
    with np.errstate(all="ignore"):
        length = np.linalg.norm(tangent, axis=-1)
    odd = ~np.isfinite(length) | (length == 0)
    if np.any(odd):
        length = np.where(odd, np.hypot(tangent[..., 0], tangent[..., 1]),
                          length)
    with np.errstate(all="ignore"):
        normal = np.stack([tangent[..., 1], -tangent[..., 0]], axis=-1) \
            / length[..., None]
    return normal, length
