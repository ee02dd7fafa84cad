r"""One load step of the friction driver :func:`~.driver.run_friction`:
:func:`setup` builds what every step shares (the formulation's system,
condensed or full; D, M and the scales); :func:`load_step` starts step κ
(:mod:`.start`), solves it (:func:`~solver.ncp.solve_ncp`), verifies it
(:func:`~solver.contact.verify.verify_contact`), records it and hands its
fields to the :class:`~.stream.StepStream`; :func:`make_result` checks the
last step against the original K and f and makes the result."""

import time
from types import SimpleNamespace

import numpy as np
import scipy.sparse.linalg as sla

from ...ncp import MESSAGES, solve_ncp, stable_norm
from ..result import ContactResult
from .disc import DiscSystem
from .projection import ProjectionSystem
from .split import SplitSystem
from .start import contact_corrected, extrapolated
from ..geometry import contact_stiffness
from ..kinematics import kinematic_breaches
from ..verify import (accept_at_roundoff, describe_failure, force_scale,
                     unit_free_options,
                     verification_tolerance, verify_contact,
                     verify_excluded, worst_verification)

__all__ = ["GAP_WEIGHT", "STOPPING_TEST", "setup", "load_step",
           "make_result", "step_fields", "FIELDS"]

#: c = GAP_WEIGHT·k̄ on the condensed system. Any c ∝ k̄ makes the
#: iterates independent of the units; c = k̄ (as frictionless) weighs the
#: gaps as the stopping test does (benchmarks/README.md: a smaller c
#: stalled the thesis's split).
GAP_WEIGHT = 1.0

#: A step's fields over Γc, in the order of the result's keys.
FIELDS = ("contact_force", "contact_pressure", "friction_traction",
          "friction_bound", "tangential_displacement", "in_contact", "stick",
          "slip")

#: The stopping test of each load step, as reported.
STOPPING_TEST = ("‖[E; w·(contact rows)]‖₂ (force units) ≤ tol·F, "
                 "F = max(‖f‖₂, ‖f_κ‖₂, ‖λ⁺‖₂), "
                 "w = F/max(‖λ⁺‖₂, ‖t‖₂, 0.01·F)")


def _check_step(system, x, load, friction, p_previous, tol_v):
    """:func:`verify_contact` of a load step's answer x on the system
    solved (the condensed one when condensed), ``load`` its load vector."""
    du, g = x[:system.n], system.traction(x)
    r = system._force(du)
    lam = -r[system.n_rows]
    pressure = np.maximum(lam, 0.0) / system.lumped
    bound = friction * (p_previous if system.coulomb == "lagged"
                        else pressure)
    geometry = system.geometry
    return verify_contact(system.K, load, system.u_previous + du,
                          geometry.node_dofs, geometry.normal, geometry.gap,
                          lam, system.stiffness, tol_v,
                          _nodal(system.lumped, g),
                          system.lumped * bound, geometry.tangents,
                          system.load_norm)  # the stopping test's F


def _nodal(lumped, g):
    """Nodal friction forces D_ii g_t,i: (m,) in 2D, (m, d − 1) else."""
    if len(g) == len(lumped):
        return lumped * g
    return lumped[:, None] * np.reshape(g, (len(lumped), -1))


def _final_check(problem, geometry, stiffness, tol_v, space, last,
                 checks):
    """The worst of the steps' checks, merged with the last completed
    step's check against the original K and f when condensed (u recovered by
    one solve with K) or when the system's unknowns are not u (a floating
    body's full system, u = W y)."""
    if last is not None and (space.condensed or space.K is not problem.K):
        # condensed, or a floating body's unknowns (u_J, α): u recovered
        _, u_c, w, f_step, lam, t, bound, _ = last
        u = space.displacement(u_c, w)
        checks = checks + [verify_contact(
            problem.K, f_step, u, geometry.node_dofs, geometry.normal,
            geometry.gap, lam, stiffness, tol_v, t, bound,
            geometry.tangents)]
    elif last is not None:
        u = last[1]
    worst = worst_verification(checks, tol_v)
    if last is not None:  # the nodes left out, at the last step
        worst["excluded"] = verify_excluded(
            problem, geometry, u, checks[-1]["length_scale"], tol_v)
        worst["kinematics"] = kinematic_breaches(problem, geometry, u)
    return worst


