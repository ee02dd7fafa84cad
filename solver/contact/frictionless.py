r"""The frictionless discrete contact system (thesis §3.2, (56)-(69), (87)).

Unknown: the reduced displacement vector u (Ñ entries). At each contact node
i with DOFs (a_i, b_i), unit normal ν_i (from the body towards the obstacle)
and tangent γ_i = (−ν_y, ν_x), the rotation **R** maps the nodal vector to
(tangential, normal) components (58)-(60); R is the identity elsewhere.
**X** keeps every row except the normal rows of contact nodes and **Y** keeps
only those (66). The system (67) is the mixed NCP

.. math::
    X(RKu − Rf) = 0, \quad
    A(u) = −Y(RKu − Rf) \ge 0,\ B(u) = s − YRu \ge 0,\ A^T B = 0,

(the thesis's (69) is the same with φ_min and signs flipped; its
"−Y(RKu + Rf)" is a typo for −Y(RKu − Rf)). A is the normal contact force
λ at each contact node, B the remaining gap. The contact stress (87) is
g_n = M⁻¹Y(RKu − Rf) = −M⁻¹λ; we report the contact pressure p = M⁻¹λ ≥ 0
(so g_n = −p), solving with the sparse M, never inverting it.

Only contact nodes whose two DOFs are free take part (a node with a
Dirichlet DOF is a support); their λ is 0 in the nodal arrays, which cover
every node of Γc in ``problem.contact_nodes`` order.

Optionally the gap rows are scaled, B = c(s − YRu) with c > 0 (same solution,
other Newton path); c = 1 is the thesis.

Condensed onto Γc (the default), the solve starts by nested iteration over
ever coarser node subsets of Γc (:mod:`solver.contact.nested`), which keeps
the Newton iterations on the full Γc at a fixed small number.
"""

import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from ..errors import SolverError
from ..linalg import Condensation, resolve
from ..ncp import MESSAGES, solve_ncp, stable_norm
from .result import ContactResult
from .verify import (describe_failure, force_scale, unit_free_options,
                     verification_tolerance, verify_contact)

__all__ = ["GAP_MODES", "ContactGeometry", "contact_geometry",
           "condense_onto_contact", "FrictionlessSystem",
           "solve_frictionless", "STARTS"]

#: How gaps and normals are found (thesis §2.1.1 / §2.1.2).
GAP_MODES = ("obstacle", "body")


class ContactGeometry:
    """Gaps and normals at the free contact nodes (evaluated once, §2.1).

    Attributes
    ----------
    index : (Nca,) int
        Rows of ``problem.contact_dofs`` (positions along Γc) of the free
        contact nodes.
    dofs : (Nca, 2) int
        Their reduced DOFs (x, y).
    gap : (Nca,) float
        Initial signed gap s along ``normal`` (negative = penetration).
    normal : (Nca, 2) float
        Unit normals ν from the body towards the obstacle.
    foot : (Nca,) float or None
        Obstacle parameter t of the point the gap is measured to.
    mode : str
        ``"obstacle"``, ``"body"`` or ``"given"`` (discrete problems).
    """

    def __init__(self, index, dofs, gap, normal, foot=None, mode="given"):
        self.index, self.dofs = index, dofs
        self.gap, self.normal, self.foot, self.mode = gap, normal, foot, mode


