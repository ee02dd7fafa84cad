r"""Coulomb friction by load steps (thesis §5-§6, (88)-(111)).

The load is applied in κc steps, f_κ = κ/κc · f. Each step solves for the
increment Δu (u = u_{κ−1} + Δu) and the friction traction g_t at the free
contact nodes, starting from the previous step's solution.

Which Coulomb bound (errata of (104))
-------------------------------------
The thesis's row 3 balances the tangential nodal force with M g_t (so g_t is
a traction), while its friction bound f_c p uses p of (104), a nodal *force*
(and signed). We compare like with like, per node as the thesis intends
("neglecting neighbours", (104)): the tangential row uses the lumped
boundary matrix D = diag(Σ_j M_ij) (the length of Γc belonging to node i),
and p is the non-negative lumped contact pressure p_i = λ_i / D_ii. Then
|g_t,i| ≤ f_c p_i is the same as |t_i| ≤ f_c λ_i for the nodal friction force
t_i = D_ii g_t,i: Coulomb's law on nodal forces. For the 2-DOF bar D = M = 1.

Formulations
------------
``"thesis"`` (110)/(111): unknowns x = [Δu; g_t; Δu_t⁺; Δu_t⁻] with

.. math::
    X(RKu − f_κ R) = 0, \quad Z(RKu − f_κ R) − D g_t = 0, \quad
    ZRΔu − Δu_t^+ + Δu_t^- = 0 \ (106), \\
    λ = −Y(RKu − f_κ R) \perp s − YRu, \quad
    Δu_t^- \perp f_c p − g_t \ (98), \quad Δu_t^+ \perp f_c p + g_t \ (101),

(X drops the tangential and normal rows of contact nodes, Z keeps the
tangential ones (77)). Where p = 0 (a node out of contact) the last two
pairs only give g_t = 0 and leave the split Δu_t± non-unique: J is singular
there, and φ_FB falls back to gradient steps (errata).

``"projection"`` (beyond the thesis): unknowns x = [Δu; g_t], the split is
replaced by the semismooth projection (Alart & Curnier 1991; the
primal-dual active set form of Hüeber, Stadler & Wohlmuth 2008)

.. math::  g_t = \mathrm{proj}_{[−f_c p,\, f_c p]}(g_t − c_t\, ZRΔu),

which is non-degenerate: p = 0 gives g_t = 0 and Δu_t is left to the
tangential equilibrium row. c_t > 0 only changes the Newton path.

In 3D (any d) g_t ∈ R^{d−1} per node, in the tangent basis
``geometry.tangents``, and the clip becomes the projection onto the disc
|g_t| ≤ f_c p (Alart & Curnier 1991; Hüeber, Stadler & Wohlmuth 2008):
``friction_traction`` is then (Nc, d − 1). The thesis's split is 2D-only
(it splits a scalar slip) and is refused there, and with roller nodes. The
reduced Newton of :mod:`.friction_newton` is 2D-only: in 3D each Newton
step of the condensed system is solved with the tractions eliminated
(:mod:`.friction_disc`), by default on the candidate nodes only
(:mod:`.friction_candidates`; ``candidates=False``: every DOF of the free
contact nodes); the full system takes a sparse LU of its whole Jacobian.

Rollers (symmetry planes, :mod:`~solver.contact.geometry`): at a contact
node with u_c = 0 along the plane normal e_c and ν in the plane, the row
along e_c is a support reaction, not friction: the projection form keeps
g_t,c ≡ 0 there (w_c = 0, so g − P(w) gives it) and drops that tangential
equilibrium row, so that the Coulomb set is the disc cut to the free
tangents (an interval with one free tangent). This is exact for loads
symmetric about the plane: the whole model's friction traction has no
component across the plane there (mirror symmetry).

``coulomb="lagged"`` uses p = p_{κ−1} of the previous step (thesis: Coulomb
as a sequence of Tresca problems); ``coulomb="implicit"`` uses the current
step's p(u) (no one-step lag), with its derivative in the Jacobian.

References
----------
P. Alart, A. Curnier: A mixed formulation for frictional contact problems
prone to Newton like solution methods. CMAME 92 (1991) 353-375.
S. Hüeber, G. Stadler, B. Wohlmuth: A primal-dual active set algorithm for
three-dimensional contact problems with Coulomb friction. SIAM J. Sci.
Comput. 30 (2008) 572-596.
"""

