"""Outputs of a two-body (mortar) solve, :mod:`solver.contact.two_body`:
the arrays and VTK fields of docs/results.md ("Two bodies, added"; both
bodies in one ``result.vtu``, cell data ``body``), and the figures of the
interface pressure λ_j and traction along the slave surface and of the
deformed bodies."""

import numpy as np

from .figures import pyplot, save_png
from .folder import atomic_path

__all__ = ["RESULT_KEYS", "write_two_body_result", "write_two_body_vtk",
           "plot_interface", "plot_bodies", "write_two_body_figures"]

#: The arrays of result.npz (those present in the result).
RESULT_KEYS = ("u", "v", "displacement", "contact_force", "contact_pressure",
               "contact_pressure_consistent", "contact_pressure_patch",
               "friction_traction",
               "friction_bound", "traction", "normal", "gap",
               "weighted_gap", "mortar_D", "covered", "in_contact", "stick",
               "slip", "load_factor", "body", "normal_displacement",
               "tangential_displacement")


def _last(result, key):
    """The last step's values of a friction run, else the array."""
    value = np.asarray(result[key])
    return value[-1] if result.get("records") is not None else value


def write_two_body_result(path, result, problem):
    """``result.npz`` of a frictionless solve (atomically): the arrays of
    a rigid obstacle's (:func:`~solver.output.files.result_arrays`,
    the Newton history included) and the interface's."""
    from .files import result_arrays, write_arrays

    arrays = result_arrays(result, problem)
    arrays.update({key: np.asarray(result[key]) for key in RESULT_KEYS
                   if result.get(key) is not None})
    write_arrays(path, arrays)


def write_two_body_vtk(path, result, problem):
    """``result.vtu``: both bodies, cell data ``body``."""
    import meshio

    from .vtk import vtk_cells, on_nodes, vtk_points, vtk_vectors

    n = len(problem.nodes)
    body = np.asarray(result.body)
    data = {"u": vtk_vectors(_last(result, "displacement"), n), "body": body,
            "traction": vtk_vectors(on_nodes(problem, _last(result,
                                                          "traction")), n),
            "contact_pressure": on_nodes(problem, _last(result,
                                                         "contact_pressure")),
            "in_contact": on_nodes(problem, _last(result, "in_contact"), 0,
                                    np.int32),
            "initial_gap": on_nodes(problem, result.gap, np.nan)}
    mesh = meshio.Mesh(vtk_points(problem), vtk_cells(problem), point_data=data,
                       cell_data={"body": [body[problem.cells[:, 0]]]})
    with atomic_path(path) as tmp:
        meshio.write(tmp, mesh, file_format="vtu")


def plot_interface(problem, result, path=None, reference=None):
    """λ_j and the traction components (normal −λ, tangential g_t) along the
    slave surface, with an optional ``reference`` (s, p) curve dashed (e.g.
    Hertz's); zoomed as :func:`.figures.zoomed_axes`."""
    from .figures import (legend_outside, carries_load, finish_overview,
                          zoomed_axes)

    plt = pyplot()
    xy = problem.nodes[problem.contact_nodes]
    arc = np.r_[0, np.cumsum(np.hypot(*np.diff(xy, axis=0).T))]
    pressure = np.asarray(_last(result, "contact_pressure"), float)
    covered = np.asarray(result.covered, bool)
    friction = result.get("friction_traction") is not None
    tangential = (np.asarray(_last(result, "friction_traction"), float)
                  if friction else np.zeros_like(pressure))
    loaded = covered & (carries_load(pressure) | carries_load(tangential)
                        | np.asarray(_last(result, "in_contact"), bool))
    fig, ax, whole, window = zoomed_axes(plt, np.where(covered, arc, np.nan),
                                         loaded, (8.5, 3.8))
    for target in filter(None, (ax, whole)):
        ms = 2 if target is whole else 3
        target.plot(arc[covered], pressure[covered], "o-", ms=ms,
                    label="pressure λ_j (dual multiplier)")
        if friction:
            target.plot(arc[covered], tangential[covered], "s-", ms=ms,
                        label="tangential traction g_t")
        if reference is not None:
            target.plot(*reference, "k--", lw=1, label="reference")
        target.axhline(0.0, color="0.5", lw=0.8)
    xlabel = "arc length along the slave surface [mm]"
    ax.set_xlabel(xlabel)
    ax.set_ylabel("traction on the slave body [MPa]")
    ax.set_title(f"interface ({result.variant}): "
                 f"{int(np.sum(_last(result, 'in_contact')))} of "
                 f"{int(covered.sum())} slave nodes in contact", fontsize=10)
    ax.grid(alpha=0.3)
    if whole is not None:
        finish_overview(ax, whole, window, xlabel, "traction [MPa]",
                        what="the whole slave surface")
    legend_outside(ax, "right")
    return save_png(fig, path)