def contact_geometry(problem, gap="obstacle"):
    """Gaps and normals of ``problem`` (thesis §2.1).

    ``gap="obstacle"``: nearest obstacle point, ν = obstacle normal there
    (§2.1.1). ``gap="body"``: ν = the body's outward normal from a natural
    cubic spline through Γc (§2.1.3), gap along that line (§2.1.2).
    Discrete problems carry their gaps and normals; ``gap`` is ignored.
    """
    free = np.flatnonzero((problem.contact_dofs >= 0).all(axis=1))
    dofs = problem.contact_dofs[free]
    if problem.kind == "discrete":
        return ContactGeometry(free, dofs, problem.gap[free],
                               problem.normal[free])
    if gap not in GAP_MODES:
        raise SolverError(f"gap mode must be one of {GAP_MODES}, got {gap!r}")
    from ..geometry.gap import gap_along_normals, gap_from_obstacle
    from ..geometry.normals import boundary_normals

    body = boundary_normals(problem.nodes, problem.cells,
                            problem.contact_nodes)[free]
    ids = problem.contact_nodes[free]
    points = problem.nodes[ids]
    if gap == "obstacle":
        s, normal, t = gap_from_obstacle(points, problem.obstacle, body,
                                         node_ids=ids)
    else:
        s, normal, t = gap_along_normals(points, body, problem.obstacle,
                                         node_ids=ids)
    return ContactGeometry(free, dofs, s, normal, t, gap)


def contact_stiffness(K, geometry):
    """k̄: the mean diagonal stiffness at the contact DOFs (1 if none), the
    force per unit gap of the stopping measures."""
    if not len(geometry.dofs):
        return 1.0
    return float(K.diagonal()[geometry.dofs].mean())


def condense_onto_contact(problem, geometry, backend="auto"):
    """Factorise K once per K with the free contact DOFs last
    (:meth:`solver.linalg.Condensation.of`, which also checks that K is
    positive definite) and renumber ``geometry`` to the condensed DOFs
    (x, y of contact node i → 2i, 2i + 1), with the linear solver
    ``backend``. Returns (condensation, geometry).
    """
    condensation = Condensation.of(problem, geometry.dofs.ravel(), backend)
    problem._checked = problem.K  # the factorisation checked K's pivots
    m = len(geometry.dofs)
    local = ContactGeometry(geometry.index, np.arange(2 * m).reshape(m, 2),
                            geometry.gap, geometry.normal, geometry.foot,
                            geometry.mode)
    return condensation, local


def rotation(n, geometry):
    """R of (58)-(60), sparse (n, n): at contact node i with DOFs (a_i, b_i)
    row a_i = γ_i = (−ν_y, ν_x) (tangential), row b_i = ν_i (normal);
    identity elsewhere. Returns (R, other DOFs, a, b)."""
    a, b = geometry.dofs[:, 0], geometry.dofs[:, 1]
    nu = geometry.normal
    other = np.setdiff1d(np.arange(n), geometry.dofs.ravel())
    rows = np.concatenate([other, a, a, b, b])
    cols = np.concatenate([other, a, b, a, b])
    vals = np.concatenate([np.ones(len(other)), -nu[:, 1], nu[:, 0],
                           nu[:, 0], nu[:, 1]])
    return sp.csr_matrix((vals, (rows, cols)), shape=(n, n)), other, a, b


