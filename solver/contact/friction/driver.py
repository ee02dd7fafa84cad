r"""Coulomb friction by load steps (thesis §5-§6, (88)-(111)).

The load is applied in κc steps, f_κ = κ/κc · f. Each step solves for the
increment Δu (u = u_{κ−1} + Δu) and the friction traction g_t at the free
contact nodes, starting from the previous step's solution.

Which Coulomb bound (errata of (104)): the thesis's row 3 balances the
tangential nodal force with M g_t (g_t a traction), while its bound f_c p
uses p of (104), a nodal *force*. We compare like with like, per node as
the thesis intends: the tangential row uses the lumped boundary matrix
D = diag(Σ_j M_ij) and p is the lumped contact pressure p_i = λ_i / D_ii ≥
0, so |g_t,i| ≤ f_c p_i is |t_i| ≤ f_c λ_i for the nodal friction force
t_i = D_ii g_t,i: Coulomb's law on nodal forces (for the 2-DOF bar D = 1).
``coulomb="lagged"`` uses p = p_{κ−1} (the thesis: Coulomb as a sequence
of Tresca problems); ``"implicit"`` the current step's p(u), with its
derivative in the Jacobian.

Formulations. ``"thesis"`` (110)/(111), :mod:`.split` (2D): unknowns
x = [Δu; g_t; Δu_t⁺; Δu_t⁻] with

.. math::
    X(RKu − f_κ R) = 0, \quad Z(RKu − f_κ R) − D g_t = 0, \quad
    ZRΔu − Δu_t^+ + Δu_t^- = 0 \ (106), \\
    λ = −Y(RKu − f_κ R) \perp s − YRu, \quad
    Δu_t^- \perp f_c p − g_t \ (98), \quad Δu_t^+ \perp f_c p + g_t \ (101),

(X drops the tangential and normal rows of contact nodes, Z keeps the
tangential ones (77)). Where p = 0 the last two pairs only give g_t = 0
and leave the split Δu_t± non-unique: J is singular there, and φ_FB falls
back to gradient steps (errata). ``"projection"`` (beyond the thesis; 2D
and 3D, rollers included), :mod:`.projection`: unknowns x = [Δu; g_t] and
the semismooth projection onto the disc |g_t| ≤ f_c p (Alart & Curnier
1991; Hüeber, Stadler & Wohlmuth 2008)

.. math::  g_t = \mathrm{proj}_{[−f_c p,\, f_c p]}(g_t − c_t\, ZRΔu),

non-degenerate: p = 0 gives g_t = 0, and c_t > 0 only changes the Newton
path. Its condensed Newton systems are reduced in 2D (:mod:`.newton`) and
have the tractions eliminated in 3D (:mod:`.disc`).

References
----------
P. Alart, A. Curnier: A mixed formulation for frictional contact problems
prone to Newton like solution methods. CMAME 92 (1991) 353-375.
S. Hüeber, G. Stadler, B. Wohlmuth: A primal-dual active set algorithm for
three-dimensional contact problems with Coulomb friction. SIAM J. Sci.
Comput. 30 (2008) 572-596."""

import time
from types import SimpleNamespace

import numpy as np

from ...errors import SolverError
from ..geometry import contact_stiffness
from ..strategies.reduction import reduction
from .steps import GAP_WEIGHT, load_step, make_result, setup
from .stream import MAX_LOAD_STEPS, StepStream
from .system import COULOMB, FORMULATIONS

__all__ = ["FORMULATIONS", "COULOMB", "run_friction", "check_friction",
           "default_method"]


def default_method(formulation):
    """The Newton method of a friction run that names none: φ_FB for the
    thesis's split, as in the thesis (φ_min's Jacobian is singular there
    where p = 0), φ_min for the projection formulation (from the corrected
    start, :mod:`.start`, it needs no more Jacobians; benchmarks/README.md)."""
    return "fb" if formulation == "thesis" else "min"


