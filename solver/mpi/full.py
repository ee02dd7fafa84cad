r"""The semismooth Newton on the full system (67), each Newton system by KSP.

For candidate sets too large for a dense Schur complement. The Newton
iteration is the project's (:func:`solver.ncp.solve_ncp` on rank 0, the
iterates of the serial ``condense=False``); its Newton systems J d = −Φ
are solved on all ranks through the structured-Jacobian hook of
:mod:`solver.ncp.newton`. In the node frames, v = Rd, J Rᵀ has the rows
of K̂ = RKRᵀ except at the normal row n_i of a contact node,
−w_a K̂_{n_i,:} − c w_b e_{n_i}ᵀ (w_a, w_b ≤ 0); divided by −w_a,
K̂_{n_i,:} + c(w_b/w_a)e_{n_i}ᵀ, a non-negative diagonal shift; with
w_a = 0 it fixes v_{n_i} = Φ_i/(c w_b). The fixed rows are eliminated
symmetrically (``MatZeroRowsColumns``), so every Newton system is SPD:
MUMPS (Cholesky, refactorised on the same pattern) or CG + GAMG with the
rotated rigid-body modes as near-null space (``--ksp gamg``).

Inexact Newton on the partitioned folder (:mod:`.partitioned_full`,
:mod:`.krylov_friction`): a Krylov Newton system is solved to
‖r‖ ≤ η_k·err_k (r its unpreconditioned residual, err_k the stopping
measure at the iterate with the contact rows unweighted, in the units of
r) with the in-process AMG path's forcing term
(:func:`~solver.contact.frictionless.active_set.forcing_term`,
Eisenstat & Walker's choice 2 with its safeguards, η_0 = 10⁻³), kept by
:class:`ForcingTerm`; once the active set repeats after a full step, the
system is the last one and is solved to :data:`CG_RTOL` as before, so
that the answer stays the exact path's (the in-process path stops at
half the stopping test's bound instead, which gave a stick set other
than the serial answer's: docs/mpi.md). The stopping test of the Newton iteration is unchanged. Each system
starts from the iterate moved onto its constraints, or after a damped
step from the last system's answer (:meth:`ForcingTerm.step`). Not on
the ``.npz``'s Newton iteration here (rank 0's serial ``condense=False``
iterates, c = 1, φ_min or Fischer–Burmeister): inexact systems made its
φ_min cycle between active sets (c = 1 weighs a force error against a
gap in length units) and its FB stall, so its systems stay exact."""

import numpy as np
import scipy.sparse as sp

from ..contact.frictionless.active_set import ETA_MAX, forcing_term
from ..contact.geometry import rotate_stiffness
from ..linalg.amg import GMRES_RESTART
from ..linalg.base import PIVOT_RTOL
from ..ncp.newton import LocalReduction
from .layout import gather_vector, scatter_matrix, scatter_vector
from .service import EngineError, command

__all__ = ["full_jacobian", "ksp_statistics", "rigid_modes", "CG_RTOL",
           "newton_rows", "newton_ksp", "solve_newton_system",
           "ForcingTerm", "GAMG_OPTIONS", "TWO_BODY_GAMG", "set_defaults"]

#: Relative residual of a CG + GAMG Newton solve: the last one's where
#: tol is not known, and the floor of every one (module docstring).
CG_RTOL = 1e-12


