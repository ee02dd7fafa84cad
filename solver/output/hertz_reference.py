r"""Which Hertz curve a 3D solve's pressure figure may draw, and why.

Hertz's point contact (Johnson, *Contact Mechanics*, 1985, §4.2) needs the
whole body's force P, the relative radius of curvature R at the first
contact, E* and the contact's axis. A problem file states R, E and ν in its
``meta``; the rest is read from the problem itself, so that a user-built
half or quarter model gets the shipped one's curve, and a problem that
does not fix them gets no curve (never a wrong one):

* **Symmetry planes** (:func:`symmetry_planes`): with n mirror planes of
  rollers the whole body is 2ⁿ copies of the model, P = 2ⁿ Σ_i λ_i ν_i·e
  (e the contact axis).
* **Centre and axis** (:func:`first_contact`): near the first contact the
  initial gap is quadratic in the tangent plane, g = g* + (ξ − ξ*)ᵀA(ξ −
  ξ*); the nodes of smallest gap, mirrored in the planes, give A and the
  vertex ξ* by least squares; the centre is the obstacle point there, the
  curvature radii 1/(2 eig A).
* **R**: ``meta["R"]``, combined with a sphere obstacle's (1/R* = 1/R +
  1/R_o), accepted only if both curvature radii agree with R* within
  :data:`R_TOLERANCE`. Keys a problem file may add (``quarter``, ``half``,
  ``contact_center``) are only compared with what was derived."""

from dataclasses import dataclass

import numpy as np

from ..geometry.frames import ROLLER_TOLERANCE

__all__ = ["R_TOLERANCE", "HertzReference", "symmetry_planes",
           "first_contact", "hertz_reference"]

#: Relative difference allowed between meta R (or R* with a spherical
#: obstacle) and each curvature radius of the initial gap.
R_TOLERANCE = 0.1


@dataclass(frozen=True)
class HertzReference:
    """What the pressure-against-radius figure draws: ``center`` and
    ``axis`` of the contact (None when the first contact is not a point),
    the symmetry ``planes`` (k, c) and the model's ``copies`` in the whole
    body (2 ** len(planes)), the whole body's ``force`` P along the axis,
    the ``radius`` R* used and the gap's ``curvature_radii``, Hertz's ``a``
    and ``p0`` (None: no curve), and a ``note`` for the title: why the
    curve is drawn as it is, or why not."""

    center: np.ndarray = None
    axis: np.ndarray = None
    planes: tuple = ()
    copies: int = 1
    force: float = None
    radius: float = None
    curvature_radii: tuple = ()
    a: float = None
    p0: float = None
    note: str = ""

    @property
    def drawn(self):
        """Whether a Hertz curve is drawn."""
        return self.a is not None


def _field(result, key):
    """``result[key]`` of a mapping (a solve's result), else the
    attribute; None when absent."""
    if isinstance(result, dict):
        return result.get(key)
    return getattr(result, key, None)


def _size(problem):
    return float(np.ptp(problem.nodes, axis=0).max())


def symmetry_planes(problem, normal=None, tol=1e-9):
    """The symmetry planes of a half or quarter model, from its rollers:
    a tuple of (k, c), one per axis k along which some contact nodes have
    their only Dirichlet component, all of them on the plane x_k = c (to
    ``tol`` times the model's size). Given the contact ``normal`` (Nc, d)
    of a solve, a group whose normals have a component along its fixed
    axis is a support, not a mirror, and is skipped."""
    fixed = np.asarray(problem.contact_dofs) < 0
    points = problem.nodes[problem.contact_nodes]
    only = fixed.sum(axis=1) == 1
    planes = []
    for k in range(fixed.shape[1]):
        on = only & fixed[:, k]
        if not on.any():
            continue
        if normal is not None and (np.abs(np.asarray(normal)[on, k])
                                   > ROLLER_TOLERANCE).any():
            continue
        values = points[on, k]
        if np.ptp(values) <= tol * _size(problem):
            planes.append((k, float(values.mean())))
    return tuple(planes)


def _tangents(axis):
    """Two unit vectors completing ``axis`` to an orthonormal basis."""
    helper = np.eye(3)[np.argmin(np.abs(axis))]
    t1 = np.cross(axis, helper)
    t1 /= np.linalg.norm(t1)
    return t1, np.cross(axis, t1)


