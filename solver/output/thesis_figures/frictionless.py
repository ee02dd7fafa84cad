"""Fig. 4-15: frictionless results (convergence, pressure, meshes) (part of
:mod:`solver.output.thesis_figures`)."""

import numpy as np

from ..figures import draw_mesh
from .common import LENGTH, PRESSURE, save_png, panel_position, pyplot
from .model import outline, obstacle_for_display, contact_offset


def nice_scale(problem, displacement, fraction=0.1):
    """A round magnification making the largest displacement about
    ``fraction`` of the body's size."""
    u = np.abs(displacement).max()
    if u == 0:
        return 1.0
    target = fraction * np.ptp(problem.nodes, axis=0).max() / u
    power = 10.0 ** np.floor(np.log10(target))
    for m in (5, 2, 1):
        if m * power <= target:
            return m * power
    return power


def deformed_and_directions(problem, displacement, in_contact, scale=None,
                            title=None, path=None):
    """Fig. 4 (and 7, 10, 13, 22, 24, 26): left the deformed body
    (``displacement`` (n_nodes, 2) magnified by ``scale``, default about 10 %
    of the body) with the nodes ``in_contact`` starred and the obstacle's
    distance from Γc magnified alike (:func:`obstacle_for_display`, up to
    ``fig.contact_offset``), right the undeformed body with the displacement
    directions; ``fig.scale`` is the magnification used."""
    plt = pyplot()
    u = np.asarray(displacement)
    scale = nice_scale(problem, u) if scale is None else scale
    xy = problem.nodes + scale * u
    fig, (left, right) = plt.subplots(1, 2, figsize=(8.5, 5.6))
    draw_mesh(left, xy, problem.cells, color="0.6", lw=0.5)
    contact = problem.contact_nodes[np.asarray(in_contact, bool)]
    left.plot(xy[contact, 0], xy[contact, 1], "r*", ms=10,
              label=f"in contact ({len(contact)} nodes)")
    y = problem.nodes[:, 1]
    t = np.linspace(y.min() - 0.05 * np.ptp(y), y.max() + 0.05 * np.ptp(y),
                    300)
    obstacle = obstacle_for_display(problem, scale, t)
    left.plot(*obstacle.T, "b-", lw=2, label=f"obstacle Γo, gap × {scale:g}")
    fig.scale = scale
    fig.contact_offset = contact_offset(problem, u, in_contact, scale)
    left.set_aspect("equal")
    left.set_xlabel(f"x [{LENGTH}]")
    left.set_ylabel(f"y [{LENGTH}]")
    left.set_title(f"deformed, displacements × {scale:g}", fontsize=10)
    left.legend(fontsize=8, loc="lower left")

    nodes = problem.nodes
    size = np.hypot(u[:, 0], u[:, 1])
    direction = u / np.where(size > 0, size, 1.0)[:, None]
    for a, b in outline(problem):
        right.plot(*nodes[[a, b]].T, "-", color="0.6", lw=0.8)
    cells = np.asarray(problem.cells)
    spacing = np.median(np.linalg.norm(nodes[cells[:, 0]] - nodes[cells[:, 1]],
                                       axis=1))
    q = right.quiver(nodes[:, 0], nodes[:, 1], 0.8 * spacing * direction[:, 0],
                     0.8 * spacing * direction[:, 1], size, cmap="viridis",
                     angles="xy", scale_units="xy", scale=1, width=0.005,
                     pivot="tail")
    fig.colorbar(q, ax=right, label=f"|u| [{LENGTH}]", shrink=0.8)
    lo, hi = nodes.min(axis=0) - spacing, nodes.max(axis=0) + spacing
    right.set_xlim(lo[0], hi[0])
    right.set_ylim(lo[1], hi[1])
    right.set_aspect("equal")
    right.set_xlabel(f"x [{LENGTH}]")
    right.set_title("undeformed, displacement directions (unit arrows)",
                    fontsize=10)
    if title:
        fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    return save_png(fig, path)


