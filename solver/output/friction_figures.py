"""Figures of a friction run (load steps): chosen nodes' histories over the
steps and the tractions along Γc, in the manner of the thesis's Fig. 18-27
(part of :mod:`solver.output.figures`, whose units and conventions hold)."""

import numpy as np

from .figures import (arc_length, legend_outside, pyplot, save_png,
                      carries_load, finish_overview, plot_deformed,
                      write_jobs, zoomed_axes)

__all__ = ["ROUND_OFF", "friction_force", "history_nodes", "tidy_panel",
           "plot_step_history", "plot_friction_along_boundary",
           "write_friction_figures"]

#: Values within this fraction of the largest of their kind over the run
#: (all nodes, all steps) are round-off of the solve and drawn as zero.
ROUND_OFF = 1e-10


def friction_force(problem, result):
    """Nodal friction force per step, (steps, Nc): D_ii g_t (D the lumped
    boundary matrix), signed in 2D, its magnitude D_ii |g_t| in 3D."""
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()
    g = np.nan_to_num(np.asarray(result.friction_traction, float))
    if g.ndim == 3:
        g = np.linalg.norm(g, axis=2)
    return lumped * g


def history_nodes(problem, result):
    """The contact nodes whose histories :func:`plot_step_history` draws, as
    [(position along Γc, why)]: the node with the largest friction force (on
    a symmetric body the node of largest contact force carries only
    round-off), then, for contrast, the one with the largest friction force
    among those that end in the other state (stick or slip); else the node of
    largest contact force."""
    if problem.n_contact == 1:
        return [(0, "the only contact node")]
    force = np.abs(friction_force(problem, result))
    peak = force.max(axis=0)
    if not (peak > ROUND_OFF * np.abs(np.nan_to_num(
            result.contact_force)).max(initial=0.0)).any():
        node = int(np.argmax(np.nan_to_num(result.contact_force).max(axis=0)))
        return [(node, "largest contact force (no node carries friction)")]
    first = int(np.argmax(peak))
    slip = np.asarray(result.slip, bool)[-1]
    stick = np.asarray(result.stick, bool)[-1]
    state = "slips" if slip[first] else "sticks" if stick[first] else "open"
    nodes = [(first, f"largest friction force; {state} at the end")]
    other, word = (stick, "sticks") if slip[first] else (slip, "slips")
    other = other & carries_load(peak) & (np.arange(len(peak)) != first)
    if other.any():
        second = int(np.flatnonzero(other)[np.argmax(peak[other])])
        nodes.append((second, f"{word} at the end, largest friction force "
                              f"of those"))
    return nodes


def tidy_panel(ax, series, scale, unit):
    """Draw nothing unreadable: ``series`` (the arrays of ``ax.lines``) were
    plotted with values within :data:`ROUND_OFF` × ``scale`` set to zero;
    here the y axis loses matplotlib's offset, spans at least 2 % of
    ``scale``, and an all-zero panel says so, with the round-off it hid."""
    ax.ticklabel_format(axis="y", useOffset=False)
    raw = np.concatenate([np.ravel(s) for s in series])
    raw = raw[np.isfinite(raw)]
    clean = np.where(np.abs(raw) <= ROUND_OFF * scale, 0.0, raw)
    if not len(raw) or not scale > 0:
        return
    low, high = clean.min(), clean.max()
    if high - low < 0.02 * scale:
        mid = 0.5 * (low + high)
        ax.set_ylim(mid - 0.01 * scale, mid + 0.01 * scale)
    if not clean.any():
        hidden = np.abs(raw).max()
        text = "zero at every step" if hidden == 0 else (
            f"zero to round-off at every step\n(|values| ≤ {hidden:.2g} "
            f"{unit}, below {ROUND_OFF:g} of the largest)")
        ax.text(0.5, 0.6, text, transform=ax.transAxes, ha="center",
                va="center", fontsize=9, color="0.3")


