"""Figures of a frictionless solve, in the manner of the thesis's Fig. 4-6.

matplotlib is imported here only (Agg backend, never ``plt.show()``); each
function returns the Figure and, given ``path``, saves it as PNG.
"""

import numpy as np

__all__ = ["plot_deformed", "plot_displacement_arrows", "plot_convergence",
           "plot_contact_pressure", "write_figures", "plot_step_history",
           "plot_friction_along_boundary", "write_friction_figures"]


def _pyplot():
    """pyplot, on the Agg backend unless the caller (a notebook) already
    chose one by importing pyplot itself."""
    import sys

    import matplotlib

    if "matplotlib.pyplot" not in sys.modules:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path):
    if path is not None:
        from .files import atomic_path

        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=120, bbox_inches="tight", format="png")
    return fig


def _obstacle_curve(problem, y_range):
    """Points of the obstacle covering the body's height (with margin)."""
    curve = problem.obstacle
    if curve.t_range is not None:
        t = np.linspace(*curve.t_range, 400)
    else:
        # Parameter window around the foot points of the contact nodes.
        t = np.linspace(y_range[0], y_range[1], 400)
    return curve.point(t)


def plot_deformed(problem, result, scale=1.0, path=None, title=None):
    """Deformed body, contact nodes starred, obstacle in blue (thesis Fig. 4,
    left). ``scale`` magnifies the displacements; with scale ≠ 1 the body
    appears to cross the (unscaled) obstacle."""
    plt = _pyplot()
    u = result.displacement
    xy = problem.nodes + scale * u
    fig, ax = plt.subplots(figsize=(5, 7))
    ax.triplot(xy[:, 0], xy[:, 1], problem.cells, color="0.6", lw=0.5)
    contact = problem.contact_nodes[result.in_contact]
    ax.plot(xy[contact, 0], xy[contact, 1], "r*", ms=8,
            label=f"in contact ({len(contact)} nodes)")
    ymin, ymax = problem.nodes[:, 1].min(), problem.nodes[:, 1].max()
    margin = 0.1 * (ymax - ymin)
    obstacle = _obstacle_curve(problem, (ymin - margin, ymax + margin))
    ax.plot(obstacle[:, 0], obstacle[:, 1], "b-", lw=2, label="obstacle Γo")
    ax.set_aspect("equal")
    ax.set_xlabel("x [length]")
    ax.set_ylabel("y [length]")
    ax.set_title(title or f"deformed body, displacements × {scale:g}\n"
                 f"{result.method} method, gap from {result.gap_mode}")
    ax.legend(loc="lower left", fontsize=8)
    return _save(fig, path)


def plot_displacement_arrows(problem, result, path=None):
    """Undeformed body with displacement directions (thesis Fig. 4, right)."""
    plt = _pyplot()
    u = result.displacement
    fig, ax = plt.subplots(figsize=(5, 7))
    ax.triplot(problem.nodes[:, 0], problem.nodes[:, 1], problem.cells,
               color="0.75", lw=0.5)
    q = ax.quiver(problem.nodes[:, 0], problem.nodes[:, 1], u[:, 0], u[:, 1],
                  np.hypot(u[:, 0], u[:, 1]), cmap="viridis")
    fig.colorbar(q, ax=ax, label="|u| [length]")
    ax.set_aspect("equal")
    ax.set_xlabel("x [length]")
    ax.set_ylabel("y [length]")
    ax.set_title("undeformed body, displacement directions")
    return _save(fig, path)


