r"""Figures of a 3D solve: the contact pressure against the radius, with the
Hertz profile p(r) = p_0 √(1 − r²/a²) for r ≤ a, 0 beyond (a and p_0 of
:func:`solver.verification.hertz_point_contact`). Which curve, which axis
and why is decided in one place, :func:`.hertz_reference.hertz_reference`,
from the problem's symmetry planes and initial gap."""

import os

import numpy as np

from ..verification import hertz_pressure
from .figures import pyplot, save_png, carries_load, zoom_window
from .hertz_reference import HertzReference, hertz_reference

__all__ = ["hertz_pressure", "contact_radius", "pressure_vs_radius",
           "hertz_reference", "HertzReference", "plot_pressure_vs_radius",
           "write_figures3d"]


def pressure_vs_radius(target, radius, p, a=None, p0=None, title=None,
                       xlabel="distance from the contact axis r [mm]",
                       zoom=False):
    """The Figure of the nodal contact pressures ``p`` against their
    distance ``radius`` from the contact axis, drawn into ``target`` (Axes, a
    path for a new figure, or None). Given Hertz's ``a`` and ``p0``, the curve
    :math:`p_0\\sqrt{1 - r^2/a^2}`, *a* marked; ``xlabel`` says what the
    radius is measured from; with ``zoom`` a new figure shows the loaded part
    above all radii (:func:`.figures.zoom_window`)."""
    radius = np.asarray(radius, dtype=float).ravel()
    p = np.asarray(p, dtype=float).ravel()
    if radius.shape != p.shape:
        raise ValueError(f"radius and p differ in length ({radius.size} "
                         f"and {p.size})")
    if (a is None) != (p0 is None):
        raise ValueError("give both a and p0 for the Hertz curve, or neither")
    window = None
    if target is None or isinstance(target, (str, os.PathLike)):
        plt = pyplot()
        path = target
        loaded = carries_load(p)
        if a is not None:
            loaded = loaded | (radius <= a)
        if zoom:
            window = zoom_window(np.r_[0.0, radius], np.r_[True, loaded])
        if window is None:
            fig, ax = plt.subplots(figsize=(6.5, 4.2), layout="constrained")
            axes = (ax,)
        else:
            fig, axes = plt.subplots(
                2, 1, figsize=(6.5, 5.8), layout="constrained",
                gridspec_kw=dict(height_ratios=(3, 1.1)))
            ax = axes[0]
    else:
        ax, path = target, None
        axes = (ax,)
        fig = ax.figure
    for target_ax in axes:
        small = target_ax is not ax
        target_ax.plot(radius, p, ".", ms=3 if small else 4, color="C0",
                       label="nodal pressure")
        if a is not None:
            r_max = 1.2 * max(a, radius.max(initial=0.0))
            r = np.linspace(0.0, r_max, 600)
            target_ax.plot(r, hertz_pressure(r, a, p0), "-", color="C3",
                           label=f"Hertz: $p_0\\sqrt{{1 - r^2/a^2}}$, a = "
                                 f"{a:.4g} mm, $p_0$ = {p0:.4g} MPa")
            target_ax.axvline(a, color="C3", lw=0.6, ls=":")
        target_ax.set_xlim(left=0.0)
        # headroom: a uniform pressure would sit on the frame otherwise
        target_ax.set_ylim(0.0, max(target_ax.get_ylim()[1],
                                    1.08 * p.max(initial=0.0)))
        target_ax.grid(True, lw=0.3)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("contact pressure p [MPa]")
    ax.legend(fontsize=8)
    if window is not None:
        whole = axes[1]
        ax.set_xlim(0.0, window[1])
        whole.axvspan(0.0, window[1], color="C1", alpha=0.15, lw=0)
        whole.set_xlabel(xlabel)
        whole.set_ylabel("p [MPa]", fontsize=8)
        whole.set_title("all contact nodes; shaded: the part zoomed above",
                        fontsize=9)
    if title:
        ax.set_title(title, fontsize=10)
    return save_png(fig, path) if path is not None else fig


def contact_radius(points, pressure, center=None, axis=None):
    """Distance of each contact node ``points`` (m, 3) from the contact
    axis through ``center`` (default the node of largest ``pressure``: the
    axis of a Hertz-like contact, also in a quarter model, where a
    centroid would miss it) along ``axis`` (default the direction in which
    the loaded nodes spread least, or z with fewer than three)."""
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


def plot_pressure_vs_radius(problem, result, path=None, reference=None):
    """:func:`pressure_vs_radius` of a 3D solve, against the distance from
    the contact axis of ``reference`` (default
    :func:`.hertz_reference.hertz_reference` of the solve) with its Hertz
    curve if it has one, zoomed onto the contact zone; without an axis the
    radius is measured from the node of largest pressure (the label says so).
    The title carries ``reference.note``."""
    if reference is None:
        reference = hertz_reference(problem, result)
    points = problem.nodes[problem.contact_nodes]
    p = np.nan_to_num(np.asarray(result.contact_pressure, dtype=float))
    if reference.center is not None:
        radius = contact_radius(points, p, reference.center, reference.axis)
        xlabel = "distance from the contact axis r [mm]"
    else:
        radius = contact_radius(points, p)
        xlabel = "distance from the node of largest pressure r [mm]"
    return pressure_vs_radius(
        path, radius, p, a=reference.a, p0=reference.p0, xlabel=xlabel,
        zoom=True, title=f"contact pressure against r\n{reference.note}")


def write_figures3d(folder, problem, result, reference=None):
    """The figures of a 3D frictionless solve for ``--plots``: the Newton
    convergence and the pressure against the radius (``reference``, default
    decided from the problem and the solve); their paths by name."""
    from .figures import plot_convergence, write_jobs

    jobs = [("convergence", lambda p: plot_convergence(result, p)),
            ("pressure_radius", lambda p: plot_pressure_vs_radius(
                problem, result, p, reference=reference))]
    return write_jobs(folder, jobs)