class FrictionlessSystem:
    """Residual and Jacobian of (67) for :func:`solver.ncp.solve_ncp`.

    Parameters
    ----------
    K : sparse (Ñ, Ñ)
        Reduced stiffness.
    f : (Ñ,) array
        Load vector.
    geometry : ContactGeometry
    gap_scale : float
        c in B = c(s − YRu); 1 is the thesis.
    stiffness : float, optional
        k̄ of :meth:`error` (default: mean of diag K at the contact DOFs; a
        condensed system passes that of the full K).
    load_norm : float, optional
        ‖f‖₂ of :meth:`scale` (default: of ``f``; a condensed system or a
        coarse level passes that of the problem's load).
    """

    def __init__(self, K, f, geometry, gap_scale=1.0, stiffness=None,
                 load_norm=None):
        n = K.shape[0]
        self.K, self.f, self.geometry = sp.csr_matrix(K), f, geometry
        self.gap_scale = float(gap_scale)
        self.R, _, _, b = rotation(n, geometry)
        keep = np.ones(n, dtype=bool)
        keep[b] = False
        self.x_rows, self.y_rows = np.flatnonzero(keep), b  # X and Y (66)
        RK = (self.R @ self.K).tocsr()
        self.Rf = self.R @ f
        self._JE = RK[self.x_rows]
        self._JA = -RK[self.y_rows]
        self._JB = -self.gap_scale * self.R[self.y_rows]
        self.stiffness = contact_stiffness(self.K, geometry) \
            if stiffness is None else float(stiffness)
        self.load_norm = stable_norm(f) if load_norm is None \
            else float(load_norm)

    def residual(self, u):
        """(E, A, B) = (X(RKu − Rf), −Y(RKu − Rf), c(s − YRu)), thesis (67)."""
        r = self.R @ (self.K @ u) - self.Rf
        return (r[self.x_rows], -r[self.y_rows],
                self.gap_scale * (self.geometry.gap - (self.R @ u)[self.y_rows]))

    def jacobian(self, u):
        """(JE, JA, JB) = (XRK, −YRK, −cYR): constant, the system is linear."""
        return self._JE, self._JA, self._JB

    def error(self, E, A, B):
        """Stopping measure in force units, whatever c and the NCP function:
        ‖[E; min(A, k̄ B / c)]‖₂ with k̄ the mean stiffness diag(K) at the
        normal DOFs, so that a gap error δ counts as the force k̄δ."""
        return float(np.hypot(stable_norm(E), stable_norm(
            np.minimum(A, self.stiffness / self.gap_scale * B))))

    def scale(self, E, A, B):
        """The force scale F = max(‖f‖₂, ‖λ⁺‖₂) of the stopping test
        error ≤ tol·F (A = λ; :mod:`solver.contact.verify`)."""
        return force_scale(self.load_norm, A)

    def contact_force(self, u):
        """λ = −Y(RKu − Rf): normal contact force at the free contact nodes."""
        return -(self.R @ (self.K @ u) - self.Rf)[self.y_rows]

    def normal_displacement(self, u):
        """u_n = YRu at the free contact nodes."""
        return (self.R @ u)[self.y_rows]


#: The stopping test of :func:`solve_frictionless`, as reported.
STOPPING_TEST = ("‖[E; min(λ, k̄(s − u_n))]‖₂ ≤ tol·max(‖f‖₂, ‖λ⁺‖₂)")

#: Starts of :func:`solve_frictionless` (when no x0 is given).
STARTS = ("nested", "free")


def _start_mode(start, x0, condense):
    """The start actually used: "nested", "free", "x0" or "zero"."""
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
    return start or "nested"


