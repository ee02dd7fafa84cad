r"""The frictionless discrete contact system (thesis §3.2, (56)-(69), (87)).

Unknown: the reduced displacement vector u (Ñ entries). At each contact node
i with DOFs (a_i, …), unit normal ν_i (from the body towards the obstacle)
and tangents (2D: γ_i = (−ν_y, ν_x); 3D: τ_1, τ_2 of
:func:`solver.geometry.frames.tangent_basis`), the rotation **R** maps the
nodal vector to (tangential, normal) components (58)-(60); R is the
identity elsewhere (:func:`~solver.contact.geometry.rotation`).
**X** keeps every row except the normal rows of contact nodes and **Y** keeps
only those (66). The system (67) is the mixed NCP

.. math::
    X(RKu − Rf) = 0, \quad
    A(u) = −Y(RKu − Rf) \ge 0,\ B(u) = s − YRu \ge 0,\ A^T B = 0,

(the thesis's (69) is the same with φ_min and signs flipped; its
"−Y(RKu + Rf)" is a typo for −Y(RKu − Rf)). A is the normal contact force
λ at each contact node, B the remaining gap. The contact stress (87) is
g_n = M⁻¹Y(RKu − Rf) = −M⁻¹λ; we report the contact pressure p = M⁻¹λ ≥ 0
(so g_n = −p), solving with the sparse M, never inverting it. Everything
here works from the :class:`ContactGeometry` (DOFs, gaps, frames) and is
the same in 2D and 3D.

The contact nodes whose DOFs are all free take part, and by default
(``rollers=True``) also the *rollers*: nodes on a symmetry plane of a half
or quarter model, whose Dirichlet components have no share in ν (their
frame puts the constrained directions among the tangents, see
:mod:`solver.contact.geometry`); the λ of such a node is that of the half
(quarter) of the whole model's node it stands for. Any other node with a
Dirichlet DOF is a support: its λ is 0 in the nodal arrays, which cover
every node of Γc in ``problem.contact_nodes`` order. Friction runs
(:func:`solve_friction`) keep every node with a Dirichlet DOF a support.

Optionally the gap rows are scaled, B = c(s − YRu) with c > 0 (same solution,
other Newton path); c = 1 is the thesis.

Three ways to solve it (:func:`solve_frictionless`):

* 2D default: condensed onto every DOF of Γc (S of size 2Nc), started by
  nested iteration over ever coarser node subsets of Γc
  (:mod:`solver.contact.strategies.nested`), which keeps the Newton iterations on the
  full Γc at a fixed small number.
* 3D default: condensed onto the *normal* DOF of *candidate* nodes only
  (:mod:`solver.contact.strategies.candidates`: one unknown per node that can touch,
  enlarged and re-solved if a non-candidate penetrates), from the free
  start. The nested start coarsens by taking every other node along the
  ordered curve Γc; a contact surface has no such order, so 3D uses the
  free start (λ = 0) instead.
* ``condense=False``: the thesis's system in all Ñ unknowns.

In 2D the (x, y) condensation onto all of Γc stays the default. Measured
on the thesis blocks 118/454/1878 (gap from the obstacle, free start,
every node a candidate): the normal-only condensation takes the same
Newton counts as the (x, y) one (φ_min 3/5/6 J, φ_FB 8/11/14 J) and the
same u to 2e-14 (the tangential rows are linear and stay satisfied from
the free start on), but the nested start, the 2D default, is built on the
(x, y) condensation and its answers are kept bit for bit; with the
default margin the candidates grow once on those blocks (one more
factorisation), which a 2D Γc of 10²-10³ nodes does not need to save.
"""

import time

import numpy as np
import scipy.sparse.linalg as sla

from ...errors import SolverError
from ...linalg import Condensation, resolve
from ...ncp import MESSAGES, solve_ncp, stable_norm
from .system import FrictionlessSystem
from ..geometry import (GAP_MODES, ContactGeometry, contact_geometry,
                       contact_stiffness, rotation)
from ..result import ContactResult
from ..verify import (describe_failure, force_scale, unit_free_options,
                     verification_tolerance, verify_contact)

__all__ = ["GAP_MODES", "ContactGeometry", "contact_geometry",
           "condense_onto_contact", "FrictionlessSystem",
           "solve_frictionless", "STARTS", "rotation", "contact_stiffness"]