def plot_step_history(problem, result, node=None, path=None,
                      reference=None):
    """Contact force, friction force and the displacement components of
    contact nodes per load step (thesis Fig. 18-21 for the bar's point A):
    ``node`` a position along Γc or a list of them (default
    :func:`history_nodes`); ``reference``, an array (steps, 4) of (u_x, u_y,
    λ, t) such as the bar's closed form, drawn as a line under the first
    node's points; round-off drawn as zero (:func:`tidy_panel`). In 3D the
    friction panel shows |t| = D |g_t| and a panel u_z is added."""
    plt = pyplot()
    if node is None:
        chosen = history_nodes(problem, result)
    else:
        chosen = [(int(n), "") for n in np.atleast_1d(node)]
    steps = np.arange(1, result.steps_completed + 1)
    dim = np.asarray(result.displacement).shape[-1]
    force = friction_force(problem, result)
    lam = np.nan_to_num(np.asarray(result.contact_force, float))
    u_all = np.asarray(result.displacement, float)
    if problem.kind == "mesh":
        ids = [problem.contact_nodes[n] for n, _ in chosen]
    else:
        ids = [n for n, _ in chosen]
    labels = []
    for (n, why), i in zip(chosen, ids):
        if problem.kind == "mesh":
            where = ", ".join(f"{c:.3g}" for c in problem.nodes[i])
            labels.append(f"node at ({where}) mm" + (f": {why}" if why
                                                      else ""))
        else:
            labels.append("point A" if problem.n_contact == 1
                          else f"contact node {n}")
    names = "xyz"[:dim]
    panels = [("lam", "contact force λ [N]", "Fig. 18: contact force",
               lam, "N"),
              ("t", ("friction force |t| = D |g_t| [N]" if dim == 3 else
                     "friction force t = D g_t [N]"),
               "Fig. 19: friction force", force, "N")]
    panels += [(f"u{c}", f"u_{c} [mm]", (f"Fig. {20 + k}: u_{c}" if k < 2
                                         else f"u_{c}"), u_all[..., k],
                "mm") for k, c in enumerate(names)]
    if dim == 2:
        fig, grid = plt.subplots(2, 2, figsize=(10, 7), sharex=True,
                                 layout="constrained")
        axes = dict(zip(("lam", "t", "ux", "uy"), grid.ravel()))
        bottom = grid[1]
    else:
        fig, axes = plt.subplot_mosaic(
            [["lam"] * 3 + ["t"] * 3, ["ux", "ux", "uy", "uy", "uz", "uz"]],
            figsize=(12, 7), sharex=True, layout="constrained")
        bottom = [axes["ux"], axes["uy"], axes["uz"]]
    order = {"ux": 0, "uy": 1, "lam": 2, "t": 3}  # reference columns
    for key, ylabel, title, values, unit in panels:
        ax = axes[key]
        scale = np.abs(np.nan_to_num(values)).max(initial=0.0)
        column = (values[:, list(ids)] if key.startswith("u")
                  else values[:, [n for n, _ in chosen]])
        series = []
        for k, label in enumerate(labels):
            y = column[:len(steps), k]
            series.append(y)
            y = np.where(np.abs(y) <= ROUND_OFF * scale, 0.0, y)
            ax.plot(steps, y, "o", ms=4, mfc="none", mew=0.8,
                    color=f"C{k}", zorder=2,
                    label="computed" if reference is not None else label)
        if reference is not None and key in order:
            ax.plot(steps, np.asarray(reference)[:len(steps), order[key]],
                    "-", color="k", lw=1.2, zorder=3, label="closed form")
        tidy_panel(ax, series, scale, unit)
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=10)
        ax.grid(alpha=0.3)
    first = axes["lam"]
    if reference is not None or len(labels) > 1:
        fig.legend(*first.get_legend_handles_labels(), loc="outside "
                   "lower center", ncols=2 if reference is not None else 1,
                   fontsize=9)
    for ax in bottom:
        ax.set_xlabel("load step κ")
    settings = (f"f_c = {result.friction:g}, {result.steps} steps, "
                f"{result.formulation} formulation, {result.coulomb} normal "
                "force")
    fig.suptitle(f"{labels[0]}: {settings}" if len(labels) == 1
                 and problem.kind != "mesh" else f"{labels[0]}\n{settings}"
                 if len(labels) == 1 else settings, fontsize=11)
    return save_png(fig, path)


def plot_friction_along_boundary(problem, result, step=-1, path=None):
    """Contact pressure and friction traction along Γc at one load step
    (thesis Fig. 23-27), stick and slip nodes marked, zoomed as
    :func:`.figures.zoomed_axes`."""
    plt = pyplot()
    arc, label = arc_length(problem)
    p = np.asarray(result.contact_pressure[step], float)
    g = np.asarray(result.friction_traction[step], float)
    bound = np.asarray(result.friction_bound[step], float)
    stick = np.asarray(result.stick[step], bool)
    slip = np.asarray(result.slip[step], bool)
    loaded = (stick | slip | carries_load(p) | carries_load(g)) \
        if problem.kind == "mesh" else np.zeros(len(p), bool)
    fig, ax, whole, window = zoomed_axes(plt, arc, loaded, (9, 4.5))
    for target in filter(None, (ax, whole)):
        small = target is whole
        target.plot(arc, p, "o-", ms=3 if small else 5,
                    label="contact pressure\np = λ / D")
        target.plot(arc, g, "s-", ms=3 if small else 4,
                    label="friction traction g_t")
        target.plot(arc, bound, "k:", label="± f_c p (bound used\nin the "
                    "step)")
        target.plot(arc, -bound, "k:")
        if not small:
            target.plot(arc[stick], g[stick], "g^", ms=9, mfc="none",
                        mew=1.5, label="stick")
            target.plot(arc[slip], g[slip], "rv", ms=9, mfc="none",
                        mew=1.5, label="slip")
        target.axhline(0.0, color="0.5", lw=0.8)
    ax.set_xlabel(label)
    ax.set_ylabel("traction [MPa]")
    ax.grid(alpha=0.3)
    k = result.steps_completed if step == -1 else step + 1
    ax.set_title(f"step {k} of {result.steps}, f_c = {result.friction:g} "
                 f"({result.formulation}, {result.coulomb})", fontsize=10)
    if whole is not None:
        finish_overview(ax, whole, window, label, "traction [MPa]")
    legend_outside(ax, "right")
    return save_png(fig, path)


def write_friction_figures(folder, problem, result):
    """Per-step history; for a 2D mesh also the deformed body and
    tractions along Γc at the last completed step (3D: the history only;
    the tractions are in the VTU steps). Returns the paths."""
    from types import SimpleNamespace

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
    return write_jobs(folder, jobs)
