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
(:func:`solver.verification.sphere_flat_contact`)."""

import numpy as np

from .verification import (contact_radius_from_moment, fit_hertz_profile,
                           hertz_point_contact, hertz_pressure)

__all__ = ["hertz_sphere_row", "HERTZ_COLUMNS"]

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