import time

import numpy as np
import scipy.sparse.linalg as sla

from ..errors import SolverError
from ..linalg import resolve
from ..ncp import MESSAGES, solve_ncp, stable_norm
from .result import FrictionResult
from .steps import MAX_LOAD_STEPS, StepStream
from .friction_candidates import friction_on_candidates, use_candidates
from .friction_disc import condensed_system
from .friction_system import (COULOMB, FORMULATIONS, FrictionSystem,
                              check_geometry)
from .frictionless import (condense_onto_contact, contact_geometry,
                           contact_stiffness)
from .geometry import problem_dim
from .verify import (describe_failure, force_scale, unit_free_options,
                     verification_tolerance, verify_contact,
                     worst_verification)

__all__ = ["FORMULATIONS", "COULOMB", "FrictionSystem", "solve_friction"]

#: c = GAP_WEIGHT·k̄ on the condensed system. Any c ∝ k̄ makes the
#: iterates independent of the units. With 1e-5·k̄ (close to the thesis's
#: c = 1 in N, mm) φ_FB took 30 % fewer Jacobians on the projection form
#: (75 against 108 on the 118 block, f_c = 0.3, 25 steps), but the thesis's
#: split, condensed, stalled at a relative residual of 1e-9 (454 block,
#: f_c = 0.05, step 26): Φ then weighs the gaps 1e5 times less than the
#: stopping test does. c = k̄ (as frictionless) converged in every case
#: measured.
GAP_WEIGHT = 1.0

#: The stopping test of each load step, as reported.
STOPPING_TEST = ("‖[E; min(A, k̄B)]‖₂ (force units) ≤ "
                 "tol·max(‖f‖₂, ‖f_κ‖₂, ‖λ⁺‖₂)")


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


def _final_check(problem, geometry, stiffness, tol_v, condensation, last,
                 checks):
    """The worst of the steps' checks, merged with the last completed
    step's check against the original K and f (condensed: u recovered by
    one solve with K; the full system's steps were checked with K
    already)."""
    if condensation is not None and last is not None:
        _, u_c, w, f_step, lam, t, bound, _ = last
        u = condensation.displacement(u_c, w)
        checks = checks + [verify_contact(
            problem.K, f_step, u, geometry.node_dofs, geometry.normal,
            geometry.gap, lam, stiffness, tol_v, t, bound,
            geometry.tangents)]
    return worst_verification(checks, tol_v)


def _is_real(value):
    return isinstance(value, (int, float, np.integer, np.floating)) \
        and not isinstance(value, bool)