def condense_onto_contact(problem, geometry, backend="auto"):
    """Factorise K once per K with the free contact DOFs last
    (:meth:`solver.linalg.Condensation.of`, which also checks that K is
    positive definite) and renumber ``geometry`` to the condensed DOFs
    (the d DOFs of contact node i → d·i, …, d·i + d − 1; a roller's free
    DOFs only, :meth:`ContactGeometry.compact`), with the linear solver
    ``backend``. Returns (condensation, geometry).
    """
    condensation = Condensation.of(problem, geometry.free_dofs(), backend)
    problem._checked = problem.K  # the factorisation checked K's pivots
    return condensation, geometry.compact()


#: The stopping test of :func:`solve_frictionless`, as reported.
STOPPING_TEST = ("‖[E; min(λ, k̄(s − u_n))]‖₂ ≤ tol·max(‖f‖₂, ‖λ⁺‖₂)")

#: Starts of :func:`solve_frictionless` (when no x0 is given).
STARTS = ("nested", "free")


def _start_mode(start, x0, condense, nested=True):
    """The start actually used: "nested", "free", "x0" or "zero".
    ``nested``: whether the nested start is possible (2D, condensed onto
    all of Γc); else "free" is the default and "nested" refused."""
    if start is not None and start not in STARTS:
        raise SolverError(f"start must be one of {STARTS}, got {start!r}")
    if x0 is not None:
        if start is not None:
            raise SolverError("give either x0 or start, not both")
        return "x0"
    if not condense:
        if start == "nested":
            raise SolverError("the nested start needs the condensed system "
                              "(condense=True)")
        return "zero"
    if not nested:
        if start == "nested":
            raise SolverError("the nested start coarsens along the ordered "
                              "2D curve Γc: use start='free' in 3D and with "
                              "candidates=True")
        return "free"
    return start or "nested"


def _use_candidates(candidates, condense, dim):
    """Whether to condense onto the candidates' normal DOFs (default: in
    3D, condensed)."""
    if candidates is None:
        return condense and dim == 3
    if candidates and not condense:
        raise SolverError("candidates=True needs the condensed system "
                          "(condense=True)")
    return bool(candidates)