class ForcingTerm:
    """The absolute tolerances of successive Newton systems of one Newton
    iteration (module docstring): η_k by
    :func:`~solver.contact.frictionless.active_set.forcing_term` while
    the sets change, from η_0 = :data:`~solver.contact.frictionless.
    active_set.ETA_MAX`. ``history`` holds each system's tolerance
    relative to err_k (the in-process path's ``forcing``; :data:`CG_RTOL`
    where it is solved to that relative tolerance)."""

    def __init__(self, reduction=None):
        self.eta, self.previous_error = ETA_MAX, None
        self.history = []
        self.reduction = reduction or LocalReduction()
        self.target, self.pattern = None, None

    def step(self, x, pattern):
        """(final, guess) of the semismooth Newton's next system at the
        iterate ``x`` with the active set ``pattern`` (this rank's
        rows): ``final`` when the set repeats after a full step (φ_min's
        Jacobian is constant on a set, so a damped step leaves the same
        linear system unsolved, not solved); ``guess`` the correction
        from x to the last system's solution (:attr:`target`, set by the
        caller; None before the first): zero after a full step, (1 − α)
        times the last correction after a damped one, which is that
        system's answer again while the set holds."""
        red, target = self.reduction, self.target
        full = red.all(target is not None and np.array_equal(x, target))
        final = full and red.all(self.pattern is not None and
                                 np.array_equal(pattern, self.pattern))
        self.pattern = pattern
        return final, None if target is None or full else target - x

    def tolerance(self, err, final, weight=1.0, turning=False):
        """The next system's absolute tolerance on its residual at the
        iterate's stopping measure ``err``: η·err/``weight`` (``weight``:
        the contact rows' weight in err, friction's); 0 when ``final``
        (every set repeats: :data:`CG_RTOL` relative), but where
        ``turning`` (3D slip directions still turn) Newton's own rate,
        capped, as the in-process friction path does."""
        previous, self.previous_error = self.previous_error, err
        if previous is not None and not final:
            self.eta = forcing_term(self.eta, err, previous)
        eta = self.eta
        if final:
            eta = forcing_term(self.eta, err, previous, False) \
                if turning and previous else 0.0
        atol = eta * err / weight
        self.history.append(eta if atol > 0 else CG_RTOL)
        return atol

#: GAMG's Chebyshev smoothers: eigenvalue bounds by each level's own CG
#: estimate with a 1.5 safety factor (PETSc's defaults made the
#: preconditioner indefinite where rows with w_a → 0 carry large
#: shifts). ``pc_gamg_use_sa_esteig`` false: since PETSc 3.17 the
#: smoothers otherwise reuse the estimate GAMG made for smoothing its
#: prolongators (manual page PCGAMGSetUseSAEstEig), the level's own
#: estimate never runs, and that reused bound left CG's preconditioner
#: indefinite (DIVERGED_INDEFINITE_PC) on most Newton systems of larger
#: problems, where MUMPS then factorised (benchmarks/README.md, "GAMG's
#: smoothers estimate their own eigenvalues"). Where CG still fails
#: MUMPS solves (counted in ``ksp_fallbacks``, iteration count 0). The
#: aggregation graph keeps every coupling (``pc_gamg_threshold`` 0,
#: PETSc's default) except on two bodies (:data:`TWO_BODY_GAMG`).
GAMG_OPTIONS = {"mg_levels_ksp_chebyshev_esteig": "0,0.2,0,1.5",
                "mg_levels_esteig_ksp_type": "cg",
                "pc_gamg_use_sa_esteig": "false",
                "pc_gamg_threshold": "0"}

#: Two bodies: the aggregation graph drops couplings weaker than 2 % of
#: the diagonal's scale. Otherwise the weak couplings that T⁻¹ spreads
#: across the contact surface decide the aggregates, which GAMG builds
#: per rank, so the Krylov counts depend on where the rank ranges cut
#: the bodies. One body keeps 0: its counts stay within ±10 % over 1, 2
#: and 4 ranks with either (benchmarks/README.md, "GAMG's smoothers
#: estimate their own eigenvalues"; the CG failures that 0.02 once met
#: on one body were the smoothers' reused bound, above).
TWO_BODY_GAMG = dict(GAMG_OPTIONS, pc_gamg_threshold="0.02")

#: The option names this process set (``$PETSC_OPTIONS`` wins over the
#: defaults above; a later solve in the process resets what an earlier
#: one set, e.g. two bodies' threshold).
_DEFAULTED = set()