def plot_convergence(result, path=None):
    """‖Φ‖ and the step length α per iteration (thesis Fig. 5 and 8). A
    nested start's levels (``history["level"]``) are drawn as separate
    lines, labelled with their number of contact nodes."""
    plt = _pyplot()
    history = result.history
    k = np.arange(len(history["residual"]) + 1)
    residual = list(history["residual"]) + [result.residual]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(6, 6), sharex=True)
    level = np.asarray(history.get("level", []) + [None], dtype=object)
    if len(set(level[:-1])) > 1:  # each level from its start to the next's
        level[-1] = level[-2]
        starts = np.flatnonzero(np.r_[True, level[1:] != level[:-1]])
        for a, b in zip(starts, np.r_[starts[1:], len(k)]):
            top.semilogy(k[a:b], np.maximum(residual[a:b], 1e-300), "o-",
                         label=f"{level[a]} contact nodes")
        top.legend(fontsize=8, title="nested start, level of",
                   title_fontsize=8)
    else:
        top.semilogy(k, np.maximum(residual, 1e-300), "o-")
    top.set_ylabel("‖Φ(x)‖")
    top.set_title(f"{result.method} method: {result.njev} Jacobian, "
                  f"{result.nfev} residual evaluations")
    alpha = np.array(history["alpha"], dtype=float)
    failed = np.array(history["line_search_failed"], dtype=bool)
    gradient = np.array([s == "gradient" for s in history["step"]])
    it = np.arange(len(alpha))
    bottom.semilogy(it, alpha, "s-", label="α (step length)")
    if failed.any():
        bottom.semilogy(it[failed], alpha[failed], "rx", ms=10,
                        label="no decreasing α found")
    if gradient.any():
        bottom.semilogy(it[gradient], alpha[gradient], "k^",
                        label="gradient step")
    bottom.set_ylabel("α")
    bottom.set_xlabel("iteration k")
    bottom.legend(fontsize=8)
    return _save(fig, path)


def plot_contact_pressure(problem, result, path=None):
    """Contact pressure p = −g_n (87) and contact force λ along Γc."""
    plt = _pyplot()
    if problem.kind == "mesh":
        xy = problem.nodes[problem.contact_nodes]
        arc = np.r_[0, np.cumsum(np.hypot(*np.diff(xy, axis=0).T))]
        label = "arc length along Γc from its first node [length]"
    else:
        arc = np.arange(problem.n_contact)
        label = "contact node"
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(arc, result.contact_pressure_consistent, "s--", ms=4,
            label="p = −g_n = M⁻¹λ (thesis (87), consistent M)")
    ax.plot(arc, result.contact_pressure, "o-",
            label="λ_i / Σ_j M_ij (lumped M)")
    ax.plot(arc[result.in_contact], result.contact_pressure[result.in_contact],
            "r*", ms=9, label="in contact")
    ax.axhline(0.0, color="0.5", lw=0.8)
    ax.set_xlabel(label)
    ax.set_ylabel("contact pressure [force / length]")
    ax.set_title("contact stress along Γc; the consistent M⁻¹ spreads the "
                 "nodal forces\nand oscillates next to the contact zone, "
                 "the lumped value does not", fontsize=10)
    ax.legend(fontsize=8)
    return _save(fig, path)


def write_figures(folder, problem, result):
    """Write the four figures into ``folder``; return their paths."""
    import os

    plt = _pyplot()
    paths = {}
    jobs = [("convergence", lambda p: plot_convergence(result, p)),
            ("contact_pressure",
             lambda p: plot_contact_pressure(problem, result, p))]
    if problem.kind == "mesh":
        jobs += [("deformed", lambda p: plot_deformed(problem, result,
                                                       path=p)),
                 ("displacement",
                  lambda p: plot_displacement_arrows(problem, result, p))]
    for name, job in jobs:
        path = os.path.join(folder, f"{name}.png")
        plt.close(job(path))
        paths[name] = path
    return paths