def setup(problem, geometry, space, friction, formulation, coulomb, method,
          tol, options, gap_scale):
    """What every load step shares: the system on the reduction ``space``
    (:mod:`~solver.contact.strategies.reduction`), its scales and
    tolerances, the lumped boundary matrix D and a factorisation of M (for
    M⁻¹λ, (87))."""
    lumped_all = np.asarray(problem.M.sum(axis=1)).ravel()
    lumped = lumped_all[geometry.index]
    stiffness = contact_stiffness(problem.K, geometry)
    if gap_scale is None:  # ∝ k̄: Φ's rows all in force units
        gap_scale = GAP_WEIGHT * stiffness if space.condensed else 1.0
    reference_norm = stable_norm(problem.f)
    if space.condensed:  # φ_FB's (26) unit-free, as frictionless
        options = unit_free_options(method, options, reference_norm,
                                    stiffness, geometry.gap)
    watchdog = getattr(space, "watchdog", 0)  # a floating body's steps
    if method == "fb" and watchdog and "watchdog" not in (options or {}):
        options = dict(options or {}, watchdog=watchdog)
    if getattr(space, "system_kind", None) is not None:
        kind = space.system_kind  # the iterative path's (.active_set)
    elif formulation == "thesis":
        kind = SplitSystem
    elif space.condensed and geometry.dim == 3:
        kind = DiscSystem  # the tractions eliminated
    else:
        kind = ProjectionSystem
    system = kind(space.K, space.load(problem.f)[0], space.geometry, lumped,
                  friction, coulomb, gap_scale, stiffness)
    jacobian = space.jacobian(system)
    return SimpleNamespace(
        system=system, space=space, jacobian=jacobian,
        condensed=space.condensed, linear_solver=space.linear_solver,
        options=options, lumped=lumped, mass=sla.splu(problem.M.tocsc()),
        stiffness=stiffness, reference_norm=reference_norm,
        tol_v=verification_tolerance(tol), geometry=geometry,
        coulomb=coulomb, n_contact=problem.n_contact)


