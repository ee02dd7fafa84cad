"""Figures of a friction run (load steps): one node's history over the
steps and the tractions along Γc, in the manner of the thesis's Fig. 18-27
(part of :mod:`solver.output.figures`, whose units and conventions hold).
"""

import numpy as np

from .figures import (_arc_length, _legend_outside, _pyplot, _save,
                      plot_deformed)

__all__ = ["plot_step_history", "plot_friction_along_boundary",
           "write_friction_figures"]


def plot_step_history(problem, result, node=None, path=None,
                      reference=None):
    """Contact force, friction force, u_x and u_y of one contact node per
    load step (thesis Fig. 18-21 for the bar's point A).

    ``node`` is a position along Γc; default: the node with the largest
    final contact force (for the bar, its only node A). ``reference``, an
    array (steps, 4) of (u_x, u_y, λ, t) such as the bar's closed form, is
    drawn as a line over the computed points (hollow markers).
    """
    plt = _pyplot()
    if node is None:
        node = int(np.argmax(result.contact_force[-1]))
    steps = np.arange(1, result.steps_completed + 1)
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()[node]
    if problem.kind == "mesh":
        u = result.displacement[:, problem.contact_nodes[node]]
        where = problem.nodes[problem.contact_nodes[node]]
        label = f"contact node at ({where[0]:.3g}, {where[1]:.3g}) mm"
    else:
        u = result.displacement[:, node]
        label = "point A"
    fig, axes = plt.subplots(2, 2, figsize=(10, 7), sharex=True,
                             layout="constrained")
    panels = [
        (axes[0, 0], result.contact_force[:, node], "contact force λ [N]",
         "Fig. 18: contact force"),
        (axes[0, 1], lumped * result.friction_traction[:, node],
         "friction force t = D g_t [N]", "Fig. 19: friction force"),
        (axes[1, 0], u[:, 0], "u_x [mm]", "Fig. 20: u_x"),
        (axes[1, 1], u[:, 1], "u_y [mm]", "Fig. 21: u_y")]
    order = (2, 3, 0, 1)  # reference columns of the four panels
    for i, (ax, values, ylabel, title) in enumerate(panels):
        ax.plot(steps, values, "o", ms=4, mfc="none", mew=0.8, color="C0",
                zorder=2, label="computed")
        if reference is not None:
            ax.plot(steps, np.asarray(reference)[:len(steps), order[i]],
                    "-", color="k", lw=1.2, zorder=3, label="closed form")
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=10)
        ax.grid(alpha=0.3)
    if reference is not None:
        fig.legend(*axes[0, 0].get_legend_handles_labels(), loc="outside "
                   "lower center", ncols=2, fontsize=9)
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
    arc, label = _arc_length(problem)
    p = result.contact_pressure[step]
    g = result.friction_traction[step]
    bound = result.friction_bound[step]
    stick, slip = result.stick[step], result.slip[step]
    fig, ax = plt.subplots(figsize=(9, 4.5), layout="constrained")
    ax.plot(arc, p, "o-", ms=5, label="contact pressure\np = λ / D")
    ax.plot(arc, g, "s-", ms=4, label="friction traction g_t")
    ax.plot(arc, bound, "k:", label="± f_c p (bound used\nin the step)")
    ax.plot(arc, -bound, "k:")
    ax.plot(arc[stick], g[stick], "g^", ms=9, mfc="none", mew=1.5,
            label="stick")
    ax.plot(arc[slip], g[slip], "rv", ms=9, mfc="none", mew=1.5,
            label="slip")
    ax.axhline(0.0, color="0.5", lw=0.8)
    ax.set_xlabel(label)
    ax.set_ylabel("traction [MPa]")
    ax.grid(alpha=0.3)
    k = result.steps_completed if step == -1 else step + 1
    ax.set_title(f"step {k} of {result.steps}, f_c = {result.friction:g} "
                 f"({result.formulation}, {result.coulomb})", fontsize=10)
    _legend_outside(ax, "right")
    return _save(fig, path)


def write_friction_figures(folder, problem, result):
    """Per-step history; for a 2D mesh also the deformed body and
    tractions along Γc at the last completed step (3D: the history only;
    the tractions are in the VTU steps). Returns the paths."""
    import os
    from types import SimpleNamespace

    plt = _pyplot()
    paths = {}
    jobs = [("history", lambda p: plot_step_history(problem, result,
                                                     path=p))]
    if problem.kind == "mesh" and getattr(problem, "dim", 2) == 2:
        last = SimpleNamespace(displacement=result.displacement[-1],
                               in_contact=result.in_contact[-1])
        title = (f"deformed body after step {result.steps_completed} of "
                 f"{result.steps}: f_c = {result.friction:g}, "
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