def first_contact(points, gap, normal, planes=(), in_contact=None,
                  least=12):
    """Where a smooth convex contact starts: the vertex of the initial gap
    (module docstring) of the contact nodes ``points`` with their ``gap`` and
    unit ``normal`` (NaN rows ignored), mirrored in the symmetry ``planes``,
    fitted on the nodes whose gap is at most the largest of those
    ``in_contact`` (and at least ``least``): (center, axis, radii), or
    (None, None, reason) when the first contact is not a point."""
    points = np.asarray(points, float)
    gap = np.asarray(gap, float)
    normal = np.asarray(normal, float)
    ok = np.isfinite(gap) & np.isfinite(normal).all(axis=1)
    if ok.sum() < 3:
        return None, None, "too few contact nodes with a gap"
    order = np.flatnonzero(ok)[np.argsort(gap[ok])]
    limit = gap[order[min(least, len(order)) - 1]]
    if in_contact is not None and np.any(np.asarray(in_contact, bool) & ok):
        limit = max(limit, gap[np.asarray(in_contact, bool) & ok].max())
    use = ok & (gap <= limit)
    x, g, n = points[use], gap[use], normal[use]
    for k, c in planes:  # mirror images of the nodes off each plane
        off = np.abs(x[:, k] - c) > 1e-12 * max(1.0, np.abs(x).max())
        mirrored = x[off].copy()
        mirrored[:, k] = 2 * c - mirrored[:, k]
        flipped = n[off].copy()
        flipped[:, k] *= -1
        x, g, n = np.vstack([x, mirrored]), np.r_[g, g[off]], \
            np.vstack([n, flipped])
    axis = n.mean(axis=0)
    if not np.linalg.norm(axis) > 0.5:
        return None, None, "the contact normals of the nodes nearest the " \
                           "obstacle disagree"
    axis /= np.linalg.norm(axis)
    t1, t2 = _tangents(axis)
    origin = points[order[0]]
    xi = np.column_stack([(x - origin) @ t1, (x - origin) @ t2])
    span = np.abs(xi).max()
    if not span > 0:
        return None, None, "the nodes nearest the obstacle coincide"
    s = xi / span  # scaled for conditioning
    design = np.column_stack([np.ones(len(s)), s, s[:, 0] ** 2,
                              s[:, 0] * s[:, 1], s[:, 1] ** 2])
    coef, _, rank, _ = np.linalg.lstsq(design, g, rcond=None)
    if rank < 6:
        return None, None, "too few nodes near the first contact to fit " \
                           "the gap"
    A = np.array([[coef[3], coef[4] / 2], [coef[4] / 2, coef[5]]]) / span ** 2
    b = coef[1:3] / span
    eig = np.linalg.eigvalsh(A)
    if not eig[0] > 0.05 * eig[1]:
        return None, None, "the initial gap has no single minimum (not a " \
                           "point contact)"
    vertex = -0.5 * np.linalg.solve(A, b)
    if np.abs(vertex).max() > span:
        return None, None, "the gap's minimum lies outside the nodes " \
                           "nearest the obstacle"
    g_min = coef[0] + 0.5 * b @ vertex
    center = origin + vertex[0] * t1 + vertex[1] * t2 + g_min * axis
    for k, c in planes:
        center[k] = c
    return center, axis, tuple(float(r) for r in 1.0 / (2.0 * eig[::-1]))


def _obstacle_radius(problem, R):
    """R* of the body's R against the obstacle: R for anything but a
    sphere; for a sphere of radius R_o, 1/R* = 1/R + 1/R_o."""
    spec = problem.obstacle.spec() if hasattr(problem.obstacle, "spec") \
        else {}
    if spec.get("kind") == "sphere":
        return 1.0 / (1.0 / R + 1.0 / float(spec["radius"]))
    return R


def hertz_reference(problem, result):
    """The :class:`HertzReference` (a curve, or none and why) of a 3D
    frictionless solve: ``problem``'s ``meta`` names R, E, nu; ``result``
    (a ContactResult or mapping) holds ``contact_force``, ``gap``,
    ``normal`` and ``in_contact`` per contact node. The module docstring
    explains each step."""
    from ..verification import hertz_point_contact

    if getattr(problem, "dim", 2) != 3:
        return HertzReference(note="no Hertz curve: Hertz's point contact "
                                   "needs a 3D problem")
    meta = dict(problem.meta or {})
    missing = [k for k in ("gap", "normal", "contact_force")
               if _field(result, k) is None]
    if missing:
        return HertzReference(note="no Hertz curve: the result has no "
                                   + ", ".join(missing))
    normal = np.asarray(_field(result, "normal"), float)
    planes = symmetry_planes(problem, normal)
    copies = 2 ** len(planes)
    points = problem.nodes[problem.contact_nodes]
    center, axis, radii = first_contact(
        points, _field(result, "gap"), normal, planes,
        _field(result, "in_contact"))
    common = dict(planes=planes, copies=copies)
    if center is None:
        return HertzReference(note=f"no Hertz curve: {radii}", **common)
    common.update(center=center, axis=axis, curvature_radii=radii)
    lam = np.nan_to_num(np.asarray(_field(result, "contact_force"), float))
    force = copies * float(lam @ np.nan_to_num(normal @ axis))
    common.update(force=force)
    where = {0: "whole model", 1: "half model (1 symmetry plane)",
             2: "quarter model (2 symmetry planes)"}.get(
        len(planes), f"{len(planes)} symmetry planes")
    missing = [k for k in ("R", "E", "nu")
               if not isinstance(meta.get(k), (int, float))]
    if missing:
        return HertzReference(note="no Hertz curve: the problem's meta has "
                                   f"no {', '.join(missing)}", **common)
    if not force > 0:
        return HertzReference(note="no Hertz curve: no contact force",
                              **common)
    expected = {"quarter": 4, "half": 2}
    for key, n in expected.items():
        if meta.get(key) and copies != n:
            return HertzReference(
                note=f"no Hertz curve: meta says {key}, the supports make "
                     f"a {where}", **common)
    stated = meta.get("contact_center")
    if stated is not None and np.linalg.norm(np.asarray(stated, float)
                                             - center) > 1e-3 * _size(
                                                 problem):
        return HertzReference(note="no Hertz curve: meta contact_center "
                                   "is not where the gap is least",
                              **common)
    R = _obstacle_radius(problem, float(meta["R"]))
    if max(abs(r / R - 1) for r in radii) > R_TOLERANCE:
        return HertzReference(
            note=f"no Hertz curve: the gap's curvature radii "
                 f"{radii[0]:.3g}, {radii[1]:.3g} are not R* = {R:.3g}",
            **common)
    a, p0 = hertz_point_contact(force, R, float(meta["E"]),
                                float(meta["nu"]))
    return HertzReference(radius=R, a=float(a), p0=float(p0),
                          note=f"Hertz for P = {force:.4g} N, the {where}",
                          **common)