def solve_frictionless(problem, method="min", gap="obstacle", tol=1e-10,
                       max_iter=100, x0=None, gap_scale=None, options=None,
                       geometry=None, condense=None, start=None,
                       backend="auto", candidates=None, margin=None,
                       rollers=True):
    r"""Solve the frictionless contact problem (67) by semismooth Newton.

    Parameters
    ----------
    problem : ContactProblem
    method : {"min", "fb"}
        φ_min damped Newton (§2.2.1) or Fischer–Burmeister (§2.2.2).
    gap : {"obstacle", "body"}
        Gap and normals from the obstacle (§2.1.1) or from the body's spline
        normals (§2.1.2-2.1.3). Ignored for discrete problems.
    tol : float
        Relative tolerance, independent of units: stop when
        ‖[E; min(λ, k̄(s − u_n))]‖₂ ≤ tol·F with the force scale
        F = max(‖f‖₂, ‖λ⁺‖₂) of the iterate (:mod:`solver.contact.verify`;
        :meth:`FrictionlessSystem.error`, :meth:`FrictionlessSystem.scale`).
        Scaling K and f by any factor, or all lengths, gives the same
        verdict; the condensed and nested solves (c = k̄) also take the
        same iterates. The full system's thesis choice c = 1 compares a
        force with a length in φ(λ, c(s − u_n)), so its Newton path (not
        its verdict or answer) depends on the units. The methods iterate
        on their own Φ (gap rows scaled by ``gap_scale``). A converged
        answer is then verified (see Returns).
    max_iter : int
        Maximum number of Newton iterations (all levels of a nested start
        together).
    x0 : (Ñ,) array, optional
        Starting displacement (read on Γc only when condensed). Default:
        see ``start``.
    gap_scale : float, optional
        c in B = c(s − YRu), see :class:`FrictionlessSystem`. Default: 1 on
        the full system (the thesis), the contact stiffness k̄ (gaps in force
        units, see :mod:`solver.contact.strategies.nested`) on the condensed one.
    options : dict, optional
        Method options of :func:`solver.ncp.solve_ncp`.
    geometry : ContactGeometry, optional
        Precomputed gaps and normals (else :func:`contact_geometry`).
    condense : bool or None
        True (default; None means True): factorise K once, with the contact
        DOFs last, and iterate on the same system (67) condensed exactly
        onto Γc (K → its
        Schur complement S, f → g̃; :class:`solver.linalg.Condensation`):
        a solve costs about one factorisation of K. The start u = x0 is then
        read on Γc only (the other DOFs are in equilibrium throughout).
        False: the thesis's system in all Ñ unknowns with one sparse LU of
        the Jacobian per iteration (faithful mode; its iteration counts are
        those of Table 1).
    start : {"nested", "free"}, optional
        Start when ``x0`` is not given. Condensed in 2D: "nested" (default)
        solves the problem on ever coarser subsets of Γc first
        (:func:`solver.contact.strategies.nested.solve_nested`); "free" starts from no
        contact force, u = K⁻¹f. In 3D and with ``candidates=True`` only
        "free" (the default there; "nested" raises). The full system
        always starts from the thesis's u = 0.
    backend : {"auto", "superlu", "pardiso", "cholmod"}
        Sparse direct solver of the condensed system
        (:mod:`solver.linalg`; "auto": the fastest installed). The full
        system's Newton steps are general sparse LUs (SciPy) whatever it
        is.
    candidates : bool, optional
        Condense onto the normal DOFs of candidate nodes only
        (:mod:`solver.contact.strategies.candidates`). Default: True in 3D when
        condensed, False in 2D (the (x, y) condensation onto all of Γc).
    margin : float, optional
        The candidates' round-0 screening margin δ₀, a length: nodes with
        initial gap s_i ≤ δ₀ (default: every free contact node in 2D,
        :func:`~solver.contact.strategies.candidates.initial_candidates`'s screening
        in 3D). Too small a margin costs refactorisations, never accuracy.
    rollers : bool
        Whether contact nodes with Dirichlet components orthogonal to ν
        (symmetry planes) take part in contact (default) or are supports
        (:func:`contact_geometry`; the thesis's blocks have none). Ignored
        when ``geometry`` is given: that geometry decides.

    Returns
    -------
    OptimizeResult
        The NCP result (``success``, ``status``, ``message``, ``nit``,
        ``njev``, ``nfev``, ``history``, ``residual``) plus ``u`` (reduced),
        ``displacement`` (nodal, (n_nodes, d); for a discrete problem the
        contact nodes' (Nc, d)), and over all nodes of Γc: ``contact_force``
        λ, ``contact_pressure`` p_i = max(λ_i, 0) / D_ii with the lumped
        boundary matrix D_ii = Σ_j M_ij (a nodal force per unit length; λ
        is ≥ 0 by complementarity up to the tolerance, cut off at 0 here
        as in the friction bound), ``contact_pressure_consistent`` M⁻¹λ (the
        thesis's g_n = −p of (87); it oscillates, negative outside the
        contact zone),
        ``gap`` s and ``normal`` ν (NaN at supports), ``normal_displacement``
        u_n, ``in_contact``; and ``complementarity`` = max|min(λ, s − u_n)|,
        ``n_contact``, ``gap_mode``, ``gap_scale`` (c used), ``condensed``,
        ``condensation`` ("contact": every DOF of Γc; "normal candidates";
        "none": the full system), ``candidates`` (None, or the screening
        dict of :func:`~solver.contact.strategies.candidates.solve_on_candidates`:
        ``margin``, ``rounds``, ``n_candidates``, ``enlarged``,
        ``exhausted``),
        ``start`` ("nested", "free", "zero" or "x0"), ``levels`` (per-level
        counts of a nested start, coarsest first, else []; ``nit``,
        ``njev`` and ``nfev`` then count all levels), ``geometry_time``,
        ``time``, ``linear_solver`` (the backend that factorised K);
        ``stopping`` (dict: ``test``, the formula; ``tol``;
        ``scale``, F at the answer; ``absolute``, the measure at the
        answer; ``relative`` = absolute / F) and ``verification`` (dict of
        :func:`~solver.contact.verify.verify_contact`: ``passed``,
        ``finite``, ``max_penetration``, ``min_multiplier``,
        ``complementarity``, ``equilibrium``, ``force_scale``,
        ``length_scale``, ``tolerances``, ``failed``). An answer that meets
        the stopping test but fails verification is reported with
        ``success`` False and ``status`` 6, its history kept.

    Raises
    ------
    SolverError
        If ``start`` is unknown, given together with ``x0``, or "nested"
        on the full system, in 3D or with candidates; or candidates=True
        with condense=False.
    ProblemError
        If K is not positive definite (checked once per K by one sparse
        factorisation, :meth:`ContactProblem.check_stiffness`), or a
        normal line misses the obstacle
        (:class:`~solver.geometry.curves.GapError`). A solve that does not
        converge raises nothing: see ``success`` and ``status``.
    """
    clock = time.perf_counter()
    if geometry is None:
        geometry = contact_geometry(problem, gap, rollers=rollers)
    geometry_time = time.perf_counter() - clock
    load_norm = stable_norm(problem.f)
    stiffness = contact_stiffness(problem.K, geometry)
    condense = condense is None or bool(condense)
    by_candidates = _use_candidates(candidates, condense, geometry.dim)
    start = _start_mode(start, x0, condense,
                        geometry.dim == 2 and not by_candidates)
    linear_solver = resolve(backend)  # unknown or not installed: raises
    if not condense:  # K checked by SuperLU, Newton steps by SciPy's LU
        linear_solver = "superlu"
    if gap_scale is None:
        gap_scale = stiffness if condense else 1.0
    if condense:  # c = k̄ and (26) unit-free: iterates independent of units
        options = unit_free_options(method, options, load_norm, stiffness,
                                    geometry.gap)
    screening = None
    if by_candidates:
        from ..strategies.candidates import solve_on_candidates

        result, u, lam_free, un_free, screening = solve_on_candidates(
            problem, geometry, method, tol, max_iter, x0, gap_scale,
            stiffness, options, load_norm, linear_solver, margin)
    elif condense:
        condensation, local = condense_onto_contact(problem, geometry,
                                                    linear_solver)
        g, w = condensation.load(problem.f)
        w_c = w[condensation.dofs]
        if start == "nested":
            from ..strategies.nested import contact_levels, solve_nested

            result, system = solve_nested(
                contact_levels(condensation.S, w_c, local), method,
                tol, max_iter, gap_scale, stiffness, options, load_norm)
        else:
            system = FrictionlessSystem(condensation.S, g, local, gap_scale,
                                        stiffness, load_norm)
            # "free": no contact force, as the thesis's u = 0 has λ = 0 on
            # Γc; condensed, λ = 0 is the unconstrained solution w = K⁻¹f.
            x0 = w_c if x0 is None else np.asarray(x0, float)[
                condensation.dofs]
    else:
        x0 = np.zeros(problem.n_dofs) if x0 is None else \
            np.asarray(x0, float)
        problem.check_stiffness()  # singular / indefinite K: input error
        system = FrictionlessSystem(problem.K, problem.f, geometry,
                                    gap_scale, stiffness, load_norm)
    if not by_candidates:
        if start != "nested":
            result = solve_ncp(system.residual, system.jacobian, x0,
                               method=method, tol=tol, max_iter=max_iter,
                               options=options, error=system.error,
                               scale=system.scale)
            result.levels = []
        lam_free = system.contact_force(result.x)
        un_free = system.normal_displacement(result.x)
        u = condensation.displacement(result.x, w) if condense else result.x
    result.stopping["test"] = STOPPING_TEST
    result.x = u
    verification = verify_contact(
        problem.K, problem.f, u, geometry.node_dofs, geometry.normal,
        geometry.gap, lam_free, stiffness, verification_tolerance(tol))
    if result.success and not verification["passed"]:
        result.update(success=False, status=6, message=(
            f"{MESSAGES[6]}: {describe_failure(verification)}"))
        if screening and screening["exhausted"]:
            result.message += (f" (the candidates still grew after "
                               f"{len(screening['rounds'])} rounds: give a "
                               "larger margin)")
    result.update(_nodal_arrays(problem, geometry, u, lam_free, un_free,
                                load_norm))
    result.update(
        gap_mode=geometry.mode, gap_scale=float(gap_scale),
        geometry_time=geometry_time, condensed=bool(condense),
        condensation=("normal candidates" if by_candidates else
                      "contact" if condense else "none"),
        candidates=screening, start=start, linear_solver=linear_solver,
        verification=verification, time=time.perf_counter() - clock)
    return ContactResult(result)


def _nodal_arrays(problem, geometry, u, lam_free, un_free, load_norm):
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
    if problem.kind == "mesh":
        displacement = problem.full_displacement(u)
    else:
        displacement = u[problem.contact_dofs]
    return dict(
        u=u, displacement=displacement, contact_force=lam,
        contact_pressure=lumped, contact_pressure_consistent=pressure,
        gap=s, normal=normal, normal_displacement=un, in_contact=in_contact,
        complementarity=float(comp.max(initial=0.0)),
        n_contact=int(in_contact.sum()))
