r"""Figures of a 3D two-body (mortar) solve: the interface pressure λ_j
against the distance from the contact axis, with Hertz's profile for two
spheres (1/R* = 1/R₁ + 1/R₂, 1/E* = Σ (1 − ν_b²)/E_b, a = (3PR*/(4E*))^⅓,
p₀ = 3P/(2πa²); Johnson, *Contact Mechanics*, §4.2) when the problem's
``meta`` gives the bodies' ``radii``; and a map of the slave surface in
the interface plane: open, stick and slip nodes (friction) or the
pressure (frictionless)."""

import os

import numpy as np

from ..verification import hertz_two_spheres
from .figures import pyplot, save_png
from .figures3d import contact_radius, pressure_vs_radius

__all__ = ["two_sphere_reference", "interface_frame", "plot_interface3d",
           "plot_stick_slip_map", "write_two_body_figures3d"]


def _last(result, key):
    value = np.asarray(result[key])
    return value[-1] if result.get("records") is not None else value


def two_sphere_reference(meta, P):
    """(a, p₀) of Hertz for two spheres pressed by the force P of the model
    (the whole pair's: P / ``meta["fraction"]``, ¼ for a quarter model),
    from ``meta["radii"]`` (one per body) and ``meta["bodies"]`` (E, ν);
    None when the radii are not given or P ≤ 0."""
    radii = (meta or {}).get("radii")
    bodies = (meta or {}).get("bodies")
    if not radii or not bodies or not P > 0:
        return None
    P = P / float((meta or {}).get("fraction", 1.0))  # the whole pair's
    return hertz_two_spheres(P, radii, [(b["E"], b["nu"]) for b in bodies])


def interface_frame(problem, result):
    """(centre, normal, tangents (2, 3)) of the loaded interface:
    ``meta["contact_center"]`` and ``meta["contact_axis"]`` if given (a
    quarter model's), else the pressure-weighted mean of the slave nodes
    (their positions if none carries load) and the D-weighted mean slave
    normal."""
    meta = problem.meta or {}
    points = problem.nodes[problem.contact_nodes]
    p = np.nan_to_num(np.asarray(_last(result, "contact_pressure"), float))
    D = np.asarray(result.mortar_D, float)
    force = D * np.maximum(p, 0.0)
    centre = (force @ points / force.sum() if force.sum() > 0
              else points.mean(axis=0))
    normal = (D[:, None] * np.asarray(result.normal, float)).sum(axis=0)
    if meta.get("contact_center") is not None:
        centre = np.asarray(meta["contact_center"], float)
    if meta.get("contact_axis") is not None:
        normal = np.asarray(meta["contact_axis"], float)
    normal /= np.linalg.norm(normal)
    helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
    t1 = np.cross(normal, helper)
    t1 /= np.linalg.norm(t1)
    return centre, normal, np.stack([t1, np.cross(normal, t1)])


def plot_interface3d(problem, result, path=None):
    """λ_j of the covered slave nodes against their distance from the
    contact axis (:func:`interface_frame`), with Hertz's curve for two
    spheres (:func:`two_sphere_reference`) at the computed normal force."""
    centre, normal, _ = interface_frame(problem, result)
    points = problem.nodes[problem.contact_nodes]
    covered = np.asarray(result.covered, bool)
    p = np.nan_to_num(np.asarray(_last(result, "contact_pressure"), float))
    P = float(np.asarray(result.mortar_D) @ p)
    r = contact_radius(points, p, centre, normal)
    reference = two_sphere_reference(problem.meta, P)
    a, p0 = reference if reference is not None else (None, None)
    return pressure_vs_radius(
        path, r[covered], p[covered], a=a, p0=p0, zoom=True,
        xlabel="distance from the contact axis r [mm]",
        title=f"interface pressure λ_j (dual mortar), normal force "
              f"{P:.4g} N (the model's)" + ("" if reference is None else
                                            "; Hertz for two spheres"))


def plot_stick_slip_map(problem, result, path=None):
    """The slave nodes in the interface plane (coordinates along
    :func:`interface_frame`'s tangents): open nodes grey, stick blue, slip
    red with the friction traction as arrows (friction), or coloured by λ_j
    (frictionless)."""
    plt = pyplot()
    centre, _, tangents = interface_frame(problem, result)
    xy = (problem.nodes[problem.contact_nodes] - centre) @ tangents.T
    covered = np.asarray(result.covered, bool)
    contact = np.asarray(_last(result, "in_contact"), bool) & covered
    fig, ax = plt.subplots(figsize=(6.2, 5.4), layout="constrained")
    ax.plot(*xy[~contact].T, ".", color="0.75", ms=3, label="open")
    if result.get("friction_traction") is not None:
        stick = np.asarray(_last(result, "stick"), bool) & contact
        slip = np.asarray(_last(result, "slip"), bool) & contact
        ax.plot(*xy[stick].T, "o", color="tab:blue", ms=3,
                label=f"stick ({int(stick.sum())})")
        ax.plot(*xy[slip].T, "o", color="tab:red", ms=3,
                label=f"slip ({int(slip.sum())})")
        traction = np.asarray(_last(result, "traction"), float)
        t = traction[contact] @ tangents.T
        ax.quiver(*xy[contact].T, *t.T, color="0.3", width=0.002)
        title = "stick and slip on the slave surface (friction traction)"
    else:
        p = np.asarray(_last(result, "contact_pressure"), float)
        shown = p[contact]
        low, high = (shown.min(), shown.max()) if len(shown) else (0, 1)
        if high - low < 0.02 * max(abs(high), 1e-300):  # uniform: no noise
            low, high = 0.99 * low, 1.01 * high  # of round-off in colour
        dots = ax.scatter(*xy[contact].T, c=shown, s=10, cmap="viridis",
                          vmin=low, vmax=high)
        bar = fig.colorbar(dots, ax=ax, label="pressure λ_j [MPa]",
                           shrink=0.8)
        bar.formatter.set_useOffset(False)
        bar.update_ticks()
        title = "interface pressure on the slave surface"
    ax.set_aspect("equal")
    if contact.any():
        span = np.ptp(xy[contact], axis=0).max() * 0.75 + 1e-12
        mid = 0.5 * (xy[contact].min(axis=0) + xy[contact].max(axis=0))
        ax.set_xlim(mid[0] - span, mid[0] + span)
        ax.set_ylim(mid[1] - span, mid[1] + span)
    ax.set_xlabel("in-plane coordinate 1 [mm]")
    ax.set_ylabel("in-plane coordinate 2 [mm]")
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8, loc="upper right")
    return save_png(fig, path)


def write_two_body_figures3d(folder, problem, result):
    """interface_pressure.png and interface_map.png in ``folder``; their
    paths by name."""
    paths = {name: os.path.join(folder, f"{name}.png")
             for name in ("interface_pressure", "interface_map")}
    plt = pyplot()
    for name, plot in (("interface_pressure", plot_interface3d),
                       ("interface_map", plot_stick_slip_map)):
        plt.close(plot(problem, result, paths[name]))
    return paths
