r"""Counterparts of the thesis's Fig. 1-27, for the notebooks.

Each function draws one figure in the thesis's layout, returns the matplotlib
Figure and, given ``path``, saves it as a PNG (100 dpi). matplotlib is
imported here only; nothing here prints or calls ``plt.show()``. The
notebooks in ``notebooks/`` call these functions and list which thesis
figure each file stands for (``notebooks/README.md``).

Units (one convention, every axis label uses it). The thesis gives no
units; its numbers (E = 2·10⁵, a 10 × 20 block, F = 4000) read naturally as
**lengths in mm, E in MPa, plane strain per unit thickness**: a nodal force
(F, the contact force λ_i, the friction force t_i) is in N per mm of
thickness, written [N]; pressures and tractions (p = λ_i/D_ii with
D_ii = Σ_j M_ij in mm, g_t) are in N/mm² = MPa.

Sketches (Fig. 1, 2, 3, 16, 17) are drawn from the problem data where there
is data: Fig. 3 from the exported mesh, supports and load, Fig. 16 from the
bar's computed load path.
"""

import numpy as np

from .figures import _pyplot
from .figures import _save as save_png

__all__ = ["LENGTH", "FORCE", "PRESSURE", "UNITS",
           "ncp_functions", "boundary_conditions_sketch", "model_problem",
           "deformed_and_directions", "obstacle_for_display",
           "convergence", "pressure_along_contact", "mesh_comparison",
           "load_increment", "bar_sketch", "bar_history",
           "tractions_along_contact", "tangential_displacement"]

#: Units of the axis labels (see the module docstring).
LENGTH, FORCE, PRESSURE = "mm", "N", "MPa"

#: The convention in one sentence, for notebooks to print.
UNITS = ("Units: lengths in mm, E in MPa, plane strain per unit thickness; "
         "nodal forces in N (per mm of thickness), pressures and tractions "
         "in MPa = N/mm².")

DPI = 100


def _save(fig, path):
    return save_png(fig, path, dpi=DPI)


def _position(problem, axis=1):
    """Coordinate ``axis`` of the nodes of Γc (y for the block's edge)."""
    return problem.nodes[problem.contact_nodes, axis]


# --------------------------------------------------------------------------
# Fig. 1-3: the NCP functions, the boundary conditions, the model problem
# --------------------------------------------------------------------------

def ncp_functions(path=None):
    """Fig. 1: a function of one variable with a kink and its
    subderivatives; beside it, the zero sets of φ_min (19) and φ_FB (20)
    (both are the complementarity corner a ≥ 0, b ≥ 0, ab = 0)."""
    plt = _pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    x = np.linspace(-0.5, 2.5, 301)
    g = np.minimum(x, 2 - x)  # φ_min(x, 2 − x): kink at x = 1
    left.plot(x, g, "b-", lw=2.5, label="g(x) = min(x, 2 − x)")
    xs = np.linspace(0.3, 1.7, 2)
    for slope in np.linspace(-1, 1, 9):
        left.plot(xs, 1 + slope * (xs - 1), "r-", lw=0.8, alpha=0.7)
    left.plot([], [], "r-", lw=0.8,
              label="slopes in ∂g(1) = [−1, 1] (Clarke)\n"
                    "∂_B g(1) = {−1, 1} (its end points)")
    left.annotate("non-smooth point", xy=(1, 1), xytext=(1.75, 1.55),
                  arrowprops=dict(arrowstyle="->"))
    left.set_ylim(-0.6, 1.8)
    left.set_xlabel("x")
    left.set_ylabel("g(x)")
    left.set_title("Fig. 1: a kink and its subdifferential", fontsize=10)
    left.legend(fontsize=8, loc="lower center")

    a, b = np.meshgrid(np.linspace(-1, 2, 301), np.linspace(-1, 2, 301))
    phi_min = np.minimum(a, b)
    phi_fb = np.hypot(a, b) - (a + b)
    right.contour(a, b, phi_min, levels=[-0.5, 0.5], colors="C0",
                  linestyles="--", linewidths=0.8)
    right.contour(a, b, phi_fb, levels=[-0.5, 0.5], colors="C1",
                  linestyles=":", linewidths=1.0)
    right.plot([0, 0, 2], [2, 0, 0], "k-", lw=3,
               label="φ(a, b) = 0 for both: a, b ≥ 0, ab = 0")
    right.plot([], [], "C0--", lw=0.8, label="φ_min = ±0.5")
    right.plot([], [], "C1:", lw=1.0, label="φ_FB = ±0.5")
    right.set_aspect("equal")
    right.set_xlabel("a")
    right.set_ylabel("b")
    right.set_title("NCP functions (19), (20): same zero set", fontsize=10)
    right.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.15))
    fig.tight_layout()
    return _save(fig, path)


