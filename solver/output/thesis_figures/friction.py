"""Fig. 22-27: the block with friction (part of
:mod:`solver.output.thesis_figures`)."""

import numpy as np

from .common import LENGTH, PRESSURE, save_png, panel_position, pyplot


def tractions_along_contact(problem, result, step=-1, path=None, xlim=None):
    """Fig. 23 (25, 27): contact pressure p = λ/D and friction traction g_t
    along Γc at one load step, the Coulomb bound ±f_c p used in that step,
    stick and slip nodes marked."""
    plt = pyplot()
    y = panel_position(problem)
    p = result.contact_pressure[step]
    g = result.friction_traction[step]
    bound = result.friction_bound[step]
    stick, slip = result.stick[step], result.slip[step]
    fig, ax = plt.subplots(figsize=(9.5, 4.2))
    ax.plot(y, p, "o-", ms=4, label="contact pressure p = λ_i/D_ii")
    ax.plot(y, g, "s-", ms=4, label="friction traction g_t")
    top = 1.3 * max(np.nanmax(p), np.nanmax(np.abs(g)), 1e-300)
    beyond = np.nanmax(bound) > top
    ax.plot(y, bound, "k:", label="±f_c p (bound used in the step)"
            + (", beyond the axes" if beyond else ""))
    ax.plot(y, -bound, "k:")
    if stick.any():
        ax.plot(y[stick], g[stick], "g^", ms=10,
                label=f"stick ({stick.sum()} nodes)")
    if slip.any():
        ax.plot(y[slip], g[slip], "rv", ms=10,
                label=f"slip ({slip.sum()} nodes)")
    ax.axhline(0.0, color="0.5", lw=0.8)
    low = 1.3 * max(np.nanmax(np.abs(g)), min(np.nanmax(bound), top / 1.3),
                    0.2 * top)
    ax.set_ylim(-low, top)
    ax.set_xlabel(f"y on Γc [{LENGTH}]")
    ax.set_ylabel(f"traction [{PRESSURE}]")
    if xlim is not None:
        ax.set_xlim(*xlim)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    k = result.steps_completed if step == -1 else step + 1
    ax.set_title(f"step {k} of {result.steps}, f_c = {result.friction:g} "
                 f"({result.formulation} formulation, {result.coulomb} "
                 "normal force)", fontsize=10)
    return save_png(fig, path)


def fit_y(ax, x, arrays, xlim, margin=0.08):
    """y-limits of ``ax`` fitted to the values whose x lies in ``xlim``."""
    inside = (x >= xlim[0]) & (x <= xlim[1])
    values = np.concatenate([np.asarray(a)[inside] for a in arrays])
    values = values[np.isfinite(values)]
    if len(values):
        lo, hi = values.min(), values.max()
        pad = margin * max(hi - lo, 1e-300)
        ax.set_ylim(lo - pad, hi + pad)


def tangential_displacement(problem, curves, path=None, xlim=None,
                            title=None):
    """Tangential displacement u_t of the nodes of Γc, one curve per entry
    of ``curves`` ({label: (values over Γc, style dict)})."""
    plt = pyplot()
    y = panel_position(problem)
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for label, (values, style) in curves.items():
        ax.plot(y, values, label=label, **style)
    ax.set_xlabel(f"y on Γc [{LENGTH}]")
    ax.set_ylabel(f"tangential displacement u_t [{LENGTH}]")
    if xlim is not None:
        ax.set_xlim(*xlim)
        fit_y(ax, y, [values for values, _ in curves.values()], xlim)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    if title:
        ax.set_title(title, fontsize=10)
    return save_png(fig, path)
