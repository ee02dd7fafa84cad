r"""Figures of a 3D solve: the contact pressure against the radius, with the
Hertz profile (issue 18, part 7).

For a sphere pressed on a half-space (Hertz 1882; Johnson, *Contact
Mechanics*, 1985, §4.2) the pressure is

.. math::  p(r) = p_0 \sqrt{1 - r^2/a^2} \quad (r \le a),
           \qquad p(r) = 0 \quad (r > a),

with :math:`a = (3PR/(4E^*))^{1/3}`, :math:`p_0 = 3P/(2\pi a^2)`. The figure
draws the nodal pressures against their distance *r* from the axis of the
contact and, given *a* and :math:`p_0`, that curve (:func:`pressure_vs_radius`
from arrays; :func:`plot_pressure_vs_radius` from a problem and its result,
the radius by :func:`contact_radius`; :func:`write_figures3d` for
``--plots``). matplotlib is imported lazily, on the Agg backend (as
:mod:`.figures`).
"""

import os

import numpy as np

from ..verification import hertz_pressure
from .figures import _pyplot, _save

__all__ = ["hertz_pressure", "contact_radius", "pressure_vs_radius",
           "plot_pressure_vs_radius", "write_figures3d"]


def pressure_vs_radius(target, radius, p, a=None, p0=None, title=None):
    """Nodal contact pressure against the radius, with the Hertz curve.

    Parameters
    ----------
    target : matplotlib Axes, path or None
        Axes to draw into, or a path to save a new figure at (PNG), or
        None for a new figure that is not saved.
    radius, p : (m,) arrays
        Distance of each contact node from the contact axis, and its
        pressure (contact force over nodal area).
    a, p0 : float, optional
        Hertz contact radius and peak pressure; both or neither. Given, the
        curve :math:`p_0\\sqrt{1 - r^2/a^2}` is drawn over [0, 1.2 max(a, r)]
        and *a* is marked.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    radius = np.asarray(radius, dtype=float).ravel()
    p = np.asarray(p, dtype=float).ravel()
    if radius.shape != p.shape:
        raise ValueError(f"radius and p differ in length ({radius.size} "
                         f"and {p.size})")
    if (a is None) != (p0 is None):
        raise ValueError("give both a and p0 for the Hertz curve, or neither")
    if target is None or isinstance(target, (str, os.PathLike)):
        plt = _pyplot()
        fig, ax = plt.subplots(figsize=(6.0, 4.0))
        path = target
    else:
        ax, path = target, None
        fig = ax.figure
    ax.plot(radius, p, ".", ms=4, color="C0", label="nodal pressure")
    if a is not None:
        r_max = 1.2 * max(a, radius.max(initial=0.0))
        r = np.linspace(0.0, r_max, 400)
        ax.plot(r, hertz_pressure(r, a, p0), "-", color="C3",
                label=f"Hertz: $p_0\\sqrt{{1 - r^2/a^2}}$, a = {a:.4g}, "
                      f"$p_0$ = {p0:.4g}")
        ax.axvline(a, color="C3", lw=0.6, ls=":")
    ax.set_xlabel("distance from the contact axis r [mm]")
    ax.set_ylabel("contact pressure p [MPa]")
    ax.set_xlim(left=0.0)
    ax.set_ylim(bottom=0.0)
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=8)
    if title:
        ax.set_title(title)
    return _save(fig, path) if path is not None else fig


def contact_radius(points, pressure, center=None, axis=None):
    """Distance of each point from the contact axis.

    Parameters
    ----------
    points : (m, 3) array
        The contact nodes.
    pressure : (m,) array
        Their pressures.
    center : (3,) array, optional
        A point of the axis; default the node of largest pressure (the
        axis of a Hertz-like contact, also in a quarter model, where a
        centroid would miss the axis).
    axis : (3,) array, optional
        Direction of the axis; default the direction in which the loaded
        nodes (p > 0) spread least (the normal of a flat contact patch),
        or z with fewer than three loaded nodes.
    """
    points = np.asarray(points, dtype=float)
    pressure = np.asarray(pressure, dtype=float)
    if center is None:
        center = points[np.argmax(pressure)]
    if axis is None:
        loaded = points[pressure > 0]
        if len(loaded) >= 3:
            axis = np.linalg.svd(loaded - loaded.mean(axis=0))[2][-1]
        else:
            axis = np.array([0.0, 0.0, 1.0])
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    d = points - center
    return np.linalg.norm(d - np.outer(d @ axis, axis), axis=1)


def plot_pressure_vs_radius(problem, result, path=None, a=None, p0=None,
                            center=None, axis=None):
    """:func:`pressure_vs_radius` of a 3D solve: ``result.contact_pressure``
    at ``problem.nodes[problem.contact_nodes]`` against
    :func:`contact_radius` (``center``, ``axis`` passed on)."""
    points = problem.nodes[problem.contact_nodes]
    p = np.asarray(result.contact_pressure, dtype=float)
    return pressure_vs_radius(path, contact_radius(points, p, center, axis),
                              p, a=a, p0=p0, title="contact pressure "
                              "against the distance from the contact axis")


def write_figures3d(folder, problem, result, a=None, p0=None, center=None):
    """The figures of a 3D frictionless solve for ``--plots``: the
    Newton convergence (as in 2D) and the pressure against the radius;
    returns their paths by name (``center``: a point of the contact's
    axis, see :func:`contact_radius`)."""
    from .figures import plot_convergence

    plt = _pyplot()
    paths = {}
    jobs = [("convergence", lambda p: plot_convergence(result, p)),
            ("pressure_radius", lambda p: plot_pressure_vs_radius(
                problem, result, p, a=a, p0=p0, center=center))]
    for name, job in jobs:
        path = os.path.join(folder, f"{name}.png")
        plt.close(job(path))
        paths[name] = path
    return paths
