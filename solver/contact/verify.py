r"""Scales of the stopping test and verification of a computed answer.

Units, and what the contact carries. A solver's verdict must depend
neither on the units the user chose nor on how the same physical problem
is loaded, so the contact drivers stop relative to the problem's own
forces,

.. math::  \|[E;\ w\,\min(λ, \bar k (s − u_n))]\|_2 \le \mathrm{tol}\cdot
           F, \qquad F = \max(\|f\|_2, \|λ^+\|_2), \quad w = F/F_c,

E the equilibrium rows, λ the normal contact forces of the iterate, s − u_n
the remaining gaps (thesis (67)) and k̄ the mean of diag(K) at the contact
DOFs, which turns a gap error into a force: scaling K and f, or all
lengths, scales both sides alike. The contact rows (pairs and Coulomb
projection) are weighted by w so as to be measured against what the
contact carries, F_c = max(‖λ⁺‖₂, ‖t‖₂, :data:`CONTACT_FLOOR`·F)
(:func:`contact_scale`, t the nodal friction forces), not against a
Dirichlet lifting f = −K_fD u_D that may exceed them by orders of
magnitude. The floor, and :func:`accept_at_roundoff`, respect floating
point: λ is a difference of forces of the load's size. The thesis's split
keeps one scale for all its rows, as the thesis poses it.

Verification. The stopping test looks at the system Newton iterated on (a
condensed one, a coarse level, a load step); before reporting success the
solvers check the answer itself with the original sparse K and f
(:func:`verify_contact`): it is finite; the penetration, the negative part
of λ, the complementarity |min(λ, k̄(s − u_n))| and (with friction) the
excess of the nodal friction force over the Coulomb bound are at most
tol_v·F_c (lengths through F_c/k̄); and the equilibrium residual

.. math::  \frac{\|K u − f − f_c\|_2}{\|f\|_2 + \|f_c\|_2} \le \mathrm{tol}_v,

f_c = Σ_i (−λ_i ν_i + Σ_k t_ik τ_ik) the contact forces on the body, which
catches a factorisation too inaccurate for the problem (a nearly free
rigid body mode). tol_v = max(:data:`VERIFY_FACTOR`·tol,
:data:`VERIFY_FLOOR`): ∞-norms of what the stopping test bounds in the
2-norm, plus the round-off of recomputing them from K."""

import numpy as np

from ..geometry.frames import tangent_basis
from ..ncp import stable_norm as _norm

__all__ = ["VERIFY_FACTOR", "VERIFY_FLOOR", "CONTACT_FLOOR",
           "verification_tolerance", "force_scale", "contact_scale",
           "contact_weight", "accept_at_roundoff", "typical_sizes", "unit_free_options",
           "verify_contact", "verify_excluded", "worst_verification",
           "describe_failure"]

#: tol_v = max(VERIFY_FACTOR·tol, VERIFY_FLOOR).
VERIFY_FACTOR = 10.0
VERIFY_FLOOR = 1e-8


def verification_tolerance(tol):
    """tol_v of the verification for the stopping tolerance ``tol``."""
    return max(VERIFY_FACTOR * float(tol), VERIFY_FLOOR)


def force_scale(load_norm, lam):
    """F = max(‖f‖₂, ‖λ⁺‖₂): the force scale of the stopping test."""
    return max(float(load_norm), _norm(np.maximum(lam, 0.0)))


#: F_c is at least this fraction of F (module docstring).
CONTACT_FLOOR = 1e-2


def contact_scale(load_norm, lam, friction_force=None):
    """F_c = max(‖λ⁺‖₂, ‖t‖₂, CONTACT_FLOOR·F), at most F: the scale of the
    contact rows (module docstring); t, the nodal friction forces, where a
    large f_c makes them the larger part of what the contact carries."""
    F = force_scale(load_norm, lam)
    carried = _norm(np.maximum(lam, 0.0))
    if friction_force is not None:
        carried = max(carried, _norm(np.ravel(friction_force)))
    return min(F, max(carried, CONTACT_FLOOR * F)) if F > 0 else carried


def contact_weight(load_norm, lam, friction_force=None):
    """w = F / F_c ≥ 1, the weight of the contact rows in the stopping
    measure (module docstring); 1 when F is 0 (nothing loads the body)."""
    F = force_scale(load_norm, lam)
    return F / contact_scale(load_norm, lam, friction_force) if F > 0 \
        else 1.0


