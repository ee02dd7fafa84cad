r"""The frictionless driver: the system (67) of :mod:`.system` solved by
semismooth Newton, its answer verified and reported over every node of Γc
(λ = 0 at supports), with the contact pressure p = M⁻¹λ ≥ 0 of (87)
(g_n = −p; the sparse M solved, never inverted) and its lumped form
λ_i / D_ii. Three ways to solve it (:func:`run_frictionless`):

* 2D default: condensed onto every DOF of Γc (S of size 2Nc), started by
  nested iteration (:mod:`solver.contact.strategies.nested`), which keeps
  the Newton iterations on the full Γc at a fixed small number.
* 3D default: condensed onto the *normal* DOF of *candidate* nodes only
  (:mod:`solver.contact.strategies.candidates`), from the free start λ = 0.
* ``condense=False``: the thesis's system in all Ñ unknowns.
* An iterative engine (``backend="amg"``): the active set method on the
  full primal system, its Newton systems by AMG-preconditioned CG
  (:mod:`.active_set`), nothing factorised; a body held by contact only
  starts from its rigid placement (:class:`~solver.contact.strategies.
  floating.RigidPlacement`)."""

import time

import numpy as np
import scipy.sparse.linalg as sla
from scipy.optimize import OptimizeResult

from ...ncp import MESSAGES, solve_ncp, stable_norm
from ..geometry import contact_stiffness
from ..kinematics import kinematic_breaches
from ..result import ContactResult
from ..strategies.reduction import reduction
from ..verify import (accept_at_roundoff, describe_failure, force_scale,
                      unit_free_options,
                      verification_tolerance, verify_contact,
                      verify_excluded)
from .system import FrictionlessSystem

__all__ = ["run_frictionless", "STOPPING_TEST", "nodal_arrays"]

#: The stopping test of the frictionless solve, as reported.
STOPPING_TEST = ("‖[E; w·min(λ, k̄(s − u_n))]‖₂ ≤ tol·F, F = max(‖f‖₂, "
                 "‖λ⁺‖₂), w = F/max(‖λ⁺‖₂, 0.01·F)")