def set_defaults(prefix, defaults):
    """(every rank) PETSc options ``prefix + name`` = value for each of
    ``defaults``: a user's value ($PETSC_OPTIONS) wins, one this process
    set earlier is replaced (:data:`_DEFAULTED`)."""
    from petsc4py import PETSc

    options = PETSc.Options()
    for name, value in defaults.items():
        key = prefix + name
        if key in _DEFAULTED or not options.hasName(key):
            options.setValue(key, value)
            _DEFAULTED.add(key)

#: hypre's BoomerAMG on elasticity (``--ksp hypre``): the nodal
#: (unknown-blocked) coarsening and interpolation for systems (hypre's
#: manual, "BoomerAMG", systems of PDEs); no near-null space of PETSc's.
HYPRE_OPTIONS = {"pc_hypre_boomeramg_nodal_coarsen": "6",
                 "pc_hypre_boomeramg_vec_interp_variant": "3",
                 "pc_hypre_boomeramg_strong_threshold": "0.5"}


def rigid_modes(problem, layout, R):
    """Orthonormal rigid-body modes (2D: 3, 3D: 6) in the padded numbering,
    rotated into the node frames at the free DOFs: (n_pad, k). Two bodies'
    nodewise problem gives its own near-null space (each body's modes in
    v = Tu, :func:`solver.contact.two_body.near_null_space`; 6 in 2D, 12
    in 3D), zero at the Dirichlet rows."""
    near = getattr(problem, "near_null_space", None)  # two bodies
    if near is not None:
        Z = layout.pad(R @ near())
        return np.linalg.qr(Z)[0]
    x = np.asarray(problem.nodes, float)[:, :layout.dim]
    x = x - x.mean(axis=0)
    d, n = layout.dim, len(x)
    modes = [np.eye(d)[k][None, :].repeat(n, 0) for k in range(d)]
    pairs = [(0, 1)] if d == 2 else [(0, 1), (1, 2), (2, 0)]
    for a, b in pairs:
        m = np.zeros((n, d))
        m[:, a], m[:, b] = -x[:, b], x[:, a]
        modes.append(m)
    Z = np.column_stack([m.ravel() for m in modes])
    Z[layout.red_to_pad] = R @ Z[layout.red_to_pad]
    return np.linalg.qr(Z)[0]


class _Jacobian:
    def __init__(self, owner):
        self.owner = owner
        self.JA, self.JB = owner.system._JA, owner.system._JB

    def combine(self, wa, wb):
        return _Combined(self.owner, np.asarray(wa, float),
                         np.asarray(wb, float))


class _Combined:
    def __init__(self, owner, wa, wb):
        self.owner, self.wa, self.wb = owner, wa, wb

    def rmatvec(self, F):
        s = self.owner.system
        ne = len(s.x_rows)
        return s._JE.T @ F[:ne] + s._JA.T @ (self.wa * F[ne:]) + \
            s._JB.T @ (self.wb * F[ne:])

    def direction(self, F):
        o, s = self.owner, self.owner.system
        rhs = np.zeros(o.layout.n)
        rows = o.layout.red_to_pad[s.y_rows]
        parts = newton_rows(rhs, o.layout.red_to_pad[s.x_rows], rows, F,
                            self.wa, self.wb, s.gap_scale)
        if parts is None:
            return None
        dv = o.service.call("newton_solve", parts, rhs)
        d = s.R.T @ o.layout.unpad(dv)
        return d if np.all(np.isfinite(d)) else None