def run_friction(problem, geometry, engine, friction, steps=None,
                 formulation="projection", coulomb="lagged", method="min",
                 tol=1e-10, max_iter=100, gap_scale=None, options=None,
                 progress=None, condense=True, on_step=None,
                 keep_steps=True, candidates=False, margin=None):
    r"""Quasi-static Coulomb friction in load steps (thesis §5, (110)/(111)).

    The driver behind :func:`solver.solve` with ``friction`` f_c, whose
    docstring explains the options; they arrive resolved and checked, with
    the ``geometry`` of the contact nodes that take part and the ``engine``.
    ``tol``, ``max_iter``, ``options`` are per step, the test ‖[E; min(A,
    k̄B)]‖₂ ≤ tol·max(‖f‖₂, ‖f_κ‖₂, ‖λ⁺‖₂); every converged step is verified
    (:func:`~solver.contact.verify.verify_contact`, the Coulomb bound
    included), the last also against the original K and f, and a step that
    fails ends the run (status 6). ``gap_scale`` c: 1 on the full system,
    :data:`GAP_WEIGHT`·k̄ condensed. ``on_step(fields)`` is called once per
    completed step, in order (condensed: up to :data:`~.stream.BATCH` steps
    late), also when an exception ends the run.

    Returns a ContactResult: ``success``, ``message``, ``steps_completed``,
    ``failed_step``, the totals, the per-step arrays and ``records`` of
    docs/results.md ("A friction run"), ``verification`` (the worst step's)
    and ``stopping`` (the step with the largest relative measure)."""
    path = problem.load_steps(steps)
    steps = problem.n_load_steps(steps)
    start = time.perf_counter()
    if candidates:
        from ..strategies.friction_candidates import friction_on_candidates

        if gap_scale is None:
            gap_scale = GAP_WEIGHT * contact_stiffness(problem.K, geometry)
        keywords = dict(
            steps=None if problem.load_path is not None else steps,
            formulation=formulation, coulomb=coulomb, method=method, tol=tol,
            max_iter=max_iter, options=options, gap_scale=gap_scale,
            progress=progress, on_step=on_step, keep_steps=keep_steps)
        return friction_on_candidates(run_friction, problem, friction,
                                      geometry, engine, margin, keywords)
    if steps > MAX_LOAD_STEPS:
        raise SolverError(f"{steps} load steps: at most {MAX_LOAD_STEPS} are "
                          "supported")
    if getattr(engine, "iterative", False):  # AMG: the active set method
        from .active_set import FloatingIterativeSpace, IterativeSpace

        space = FloatingIterativeSpace(problem, geometry, engine, friction,
                                       coulomb) if problem.floating \
            else IterativeSpace(problem, geometry, engine)
    else:
        space = reduction(problem, geometry, engine, condense, friction)
    shared = setup(problem, geometry, space, friction, formulation, coulomb,
                   method, tol, options, gap_scale)
    stream = StepStream(problem, space, on_step, keep_steps, steps)
    run = SimpleNamespace(records=[], failed=None, checks=[], stoppings=[],
                          last=None, totals=dict(njev=0, nfev=0, nit=0),
                          message="all load steps converged")
    state = SimpleNamespace(u=np.zeros(shared.system.n),  # u, or u on Γc
                            w=np.zeros(problem.n_dofs),  # K⁻¹f of step κ−1
                            p=np.zeros(shared.system.m),
                            g=np.zeros(shared.system.mt))
    try:
        for kappa, (load, factor, prescribed, stage) in enumerate(path, 1):
            if not load_step(shared, state, run, stream, kappa, steps, load,
                             friction * factor, prescribed, stage, method,
                             tol, max_iter):
                break
            if progress is not None:
                progress(run.records[-1])
    finally:  # also on KeyboardInterrupt: deliver every completed step
        stream.flush()
    return make_result(problem, geometry, shared, run, stream, steps,
                       friction, formulation, coulomb, method, tol, start)


def check_friction(problem, friction, steps):
    """SolverError for a bad friction coefficient or number of steps."""
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
    total = problem.n_load_steps(steps)
    if total > MAX_LOAD_STEPS:
        raise SolverError(f"the load path has {total} load steps; at most "
                          f"{MAX_LOAD_STEPS} are supported")


def _is_real(value):
    return isinstance(value, (int, float, np.integer, np.floating)) \
        and not isinstance(value, bool)