def convergence(results, path=None, title=None):
    """Fig. 5 and 8 (11 and 14) side by side: per result (``{label:
    OptimizeResult}``, one column each) ‖Φ(x^k)‖ on top and the damping
    parameter α below, with the iterations where no decreasing α was found
    and the gradient steps marked."""
    plt = pyplot()
    fig, axes = plt.subplots(2, len(results), figsize=(5 * len(results), 6),
                             sharex="col", squeeze=False)
    smallest = min(min(r.history["alpha"], default=1.0)
                   for r in results.values())
    for (label, r), (top, bottom) in zip(results.items(), axes.T):
        history = r.history
        residual = list(history["residual"]) + [r.residual]
        top.semilogy(np.arange(len(residual)),
                     np.maximum(residual, 1e-300), "o-", ms=4)
        top.set_title(f"{label}: {r.njev} J, {r.nfev} F evaluations",
                      fontsize=10)
        top.set_ylabel("‖Φ(x^k)‖")
        top.grid(alpha=0.3)
        alpha = np.asarray(history["alpha"], float)
        k = np.arange(len(alpha))
        failed = np.asarray(history["line_search_failed"], bool)
        gradient = np.array([s == "gradient" for s in history["step"]],
                            bool)
        bottom.semilogy(k, alpha, "s-", ms=4, label="α")
        if failed.any():
            bottom.semilogy(k[failed], alpha[failed], "rx", ms=11, mew=2,
                            label="no decreasing α found, step taken")
        if gradient.any():
            bottom.semilogy(k[gradient], alpha[gradient], "k^",
                            label="gradient step")
        bottom.set_ylim(min(smallest / 3, 0.1), 3)
        bottom.set_ylabel("α")
        bottom.set_xlabel("iteration k")
        bottom.legend(fontsize=8, loc="lower left")
        bottom.grid(alpha=0.3)
    if title:
        fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    return save_png(fig, path)


def pressure_along_contact(problem, results, path=None, title=None,
                           consistent=True, xlim=None):
    """Fig. 6 and 9 (12, 15): contact pressure along Γc for each result of
    ``{label: result}``: the lumped λ_i/D_ii ≥ 0 and, thin and grey, the
    thesis's consistent g_n = M⁻¹λ of (87), which oscillates below zero next
    to the contact zone."""
    plt = pyplot()
    y = panel_position(problem)
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for i, (label, r) in enumerate(results.items()):
        color = f"C{i}"
        ax.plot(y, r.contact_pressure, "o-", color=color, ms=4,
                label=f"{label}: lumped λ_i/D_ii")
        ax.plot(y[r.in_contact], r.contact_pressure[r.in_contact], "*",
                color=color, ms=11, mec="k", mew=0.5)
        if consistent:
            ax.plot(y, r.contact_pressure_consistent, ":", color=color,
                    lw=1, alpha=0.8, label=f"{label}: consistent M⁻¹λ (87)")
    ax.plot([], [], "k*", ms=9, label="nodes in contact")
    ax.axhline(0.0, color="0.5", lw=0.8)
    ax.set_xlabel(f"y on Γc [{LENGTH}]")
    ax.set_ylabel(f"contact pressure [{PRESSURE}]")
    if xlim is not None:
        ax.set_xlim(*xlim)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    ax.set_title(title or "contact pressure along Γc", fontsize=10)
    return save_png(fig, path)


def mesh_comparison(problems, results, path=None, xlim=None):
    """Contact zones and pressures on several meshes (the thesis's §4.1
    remark that finer meshes locate the zone more precisely): ``problems``
    and ``results`` keyed alike. Top: lumped pressure along Γc; bottom: the
    zone from the first to the last node in contact, ± half a node spacing."""
    plt = pyplot()
    fig, (top, bottom) = plt.subplots(
        2, 1, figsize=(8, 6), sharex=True,
        gridspec_kw=dict(height_ratios=[3, 1]))
    for i, (key, problem) in enumerate(problems.items()):
        r = results[key]
        y = panel_position(problem)
        top.plot(y, r.contact_pressure, "o-", ms=3, color=f"C{i}",
                 label=f"{key} elements ({r.n_contact} nodes in contact)")
        inside = np.flatnonzero(r.in_contact)
        lo, hi = inside.min(), inside.max()
        a = y[lo] - 0.5 * (y[lo] - y[lo - 1]) if lo > 0 else y[lo]
        b = y[hi] + 0.5 * (y[hi + 1] - y[hi]) if hi + 1 < len(y) else y[hi]
        bottom.plot([a, b], [i, i], "-", color=f"C{i}", lw=8,
                    solid_capstyle="butt")
        bottom.plot(y[inside], np.full(len(inside), i), "k*", ms=8)
    top.axhline(0.0, color="0.5", lw=0.8)
    top.set_ylabel(f"lumped pressure λ_i/D_ii [{PRESSURE}]")
    top.legend(fontsize=8)
    top.grid(alpha=0.3)
    top.set_title("contact pressure and contact zone on the three meshes",
                  fontsize=10)
    bottom.set_yticks(range(len(problems)), [f"{k}" for k in problems])
    bottom.set_ylim(-0.7, len(problems) - 0.3)
    bottom.set_ylabel("elements")
    bottom.set_xlabel(f"y on Γc [{LENGTH}] (★ nodes in contact)")
    if xlim is not None:
        bottom.set_xlim(*xlim)
    bottom.grid(alpha=0.3, axis="x")
    fig.tight_layout()
    return save_png(fig, path)