def load_step(shared, state, run, stream, kappa, steps, load,
              step_friction, prescribed, stage, method, tol, max_iter):
    """Solve and verify load step κ from ``state`` (u, w, p, g of step
    κ−1, updated here), append its record to ``run`` and its fields to
    ``stream``. False when it did not converge or failed verification."""
    system, space = shared.system, shared.space
    f_step = load
    step_norm = max(shared.reference_norm, stable_norm(load))
    du = None
    begin = getattr(space, "begin_step", None)  # a floating body
    if begin is not None:
        refused = begin(system, load, step_friction, state, shared.lumped,
                        shared.coulomb)
        if refused is not None:
            return _unheld(run, kappa, steps, refused)
    load, w = space.load(load)
    system.set_step(state.u, load, state.p, step_friction, step_norm)
    g_start, free = state.g, None
    if w is not None:  # the predictor: Γc moves as the unconstrained body
        du = free = space.restrict(w - state.w)
        if begin is None:  # in 3D extrapolated from the previous step
            du, g_start = extrapolated(system, state, free)
            du = contact_corrected(system, du)
        else:
            du = space.step_start(system, du, state.u, f_step)
    elif begin is not None:  # floating, full system: put onto the obstacle
        du = space.step_start(system, None, state.u, f_step)
    x0 = system.initial_guess(g_start, du)
    newton = getattr(space, "newton", None)  # the iterative path's own
    if newton is not None:
        result = newton(system, x0, load, tol, max_iter)
    else:
        result = solve_ncp(system.residual, shared.jacobian, x0,
                           method=method, tol=tol, max_iter=max_iter,
                           options=shared.options, error=system.error,
                           scale=system.scale)
    result.stopping.update(test=STOPPING_TEST, step=kappa)
    for key in run.totals:
        run.totals[key] += int(result[key])
    du, g = result.x[:system.n], system.traction(result.x)
    check = _check_step(system, result.x, load, step_friction, state.p,
                        shared.tol_v)
    accept_at_roundoff(result, system, result.x, tol, check["passed"])
    if result.success and not check["passed"]:
        result.update(success=False, status=6, message=(
            f"{MESSAGES[6]}: {describe_failure(check)}"))
    record = dict(step=kappa, converged=bool(result.success),
                  verified=bool(check["passed"]), status=int(result.status),
                  njev=int(result.njev), nfev=int(result.nfev),
                  nit=int(result.nit), error=float(result.error),
                  relative=float(result.stopping["relative"]),
                  message=result.message,
                  gradient_steps=int(sum(s == "gradient" for s in
                                         result.history["step"])))
    if "krylov" in result:  # the iterative path: Krylov iterations
        record["krylov"] = int(result["krylov"])
    run.records.append(record)
    if not result.success:
        run.failed = kappa
        record.update(n_contact=None, n_stick=None, n_slip=None,
                      residual_history=list(map(float, result.history[
                          "residual"])))
        run.message = (f"load step {kappa} of {steps} did not converge: "
                       f"{result.message}")
        return False
    run.checks.append(check)
    run.stoppings.append(result.stopping)
    state.g_last, state.du_last, state.free_last = state.g, du, free
    state.u, state.g = state.u + du, g
    lam = -system._force(du)[system.n_rows]
    fields = step_fields(shared, lam, g, step_friction, state.p, step_norm)
    fields["tangential_displacement"] = system.tangential(system.R @ state.u)
    run.last = (kappa, state.u.copy(), w, f_step, lam,
                _nodal(shared.lumped, g),
                shared.lumped * fields["friction_bound"],
                result.history["residual"])
    if w is not None:
        state.w = w
    record.update(stage=int(stage), n_contact=int(fields["in_contact"].sum()),
                  n_stick=int(fields["stick"].sum()),
                  n_slip=int(fields["slip"].sum()),
                  max_pressure=float(fields["contact_pressure"].max(
                      initial=0.0)))
    state.p = fields["contact_pressure"]
    stream.add(_on_contact_nodes(shared, fields, kappa / steps, stage),
               state.u, w, prescribed)
    return True


def _unheld(run, kappa, steps, reason):
    """End the run before step κ, whose load no contact forces can hold
    (a floating body, ``reason``): a failed step, nothing solved."""
    run.failed = kappa
    run.records.append(dict(step=kappa, converged=False, verified=False,
                            status=6, njev=0, nfev=0, nit=0,
                            error=float("nan"), relative=float("nan"),
                            message=reason, gradient_steps=0,
                            n_contact=None, n_stick=None, n_slip=None))
    run.message = f"load step {kappa} of {steps} has no answer: {reason}"
    return False


def step_fields(shared, lam, g, step_friction, p_previous, step_norm,
                system=None):
    """A converged step's fields on the free contact nodes: pressure
    p = λ⁺/D, the bound f_c p used (p_{κ−1} if lagged), contact (λ above
    a force-scaled threshold), slip (traction at the bound: a node in
    contact with a zero bound slides freely) and stick (strictly inside).
    ``shared``: ``lumped``, ``coulomb`` and ``geometry`` of :func:`setup`;
    ``system``: the step's, whose :meth:`~.system.FrictionSystem.gathered`
    gives the scale's ‖λ⁺‖ over the ranks of a distributed run."""
    pressure = np.maximum(lam, 0.0) / shared.lumped
    bound = step_friction * (p_previous if shared.coulomb == "lagged"
                             else pressure)
    plus = np.maximum(lam, 0.0)
    scale = force_scale(step_norm, plus if system is None
                        else system.gathered(plus))  # the stopping test's
    contact = lam > 1e-9 * scale
    k = shared.geometry.dim - 1
    size = np.abs(g) if k == 1 else np.linalg.norm(g.reshape(-1, k), axis=1)
    slip = contact & (size >= bound * (1 - 1e-6) - 1e-12 * scale)
    return dict(contact_force=lam, contact_pressure=pressure,
                friction_traction=g, friction_bound=bound,
                in_contact=contact, stick=contact & ~slip, slip=slip)