def newton_rows(rhs, x_rows, y_rows, F, wa, wb, c):
    r"""The Newton system J d = −F of (67) in the node frames, v = R d
    (module docstring): fills ``rhs`` (K̂ v = rhs at the rows ``x_rows`` of
    the equations and ``y_rows`` of the normal rows with w_a ≠ 0, there
    divided by −w_a) and returns the rows' changes as ``newton_solve``
    takes them: ``shift_rows``, ``shift`` (c w_b/w_a added to the
    diagonal) and ``fixed_rows``, ``fixed`` (v = Φ_i/(c w_b) where
    w_a = 0); None where a row has w_a = w_b = 0 (J singular)."""
    ne = len(x_rows)
    FE, FC = F[:ne], F[ne:]
    mixed = wa != 0.0
    if np.any(~mixed & (wb == 0.0)):
        return None
    rhs[x_rows] = -FE
    rhs[y_rows[mixed]] = FC[mixed] / wa[mixed]
    fixed = ~mixed
    return dict(shift_rows=y_rows[mixed], shift=c * wb[mixed] / wa[mixed],
                fixed_rows=y_rows[fixed], fixed=FC[fixed] / (c * wb[fixed]))


class _Owner:
    def __init__(self, service, layout, system):
        self.service, self.layout, self.system = service, layout, system


def full_jacobian(service, layout, problem, geometry, system, ksp):
    """The Jacobian callable of the full-system Newton on ``system`` whose
    Newton systems KSP solves on all ranks, after K̂ is scattered and checked
    (positive definite, as on the serial engine)."""
    R = system.R
    if abs(sp.linalg.norm(R @ R.T - sp.identity(R.shape[0]))) > 1e-12:
        raise EngineError("the full system on the petsc engine needs "
                          "orthogonal node frames (no rollers)")
    K_hat = rotate_stiffness(problem.K, R, geometry.free_dofs())
    modes = rigid_modes(problem, layout, R) if ksp == "gamg" else None
    service.call("newton_setup", dict(ksp=ksp, bsize=layout.dim,
                                      scale=float(K_hat.diagonal().mean())),
                 (layout.matrix(K_hat), modes))
    # K positive definite? As the serial check_stiffness, on all ranks
    service.call("check_spd" if ksp == "mumps" else "check_spd_cg",
                 dict(key="newton"))
    owner = _Owner(service, layout, system)
    return lambda x: _Jacobian(owner)


def ksp_statistics(service, ksp):
    """The engine's record of the full-system Newton solves: the Krylov
    iterations of each (0 for a warm start that already meets its
    tolerance, and for a fallback), their number, the CG solves that fell
    back to MUMPS and each one's forcing term (:class:`ForcingTerm`)."""
    its = service.call("ksp_iterations")
    record = service.call("ksp_record")
    return dict(ksp_iterations=its, newton_solves=len(its),
                ksp_fallbacks=record["fallbacks"] if ksp == "gamg" else 0,
                ksp_forcing=record["forcing"])


@command("newton_setup")
def _setup(service, payload, local):
    A_pad, modes = local if service.root else (None, None)
    A = scatter_matrix(service, A_pad, payload["bsize"])
    vecs = []
    if payload["ksp"] == "gamg":
        k = service.comm.bcast(None if modes is None else modes.shape[1])
        for j in range(k):
            v = A.createVecLeft()
            scatter_vector(service, None if modes is None else
                           np.ascontiguousarray(modes[:, j]), v)
            vecs.append(v)
    newton_ksp(service, A, payload["ksp"], payload["scale"], vecs)