def accept_at_roundoff(result, system, x, tol, verified):
    """Turn a stall (status 5) into success when floating point, not the
    method, stopped it: at the iterate ``x`` of ``system`` the
    load-relative measure (contact weight 1) is within ``tol``·F and the
    answer is ``verified`` on every node. The message keeps how far the
    weighted measure got. Updates ``result`` (of
    :func:`~solver.ncp.solve_ncp`) in place."""
    if result.status != 5 or not verified:
        return
    parts = system.residual(x)
    plain = system.error(*parts, weighted=False)
    size = system.scale(*parts)
    if plain <= tol * size:
        result.update(success=True, status=0, message=(
            "converged at round-off: the residual is within tol of the "
            f"load (relative {plain / size:.1e}); the contact rows reached "
            f"{result.stopping['relative']:.1e} of the load weighted by "
            "F/F_c, below which floating point does not go here"))


#: ρ of φ_FB's descent test (26) in unit-free form (Φ in units of F, x of
#: F/k̄): as lenient as the thesis's ρ = 1e-8 in N, mm (8e-20 on the §4
#: block, 8e-19 on the bar); a larger one stalls the bar.
UNIT_FREE_RHO = 1e-20


def typical_sizes(load_norm, stiffness, gap):
    """(force, length) of a problem for φ_FB's unit-free descent test (26)
    (option ``typical`` of :func:`solver.ncp.solve_ncp`): F = the load's
    norm (else k̄ times the norm of the negative gaps, else of the gaps)
    and F/k̄."""
    force = float(load_norm)
    for candidate in (np.minimum(gap, 0.0), gap):
        if force > 0:
            break
        force = stiffness * _norm(candidate)
    force = force if force > 0 and np.isfinite(force) else 1.0
    return force, force / stiffness


def unit_free_options(method, options, load_norm, stiffness, gap):
    """``options`` with φ_FB's descent test (26) made unit-free (``typical``
    sizes and :data:`UNIT_FREE_RHO`), unless either is given: then the
    iterates do not depend on the units of force or length."""
    options = dict(options or {})
    if method == "fb" and options.get("typical") is None \
            and "rho" not in options:
        options.update(typical=typical_sizes(load_norm, stiffness, gap),
                       rho=UNIT_FREE_RHO)
    return options


def _relative(value, size):
    value = float(value)
    if value <= 0.0:
        return max(value, 0.0) if size > 0 else 0.0
    return value / size if size > 0 else np.inf


def verify_contact(K, f, u, dofs, normal, gap, lam, stiffness, tol_v,
                   friction_force=None, friction_bound=None, tangents=None,
                   load_norm=None):
    """Check a computed contact answer against the original K and f.

    ``K``, ``f``, ``u``: the original reduced stiffness (never the condensed
    one), the load of the answer (a load step's f_κ) and the reduced
    displacement. ``dofs`` (Nca, d): the contact nodes' reduced DOFs
    (``ContactGeometry.node_dofs``; −1 at a roller's Dirichlet component,
    whose reaction is the support's, left out of f_c). ``normal``, ``gap``,
    ``lam``: ν, s and the solver's normal contact forces; ``stiffness`` k̄;
    ``tol_v`` of :func:`verification_tolerance`. With friction,
    ``friction_force`` t_i = D_ii g_t,i (components along ``tangents``, by
    default those of :func:`solver.geometry.frames.tangent_basis`) and
    ``friction_bound`` D_ii f_c p_i. ``load_norm``: ‖f‖₂ of the force scale F
    (default: of ``f``; a condensed system passes the stopping test's).

    Returns a dict: ``passed``, ``finite``, ``max_penetration``
    (max(u_n − s, 0) / (F_c/k̄)), ``min_multiplier`` (min λ / F_c),
    ``complementarity`` (max|min(λ, k̄(s − u_n))| / F_c), ``equilibrium``
    (module docstring), with friction ``friction_bound_violation``
    (max(|t| − bound, 0) / F_c); ``force_scale`` F_c (what the contact
    carries, :func:`contact_scale`), ``length_scale`` F_c/k̄,
    ``tolerances`` and ``failed`` (the measures beyond their bound)."""
    u, lam = np.asarray(u, float), np.asarray(lam, float)
    arrays = [u, lam] + [np.asarray(a, float) for a in
                         (friction_force, friction_bound) if a is not None]
    finite = all(bool(np.all(np.isfinite(a))) for a in arrays)
    F = contact_scale(_norm(f) if load_norm is None else load_norm, lam,
                      friction_force) if finite else np.inf
    L = F / stiffness
    dofs = np.asarray(dofs)
    # −1 (a roller's Dirichlet component, where ν is 0) reads the appended 0
    padded = np.append(u, 0.0)
    un = (normal * padded[dofs]).sum(axis=1) if len(dofs) else np.zeros(0)
    remaining = gap - un
    checks = {}
    with np.errstate(all="ignore"):
        checks["max_penetration"] = _relative(
            np.max(-remaining, initial=0.0), L)
        checks["min_multiplier"] = -_relative(-np.min(lam, initial=0.0), F)
        checks["complementarity"] = _relative(np.max(np.abs(np.minimum(
            lam, stiffness * remaining)), initial=0.0), F)
        contact = np.zeros(len(u) + 1)  # the last entry takes the −1s
        if len(dofs):  # −λν + Σ_k t_k τ_k; distinct nodes
            contact[dofs] = -lam[:, None] * normal
        if friction_force is not None and len(dofs):
            tau = tangent_basis(normal) if tangents is None else tangents
            t = np.asarray(friction_force, float).reshape(len(dofs), -1)
            contact[dofs] += (t[:, :, None] * tau).sum(axis=1)
        contact = contact[:-1]  # a support's reaction is not a contact force
        residual = _norm(K @ u - f - contact)
        checks["equilibrium"] = _relative(residual,
                                          _norm(f) + _norm(contact))
        if friction_force is not None:
            t = np.asarray(friction_force, float)
            size = np.abs(t) if t.ndim == 1 else np.linalg.norm(t, axis=1)
            checks["friction_bound_violation"] = _relative(np.max(
                size - np.asarray(friction_bound, float), initial=0.0), F)
    tolerances = {name: tol_v for name in checks}
    tolerances["min_multiplier"] = -tol_v
    failed = [] if finite else ["finite"]
    for name, value in checks.items():
        bad = (value < -tol_v) if name == "min_multiplier" else \
            not (value <= tol_v)
        if bad:
            failed.append(name)
    out = dict(passed=not failed, finite=finite)
    out.update({k: float(v) for k, v in checks.items()})
    out.update(force_scale=float(F), length_scale=float(L),
               tolerances=tolerances, failed=failed)
    return out