def run_frictionless(problem, geometry, engine, method="min", tol=1e-10,
                     max_iter=100, x0=None, gap_scale=None, options=None,
                     condense=True, start="nested", candidates=False,
                     margin=None, nodal=False):
    r"""Solve the frictionless contact problem (67) by semismooth Newton.

    The driver behind :func:`solver.solve` for frictionless contact, whose
    docstring explains the options; they arrive resolved and checked, with
    the ``geometry`` of the contact nodes that take part and the ``engine``.
    ``tol`` is relative to the force scale of the iterate
    (:mod:`solver.contact.verify`), so neither the verdict nor the condensed
    and nested iterates (c = k̄) depend on the units; the full system's c = 1
    (the thesis) makes its path depend on them. ``start``: "nested", "free"
    (λ = 0), "x0", "zero" (the thesis's u = 0) or "rigid" (a body held by
    contact only on the full system: put onto the obstacle as a rigid
    body, :mod:`~solver.contact.strategies.floating_full`). ``max_iter``
    counts all levels and rounds together. ``nodal`` (with
    ``candidates``): condense K onto every free DOF of the candidates, for
    a friction run to reuse (:class:`~solver.contact.strategies.candidates.
    NodalCondensation`).

    Returns a ContactResult: the NCP result's counts, ``history`` and
    ``status`` (6: the stopping test met but the verification failed), the
    answer over all nodes of Γc (docs/results.md, "A frictionless solve"),
    and ``condensation``, ``candidates``, ``start``, ``levels``,
    ``linear_solver``, ``stopping`` and ``verification``."""
    clock = time.perf_counter()
    load_norm = stable_norm(problem.f)
    stiffness = contact_stiffness(problem.K, geometry)
    iterative = getattr(engine, "iterative", False)
    if gap_scale is None:  # the active set method's c = k̄: unit-free
        gap_scale = stiffness if condense or iterative else 1.0
    if condense:  # c = k̄ and (26) unit-free: iterates independent of units
        options = unit_free_options(method, options, load_norm, stiffness,
                                    geometry.gap)
    screening, iterate = None, None
    if iterative:
        from .active_set import solve_active_set

        floating = None
        if problem.floating:  # the load checked, the rigid placement
            from ..strategies.floating import RigidPlacement

            floating = RigidPlacement(problem, geometry)
        result, lam_free, un_free = solve_active_set(
            problem, geometry, engine.multigrid(problem), tol, max_iter, x0,
            gap_scale, stiffness, load_norm, floating)
        result = OptimizeResult(result)
        u = result.x
        linear_solver, name = engine.linear_solver, "none"
        if floating is not None:  # held by contact only: its rigid motion
            from ...problem.rigid import rigid_motion

            result.rigid_body = rigid_motion(problem, u)
            result.rigid_body["start_nodes"] = floating.start_nodes
            result.rigid_body["weakly_held"] = floating.weakly_held
    elif candidates:
        from ..strategies.candidates import solve_on_candidates

        result, u, lam_free, un_free, screening = solve_on_candidates(
            problem, geometry, method, tol, max_iter, x0, gap_scale,
            stiffness, options, load_norm, margin,
            engine.normal_condensation(problem, geometry, nodal=True)
            if nodal else engine.normal_condensation(problem, geometry))
        linear_solver, name = engine.linear_solver, "normal candidates"
    else:
        space = reduction(problem, geometry, engine, condense)
        linear_solver, name = space.linear_solver, space.name
        f, w = space.load(problem.f)
        if start == "nested" and hasattr(space, "nested"):
            system = FrictionlessSystem(space.K, f, space.geometry,
                                        gap_scale, stiffness, load_norm)
            result = space.nested(system, method, tol, max_iter, gap_scale,
                                  stiffness, options, load_norm)
        elif start == "nested":
            from ..strategies.nested import contact_levels, solve_nested

            result, system = solve_nested(
                contact_levels(space.K, w[space.dofs], space.geometry),
                method, tol, max_iter, gap_scale, stiffness, options,
                load_norm)
        else:
            system = FrictionlessSystem(space.K, f, space.geometry,
                                        gap_scale, stiffness, load_norm)
            # "free": no contact force, as the thesis's u = 0 has λ = 0 on
            # Γc; condensed, λ = 0 is the unconstrained solution w = K⁻¹f.
            if start == "x0":
                start_x = space.restrict(x0)
            elif start in ("free", "rigid"):  # rigid: floating, full
                start_x = space.free_start(system, w)
            else:
                start_x = np.zeros(problem.n_dofs)
            result = solve_ncp(system.residual, space.jacobian(system),
                               start_x, method=method, tol=tol,
                               max_iter=max_iter, options=options,
                               error=system.error, scale=system.scale)
            result.levels = []
        lam_free = system.contact_force(result.x)
        un_free = system.normal_displacement(result.x)
        u = space.displacement(result.x, w)
        iterate = (system, result.x)
        if hasattr(space, "alpha"):  # held by contact only: its rigid motion
            from ...problem.rigid import rigid_motion

            result.rigid_body = rigid_motion(problem, u)
            result.rigid_body["start_nodes"] = space.start_nodes
            result.rigid_body["weakly_held"] = space.weakly_held
    result.stopping["test"] = STOPPING_TEST
    result.x = u
    tol_v = verification_tolerance(tol)
    verification = verify_contact(
        problem.K, problem.f, u, geometry.node_dofs, geometry.normal,
        geometry.gap, lam_free, stiffness, tol_v)
    verification["excluded"] = verify_excluded(
        problem, geometry, u, verification["length_scale"], tol_v)
    verification["kinematics"] = kinematic_breaches(problem, geometry, u)
    if iterate is not None:
        accept_at_roundoff(result, *iterate, tol, verification["passed"])
    if result.success and not verification["passed"]:
        result.update(success=False, status=6, message=(
            f"{MESSAGES[6]}: {describe_failure(verification)}"))
        if screening and screening["exhausted"]:
            result.message += (f" (the candidates still grew after "
                               f"{len(screening['rounds'])} rounds: give a "
                               "larger margin)")
    result.update(nodal_arrays(problem, geometry, u, lam_free, un_free,
                               load_norm))
    result.update(
        gap_mode=geometry.mode, gap_scale=float(gap_scale),
        condensed=bool(condense), condensation=name, candidates=screening,
        start=start, linear_solver=linear_solver,
        verification=verification, time=time.perf_counter() - clock)
    return ContactResult(result)


def nodal_arrays(problem, geometry, u, lam_free, un_free, load_norm):
    """The result's arrays over every node of Γc (NaN / 0 at supports)."""
    nc, d = problem.n_contact, geometry.dim
    lam = np.zeros(nc)
    lam[geometry.index] = lam_free
    un = np.full(nc, np.nan)
    un[geometry.index] = un_free
    s = np.full(nc, np.nan)
    s[geometry.index] = geometry.gap
    normal = np.full((nc, d), np.nan)
    normal[geometry.index] = geometry.normal
    pressure = sla.spsolve(problem.M.tocsc(), lam) + 0.0  # no -0.0
    lumped = np.maximum(lam, 0.0) / np.asarray(problem.M.sum(axis=1)).ravel()
    remaining = s - un
    comp = np.abs(np.minimum(lam, remaining))[geometry.index]
    threshold = 1e-9 * force_scale(load_norm, lam)
    in_contact = lam > threshold
    # Σ −λ_i ν_i: the force of the obstacle on the body (ν: body → obstacle)
    total = -(lam[geometry.index, None] * geometry.normal).sum(axis=0)
    if problem.kind == "mesh":
        displacement = problem.full_displacement(u)
    else:
        displacement = u[problem.contact_dofs]
    return dict(
        u=u, displacement=displacement, contact_force=lam,
        contact_pressure=lumped, contact_pressure_consistent=pressure,
        gap=s, normal=normal, normal_displacement=un, in_contact=in_contact,
        complementarity=float(comp.max(initial=0.0)),
        total_contact_force=total + 0.0,
        n_contact=int(in_contact.sum()))
