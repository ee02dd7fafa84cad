r"""The Hertz sphere study: one row per mesh, measured against Hertz's
closed form (Johnson, *Contact Mechanics*, 1985, §4.2;
:mod:`solver.verification`).

The quarter model (``sfepy_problems/hertz_sphere.py``) is pressed by a
prescribed approach; its total force is then a result, P = 4 Σ λ_i
ν_i·(−e_z), and Hertz's a and p0 follow from that P. The contact radius is
measured from the first moment of the nodal contact forces (no fit) and by
a least-squares fit of p0 √(1 − r²/a²) through the nodal pressures: the
lumped λ_i/D_ii (exact for a uniform pressure) or, with ``pressure=``, the
consistent M⁻¹λ, an L² projection that overshoots where Hertz's profile
has an infinite slope, at r = a (``notebooks/three_d.ipynb``). Hertz's
paraboloid is itself off a true sphere by O((a/R)²)
(:func:`solver.verification.sphere_flat_contact`).

The 3D two-body checks: Hertz for two spheres, Cattaneo–
Mindlin's stick radius for two identical spheres, and Coulomb's law on the
totals at full slip, each from a problem and a result of
:func:`solver.solve`, as a dict. Forces on the model: the slave's contact
forces D_jj λ_j (normal) and D_jj g_t,j (friction), summed as vectors from
the slave tractions (``result.traction``); a quarter or half model's totals
are the whole pair's times ``meta["fraction"]``, ratios the whole pair's."""

import numpy as np

from .verification import (cattaneo_mindlin_stick_radius,
                           contact_radius_from_moment, fit_hertz_profile,
                           hertz_point_contact, hertz_pressure,
                           hertz_two_spheres)

__all__ = ["hertz_sphere_row", "HERTZ_COLUMNS", "interface_force",
           "hertz_checks", "stick_radius_checks", "full_slip_checks"]

#: Columns of :func:`hertz_sphere_row`, in order.
HERTZ_COLUMNS = ("a/h", "DOFs", "in contact", "P", "a Hertz",
                 "a moment err %", "a fit err %", "p0 fit err %",
                 "max p err %", "RMS/p0 %")


def hertz_sphere_row(problem, result, pressure="contact_pressure"):
    """The study's measurements of one solve of a Hertz sphere export.

    ``pressure``: the result's nodal pressure used for the fit, the peak
    and the RMS (``"contact_pressure"``, lumped λ_i/D_ii, or
    ``"contact_pressure_consistent"``, M⁻¹λ). Errors are relative to
    Hertz's values for the computed P, in per cent; the RMS deviation is
    over the nodes inside Hertz's contact circle, relative to p0."""
    meta = problem.meta
    quarter = 4.0 if meta.get("quarter") else 1.0
    lam = np.nan_to_num(np.asarray(result.contact_force, float))
    down = -np.nan_to_num(np.asarray(result.normal, float))[:, 2]
    P = quarter * float(lam @ down)
    a, p0 = hertz_point_contact(P, meta["R"], meta["E"], meta["nu"])
    points = problem.nodes[problem.contact_nodes]
    center = np.asarray(meta.get("contact_center", [0.0, 0.0, 0.0]), float)
    r = np.hypot(points[:, 0] - center[0], points[:, 1] - center[1])
    p = np.nan_to_num(np.asarray(result[pressure], float))
    a_fit, p0_fit = fit_hertz_profile(r, p, (a, p0))
    inside = r < a
    rms = np.sqrt(np.mean((p[inside] - hertz_pressure(r[inside], a, p0))
                          ** 2))
    values = (float(meta.get("a_h", np.nan)), int(problem.n_dofs),
              int(np.count_nonzero(result.in_contact == 1)), P, a,
              100 * (contact_radius_from_moment(r, lam) / a - 1),
              100 * (a_fit / a - 1), 100 * (p0_fit / p0 - 1),
              100 * (p.max() / p0 - 1), 100 * rms / p0)
    return dict(zip(HERTZ_COLUMNS, values))


def _last(result, key):
    value = np.asarray(result[key])
    return value[-1] if result.get("records") is not None else value


def interface_force(result):
    """Σ_j D_jj t_j: the contact force on the slave body (d,), t the slave
    traction −λ n + Σ g_t τ of the (last) step."""
    D = np.asarray(result.mortar_D)
    return (D[:, None] * _last(result, "traction")).sum(axis=0)


def _axis(problem):
    meta = problem.meta or {}
    centre = np.asarray(meta.get("contact_center", (0.0, 0.0, 0.0)), float)
    axis = np.asarray(meta.get("contact_axis", (0.0, 0.0, 1.0)), float)
    return centre, axis / np.linalg.norm(axis)


