r"""Figures of a 3D solve: the contact pressure against the radius, with the
Hertz profile (issue 18, part 7).

For a sphere pressed on a half-space (Hertz 1882; Johnson, *Contact
Mechanics*, 1985, §4.2) the pressure is

.. math::  p(r) = p_0 \sqrt{1 - r^2/a^2} \quad (r \le a), \qquad 0 \text{ beyond},

with :math:`a = (3PR/(4E^*))^{1/3}`, :math:`p_0 = 3P/(2\pi a^2)`. The figure
draws the nodal pressures against their distance *r* from the axis of the
contact and, given *a* and :math:`p_0`, that curve. matplotlib is imported
lazily, on the Agg backend (as :mod:`.figures`).
"""

import os

import numpy as np

from .figures import _pyplot, _save

__all__ = ["hertz_pressure", "pressure_vs_radius"]


def hertz_pressure(radius, a, p0):
    r""":math:`p_0\sqrt{1 - r^2/a^2}` for :math:`r < a`, 0 beyond."""
    r = np.asarray(radius, dtype=float)
    return p0 * np.sqrt(np.clip(1.0 - (r / a) ** 2, 0.0, None))


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
