"""Figures of a solve, in the manner of the thesis's Fig. 4-8 and 18-27.

matplotlib is imported here only (Agg backend, never ``plt.show()``); each
function returns the Figure and, given ``path``, saves it as PNG. Axes are
labelled in one convention, :data:`UNITS` (mm, MPa, N per mm of
thickness): the solver is unit-free, and the labels hold when K, f and M
were built in those units, as ``sfepy_problems/`` does."""

import numpy as np

from ..geometry.cells import cell_edges
from ..geometry.mesh import boundary_edges
from .scene import moved_obstacle, obstacle_in_box, piece_joins, with_breaks

__all__ = ["UNITS", "draw_mesh", "magnification", "carries_load", "zoom_window",
           "zoomed_axes", "finish_overview", "plot_deformed",
           "plot_displacement_arrows", "step_halvings", "plot_convergence",
           "plot_contact_pressure", "write_jobs", "write_figures"]


#: The unit convention of every axis label (stated once, here).
UNITS = ("lengths in mm, forces in N and pressures in MPa = N/mm², "
         "plane strain per mm of thickness")

#: Fraction of the body's size that the largest magnified displacement
#: should appear as (:func:`magnification`).
TARGET_FRACTION = 0.12



def draw_mesh(ax, xy, cells, **style):
    """The edges of the 2D cells (triangles or quadrilaterals) at the
    positions ``xy`` on ``ax``, as one LineCollection (``style``: its
    color, lw, ...)."""
    from matplotlib.collections import LineCollection

    edges = cell_edges(cells, 2)
    ax.add_collection(LineCollection(np.asarray(xy)[edges], **style))
    ax.autoscale_view()

def pyplot():
    """pyplot, on the Agg backend unless the caller (a notebook) already
    chose one by importing pyplot itself."""
    import sys

    import matplotlib

    if "matplotlib.pyplot" not in sys.modules:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_png(fig, path, dpi=120):
    """Save ``fig`` as PNG at ``path`` (atomically), if a path is given."""
    if path is not None:
        from .folder import atomic_path

        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=dpi, bbox_inches="tight", format="png")
    return fig


def legend_outside(ax, where="below", **kwargs):
    """A legend next to the axes, never over the data: ``"below"`` (under
    the x label) or ``"right"``."""
    kwargs.setdefault("fontsize", 8)
    if where == "right":
        return ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0),
                         borderaxespad=0.0, **kwargs)
    return ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16),
                     borderaxespad=0.0, **kwargs)


def arc_length(problem):
    """Position of each contact node along Γc (mm), or its index for a
    discrete problem; returns (positions, axis label). A Γc of separate
    pieces is measured along its edges only: each piece starts where the
    previous one ended."""
    if problem.kind == "mesh":
        xy = problem.nodes[problem.contact_nodes]
        steps = np.hypot(*np.diff(xy, axis=0).T)
        steps[piece_joins(problem)] = 0.0  # separate pieces: no edge between
        arc = np.r_[0, np.cumsum(steps)]
        return arc, "arc length along Γc from its first node [mm]"
    return np.arange(problem.n_contact), "contact node"


def zoom_window(x, loaded, fraction=0.5):
    """Interval of ``x`` to zoom a plot into: from the last position before
    the ``loaded`` ones to the first after them, padded by 10 %; None when
    nothing is loaded or it covers ``fraction`` or more of the range."""
    x = np.asarray(x, float)
    loaded = np.asarray(loaded, bool) & np.isfinite(x)
    if not loaded.any() or len(x) < 3:
        return None
    lo, hi = x[loaded].min(), x[loaded].max()
    before, after = x[x < lo], x[x > hi]
    lo = before.max() if len(before) else lo
    hi = after.min() if len(after) else hi
    whole = np.ptp(x[np.isfinite(x)])
    pad = 0.1 * max(hi - lo, 1e-3 * whole)
    lo, hi = lo - pad, hi + pad
    if hi - lo >= fraction * whole:
        return None
    return lo, hi