def _on_contact_nodes(shared, fields, load_factor, stage):
    """The step's fields over all nodes of Γc (supports: 0, NaN for the
    tangential displacement, never in contact), with M⁻¹λ (87)."""
    idx, k = shared.geometry.index, shared.geometry.dim - 1
    out = dict(load_factor=load_factor, stage=stage)
    for key in FIELDS:
        values = np.asarray(fields[key])
        if k > 1 and values.size == k * len(idx):  # (Nca, d − 1)
            values = values.reshape(len(idx), k)
        boolean = values.dtype == bool
        fill = False if boolean else \
            np.nan if key == "tangential_displacement" else 0.0
        out[key] = np.full((shared.n_contact,) + values.shape[1:], fill,
                           dtype=bool if boolean else float)
        out[key][idx] = values
        if key == "contact_pressure":
            out["contact_pressure_consistent"] = \
                shared.mass.solve(out["contact_force"]) + 0.0
    return out


def make_result(problem, geometry, shared, run, stream, steps, friction,
                formulation, coulomb, method, tol, start):
    """The ContactResult of the run: the final verification against the original K
    and f (a failure there fails the last step), the worst stopping
    measure, the delivered per-step arrays, gaps and normals over Γc."""
    verification = _final_check(problem, geometry, shared.stiffness,
                                shared.tol_v, shared.space, run.last,
                                run.checks)
    failed, message = run.failed, run.message
    if failed is None and not verification["passed"]:
        failed = run.last[0]
        message = (f"load step {failed} of {steps} fails verification "
                   f"against the original K and f: "
                   f"{describe_failure(verification)}")
        run.records[-1].update(converged=False, verified=False, status=6,
                               message=f"{MESSAGES[6]}: {message}",
                               residual_history=list(map(float,
                                                         run.last[-1])))
    stopping = max(run.stoppings, key=lambda s: s["relative"]) \
        if run.stoppings else dict(test=STOPPING_TEST, tol=float(tol),
                                   scale=np.nan, absolute=np.nan,
                                   relative=np.nan, step=None)
    rigid = None
    if hasattr(shared.space, "alpha") and run.last is not None:
        from ...problem.rigid import rigid_motion  # held by contact only

        rigid = rigid_motion(problem, shared.space.displacement(
            run.last[1], run.last[2]))
        rigid["start_nodes"] = None
        rigid["weakly_held"] = getattr(shared.space, "weakly_held", [])
    nc, idx = problem.n_contact, geometry.index
    normal = np.full((nc, geometry.normal.shape[1]), np.nan)
    normal[idx] = geometry.normal
    gap_all = np.full(nc, np.nan)
    gap_all[idx] = geometry.gap
    return ContactResult(
        success=failed is None, message=message, failed_step=failed,
        steps=int(steps), steps_completed=stream.count,
        friction=float(friction), formulation=formulation, coulomb=coulomb,
        method=method, gap_mode=geometry.mode, records=run.records,
        condensed=shared.condensed, gap=gap_all, normal=normal,
        linear_solver=shared.linear_solver, verification=verification,
        stopping=stopping, time=time.perf_counter() - start, **run.totals,
        rigid_body=rigid,
        **stream.arrays())