def solve_friction(problem, friction, steps=None, formulation="projection",
                   coulomb="lagged", method="fb", gap="obstacle", tol=1e-10,
                   max_iter=100, gap_scale=None, options=None, progress=None,
                   geometry=None, condense=None, on_step=None,
                   keep_steps=True, backend="auto", rollers=None,
                   candidates=None, margin=None, condensation=None):
    r"""Quasi-static Coulomb friction in load steps (thesis §5, (110)/(111)).

    Parameters
    ----------
    problem : ContactProblem
    friction : float
        Coefficient of friction f_c ≥ 0.
    steps : int, optional
        Number of load steps κc; step κ applies κ/κc · f (default 100).
        A problem with a ``load_path`` follows its stages instead (their
        steps, loads and friction multipliers); ``steps`` must then be None.
    formulation : {"projection", "thesis"}
        The projection form (see module; in 3D onto the Coulomb disc), the
        default, or the thesis's split (110)/(111), which reproduces Table 2
        (2D only: SolverError in 3D). The split is singular where p = 0; with
        φ_FB it stalls at load step 28 of 100 on the thesis's own 1878-cell
        block at f_c = 0.3 (tests/test_friction_default.py), hence not the
        default.
    coulomb : {"lagged", "implicit"}
        Friction bound from the previous step's pressure (thesis) or from
        the current one.
    method : {"fb", "min"}
        Newton method of each step (the thesis used φ_FB only).
    gap : {"obstacle", "body"}
        As in :func:`solve_frictionless`.
    tol, max_iter, options
        Per step, as in :func:`solve_frictionless`: the stopping test is
        relative, ‖[E; min(A, k̄B)]‖₂ (force units, :meth:`FrictionSystem.
        error`) ≤ tol·max(‖f‖₂, ‖f_κ‖₂, ‖λ⁺‖₂), with f the full load and
        f_κ the step's, so the verdict does not depend on units (nor, on
        the condensed system, the iterates); every converged step is then
        verified (:func:`~solver.contact.verify.verify_contact`: finite,
        penetration, λ ≥ 0, complementarity, Coulomb bound |t| ≤ f_c λ on
        nodal forces, equilibrium of the system solved), and the last one
        also against the original K and f when condensed. A step that
        fails verification ends the run like one that does not converge
        (its record says ``verified`` False, status 6).
    gap_scale : float, optional
        c of the gap rows, as in :func:`solve_frictionless`: default 1 (the
        thesis) on the full system, :data:`GAP_WEIGHT`·k̄ on the condensed
        one (every row of Φ then in force units, so that its iterates do
        not depend on the units).
    progress : callable, optional
        ``progress(step_record)`` after every completed step.
    on_step : callable, optional
        ``on_step(fields)`` once per completed step, in order, with that
        step's arrays (the per-step keys listed under Returns, without the
        first axis). On the condensed system the displacements of up to 32
        steps are recovered in one batched solve, so calls may lag the
        steps by up to 32; an exception (KeyboardInterrupt included) still
        delivers every completed step before it propagates.
    keep_steps : bool
        Keep the per-step arrays in the result (default). False keeps only
        the records, so that memory does not grow with the number of steps
        (stream them with ``on_step`` instead).
    geometry : ContactGeometry, optional
    condense : bool or None
        True: factorise K once and solve every step's system condensed
        exactly onto Γc (as in :func:`solve_frictionless`; the projection
        form's Newton systems are then solved reduced to the free
        components or to the contact constraints,
        :mod:`~solver.contact.friction_newton`); False: the
        system in all unknowns, one sparse LU per iteration (faithful mode;
        the iteration counts of Table 2). None (default): True for the
        projection formulation, False for the thesis's: its split is
        degenerate where p = 0 and its Newton path depends on the merit
        function; condensed (interior equilibrium always exact) it needs
        about twice the iterations and failed on the 118 block at f_c =
        0.05 (the same solution where both converge).
    backend : {"auto", "superlu", "pardiso", "cholmod"}
        Sparse direct solver of the condensed system, as in
        :func:`solve_frictionless`: one factorisation and its Schur
        complement serve every load step and Newton iteration.
    rollers : bool or None
        Whether contact nodes on symmetry planes (a Dirichlet component
        along which ν has none, :mod:`~solver.contact.geometry`) take part
        in contact and friction, as in :func:`solve_frictionless`: their
        friction traction lives in the free tangents only (module
        docstring). None (default): True in 3D, False in 2D (the thesis's
        runs: a roller is a support, λ = 0; the thesis's split refuses
        rollers). Ignored when ``geometry`` is given.
    candidates : bool, optional
        Condense onto the d DOFs of candidate nodes only, enlarged until
        no other node penetrates (:mod:`.friction_candidates`; result keys
        ``condensation`` "candidates" and ``candidates``). Default: True
        in 3D with the condensed projection form.
    margin : float, optional
        The candidates' round-0 gap margin δ₀, as in
        :func:`solve_frictionless`.
    condensation : :class:`~solver.linalg.Condensation`, optional
        K already condensed onto ``geometry.free_dofs()`` (its ``S``,
        ``load``, ``displacement``), used instead of factorising K with
        ``backend`` (the PETSc engine passes its distributed one).

    Returns
    -------
    OptimizeResult
        ``success``, ``message``, ``steps_completed``, ``failed_step``
        (None or κ), totals ``njev``, ``nfev``, ``nit``, ``time``; per step
        (arrays, first axis = completed steps): ``load_factor``,
        ``displacement`` (nodal), ``u`` (reduced), ``contact_force`` λ,
        ``contact_pressure`` (lumped λ/D, ≥ 0), ``contact_pressure_consistent``
        (M⁻¹λ, thesis (87)), ``friction_traction`` g_t ((Nc,) per step in
        2D, (Nc, d − 1) in the tangent basis ``geometry.tangents`` in 3D;
        so is ``tangential_displacement``),
        ``friction_bound`` f_c p used in the step (p_{κ−1} if lagged),
        ``tangential_displacement``, ``in_contact``, ``stick``, ``slip``
        (over all nodes of Γc; supports are never in contact), and
        ``records``: a list of dicts (κ, converged, verified, status, njev,
        nfev, nit, n_contact, n_stick, n_slip, error, relative (the
        stopping measure over its scale), message); per contact node
        (steps share them): ``gap`` s and ``normal`` ν (NaN at supports);
        ``verification`` (the worst of every completed step's checks, plus
        the last step's against the original K and f: keys as in
        :func:`solve_frictionless`, with ``friction_bound_violation``) and
        ``stopping`` (that of the step with the largest relative measure,
        with its ``step``); ``linear_solver`` (the backend that factorised
        K).

    Raises
    ------
    SolverError
        For a negative or non-finite ``friction``, a bad ``steps``, an
        unknown formulation; :class:`~solver.errors.ProblemError` if K is
        not positive definite or a normal line misses the obstacle (as in
        :func:`solve_frictionless`). A load step that does not converge
        ends the run without raising: see ``success`` and ``failed_step``.
    """
    if not _is_real(friction) or not np.isfinite(friction) or friction < 0:
        raise SolverError(f"friction coefficient must be >= 0 and finite, "
                          f"got {friction!r}")
    if steps is not None and problem.load_path is not None:
        raise SolverError(f"the problem defines a load path of "
                          f"{int(problem.load_path_steps.sum())} steps in "
                          f"{len(problem.load_path)} stages; do not give "
                          "the number of steps")
    if steps is not None and (not _is_real(steps) or not np.isfinite(steps)
                              or int(steps) != steps or steps < 1):
        raise SolverError(f"number of load steps must be a positive "
                          f"integer, got {steps!r}")
    path = problem.load_steps(steps)
    steps = problem.n_load_steps(steps)
    start = time.perf_counter()
    if rollers is None:  # 3D: rollers (the projection takes them)
        rollers = problem_dim(problem) == 3
    if geometry is None:
        geometry = contact_geometry(problem, gap, rollers=rollers)
    if use_candidates(candidates, condense, formulation, geometry.dim):
        check_geometry(geometry, formulation)
        return friction_on_candidates(solve_friction, problem, friction,
                                      geometry, margin, dict(
            steps=None if problem.load_path is not None else steps,
            formulation=formulation, coulomb=coulomb, method=method,
            tol=tol, max_iter=max_iter, options=options, gap_scale=(
                gap_scale if gap_scale is not None else GAP_WEIGHT *
                contact_stiffness(problem.K, geometry)), progress=progress,
            on_step=on_step, keep_steps=keep_steps, backend=backend))
    if formulation in FORMULATIONS:  # an unknown one: FrictionSystem says
        check_geometry(geometry, formulation)
    if steps > MAX_LOAD_STEPS:
        raise SolverError(f"{steps} load steps: at most {MAX_LOAD_STEPS} are "
                          "supported")
    lumped_all = np.asarray(problem.M.sum(axis=1)).ravel()
    mass = sla.splu(problem.M.tocsc())  # M⁻¹λ of every step
    lumped = lumped_all[geometry.index]
    stiffness = contact_stiffness(problem.K, geometry)
    if condense is None:
        condense = formulation != "thesis"
    linear_solver = resolve(backend)  # unknown or not installed: raises
    if not condense:  # K checked by SuperLU, Newton steps by SciPy's LU
        linear_solver = "superlu"
    if gap_scale is None:  # ∝ k̄: Φ's rows all in force units
        gap_scale = GAP_WEIGHT * stiffness if condense else 1.0
    reference_norm = stable_norm(problem.f)
    tol_v = verification_tolerance(tol)
    if condense:  # φ_FB's (26) unit-free, as in solve_frictionless
        options = unit_free_options(method, options, reference_norm,
                                    stiffness, geometry.gap)
        if condensation is None:
            condensation, local = condense_onto_contact(problem, geometry,
                                                        linear_solver)
        else:
            local = geometry.compact()
        system = condensed_system(geometry.dim, formulation)(
            condensation.S, condensation.load(problem.f)[0], local, lumped,
            friction, formulation, coulomb, gap_scale, stiffness)
    else:
        problem.check_stiffness()  # singular / indefinite K: input error
        system = FrictionSystem(problem.K, problem.f, geometry, lumped,
                                friction, formulation, coulomb, gap_scale,
                                stiffness)
    nc, idx = problem.n_contact, geometry.index
    u = np.zeros(system.n)  # u, or u on Γc if condensed
    w_previous = np.zeros(problem.n_dofs)  # K⁻¹f of the previous step
    p_previous = np.zeros(system.m)
    g = np.zeros(system.mt)
    k = geometry.dim - 1
    delivered = StepStream(problem, condensation if condense else None,
                           on_step, keep_steps, steps)
    records, failed = [], None
    checks, stoppings, last = [], [], None
    totals = dict(njev=0, nfev=0, nit=0)
    message = "all load steps converged"
    try:
        for kappa, (load, factor, prescribed, stage) in enumerate(path, 1):
            step_friction = friction * factor
            f_step, step_norm = load, max(reference_norm, stable_norm(load))
            du = None
            if condense:
                load, w = condensation.load(load)
                # Start with the contact forces of the previous step, as the
                # full system's Δu = 0 does: Γc moves as the unconstrained body.
                du = (w - w_previous)[condensation.dofs]
            x0 = system.initial_guess(g, du)
            system.set_step(u, load, p_previous, step_friction, step_norm)
            result = solve_ncp(system.residual, system.jacobian, x0,
                               method=method, tol=tol, max_iter=max_iter,
                               options=options, error=system.error,
                               scale=system.scale)
            result.stopping.update(test=STOPPING_TEST, step=kappa)
            for key in totals:
                totals[key] += int(result[key])
            du, g_new = result.x[:system.n], system.traction(result.x)
            check = _check_step(system, result.x, load, step_friction,
                                p_previous, tol_v)
            if result.success and not check["passed"]:
                result.update(success=False, status=6, message=(
                    f"{MESSAGES[6]}: {describe_failure(check)}"))
            record = dict(step=kappa, converged=bool(result.success),
                          verified=bool(check["passed"]),
                          status=int(result.status),
                          njev=int(result.njev), nfev=int(result.nfev),
                          nit=int(result.nit), error=float(result.error),
                          relative=float(result.stopping["relative"]),
                          message=result.message,
                          gradient_steps=int(sum(s == "gradient" for s in
                                                 result.history["step"])))
            if not result.success:
                failed = kappa
                record.update(n_contact=None, n_stick=None, n_slip=None,
                              residual_history=list(map(float, result.history[
                                  "residual"])))
                records.append(record)
                message = (f"load step {kappa} of {steps} did not converge: "
                           f"{result.message}")
                break
            checks.append(check)
            stoppings.append(result.stopping)
            u = u + du
            g = g_new
            r = system._force(du)
            lam = -r[system.n_rows]
            pressure = np.maximum(lam, 0.0) / lumped
            bound = step_friction * (p_previous if coulomb == "lagged"
                                     else pressure)
            scale = force_scale(step_norm, lam)  # as the stopping test's
            threshold = 1e-9 * scale
            contact = lam > threshold
            # Slip: the traction is at the Coulomb bound (a node in contact with
            # a zero bound slides freely); stick: strictly inside it.
            size = np.abs(g) if k == 1 else \
                np.linalg.norm(g.reshape(-1, k), axis=1)
            at_bound = size >= bound * (1 - 1e-6) - 1e-12 * scale
            slip_nodes = contact & at_bound
            stick_nodes = contact & ~slip_nodes
            ut = system.tangential(system.R @ u)
            last = (kappa, u.copy(), w if condense else None, f_step, lam,
                    _nodal(lumped, g), lumped * bound,
                    result.history["residual"])
            if condense:
                w_previous = w
            record.update(stage=int(stage), n_contact=int(contact.sum()),
                          n_stick=int(stick_nodes.sum()),
                          n_slip=int(slip_nodes.sum()),
                          max_pressure=float(pressure.max(initial=0.0)))
            records.append(record)

            def full(values, fill=0.0, dtype=float):
                values = np.asarray(values)
                if k > 1 and values.size == k * len(idx):  # (Nca, d − 1)
                    values = values.reshape(len(idx), k)
                out = np.full((nc,) + values.shape[1:], fill, dtype=dtype)
                out[idx] = values
                return out

            lam_all = full(lam)
            delivered.add(dict(
                load_factor=kappa / steps, stage=stage,
                contact_force=lam_all, contact_pressure=full(pressure),
                contact_pressure_consistent=mass.solve(lam_all) + 0.0,
                friction_traction=full(g), friction_bound=full(bound),
                tangential_displacement=full(ut, np.nan),
                in_contact=full(contact, False, bool),
                stick=full(stick_nodes, False, bool),
                slip=full(slip_nodes, False, bool)),
                u, w if condense else None, prescribed)
            p_previous = pressure
            if progress is not None:
                progress(record)
    finally:  # also on KeyboardInterrupt: deliver every completed step
        delivered.flush()
    verification = _final_check(problem, geometry, stiffness, tol_v,
                                condensation if condense else None, last,
                                checks)
    if failed is None and not verification["passed"]:
        failed = last[0]
        message = (f"load step {failed} of {steps} fails verification "
                   f"against the original K and f: "
                   f"{describe_failure(verification)}")
        records[-1].update(converged=False, verified=False, status=6,
                           message=f"{MESSAGES[6]}: {message}",
                           residual_history=list(map(float, last[-1])))
    stopping = max(stoppings, key=lambda s: s["relative"]) if stoppings \
        else dict(test=STOPPING_TEST, tol=float(tol), scale=np.nan,
                  absolute=np.nan, relative=np.nan, step=None)
    arrays = delivered.arrays()
    normal = np.full((nc, geometry.normal.shape[1]), np.nan)
    normal[idx] = geometry.normal
    gap_all = np.full(nc, np.nan)
    gap_all[idx] = geometry.gap
    return FrictionResult(
        success=failed is None, message=message, failed_step=failed,
        steps=int(steps), steps_completed=delivered.count,
        friction=float(friction), formulation=formulation, coulomb=coulomb,
        method=method, gap_mode=geometry.mode, records=records,
        condensed=bool(condense), gap=gap_all, normal=normal,
        linear_solver=linear_solver, verification=verification,
        stopping=stopping,
        time=time.perf_counter() - start, **totals, **arrays)