def magnification(problem, displacement, fraction=TARGET_FRACTION):
    """Factor for drawing ``displacement``: a 1-2-5 number (…, 2, 5, 10, 20,
    …) that makes the largest |u| appear as about ``fraction`` of the body's
    size (the larger side of its bounding box), between 0.6 and 1.6 times
    that; never below 1 (large displacements are drawn as they are)."""
    size = np.ptp(problem.nodes, axis=0).max()
    largest = np.hypot(*np.asarray(displacement, dtype=float).T).max()
    if not largest > 0:
        return 1.0
    target = fraction * size / largest
    if target <= 1:
        return 1.0
    decade = int(np.floor(np.log10(target)))
    candidates = [m * 10.0 ** e for e in (decade, decade + 1)
                  for m in (1, 2, 5)]
    return min(candidates, key=lambda c: abs(np.log(c / target)))


def plot_deformed(problem, result, scale=None, path=None, title=None):
    """Deformed body (thesis Fig. 4, left) and, beside it, Γc at true scale.

    Left: the body at X + scale·u (``scale`` default :func:`magnification`)
    over the faint undeformed outline, contact nodes starred, and the obstacle
    dotted at its true position and solid moved with the magnified boundary
    (:func:`moved_obstacle`: every gap keeps its true length). Right: Γc
    before and after deformation at scale 1 with the obstacle. ``result``
    needs ``displacement`` (nodal) and ``in_contact``."""
    from matplotlib.collections import LineCollection

    plt = pyplot()
    u = np.asarray(result.displacement, dtype=float)
    if scale is None:
        scale = magnification(problem, u)
    nodes = problem.nodes
    largest = np.hypot(*u.T).max()
    xy = nodes + scale * u
    fig = plt.figure(figsize=(10, 7.5), layout="constrained")
    left, right = fig.subfigures(1, 2, width_ratios=(1.15, 1), wspace=0.02)
    ax, zoom = left.subplots(), right.subplots()
    outline = boundary_edges(problem.cells)
    ax.add_collection(LineCollection(nodes[outline], colors="0.55", lw=1.0,
                                     linestyles="--", label="undeformed"))
    draw_mesh(ax, xy, problem.cells, color="0.6", lw=0.5)
    ax.add_collection(LineCollection(xy[outline], colors="k", lw=1.0,
                                     label=f"deformed, displacements × "
                                     f"{scale:g}"))
    contact = problem.contact_nodes[np.asarray(result.in_contact, bool)]
    ax.plot(xy[contact, 0], xy[contact, 1], "r*", ms=8, zorder=4,
            label=f"in contact ({len(contact)} nodes)")
    both = np.vstack([nodes, xy])
    margin = 0.1 * np.ptp(nodes, axis=0).max()
    obstacle = obstacle_in_box(problem.obstacle, both.min(axis=0) - margin,
                               both.max(axis=0) + margin)
    if scale != 1:
        ax.plot(*obstacle.T, ":", color="b", lw=1.0,
                label="obstacle Γo, true position")
        ax.plot(*moved_obstacle(problem, u, scale, obstacle).T, "-",
                color="b", lw=2, label=f"Γo moved with Γc × {scale - 1:g}: "
                "gaps at true size,\nnodes in contact on it")
    else:
        ax.plot(*obstacle.T, "b-", lw=2, label="obstacle Γo")
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title(f"whole body, displacements × {scale:g}\n(largest |u| = "
                 f"{largest:.3g} mm drawn as {scale * largest:.3g} mm)",
                 fontsize=10)
    left.legend(loc="outside lower center", ncols=2, fontsize=8)

    gc = problem.contact_nodes
    moved = nodes[gc] + u[gc]
    joins = piece_joins(problem)  # a Γc of separate pieces: drawn apart
    zoom.plot(*with_breaks(nodes[gc], joins).T, "--", color="0.55", lw=1.0,
              label="Γc undeformed")
    zoom.plot(*with_breaks(moved, joins).T, "k.-", lw=1.0, ms=4,
              label="Γc deformed (× 1)")
    zoom.plot(nodes[contact, 0] + u[contact, 0],
              nodes[contact, 1] + u[contact, 1], "r*", ms=8,
              label="in contact")
    box = np.vstack([nodes[gc], moved])
    low, high = box.min(axis=0), box.max(axis=0)
    pad = np.maximum(0.1 * (high - low), 0.005 * (high - low).max())
    zoom.plot(*obstacle_in_box(problem.obstacle, low - 2 * pad,
                               high + 2 * pad).T, "b-", lw=2,
              label="obstacle Γo")
    zoom.set_xlim(low[0] - pad[0], high[0] + pad[0])
    zoom.set_ylim(low[1] - pad[1], high[1] + pad[1])
    zoom.set_xlabel("x [mm]")
    zoom.set_ylabel("y [mm]")
    zoom.set_title("Γc at true scale (axes not to scale)", fontsize=10)
    right.legend(loc="outside lower center", ncols=2, fontsize=8)
    if title is None:
        parts = [getattr(result, "method", None),
                 getattr(result, "gap_mode", None)]
        title = "deformed body"
        if parts[0] is not None:
            title += f", {parts[0]} method"
        if parts[1] is not None:
            title += f", gap from {parts[1]}"
    fig.suptitle(title)
    return save_png(fig, path)