def solve_frictionless(problem, method="min", gap="obstacle", tol=1e-10,
                       max_iter=100, x0=None, gap_scale=None, options=None,
                       geometry=None, condense=None, start=None,
                       backend="auto"):
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
        units, see :mod:`solver.contact.nested`) on the condensed one.
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
        Start when ``x0`` is not given. Condensed: "nested" (default) solves
        the problem on ever coarser subsets of Γc first
        (:func:`solver.contact.nested.solve_nested`); "free" starts from no
        contact force, u = K⁻¹f. The full system always starts from the
        thesis's u = 0.
    backend : {"auto", "superlu", "pardiso", "cholmod"}
        Sparse direct solver of the condensed system
        (:mod:`solver.linalg`; "auto": the fastest installed). The full
        system's Newton steps are general sparse LUs (SciPy) whatever it
        is.

    Returns
    -------
    OptimizeResult
        The NCP result (``success``, ``status``, ``message``, ``nit``,
        ``njev``, ``nfev``, ``history``, ``residual``) plus ``u`` (reduced),
        ``displacement`` (nodal, (n_nodes, 2); for a discrete problem the
        contact nodes' (Nc, 2)), and over all nodes of Γc: ``contact_force``
        λ, ``contact_pressure`` p_i = max(λ_i, 0) / D_ii with the lumped
        boundary matrix D_ii = Σ_j M_ij (a nodal force per unit length; λ
        is ≥ 0 by complementarity up to the tolerance, cut off at 0 here
        as in the friction bound), ``contact_pressure_consistent`` M⁻¹λ (the
        thesis's g_n = −p of (87); it oscillates, negative outside the
        contact zone),
        ``gap`` s and ``normal`` ν (NaN at supports), ``normal_displacement``
        u_n, ``in_contact``; and ``complementarity`` = max|min(λ, s − u_n)|,
        ``n_contact``, ``gap_mode``, ``gap_scale`` (c used), ``condensed``,
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
        on the full system.
    ProblemError
        If K is not positive definite (checked once per K by one sparse
        factorisation, :meth:`ContactProblem.check_stiffness`), or a normal
        line misses the obstacle (:class:`~solver.geometry.gap.GapError`). A solve
        that does not converge raises nothing: see ``success`` and
        ``status``.
    """
    clock = time.perf_counter()
    if geometry is None:
        geometry = contact_geometry(problem, gap)
    geometry_time = time.perf_counter() - clock
    load_norm = stable_norm(problem.f)
    stiffness = contact_stiffness(problem.K, geometry)
    condense = condense is None or bool(condense)
    start = _start_mode(start, x0, condense)
    linear_solver = resolve(backend)  # unknown or not installed: raises
    if not condense:  # K checked by SuperLU, Newton steps by SciPy's LU
        linear_solver = "superlu"
    if gap_scale is None:
        gap_scale = stiffness if condense else 1.0
    if condense:  # c = k̄ and (26) unit-free: iterates independent of units
        options = unit_free_options(method, options, load_norm, stiffness,
                                    geometry.gap)
        condensation, local = condense_onto_contact(problem, geometry,
                                                    linear_solver)
        g, w = condensation.load(problem.f)
        w_c = w[condensation.dofs]
        if start == "nested":
            from .nested import contact_levels, solve_nested

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
    if start != "nested":
        result = solve_ncp(system.residual, system.jacobian, x0,
                           method=method, tol=tol, max_iter=max_iter,
                           options=options, error=system.error,
                           scale=system.scale)
        result.levels = []
    result.stopping["test"] = STOPPING_TEST
    lam_free = system.contact_force(result.x)
    un_free = system.normal_displacement(result.x)
    if condense:
        result.x = condensation.displacement(result.x, w)
    u = result.x
    nc = problem.n_contact
    lam = np.zeros(nc)
    lam[geometry.index] = lam_free
    un = np.full(nc, np.nan)
    un[geometry.index] = un_free
    s = np.full(nc, np.nan)
    s[geometry.index] = geometry.gap
    normal = np.full((nc, 2), np.nan)
    normal[geometry.index] = geometry.normal
    pressure = sla.spsolve(problem.M.tocsc(), lam) + 0.0  # no -0.0
    lumped = np.maximum(lam, 0.0) / np.asarray(problem.M.sum(axis=1)).ravel()
    remaining = s - un
    comp = np.abs(np.minimum(lam, remaining))[geometry.index]
    verification = verify_contact(problem.K, problem.f, u, geometry.dofs,
                                  geometry.normal, geometry.gap, lam_free,
                                  stiffness, verification_tolerance(tol))
    if result.success and not verification["passed"]:
        result.update(success=False, status=6, message=(
            f"{MESSAGES[6]}: {describe_failure(verification)}"))
    threshold = 1e-9 * force_scale(load_norm, lam)
    in_contact = lam > threshold
    if problem.kind == "mesh":
        displacement = problem.full_displacement(u)
    else:
        displacement = u[problem.contact_dofs]
    result.update(
        u=u, displacement=displacement, contact_force=lam,
        contact_pressure=lumped, contact_pressure_consistent=pressure,
        gap=s, normal=normal,
        normal_displacement=un, in_contact=in_contact,
        complementarity=float(comp.max(initial=0.0)),
        n_contact=int(in_contact.sum()), gap_mode=geometry.mode,
        gap_scale=float(gap_scale), geometry_time=geometry_time,
        condensed=bool(condense), start=start, linear_solver=linear_solver,
        verification=verification,
        time=time.perf_counter() - clock)
    return ContactResult(result)