def plot_step_history(problem, result, node=None, path=None,
                      reference=None):
    """Contact force, friction force, u_x and u_y of one contact node per
    load step (thesis Fig. 18-21 for the bar's point A).

    ``node`` is a position along Γc; default: the node with the largest
    final contact force (for the bar, its only node A). ``reference``, an
    array (steps, 4) of (u_x, u_y, λ, t) such as the bar's closed form, is
    drawn as lines under the computed points.
    """
    plt = _pyplot()
    if node is None:
        node = int(np.argmax(result.contact_force[-1]))
    steps = np.arange(1, result.steps_completed + 1)
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()[node]
    if problem.kind == "mesh":
        u = result.displacement[:, problem.contact_nodes[node]]
        where = problem.nodes[problem.contact_nodes[node]]
        label = f"contact node at ({where[0]:g}, {where[1]:g})"
    else:
        u = result.displacement[:, node]
        label = "point A"
    fig, axes = plt.subplots(2, 2, figsize=(10, 7), sharex=True)
    panels = [
        (axes[0, 0], result.contact_force[:, node], "contact force λ [force]",
         "Fig. 18: contact force"),
        (axes[0, 1], lumped * result.friction_traction[:, node],
         "friction force t = D g_t [force]", "Fig. 19: friction force"),
        (axes[1, 0], u[:, 0], "u_x [length]", "Fig. 20: u_x"),
        (axes[1, 1], u[:, 1], "u_y [length]", "Fig. 21: u_y")]
    order = (2, 3, 0, 1)  # reference columns of the four panels
    for i, (ax, values, ylabel, title) in enumerate(panels):
        if reference is not None:
            ax.plot(steps, np.asarray(reference)[:len(steps), order[i]],
                    "-", color="0.6", lw=3, label="closed form")
        ax.plot(steps, values, ".", color="C0", label="computed")
        if reference is not None and i == 0:
            ax.legend(fontsize=8)
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=10)
        ax.grid(alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel("load step κ")
    fig.suptitle(f"{label}: f_c = {result.friction:g}, {result.steps} steps, "
                 f"{result.formulation} formulation, {result.coulomb} "
                 "normal force")
    return _save(fig, path)


def plot_friction_along_boundary(problem, result, step=-1, path=None):
    """Contact pressure and friction traction along Γc at one load step
    (thesis Fig. 23-27), stick and slip nodes marked."""
    plt = _pyplot()
    xy = problem.nodes[problem.contact_nodes]
    arc = np.r_[0, np.cumsum(np.hypot(*np.diff(xy, axis=0).T))]
    p = result.contact_pressure[step]
    g = result.friction_traction[step]
    bound = result.friction_bound[step]
    stick, slip = result.stick[step], result.slip[step]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.plot(arc, p, "o-", label="contact pressure p = λ / D")
    ax.plot(arc, g, "s-", label="friction traction g_t")
    ax.plot(arc, bound, "k:", label="± f_c p (bound used in the step)")
    ax.plot(arc, -bound, "k:")
    ax.plot(arc[stick], g[stick], "g^", ms=9, label="stick")
    ax.plot(arc[slip], g[slip], "rv", ms=9, label="slip")
    ax.axhline(0.0, color="0.5", lw=0.8)
    ax.set_xlabel("arc length along Γc from its first node [length]")
    ax.set_ylabel("traction [force / length]")
    k = result.steps_completed if step == -1 else step + 1
    ax.set_title(f"step {k} of {result.steps}, f_c = {result.friction:g} "
                 f"({result.formulation}, {result.coulomb})")
    ax.legend(fontsize=8)
    return _save(fig, path)


def write_friction_figures(folder, problem, result):
    """Per-step history; for a mesh also the deformed body and tractions
    along Γc at the last completed step. Returns the paths."""
    import os
    from types import SimpleNamespace

    plt = _pyplot()
    paths = {}
    jobs = [("history", lambda p: plot_step_history(problem, result,
                                                     path=p))]
    if problem.kind == "mesh":
        last = SimpleNamespace(displacement=result.displacement[-1],
                               in_contact=result.in_contact[-1])
        title = (f"deformed body after step {result.steps_completed} of "
                 f"{result.steps}\nf_c = {result.friction:g}, "
                 f"{result.formulation} formulation, {result.method} method")
        jobs += [("deformed", lambda p: plot_deformed(problem, last, path=p,
                                                       title=title)),
                 ("friction_along_gc",
                  lambda p: plot_friction_along_boundary(problem, result,
                                                         path=p))]
    for name, job in jobs:
        path = os.path.join(folder, f"{name}.png")
        plt.close(job(path))
        paths[name] = path
    return paths