def plot_displacement_arrows(problem, result, path=None):
    """Undeformed body with displacement directions (thesis Fig. 4, right),
    on a figure shaped like the body (the thesis block is tall, the Hertz
    half-cylinder wide), so that the colour bar is as tall as the body."""
    plt = pyplot()
    u = result.displacement
    width, height = np.ptp(problem.nodes, axis=0)
    if height >= width:
        size = (5, 7)
    else:
        size = (8, float(np.clip(6.5 * height / width + 1.3, 3.2, 7)))
    fig, ax = plt.subplots(figsize=size, layout="constrained")
    draw_mesh(ax, problem.nodes, problem.cells, color="0.75", lw=0.5)
    q = ax.quiver(problem.nodes[:, 0], problem.nodes[:, 1], u[:, 0], u[:, 1],
                  np.hypot(u[:, 0], u[:, 1]), cmap="viridis")
    fig.colorbar(q, ax=ax, label="|u| [mm]")
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.margins(0.06)
    ax.set_title("undeformed body, displacement directions\n"
                 "(arrows magnified, colour = |u|)", fontsize=10)
    return save_png(fig, path)


def step_halvings(history, method):
    """Halvings of the step length α per Newton iteration: (taken, tried),
    −log₂ α of the step taken (NaN where none was, α = 0) and, where the line
    search found no acceptable α, the halvings it tried (NaN elsewhere; from
    ``history["halvings"]`` or the method's default options). φ_min then
    takes the full step anyway (``taken`` 0 hides the search), φ_FB stops."""
    from ..ncp.newton import DEFAULT_OPTIONS

    alpha = np.asarray(history["alpha"], dtype=float)
    failed = np.asarray(history["line_search_failed"], dtype=bool)
    with np.errstate(divide="ignore"):
        taken = np.where(alpha > 0, -np.log2(np.where(alpha > 0, alpha, 1)),
                         np.nan)
    if "halvings" in history:
        limit = np.asarray(history["halvings"], dtype=float)
    elif method == "min":
        limit = np.full(len(alpha), np.floor(
            -np.log2(DEFAULT_OPTIONS["min"]["alpha_min"])))
    else:
        limit = np.full(len(alpha), float(DEFAULT_OPTIONS["fb"]
                                          ["max_halvings"]))
    tried = np.where(failed, limit, np.nan)
    return taken, tried