def newton_ksp(service, A, ksp_type, scale, modes=(), gamg=None):
    """(every rank) The Newton systems' KSP on the distributed K̂ ``A``
    (kept as ``objects["newton"]``): CG + GAMG with the near-null space
    ``modes`` (PETSc vectors) and the options ``gamg``
    (:data:`GAMG_OPTIONS` when None), CG + hypre's BoomerAMG, or MUMPS's
    Cholesky; options prefix ``newton_`` ($PETSC_OPTIONS wins)."""
    from petsc4py import PETSc

    M = A.duplicate(copy=True)
    ksp = PETSc.KSP().create(comm=A.getComm())
    pc = ksp.getPC()
    if ksp_type in ("gamg", "hypre"):
        if modes:
            M.setNearNullSpace(PETSc.NullSpace().create(vectors=list(modes),
                                                        comm=A.getComm()))
        ksp.setType("cg")
        pc.setType(ksp_type)
        gamg = GAMG_OPTIONS if gamg is None else gamg
        set_defaults("newton_", gamg if ksp_type == "gamg" else
                      HYPRE_OPTIONS)
        ksp.setTolerances(rtol=CG_RTOL, atol=0.0, max_it=5000)
    else:
        ksp.setType("preonly")
        pc.setType("cholesky")
        pc.setFactorSolverType("mumps")
    ksp.setOptionsPrefix("newton_")
    ksp.setFromOptions()
    x, b = M.createVecs()
    service.objects["newton"] = dict(A=A, M=M, ksp=ksp, x=x, b=b, its=[],
                                     gamg=gamg,
                                     forcing=[], fallbacks=0,
                                     norm=ksp.getNormType(),
                                     scale=scale, krylov=ksp_type != "mumps")


@command("newton_solve")
def _newton_solve(service, payload, local):
    obj = service.objects["newton"]
    scatter_vector(service, local, obj["b"])
    solve_newton_system(obj, payload)  # exact: module docstring
    obj["forcing"].append(CG_RTOL)
    return gather_vector(service, obj["x"])


