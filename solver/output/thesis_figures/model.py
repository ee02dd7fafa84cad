"""Fig. 3-5: the model problem, the deformed body and the contact directions
(part of :mod:`solver.output.thesis_figures`)."""

import numpy as np

from ...geometry.mesh import boundary_edges
from .common import LENGTH, FORCE, PRESSURE, save_png, pyplot


def outline(problem):
    """Boundary edges of the 2D mesh (edges used by one cell)."""
    return boundary_edges(problem.cells)


def obstacle_for_display(problem, scale, t):
    """Obstacle points Γo(t) with their distance from the line through Γc
    magnified by ``scale``, like the displacements of a body drawn at
    ``scale`` × u, so that contact nodes lie on it (exact for a straight Γc
    and normals perpendicular to it)."""
    xy = problem.nodes[problem.contact_nodes]
    origin, direction = xy[0], xy[-1] - xy[0]
    direction = direction / np.linalg.norm(direction)
    points = problem.obstacle.point(t)
    along = (points - origin) @ direction
    foot = origin + along[:, None] * direction
    return foot + scale * (points - foot)


def contact_offset(problem, displacement, in_contact, scale):
    """Largest distance, across Γc, between a node in contact drawn at
    ``scale`` × u and the obstacle of :func:`obstacle_for_display`: zero to
    the linearised contact condition at scale 1, about k·Δs at scale k (the
    magnified tangential displacement moves a node along the curve)."""
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
    plt = pyplot()
    fig, (ax, gap_ax) = plt.subplots(1, 2, figsize=(9, 5.5),
                                     gridspec_kw=dict(width_ratios=[1.3, 1]))
    nodes = problem.nodes
    for a, b in outline(problem):
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
    return save_png(fig, path)