def plot_convergence(result, path=None):
    """‖Φ‖ (log axis) and the step halvings (−log₂ α) per iteration (thesis
    Fig. 5 and 8); a nested start's levels as separate ‖Φ‖ lines, a failed
    line search marked with the halvings it tried."""
    from matplotlib.ticker import MaxNLocator

    plt = pyplot()
    history = result.history
    k = np.arange(len(history["residual"]) + 1)
    residual = list(history["residual"]) + [result.residual]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.5, 6), sharex=True,
                                      layout="constrained",
                                      gridspec_kw=dict(height_ratios=(3, 2)))
    level = np.asarray(history.get("level", []) + [None], dtype=object)
    if len(set(level[:-1])) > 1:  # each level from its start to the next's
        level[-1] = level[-2]
        starts = np.flatnonzero(np.r_[True, level[1:] != level[:-1]])
        for a, b in zip(starts, np.r_[starts[1:], len(k)]):
            top.semilogy(k[a:b], np.maximum(residual[a:b], 1e-300), "o-",
                         ms=4, label=f"{level[a]} contact nodes")
        legend_outside(top, "right", title="nested start,\nlevel of",
                        title_fontsize=8)
    else:
        top.semilogy(k, np.maximum(residual, 1e-300), "o-", ms=4)
    top.set_ylabel("‖Φ(x_k)‖")
    top.grid(alpha=0.3)
    top.set_title(f"{result.method} method: {result.njev} Jacobian, "
                  f"{result.nfev} residual evaluations", fontsize=10)
    taken, tried = step_halvings(history, result.method)
    it = np.arange(len(taken))
    bottom.plot(it, taken, "o-", ms=4, label="halvings of the step taken")
    failed = np.isfinite(tried)
    if failed.any():
        then = ("then the full step" if result.method == "min"
                else "no step")
        bottom.plot(it[failed], tried[failed], "rx", ms=9, mew=2,
                    label=f"line search failed after\nthese halvings; {then}")
    gradient = np.array([s == "gradient" for s in history["step"]], bool)
    if gradient.any():
        bottom.plot(it[gradient], taken[gradient], "k^", ms=7,
                    label="gradient step")
    if not failed.any() and np.nan_to_num(taken).max() == 0:
        bottom.text(0.5, 0.45, "every step a full step, α = 1",
                    transform=bottom.transAxes, ha="center", va="center",
                    fontsize=9,
                    color="0.3")
    highest = np.nanmax(np.r_[taken, tried, 1.0])
    bottom.set_ylim(-0.6, highest + 0.6)
    bottom.yaxis.set_major_locator(MaxNLocator(integer=True, nbins=6))
    bottom.xaxis.set_major_locator(MaxNLocator(integer=True))
    bottom.grid(alpha=0.3)
    bottom.set_ylabel("halvings −log₂ α")
    bottom.set_xlabel("iteration k")
    if failed.any() or gradient.any():
        legend_outside(bottom, "right")
    return save_png(fig, path)


def carries_load(values, relative=1e-6):
    """Where |values| exceeds ``relative`` × their largest: a node that
    carries load, as opposed to one whose force is round-off of the
    solve (open nodes keep λ of order 1e-15 of the largest)."""
    values = np.abs(np.nan_to_num(np.asarray(values, float)))
    return values > relative * values.max(initial=0.0)


def zoomed_axes(plt, x, loaded, figsize):
    """A figure for a profile along ``x`` whose load sits in a small part of
    it: (fig, main axes, overview axes or None, window); with a
    :func:`zoom_window` a short overview below shows all of ``x``."""
    window = zoom_window(x, loaded)
    if window is None:
        fig, ax = plt.subplots(figsize=figsize, layout="constrained")
        return fig, ax, None, None
    fig, (ax, whole) = plt.subplots(
        2, 1, figsize=(figsize[0], 1.5 * figsize[1]), layout="constrained",
        gridspec_kw=dict(height_ratios=(3, 1.1)))
    return fig, ax, whole, window