def plot_bodies(problem, result, path=None):
    """Both bodies deformed at true scale (a magnified drawing would show
    the bodies overlapping), coloured by body, the undeformed meshes faint;
    right: the interface zoomed, the deformed slave and master segments and
    the slave nodes in contact (stretched axes). Lengths in mm."""
    plt = pyplot()
    displacement = _last(result, "displacement")
    moved = problem.nodes + displacement
    fig, (ax, zoom) = plt.subplots(1, 2, figsize=(11, 5),
                                   layout="constrained")
    body = np.asarray(result.body)[problem.cells[:, 0]]
    colours = ("tab:blue", "tab:orange", "tab:green", "tab:red")
    names = [b.get("name", f"body {i}") if isinstance(b, dict)
             else f"body {i}" for i, b in enumerate(
                 (problem.meta or {}).get("bodies", []))]
    ax.triplot(*problem.nodes.T, problem.cells, color="0.85", lw=0.3)
    ax.plot([], [], color="0.85", label="undeformed")
    for b, colour in zip(np.unique(body), colours):
        ax.triplot(*moved.T, problem.cells[body == b], color=colour, lw=0.4)
        name = names[b] if b < len(names) else f"body {b}"
        ax.plot([], [], color=colour, label=f"{name}, deformed")
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title("deformed bodies (true scale)", fontsize=10)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(0.0, -0.12),
              ncols=3, borderaxespad=0.0)
    for segments, colour, label in (
            (problem.mortar_slave, "tab:blue", "slave surface"),
            (problem.mortar_master, "tab:red", "master surface")):
        for a, b in segments:
            zoom.plot(*moved[[a, b]].T, color=colour, lw=1)
        zoom.plot([], [], color=colour, label=label)
    contact = np.asarray(_last(result, "in_contact"), bool)
    touching = moved[problem.contact_nodes[contact]]
    zoom.plot(*touching.T, "k.", ms=4, label="slave nodes in contact")
    if len(touching):
        low, high = touching.min(axis=0), touching.max(axis=0)
        span = (high - low).max() + 1e-12
        across = max((high - low).min(), 0.02 * span)
        axis = int(np.argmax(high - low))             # along the interface
        limits = [(low[k] - 0.5 * span, high[k] + 0.5 * span) if k == axis
                  else (low[k] - 4 * across, high[k] + 4 * across)
                  for k in (0, 1)]
        zoom.set_xlim(*limits[0])
        zoom.set_ylim(*limits[1])
    zoom.set_xlabel("x [mm]")
    zoom.set_ylabel("y [mm]")
    zoom.set_title("interface, deformed (stretched axes)", fontsize=10)
    zoom.legend(fontsize=8)
    return save_png(fig, path)


def write_two_body_figures(folder, problem, result):
    """interface.png and bodies.png in ``folder``; returns their paths."""
    import os

    paths = {name: os.path.join(folder, f"{name}.png")
             for name in ("interface", "bodies")}
    plt = pyplot()
    for name, plot in (("interface", plot_interface),
                       ("bodies", plot_bodies)):
        plt.close(plot(problem, result, paths[name]))
    return paths