def solve_newton_system(obj, rows, added=None, coupling=None, atol=None,
                        start=None):
    """(every rank) K̂ with the diagonal shifts and fixed rows of
    :func:`newton_rows` (``rows``: global row numbers, each rank keeps
    those it owns) solved for ``obj["b"]`` into ``obj["x"]`` (``obj`` of
    :func:`newton_ksp`): the fixed rows eliminated symmetrically, so the
    system stays SPD; a failed CG falls back to MUMPS (iteration count
    0, module docstring). Records the Krylov iterations. ``added``: a
    distributed matrix inside K̂'s pattern added to it first (friction's
    slip springs, :mod:`.krylov_friction`). ``coupling``: a distributed
    nonsymmetric matrix added on top (the implicit friction bound's rows
    N K̂, :mod:`.krylov_friction`): the system, its fixed rows and columns
    eliminated the same way, is then solved by right-preconditioned
    GMRES (:func:`gmres_ksp`) whose preconditioner is built on the
    symmetric part without it, as the serial
    :func:`~solver.linalg.amg.projected_gmres`'s; no MUMPS fallback
    there (a failure raises EngineError). ``atol``: inexact Newton's
    absolute tolerance on the unpreconditioned residual
    (:class:`ForcingTerm`; None or 0: :data:`CG_RTOL` relative only).
    ``start``: this rank's rows of the Krylov method's start (a warm
    start), its fixed rows replaced by their values (:func:`_start`);
    None: from 0."""
    from petsc4py import PETSc

    A, M, ksp, x, b = (obj[k] for k in ("A", "M", "ksp", "x", "b"))
    A.copy(M, structure=PETSc.Mat.Structure.SAME_NONZERO_PATTERN)
    if added is not None:
        M.axpy(1.0, added,
               structure=PETSc.Mat.Structure.SUBSET_NONZERO_PATTERN)
    lo, hi = M.getOwnershipRange()
    shift = M.createVecLeft()
    shift.set(0.0)
    index, vals = np.asarray(rows["shift_rows"]), rows["shift"]
    own = (index >= lo) & (index < hi)
    shift.setValues(index[own].astype(PETSc.IntType), vals[own])
    shift.assemble()
    M.setDiagonal(shift, addv=PETSc.InsertMode.ADD_VALUES)
    shift.destroy()
    index, vals = np.asarray(rows["fixed_rows"]), rows["fixed"]
    own = (index >= lo) & (index < hi)
    x.set(0.0)
    x.setValues(index[own].astype(PETSc.IntType), vals[own])
    x.assemble()
    fixed = index[own].astype(PETSc.IntType)
    if coupling is not None:
        full = M.duplicate(copy=True)
        full.axpy(1.0, coupling,
                  structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
        full.zeroRowsColumns(fixed, diag=obj["scale"], x=x, b=b)
        M.zeroRowsColumns(fixed, diag=obj["scale"])
        ksp = gmres_ksp(obj)
        ksp.setOperators(full, M)
        _start(obj, ksp, atol, start, fixed, vals[own])
        if _met(full, x, b, atol):  # the warm start is the answer
            full.destroy()
            obj["its"].append(0)
            return
        ksp.solve(b, x)
        full.destroy()
        if ksp.getConvergedReason() < 0:
            raise EngineError(f"GMRES failed on a Newton system (reason "
                              f"{ksp.getConvergedReason()})")
        obj["its"].append(ksp.getIterationNumber())
        return
    M.zeroRowsColumns(fixed, diag=obj["scale"], x=x, b=b)
    ksp.setOperators(M)
    if obj.get("krylov"):
        _start(obj, ksp, atol, start, fixed, vals[own])
        if _met(M, x, b, atol):  # the warm start is the answer
            obj["its"].append(0)
            return
    else:
        x.set(0.0)
    ksp.solve(b, x)
    its = ksp.getIterationNumber()
    if ksp.getConvergedReason() < 0 and obj.get("krylov"):
        ksp, its = _direct_solve(obj, M, b, x), 0  # CG failed: counted
        obj["fallbacks"] += 1
    if ksp.getConvergedReason() < 0:
        raise EngineError(f"KSP failed on a Newton system (reason "
                          f"{ksp.getConvergedReason()})")
    obj["its"].append(its)


def _start(obj, ksp, atol, start, fixed, values):
    """(every rank) The Krylov solve's tolerances (``atol`` on the true
    residual, :func:`solve_newton_system`) and its start in ``obj["x"]``:
    0 when ``start`` is None, else ``start`` with the ``fixed`` rows at
    their ``values`` (on the constraints, as the in-process path's
    starts)."""
    from petsc4py import PETSc

    x = obj["x"]
    if atol:
        ksp.setNormType(PETSc.KSP.NormType.UNPRECONDITIONED)
    elif ksp is obj["ksp"]:
        ksp.setNormType(obj["norm"])
    ksp.setTolerances(rtol=CG_RTOL, atol=float(atol or 0.0), max_it=5000)
    if start is None:
        x.set(0.0)
        ksp.setInitialGuessNonzero(False)
        return
    x.setArray(start)
    x.setValues(fixed, values)
    x.assemble()
    ksp.setInitialGuessNonzero(True)


def _met(A, x, b, atol):
    """(every rank) Whether the start x already meets ``atol``:
    ‖b − A x‖ ≤ atol; then neither the solve nor the preconditioner's
    set-up (GAMG's hierarchy, rebuilt for each Newton system) is run."""
    if not atol:
        return False
    r = b.duplicate()
    A.mult(x, r)
    r.aypx(-1.0, b)
    met = r.norm() <= atol
    r.destroy()
    return bool(met)


def gmres_ksp(obj):
    """(every rank) The nonsymmetric Newton systems' KSP of ``obj``
    (:func:`newton_ksp`'s, made once): restarted GMRES preconditioned on
    the right, so that its residual is the true one, with the CG KSP's
    preconditioner type and options (GAMG with the near-null space of the
    preconditioning matrix, or hypre) and its relative tolerance; options
    prefix ``newton_gmres_`` ($PETSC_OPTIONS wins)."""
    from petsc4py import PETSc

    if "gmres" not in obj:
        base = obj["ksp"]
        ksp = PETSc.KSP().create(comm=base.getComm())
        ksp.setType("gmres")
        ksp.setGMRESRestart(GMRES_RESTART)
        ksp.setPCSide(PETSc.PC.Side.RIGHT)
        ksp.getPC().setType(base.getPC().getType())
        set_defaults("newton_gmres_", (obj.get("gamg") or GAMG_OPTIONS)
                      if base.getPC().getType() == "gamg" else HYPRE_OPTIONS)
        ksp.setTolerances(rtol=CG_RTOL, atol=0.0, max_it=5000)
        ksp.setOptionsPrefix("newton_gmres_")
        ksp.setFromOptions()
        obj["gmres"] = ksp
    return obj["gmres"]


def _direct(obj, M):
    """The MUMPS KSP of a Newton system on which CG + GAMG failed."""
    from petsc4py import PETSc

    if "direct" not in obj:
        ksp = obj["direct"] = PETSc.KSP().create(comm=M.getComm())
        ksp.setType("preonly")
        ksp.getPC().setType("cholesky")
        ksp.getPC().setFactorSolverType("mumps")
    obj["direct"].setOperators(M)
    return obj["direct"]


def _direct_solve(obj, M, b, x):
    """Solve by :func:`_direct`; a Newton system that is not positive
    definite means K is not (it is a principal submatrix of K̂ plus a
    non-negative diagonal): ProblemError, as the serial engine's."""
    from .pivots import set_up_checked

    ksp = _direct(obj, M)
    set_up_checked(ksp)
    ksp.solve(b, x)
    return ksp


#: The CG test of K: relative residual and iterations.
CHECK_RTOL, CHECK_MAX_IT = 1e-8, 2000


@command("check_spd_cg")
def _check_spd_cg(service, payload, local):
    """K̂ x = b (b random) by the Newton systems' CG + GAMG, which fails on
    an indefinite or singular K̂: the ``--ksp gamg`` path's test of K (it has
    no factorisation); a test, not a proof."""
    from petsc4py import PETSc

    from .pivots import refusal

    obj = service.objects[payload["key"]]
    ksp, A, x, b = obj["ksp"], obj["A"], obj["x"], obj["b"]
    rng = np.random.default_rng(20 + service.rank)
    b.setArray(rng.standard_normal(b.getLocalSize()))
    x.set(0.0)
    norm = ksp.getNormType()
    ksp.setOperators(A)
    ksp.setNormType(PETSc.KSP.NormType.UNPRECONDITIONED)  # of K x − b
    ksp.setTolerances(rtol=CHECK_RTOL, max_it=CHECK_MAX_IT)
    ksp.setUp()
    service.mark("check_spd_cg.setup")
    ksp.solve(b, x)
    reason = ksp.getConvergedReason()
    ksp.setTolerances(rtol=CG_RTOL, max_it=5000)
    ksp.setNormType(norm)
    if reason < 0:  # singular or indefinite
        raise refusal("CG + GAMG on K x = b, b random, failed (PETSc KSP "
                      f"reason {reason}): singular or indefinite, is the "
                      "body supported?", False)
    # GAMG's coarse solve inverts an exact null mode (its near-null space
    # holds the rigid modes): then CG converges with x of size ~ 1/0
    ratio = x.norm() * A.norm(PETSc.NormType.INFINITY) / b.norm()
    if ratio > 1.0 / PIVOT_RTOL:
        raise refusal(f"K x = b, b random, gave ‖K‖‖x‖/‖b‖ = {ratio:.2g}, a "
                      f"condition number above {1 / PIVOT_RTOL:.0e}")


@command("ksp_iterations")
def _its(service, payload, local):
    its = list(service.objects["newton"]["its"])
    service.objects["newton"]["its"].clear()
    return its


@command("ksp_record")
def _record(service, payload, local):
    """Each Newton system's tolerance relative to err_k
    (:attr:`ForcingTerm.history`, as the Newton loops recorded it) and
    the number of CG solves that fell back to MUMPS."""
    obj = service.objects["newton"]
    out = dict(forcing=list(obj["forcing"]), fallbacks=obj["fallbacks"])
    obj["forcing"].clear()
    obj["fallbacks"] = 0
    return out