def hertz_checks(problem, result):
    """Two spheres against Hertz (``meta``: ``radii``, ``bodies``,
    ``fraction``, ``contact_center``, ``contact_axis``): P of the pair,
    Hertz's a and p0 for it, and the relative errors of a from the first
    moment of the nodal forces, of (a, p0) fitted together to the nodal
    pressures λ_j, and of the largest λ_j; a/h from ``meta["h_contact"]``.
    Where the largest λ_j lies (``max_p_r``, r/a) and the nodes' scatter
    about Hertz's profile inside 0.9 a (``nodal_rms`` and
    ``nodal_max``, |λ_j − p_Hertz(r_j)| / p0) tell a peak at the axis from
    one node's scatter (a node of an irregular patch). The same fit,
    largest value, its place and scatter of the patch-recovered pressure
    p̄_j (``result.contact_pressure_patch``,
    :func:`solver.geometry.mortar.patch_pressure`) end in ``_patch``."""
    meta = problem.meta
    centre, axis = _axis(problem)
    D = np.asarray(result.mortar_D)
    lam = np.asarray(_last(result, "contact_pressure"), float)
    covered = np.asarray(result.covered, bool)
    P = float(D @ lam) / float(meta.get("fraction", 1.0))
    a, p0 = hertz_two_spheres(P, meta["radii"],
                              [(b["E"], b["nu"]) for b in meta["bodies"]])
    d = problem.nodes[problem.contact_nodes] - centre
    r = np.linalg.norm(d - np.outer(d @ axis, axis), axis=1)
    a_moment = contact_radius_from_moment(r, D * lam)
    inside = covered & (r < 0.9 * a)
    checks = dict(P=P, a=a, p0=p0, a_over_h=a / meta["h_contact"],
                  in_contact=int(np.sum(_last(result, "in_contact"))),
                  a_moment=a_moment / a - 1)
    pressures = {"": lam}
    if result.get("contact_pressure_patch") is not None:
        pressures["_patch"] = np.asarray(_last(result,
                                               "contact_pressure_patch"))
    for end, p in pressures.items():
        a_fit, p0_fit = fit_hertz_profile(r[covered], p[covered], (a, p0))
        scatter = (p[inside] - hertz_pressure(r[inside], a, p0)) / p0
        checks.update({
            "a_fit" + end: a_fit / a - 1, "p0_fit" + end: p0_fit / p0 - 1,
            "max_p" + end: p.max() / p0 - 1,
            "max_p_r" + end: float(r[np.argmax(p)] / a),
            "nodal_rms" + end: float(np.sqrt(np.mean(scatter ** 2))),
            "nodal_max" + end: float(np.abs(scatter).max(initial=0.0))})
    return checks


def stick_radius_checks(problem, result, friction):
    """Two identical spheres pressed, then sheared (a half model, y ≥ 0):
    Q/(f_c P) of the last step, Hertz's a for P, Cattaneo–Mindlin's
    c = a(1 − Q/(f_c P))^⅓, and two estimates of the computed stick
    radius about the stick nodes' D-weighted centre (on y = 0): the
    midpoint between the outermost stick and the innermost slip node
    (``c_indicator``) and √(Σ_stick D_jj / (fraction · π)) (``c_area``),
    with their relative errors, and the centre's shift along x over a."""
    meta = problem.meta
    force = interface_force(result)
    centre, axis = _axis(problem)
    P = abs(force @ axis)
    Q = np.linalg.norm(force - (force @ axis) * axis)
    fraction = float(meta.get("fraction", 1.0))
    a, _ = hertz_two_spheres(P / fraction, meta["radii"],
                             [(b["E"], b["nu"]) for b in meta["bodies"]])
    c = cattaneo_mindlin_stick_radius(a, Q, P, friction)
    D = np.asarray(result.mortar_D)
    covered = np.asarray(result.covered, bool)
    stick = np.asarray(_last(result, "stick"), bool) & covered
    slip = np.asarray(_last(result, "slip"), bool) & covered
    x = problem.nodes[problem.contact_nodes]
    middle = (D[stick] @ x[stick]) / D[stick].sum()
    middle[1] = centre[1]                       # on the symmetry plane
    d = x - middle
    r = np.linalg.norm(d - np.outer(d @ axis, axis), axis=1)
    c_indicator = 0.5 * (r[stick].max() + r[slip].min())
    c_area = np.sqrt(D[stick].sum() / (fraction * np.pi))
    return dict(P=P / fraction, Q=Q / fraction, ratio=Q / (friction * P),
                a=a, c=c, c_indicator=c_indicator / c - 1,
                c_area=c_area / c - 1, shift=(middle[0] - centre[0]) / a,
                stick=int(stick.sum()), slip=int(slip.sum()),
                separated=bool(r[stick].max() < r[slip].min()))


def full_slip_checks(result, friction):
    """Coulomb's law on the totals of the last step: the resultant friction
    force |Σ D_jj g_t,j| over f_c times the normal force Σ D_jj λ_j of the
    bound (this step's λ with the implicit bound, the previous step's
    with the lagged one: Σ D_jj bound_j / f_c), minus 1; and whether every
    covered slave node slips."""
    D = np.asarray(result.mortar_D)
    g = np.asarray(result.friction_traction)[-1]
    bound = np.asarray(result.friction_bound)[-1]
    total = np.linalg.norm((D[:, None] * g.reshape(len(D), -1)).sum(axis=0))
    covered = np.asarray(result.covered, bool)
    return dict(friction_force=total, normal_force=float(D @ bound)
                / friction, ratio=total / float(D @ bound) - 1,
                all_slip=bool(np.asarray(result.slip)[-1][covered].all()))