def verify_excluded(problem, geometry, u, length, tol_v):
    """The nodes of Γc that took no part in contact (``geometry.excluded``:
    supports, uncovered slave nodes), checked: a dict of ``nodes`` (how many),
    ``reasons`` (count per reason), ``penetrating`` (positions along Γc of the
    supports whose prescribed position penetrates the obstacle, s − ν·u <
    −tol_v·L, L the verification's length scale), ``max_penetration``
    (relative to L), ``max_depth`` (a length) and ``unchecked`` (the nodes
    whose gap could not be computed)."""
    from .geometry import node_displacement

    excluded = geometry.excluded
    index = np.asarray(excluded["index"], np.int64)
    reasons = {}
    for reason in excluded["reason"]:
        reasons[reason] = reasons.get(reason, 0) + 1
    out = dict(nodes=int(len(index)), reasons=reasons, penetrating=[],
               max_penetration=0.0, unchecked=0)
    gap = np.asarray(excluded["gap"], float)
    known = np.isfinite(gap) & np.all(np.isfinite(excluded["normal"]),
                                      axis=1) if len(index) else gap > 0
    out["unchecked"] = int(np.count_nonzero(~known))
    if not known.any():
        return out
    moved = node_displacement(problem, u, index[known])
    remaining = gap[known] - np.einsum(
        "ij,ij->i", np.asarray(excluded["normal"], float)[known], moved)
    depth = np.maximum(-remaining, 0.0)
    out["max_penetration"] = _relative(depth.max(initial=0.0), length)
    out["max_depth"] = float(depth.max(initial=0.0))
    out["penetrating"] = [int(i) for i in index[known][
        depth > tol_v * length]]
    return out


def describe_failure(verification):
    """One line naming each failed measure and its bound."""
    parts = []
    for name in verification["failed"]:
        if name == "finite":
            parts.append("non-finite values in the answer")
            continue
        value, bound = verification[name], verification["tolerances"][name]
        relation = "<" if name == "min_multiplier" else ">"
        parts.append(f"{name.replace('_', ' ')} {value:.2e} {relation} "
                     f"{bound:.1e}")
    text = "; ".join(parts)
    if "equilibrium" in verification["failed"]:
        text += (" (K u − f is off: the factorisation is too inaccurate "
                 "for this K; is K nearly singular?)")
    return text


def worst_verification(checks, tol_v):
    """The worst of several :func:`verify_contact` results (load steps):
    largest measures, smallest multiplier, every failure; with no checks
    (no step completed) nothing was verified: ``passed`` is False."""
    names = ("max_penetration", "min_multiplier", "complementarity",
             "equilibrium", "friction_bound_violation")
    out = dict(passed=bool(checks) and all(c["passed"] for c in checks),
               finite=all(c["finite"] for c in checks))
    for name in names:
        values = [c[name] for c in checks if name in c]
        if values:
            out[name] = float(min(values) if name == "min_multiplier"
                              else max(values))
    failed = []
    for c in checks:
        failed += [name for name in c["failed"] if name not in failed]
    tolerances = {name: tol_v for name in names if name in out}
    if "min_multiplier" in tolerances:
        tolerances["min_multiplier"] = -tol_v
    out.update(tolerances=tolerances, failed=failed)
    return out