def boundary_conditions_sketch(path=None):
    """Fig. 2: a body Ω with ∂Ω_u (supported), ∂Ω_σ (loaded), Γc and the
    rigid obstacle Γo, the gap s and the frame (γ, ν) at a point of Γc."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6, 4.5))
    t = np.linspace(0, 2 * np.pi, 400)
    body = np.c_[1.6 * np.cos(t), 1.0 * np.sin(t) + 1.2]
    ax.fill(body[:, 0], body[:, 1], color="0.9", ec="k")
    ax.text(-0.3, 1.3, "Ω", fontsize=18)
    # Γc: the lower arc; obstacle below it
    arc = (t > 1.2 * np.pi) & (t < 1.8 * np.pi)
    ax.plot(body[arc, 0], body[arc, 1], "r-", lw=3)
    ax.text(0.55, 0.05, "Γc", color="r", fontsize=13)
    xo = np.linspace(-1.8, 1.8, 100)
    ax.plot(xo, -0.12 + 0.05 * xo ** 2, "b-", lw=2.5)
    ax.text(1.45, -0.15, "Γo", color="b", fontsize=13)
    ax.annotate("", xy=(0, -0.12), xytext=(0, 0.2),
                arrowprops=dict(arrowstyle="<->", color="0.3"))
    ax.text(0.05, 0.0, "s", fontsize=12, color="0.3")
    B = np.array([-0.75, 1.2 - np.sqrt(1 - (0.75 / 1.6) ** 2)])
    nu = np.array([B[0] / 1.6 ** 2, B[1] - 1.2])
    nu /= np.linalg.norm(nu)
    gamma = np.array([-nu[1], nu[0]])
    for vec, name in ((nu, "ν"), (gamma, "γ")):
        ax.annotate("", xy=B + 0.45 * vec, xytext=B,
                    arrowprops=dict(arrowstyle="-|>", color="k"))
        ax.text(*(B + 0.55 * vec - [0.05, 0.05]), name, fontsize=12)
    # ∂Ω_u: left part of the boundary, clamped
    left = (t > 0.8 * np.pi) & (t < 1.15 * np.pi)
    ax.plot(body[left, 0], body[left, 1], "k-", lw=4)
    for xi, yi in body[left][::12]:
        ax.plot([xi, xi - 0.15], [yi, yi - 0.1], "k-", lw=0.8)
    ax.text(-2.3, 1.5, "∂Ω_u\n(u = 0)", fontsize=10)
    # ∂Ω_σ: loaded upper boundary
    for s in np.linspace(0.3 * np.pi, 0.7 * np.pi, 5):
        x, y = 1.6 * np.cos(s), np.sin(s) + 1.2
        ax.annotate("", xy=(x, y), xytext=(x, y + 0.45),
                    arrowprops=dict(arrowstyle="->", color="C2"))
    ax.text(1.0, 2.45, "∂Ω_σ (given traction)", color="C2", fontsize=10)
    ax.set_xlim(-2.5, 2.5)
    ax.set_ylim(-0.5, 2.9)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title("Fig. 2: boundary conditions of the contact problem",
                 fontsize=10)
    return _save(fig, path)


def _outline(problem):
    """Boundary edges of the triangle mesh (edges used by one cell)."""
    cells = np.asarray(problem.cells)
    edges = np.sort(np.r_[cells[:, [0, 1]], cells[:, [1, 2]],
                          cells[:, [2, 0]]], axis=1)
    unique, count = np.unique(edges, axis=0, return_counts=True)
    return unique[count == 1]


def obstacle_for_display(problem, scale, t):
    """Obstacle points Γo(t) with their distance from the line through Γc
    (undeformed) magnified by ``scale``, like the displacements of a body
    drawn at ``scale`` × u; contact nodes (u_n = s) then lie on it.

    Exact for a straight Γc and normals perpendicular to it (the block's
    edge x = 5; its obstacle normals tilt by ≤ 2° in the contact zone).
    """
    xy = problem.nodes[problem.contact_nodes]
    origin, direction = xy[0], xy[-1] - xy[0]
    direction = direction / np.linalg.norm(direction)
    points = problem.obstacle.point(t)
    along = (points - origin) @ direction
    foot = origin + along[:, None] * direction
    return foot + scale * (points - foot)


def contact_offset(problem, displacement, in_contact, scale):
    """Largest distance, across Γc, between a node in contact drawn at
    ``scale`` × u and the obstacle drawn by :func:`obstacle_for_display`.

    Zero up to the linearised contact condition at scale 1; at scale k the
    tangential displacement, magnified too, moves a node along the curved
    obstacle, whose magnified gap there differs by about k·Δs.
    """
    inside = np.asarray(in_contact, bool)
    if not inside.any():
        return 0.0
    xy = problem.nodes[problem.contact_nodes]
    drawn_nodes = (xy + scale * np.asarray(displacement)[
        problem.contact_nodes])[inside]
    origin, direction = xy[0], xy[-1] - xy[0]
    direction = direction / np.linalg.norm(direction)
    normal = np.array([direction[1], -direction[0]])
    span = np.ptp(problem.nodes, axis=0).max()
    # the obstacle's parameter runs along Γc (t = y for the block's parabola)
    lo, hi = (xy @ direction).min() - span, (xy @ direction).max() + span
    t = np.linspace(lo, hi, 20001)
    drawn = obstacle_for_display(problem, scale, t)
    along = (drawn - origin) @ direction
    order = np.argsort(along)
    offset = (drawn - origin) @ normal
    at = np.interp((drawn_nodes - origin) @ direction, along[order],
                   offset[order])
    return float(np.abs((drawn_nodes - origin) @ normal - at).max())


def model_problem(problem, path=None, title="Fig. 3: the model problem "
                  "(our reconstruction of the lost figure)"):
    """Fig. 3: the body's outline, its supports (nodes with a fixed DOF),
    the point force (``meta['load']``), Γc and the obstacle; right, the
    initial gap s along Γc."""
    plt = _pyplot()
    fig, (ax, gap_ax) = plt.subplots(1, 2, figsize=(9, 5.5),
                                     gridspec_kw=dict(width_ratios=[1.3, 1]))
    nodes = problem.nodes
    for a, b in _outline(problem):
        ax.plot(*nodes[[a, b]].T, "k-", lw=1.2)
    free = np.zeros(nodes.shape, bool)
    free[problem.dof_map[:, 0], problem.dof_map[:, 1]] = True
    fixed = ~free.all(axis=1)
    ax.plot(*nodes[fixed].T, "ks", ms=4, label="supports (u = 0)")
    span = np.ptp(nodes, axis=0).max()
    for x, y in nodes[fixed]:
        ax.plot([x, x - 0.02 * span], [y, y - 0.03 * span], "k-", lw=0.6)
    contact = nodes[problem.contact_nodes]
    ax.plot(*contact.T, "r-", lw=3, label="Γc")
    y = np.linspace(nodes[:, 1].min(), nodes[:, 1].max(), 200)
    obstacle = problem.obstacle.point(y)
    ax.plot(*obstacle.T, "b-", lw=2, label=f"Γo(t) = [{problem.obstacle.x_text}, "
            f"{problem.obstacle.y_text}]")
    load = problem.meta.get("load", {})
    if "point_force" in load and "at" in load:
        at, force = np.asarray(load["at"]), np.asarray(load["point_force"])
        arrow = 0.25 * span * force / np.linalg.norm(force)
        ax.annotate("", xy=at, xytext=at - arrow,
                    arrowprops=dict(arrowstyle="-|>", color="C2", lw=2))
        ax.text(*(at - arrow + [0, 0.03 * span]),
                f"F = ({force[0]:g}, {force[1]:g}) {FORCE}", color="C2",
                fontsize=9)
    meta = problem.meta
    ax.set_title(f"{title}\nE = {meta.get('E', 0):g} {PRESSURE}, "
                 f"ν = {meta.get('nu', 0):g}, plane {meta.get('plane', '')}, "
                 f"{len(problem.cells)} triangles", fontsize=9)
    ax.set_aspect("equal")
    ax.set_xlabel(f"x [{LENGTH}]")
    ax.set_ylabel(f"y [{LENGTH}]")
    ax.legend(fontsize=8, loc="center left")
    lo, hi = nodes.min(axis=0), nodes.max(axis=0)
    ax.set_xlim(lo[0] - 0.35 * span, hi[0] + 0.15 * span)
    ax.set_ylim(lo[1] - 0.1 * span, hi[1] + 0.1 * span)

    s = obstacle[:, 0] - contact[0, 0]
    gap_ax.plot(s, y, "b-", label="x of Γo − x of Γc (horizontal)")
    gap_ax.set_xlabel(f"initial gap [{LENGTH}]")
    gap_ax.set_ylabel(f"y [{LENGTH}]")
    gap_ax.set_title("the gap (not visible at the scale of the body)",
                     fontsize=9)
    gap_ax.set_xlim(0, None)
    gap_ax.grid(alpha=0.3)
    fig.tight_layout()
    return _save(fig, path)


# --------------------------------------------------------------------------
# Fig. 4-15: frictionless results
# --------------------------------------------------------------------------

def _nice_scale(problem, displacement, fraction=0.1):
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
    """Fig. 4 (and 7, 10, 13, 22, 24, 26): left the deformed body with the
    nodes of Γc in contact starred and the obstacle in blue, right the
    undeformed body with the displacement directions.

    ``displacement`` (n_nodes, 2), ``in_contact`` over the nodes of Γc.
    The displacements are magnified by ``scale`` (default: a round number
    making the largest one about 10 % of the body); the obstacle's distance
    from Γc is magnified alike (:func:`obstacle_for_display`), so the
    starred nodes lie on it up to ``fig.contact_offset`` (see
    :func:`contact_offset`); ``fig.scale`` is the magnification used.
    """
    plt = _pyplot()
    u = np.asarray(displacement)
    scale = _nice_scale(problem, u) if scale is None else scale
    xy = problem.nodes + scale * u
    fig, (left, right) = plt.subplots(1, 2, figsize=(8.5, 5.6))
    left.triplot(xy[:, 0], xy[:, 1], problem.cells, color="0.6", lw=0.5)
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
    for a, b in _outline(problem):
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
    return _save(fig, path)


def convergence(results, path=None, title=None):
    """Fig. 5 and 8 (11 and 14) side by side: per result (``{label:
    OptimizeResult}``, one column each) ‖Φ(x^k)‖ on top and the damping
    parameter α below, with the iterations where no decreasing α was found
    and the gradient steps marked."""
    plt = _pyplot()
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
    return _save(fig, path)


def pressure_along_contact(problem, results, path=None, title=None,
                           consistent=True, xlim=None):
    """Fig. 6 and 9 (12, 15): contact pressure along Γc for each result of
    ``{label: result}``. Main curve: the lumped nodal pressure
    p_i = λ_i/D_ii ≥ 0 (``contact_pressure``); secondary (thin, grey
    family): the thesis's consistent g_n = M⁻¹λ of (87)
    (``contact_pressure_consistent``), which spreads each nodal force over
    its neighbours and oscillates below zero next to the contact zone."""
    plt = _pyplot()
    y = _position(problem)
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
    return _save(fig, path)


def mesh_comparison(problems, results, path=None, xlim=None):
    """Contact zones and pressures on several meshes (the thesis's §4.1
    remark that finer meshes locate the contact zone more precisely):
    ``problems`` and ``results`` keyed alike (e.g. by element count). Top:
    lumped pressure along Γc; bottom: the extent of the contact zone, from
    the first to the last node in contact, widened by half a node spacing
    on each side."""
    plt = _pyplot()
    fig, (top, bottom) = plt.subplots(
        2, 1, figsize=(8, 6), sharex=True,
        gridspec_kw=dict(height_ratios=[3, 1]))
    for i, (key, problem) in enumerate(problems.items()):
        r = results[key]
        y = _position(problem)
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
    return _save(fig, path)


# --------------------------------------------------------------------------
# Fig. 16-21: the load increment and the 2-DOF bar
# --------------------------------------------------------------------------

def load_increment(result, step, path=None, window=3):
    """Fig. 16: the displacement of point A over the load steps of a
    discrete friction run (left) and, zoomed in on ``window`` steps either
    side of ``step`` (1-based κ), the increment Δu_κ from u_{κ−1} to u_κ
    (right)."""
    plt = _pyplot()
    u = np.asarray(result.displacement)[:, 0, :]  # point A, (steps, 2)
    fig, (full, zoom) = plt.subplots(1, 2, figsize=(10, 4.2))
    near = slice(max(step - 1 - window, 0), step + window)
    a, b = u[step - 2], u[step - 1]
    for ax in (full, zoom):
        ax.plot(u[:, 0], u[:, 1], ".-", color="0.6", ms=5,
                label=f"u^A after load step κ = 1 … {len(u)}")
        ax.set_xlabel(f"u_x of A [{LENGTH}]")
        ax.set_ylabel(f"u_y of A [{LENGTH}]")
        ax.grid(alpha=0.3)
    lo, hi = u[near].min(axis=0), u[near].max(axis=0)
    pad = 0.15 * max(np.ptp(u[near], axis=0).max(), 1e-12)
    full.add_patch(plt.Rectangle(lo - pad, *(hi - lo + 2 * pad), fill=False,
                                 ec="C3", lw=1.5))
    full.set_title(f"the bar, f_c = {result.friction:g}: path of A",
                   fontsize=10)
    full.legend(fontsize=8, loc="upper right")
    zoom.plot(*a, "o", color="C0", ms=9, label=f"u_κ−1 (κ = {step})")
    zoom.plot(*b, "s", color="C3", ms=9, label="u_κ = u_κ−1 + Δu_κ")
    zoom.annotate("", xy=b, xytext=a,
                  arrowprops=dict(arrowstyle="-|>", color="k", lw=1.5,
                                  shrinkA=6, shrinkB=6))
    zoom.text(*(0.5 * (a + b)), "Δu_κ\n", fontsize=11, ha="center")
    from matplotlib.ticker import MaxNLocator

    zoom.xaxis.set_major_locator(MaxNLocator(4))
    zoom.yaxis.set_major_locator(MaxNLocator(5))
    zoom.set_xlim(lo[0] - pad, hi[0] + pad)
    zoom.set_ylim(lo[1] - pad, hi[1] + pad)
    zoom.legend(fontsize=8, loc="lower left")
    zoom.set_title(f"Fig. 16: one load step, κ = {step} (zoom)", fontsize=10)
    fig.tight_layout()
    return _save(fig, path)


def bar_sketch(problem, path=None):
    """Fig. 17: the 2-DOF bar system as we reconstruct it: point A held by
    two springs of stiffness K_xx, K_yy, loaded by f, with the rigid
    obstacle at distance s along the normal ν (``two_dof_bar``)."""
    plt = _pyplot()
    K = problem.K.toarray()
    f = np.asarray(problem.f)
    s = float(problem.gap[0])
    nu = np.asarray(problem.normal[0])
    fig, ax = plt.subplots(figsize=(6, 5))

    def spring(p, q, n=8, w=0.08):
        p, q = np.asarray(p, float), np.asarray(q, float)
        d = q - p
        L = np.linalg.norm(d)
        e, n_ = d / L, np.array([-d[1], d[0]]) / L
        pts = [p, p + 0.15 * d]
        for i in range(n):
            pts.append(p + (0.15 + 0.7 * (i + 0.5) / n) * d
                       + (w if i % 2 else -w) * n_)
        pts += [p + 0.85 * d, q]
        ax.plot(*np.array(pts).T, "k-", lw=1.2)
        return e

    A = np.array([0.0, 0.0])
    spring([-1.2, 0], A)
    spring([0, 1.2], A)
    for end, horizontal in (([-1.25, 0], False), ([0, 1.25], True)):
        if horizontal:
            ax.plot([-0.2, 0.2], [end[1]] * 2, "k-", lw=2)
            for xi in np.linspace(-0.2, 0.2, 6):
                ax.plot([xi, xi + 0.08], [end[1], end[1] + 0.08], "k-",
                        lw=0.8)
        else:
            ax.plot([end[0]] * 2, [-0.2, 0.2], "k-", lw=2)
            for yi in np.linspace(-0.2, 0.2, 6):
                ax.plot([end[0], end[0] - 0.08], [yi, yi - 0.08], "k-",
                        lw=0.8)
    ax.plot(*A, "ko", ms=9)
    ax.text(0.08, 0.08, "A", fontsize=13)
    ax.text(-0.75, 0.15, f"K_xx = {K[0, 0]:g} {FORCE}/{LENGTH}", fontsize=8,
            ha="center")
    ax.text(0.12, 0.7, f"K_yy = {K[1, 1]:g} {FORCE}/{LENGTH}", fontsize=8)
    fvec = 0.6 * f / np.linalg.norm(f)
    ax.annotate("", xy=A + fvec, xytext=A,
                arrowprops=dict(arrowstyle="-|>", color="C2", lw=2))
    ax.text(*(A + fvec + [0.05, -0.05]),
            f"f = ({f[0]:g}, {f[1]:g}) {FORCE}", color="C2", fontsize=9)
    drawn_gap = 0.9  # s is drawn out of scale
    base = A + drawn_gap * nu
    tangent = np.array([-nu[1], nu[0]])
    line = np.array([base - 1.3 * tangent, base + 1.3 * tangent])
    ax.plot(*line.T, "b-", lw=3)
    for c in np.linspace(-1.2, 1.2, 14):
        p = base + c * tangent
        ax.plot(*np.array([p, p + 0.1 * nu + 0.08 * tangent]).T, "b-",
                lw=0.8)
    ax.annotate("", xy=base - 1.1 * tangent, xytext=A - 1.1 * tangent,
                arrowprops=dict(arrowstyle="<->", color="0.3"))
    ax.text(*(A - 1.0 * tangent + 0.45 * nu), f"s = {s:g} {LENGTH}\n"
            "(not to scale)", fontsize=8, color="0.3")
    ax.text(*(base + 0.9 * tangent + 0.25 * nu), "rigid obstacle",
            color="b", fontsize=9)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_xlim(-1.6, 1.6)
    ax.set_ylim(-1.3, 1.5)
    ax.set_title("Fig. 17: the 2-DOF bar system (our reconstruction of the "
                 "lost figure)", fontsize=10)
    return _save(fig, path)


#: Quantity name -> (column of the closed form, label, thesis figure).
BAR_QUANTITIES = {
    "contact_force": (2, f"contact force λ [{FORCE}]", 18),
    "friction_force": (3, f"friction force t = D g_t [{FORCE}]", 19),
    "u_x": (0, f"u_x of A [{LENGTH}]", 20),
    "u_y": (1, f"u_y of A [{LENGTH}]", 21),
}


def _bar_values(problem, result, quantity):
    lumped = float(np.asarray(problem.M.sum(axis=1)).ravel()[0])
    if quantity == "contact_force":
        return result.contact_force[:, 0]
    if quantity == "friction_force":
        return lumped * result.friction_traction[:, 0]
    return result.displacement[:, 0, 0 if quantity == "u_x" else 1]


def bar_history(problem, results, quantity, references=None, path=None,
                identical_tol=1e-9):
    """One of Fig. 18-21 for the bar: ``quantity`` ("contact_force",
    "friction_force", "u_x", "u_y") per load step, one curve per friction
    coefficient of ``results`` ({f_c: result}), the closed form
    (``references`` {f_c: (steps, 4) array of (u_x, u_y, λ, g_t)}) drawn as
    a thick grey line under the computed points.

    Curves that coincide (max difference ≤ ``identical_tol`` times the
    largest value) are drawn once; the legend gives the measured
    difference. Returns the Figure; ``fig.max_difference`` holds that
    difference (None if the curves differ).
    """
    plt = _pyplot()
    column, ylabel, number = BAR_QUANTITIES[quantity]
    values = {fc: _bar_values(problem, r, quantity) for fc, r in
              results.items()}
    stacked = np.array(list(values.values()))
    spread = float(np.ptp(stacked, axis=0).max())
    same = spread <= identical_tol * max(np.abs(stacked).max(), 1e-300)
    fig, ax = plt.subplots(figsize=(7, 4))
    steps = np.arange(1, stacked.shape[1] + 1)
    if references is not None:
        for i, fc in enumerate(values):
            ax.plot(steps, np.asarray(references[fc])[:len(steps), column],
                    "-", color="0.75", lw=4,
                    label="closed form" if i == 0 else None)
    for i, (fc, v) in enumerate(values.items()):
        if same and i > 0:
            continue
        label = (", ".join(f"f_c = {c:g}" for c in values) +
                 f" (identical: max difference {spread:.1e})" if same
                 else f"f_c = {fc:g}")
        ax.plot(steps, v, ".", color=f"C{i}", ms=5, label=label)
    ax.set_xlabel("load step κ")
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"Fig. {number}: point A, {len(stacked[0])} load steps",
                 fontsize=10)
    fig.max_difference = spread if same else None
    return _save(fig, path)


# --------------------------------------------------------------------------
# Fig. 22-27: the block with friction
# --------------------------------------------------------------------------

def tractions_along_contact(problem, result, step=-1, path=None, xlim=None):
    """Fig. 23 (25, 27): contact pressure p = λ/D and friction traction g_t
    along Γc at one load step, the Coulomb bound ±f_c p used in that step,
    stick and slip nodes marked."""
    plt = _pyplot()
    y = _position(problem)
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
    return _save(fig, path)


def _fit_y(ax, x, arrays, xlim, margin=0.08):
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
    plt = _pyplot()
    y = _position(problem)
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for label, (values, style) in curves.items():
        ax.plot(y, values, label=label, **style)
    ax.set_xlabel(f"y on Γc [{LENGTH}]")
    ax.set_ylabel(f"tangential displacement u_t [{LENGTH}]")
    if xlim is not None:
        ax.set_xlim(*xlim)
        _fit_y(ax, y, [values for values, _ in curves.values()], xlim)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    if title:
        ax.set_title(title, fontsize=10)
    return _save(fig, path)