def finish_overview(ax, whole, window, xlabel, ylabel, what="all of Γc"):
    """Set the zoom ``window`` on ``ax`` and label the overview ``whole``
    (data already drawn into both), titled ``what``."""
    ax.set_xlim(*window)
    ax.set_title(ax.get_title() + f" (zoomed to {window[0]:.3g} … "
                 f"{window[1]:.3g} {_unit(xlabel)})".replace(" ()", ""),
                 fontsize=10)
    whole.axvspan(*window, color="C1", alpha=0.15, lw=0)
    whole.set_xlabel(xlabel)
    whole.set_ylabel(ylabel, fontsize=8)
    whole.set_title(f"{what}; shaded: the part zoomed above", fontsize=9)
    whole.grid(alpha=0.3)


def _unit(label):
    """The unit in an axis label's brackets, or ''."""
    return label[label.rfind("[") + 1:label.rfind("]")] \
        if label.endswith("]") else ""


def plot_contact_pressure(problem, result, path=None):
    """Contact pressure along Γc: the lumped p_i = λ_i / D_ii (≥ 0) and,
    dashed, the consistent M⁻¹λ of thesis (87), which oscillates below zero
    next to the contact zone; zoomed onto the loaded nodes when they lie in
    less than half of Γc (:func:`zoomed_axes`)."""
    plt = pyplot()
    arc, xlabel = arc_length(problem)
    pressure = np.asarray(result.contact_pressure, float)
    contact = np.asarray(result.in_contact, bool)
    loaded = contact | carries_load(pressure)
    fig, ax, whole, window = zoomed_axes(
        plt, arc, loaded if problem.kind == "mesh" else np.zeros_like(
            loaded), (9, 4.2))
    consistent = getattr(result, "contact_pressure_consistent", None)
    for target in filter(None, (ax, whole)):
        small = target is whole
        target.plot(arc, pressure, "o-", color="C0", ms=3 if small else 5,
                    zorder=3, label="p_i = λ_i / Σ_j M_ij:\nnodal contact "
                    "force per length")
        target.plot(arc[contact], pressure[contact], "r*",
                    ms=6 if small else 10, zorder=4, label="in contact")
        if consistent is not None:
            note = "M⁻¹λ, thesis (87): the same\nforces, consistent M"
            if np.min(consistent) < -1e-9 * np.max(np.abs(consistent)):
                note += "; dips\nbelow 0 beside the zone"
            target.plot(arc, consistent, "--", color="0.45", lw=1.0,
                        marker=".", ms=4, zorder=2, label=note)
        target.axhline(0.0, color="0.5", lw=0.8, zorder=1)
    ax.set_xlabel(xlabel)
    if problem.kind == "mesh":
        ax.set_ylabel("contact pressure [MPa]")
    else:  # M is the problem's own; with M = I (the bar) p is λ in N
        ax.set_ylabel("λ_i / Σ_j M_ij")
        ax.set_xticks(arc)
    ax.grid(alpha=0.3)
    ax.set_title("contact pressure along Γc", fontsize=10)
    if whole is not None:
        finish_overview(ax, whole, window, xlabel, "p [MPa]")
    legend_outside(ax, "right")
    return save_png(fig, path)


def write_jobs(folder, jobs):
    """Draw each (name, job) of ``jobs``, job(path), into ``folder``/name.png,
    close the figures and return their paths by name."""
    import os

    plt = pyplot()
    paths = {}
    for name, job in jobs:
        path = os.path.join(folder, f"{name}.png")
        plt.close(job(path))
        paths[name] = path
    return paths


def write_figures(folder, problem, result):
    """Write the four figures into ``folder``; return their paths."""
    jobs = [("convergence", lambda p: plot_convergence(result, p)),
            ("contact_pressure",
             lambda p: plot_contact_pressure(problem, result, p))]
    if problem.kind == "mesh":
        jobs += [("deformed", lambda p: plot_deformed(problem, result,
                                                       path=p)),
                 ("displacement",
                  lambda p: plot_displacement_arrows(problem, result, p))]
    return write_jobs(folder, jobs)

