r"""The one front: :func:`solve` for every contact problem.

As ``scipy.optimize.minimize`` dispatches on ``method=``, :func:`solve`
dispatches on the problem (2D or 3D; a rigid obstacle, two elastic bodies
or given gaps) and the options (frictionless or Coulomb friction; the
serial or the PETSc engine). Every option is first checked against
:mod:`solver.front.cases`; then the front builds the contact geometry, the
engine and, for two bodies, the nodewise problem in the mortar's
variables, and hands them to a driver
(:func:`solver.contact.run_frictionless`,
:func:`solver.contact.run_friction`)."""

import time

from ..contact import (IterativeEngine, SerialEngine, TwoBodyMap,
                       check_floating_friction, contact_geometry)
from ..contact.friction.driver import check_friction
from ..errors import SolverError
from .cases import (DEFAULTS, auto_eligible, case_of, check_geometry_rules,
                    converted, resolve)

__all__ = ["solve", "prepare", "Plan", "PartitionedPlan", "ConvertedPlan",
           "solve_frictionless",
           "solve_friction", "solve_two_body", "make_engine"]


def solve(problem, *, friction=None, method=None, system="auto", start=None,
          formulation=None, coulomb=None, steps=None, gap=None,
          backend="auto", engine=None, ksp=None, tol=1e-10, max_iter=100,
          gap_scale=None, search_interval=None, candidates=None,
          margin=None, rollers=None, x0=None, variant=None, options=None,
          geometry=None, progress=None, on_step=None, keep_steps=True):
    r"""Solve a contact problem by semismooth Newton (thesis §2.2).

    Parameters
    ----------
    problem : ContactProblem
        From :func:`solver.load_problem`: one body against a rigid obstacle
        (2D curve or 3D surface), two elastic bodies (dual mortar), or a
        discrete problem with given gaps (the §6 bar); or a partitioned
        problem (``load_problem(DIR)`` of the folder of ``python -m solver
        convert``): frictionless, ``engine="petsc"`` under ``mpiexec``,
        each rank reading only its rows (docs/mpi.md); its result's
        ``write_pieces(outdir)`` writes u, one ``.vtu`` piece per rank.
    friction : float, optional
        The coefficient of friction f_c ≥ 0: Coulomb friction in load steps
        (thesis §5); without it the problem is frictionless (67).
    method : {"min", "fb"}
        Damped Newton with φ_min (§2.2.1) or the Fischer–Burmeister method
        (§2.2.2); default "min", "fb" for the thesis's friction formulation.
    system : {"auto", "condensed", "full"}
        "condensed": factorise K once and iterate on the system condensed
        exactly onto Γc; "full": the thesis's system in all unknowns, one
        sparse LU per Newton iteration (the counts of Tables 1 and 2); "auto":
        condensed, but full for the thesis's friction formulation.
    start : {"nested", "free"}, frictionless only
        "nested" (the 2D default, condensed onto Γc): on ever coarser subsets
        of Γc first; "free": from no contact force, u = K⁻¹f. The full system
        starts from the thesis's u = 0.
    formulation, coulomb, steps : friction only
        The projection onto the Coulomb set (default; 2D and 3D) or the
        thesis's split (110)/(111) (2D); the bound from the previous step's
        normal force ("lagged", the thesis, default) or the current one
        ("implicit"); load steps (default 100; a load path has its own).
    gap : {"obstacle", "body"}, rigid obstacle only
        Gaps and normals from the obstacle (§2.1.1, default) or along the
        body's normals (§2.1.2-2.1.3).
    backend, engine, ksp
        The serial engine's sparse solver ("auto", "superlu", "pardiso",
        "cholmod"), or "amg": no factorisation, the active set method on
        the full system with AMG-preconditioned Krylov (CG; GMRES for the
        nonsymmetric systems of the implicit friction bound), against a
        rigid obstacle or between two bodies by the dual mortar,
        frictionless or with friction by the projection formulation, a
        body held by contact only too (K singular: from its rigid
        placement, the modes no constraint holds projected out, the
        coarsest level by a pseudo-inverse; "What works where"); "auto"
        takes it when CHOLMOD's estimate of the factor exceeds the memory,
        and ``linear_solver_reason`` says why; "petsc" for the PETSc engine under ``mpiexec`` (inside
        :func:`solver.mpi.engine.spmd`; docs/mpi.md) or an engine object; its
        full system's Newton systems by "mumps" or CG + "gamg".
    tol, max_iter : float, int
        Relative tolerance of the units-free stopping test
        (:mod:`solver.contact.verify`; default 1e-10) and the Newton
        iterations at most (per load step; all levels and rounds together).
    gap_scale : float, optional
        c in the gap rows c(s − u_n): the same solution, another path.
    search_interval : (t0, t1), 2D rigid obstacle only
        The obstacle parameter interval searched for the gaps.
    candidates, margin : optional
        Condense onto the contact nodes that can touch only (default: in 3D,
        and on the petsc engine without friction), enlarged until no other
        node penetrates; the screening margin, a length.
    rollers : bool, optional
        Whether contact nodes with Dirichlet components (symmetry planes) take
        part as rollers (default True) or are supports.
    x0, variant, options, geometry : optional
        A starting displacement (frictionless); the two bodies' coupling
        ("mortar", default, or "node-to-segment"); the Newton method's options
        (:func:`solver.ncp.solve_ncp`); precomputed gaps and frames
        (:func:`solver.contact.contact_geometry`).
    progress, on_step, keep_steps : friction only
        Called with each completed step's record, and with its fields; keep
        the per-step arrays in the result (default True; on the condensed
        system the steps' ``u`` and ``displacement`` are recovered when
        first read, docs/results.md).

    Returns
    -------
    ContactResult
        ``success``, ``status``, ``message``, counts (``nit``, ``njev``,
        ``nfev``), the answer (docs/results.md; per load step with friction),
        its ``verification`` and ``stopping`` test, and what ran
        (``linear_solver``, ``condensation``, ``start``, ``engine``).

    Raises
    ------
    SolverError
        For an option that does not apply to the problem or a bad value (one
        line naming it); :class:`~solver.errors.ProblemError` if K is not
        positive definite or the geometry cannot be built. A solve that does
        not converge raises nothing: see ``success``."""
    given = dict(locals())
    given.pop("problem")
    return prepare(problem, **given).run()


class Plan:
    """A checked call of :func:`solve`, ready to run (:func:`prepare`):
    ``problem``, ``case``, ``settings`` (every option resolved), ``engine``,
    ``geometry`` (for two bodies that of the nodewise problem of
    ``mapping``) and ``friction``."""

    def __init__(self, problem, case, settings, engine, geometry, mapping,
                 target, clock):
        self.problem, self.case, self.settings = problem, case, settings
        self.engine, self.geometry, self.mapping = engine, geometry, mapping
        self.target, self.friction = target, settings["friction"]
        self._clock, self.geometry_time = clock, time.perf_counter() - clock

    def run(self, progress=None, on_step=None, keep_steps=None):
        """Solve; ``progress``, ``on_step`` and ``keep_steps`` (friction
        only) replace those given to :func:`prepare`."""
        s = dict(self.settings)
        for name, value in (("progress", progress), ("on_step", on_step),
                            ("keep_steps", keep_steps)):
            if value is not None:
                if self.friction is None:
                    raise SolverError(f"{name} applies to friction runs")
                s[name] = value
        clock = time.perf_counter()
        common = dict(method=s["method"], tol=s["tol"],
                      max_iter=s["max_iter"], gap_scale=s["gap_scale"],
                      options=s["options"], condense=s["condense"],
                      candidates=s["candidates"], margin=s["margin"])
        if self.friction is None:
            from ..contact import run_frictionless

            result = run_frictionless(self.target, self.geometry,
                                      self.engine, x0=s["x0"],
                                      start=s["start"], **common)
        else:
            from ..contact import run_friction

            on_step = s["on_step"]
            if self.mapping is not None and on_step is not None:
                on_step = _chain(self.mapping.step_fields(
                    p for _, _, p, _ in self.problem.load_steps(
                        s["steps"])), on_step)
            result = run_friction(
                self.target, self.geometry, self.engine, self.friction,
                steps=s["steps"], formulation=s["formulation"],
                coulomb=s["coulomb"], progress=s["progress"],
                on_step=on_step, keep_steps=s["keep_steps"], **common)
        _warn_excluded(self.problem, result)
        if self.mapping is not None:
            result = self.mapping.result(result, self.friction, s["steps"])
        _warn_kinematics(result)
        summary = self.engine.summary()
        if summary is not None:
            result["engine"] = summary
        reason = s.get("linear_solver_reason")
        if reason is not None:
            result["linear_solver_reason"] = reason
        result.update(geometry_time=self.geometry_time,
                      time=self.geometry_time + time.perf_counter() - clock)
        return result


class PartitionedPlan:
    """A checked call of :func:`solve` on a partitioned problem (a folder
    of ``python -m solver convert``; :mod:`solver.mpi.distributed`,
    with friction :mod:`solver.mpi.partitioned_friction`): run it on rank
    0 under ``mpiexec`` (inside :func:`solver.mpi.engine.spmd`, or the
    command line's service); the result's ``write_pieces`` writes u one
    piece per rank."""

    def __init__(self, problem, case, settings, friction=None):
        from .. import mpi

        reason = mpi.missing()
        if reason:
            raise SolverError(reason)
        self.problem, self.case, self.settings = problem, case, settings
        self.friction = friction
        if friction is not None:  # before any rank works: one line
            check_friction(problem, friction, settings["steps"])
            problem.check_friction()

    def run(self, outdir=None, progress=None):
        """Solve on the ranks; a :class:`~solver.mpi.distributed.
        PartitionedResult`. With friction and ``outdir``, each load step's
        pieces are written to ``outdir/steps/`` as it completes."""
        from ..mpi.engine import service

        s = self.settings
        if self.friction is not None and s["system"] == "full":
            from ..mpi.krylov_friction import \
                solve_partitioned_krylov_friction

            return solve_partitioned_krylov_friction(
                service(), self.problem.path, self.friction, s["steps"],
                s["ksp"], s["tol"], s["max_iter"], outdir=outdir,
                progress=progress or s["progress"], coulomb=s["coulomb"])
        if self.friction is not None:
            from ..mpi.partitioned_friction import solve_partitioned_friction

            return solve_partitioned_friction(
                service(), self.problem.path, self.friction, s["steps"],
                s["formulation"], s["coulomb"], s["method"], s["tol"],
                s["max_iter"], outdir=outdir,
                progress=progress or s["progress"])
        if s["system"] == "full":  # Krylov: no rank holds all of Γc
            from ..mpi.partitioned_full import solve_partitioned_full

            return solve_partitioned_full(service(), self.problem.path,
                                          s["ksp"], s["tol"], s["max_iter"])
        from ..mpi.distributed import solve_partitioned

        return solve_partitioned(service(), self.problem.path, s["method"],
                                 s["tol"], s["max_iter"])


class ConvertedPlan:
    """A checked call of :func:`solve` with friction on the full system of
    a ``.npz`` (one supported body against a rigid obstacle) on the petsc
    engine: the problem is converted on the fly to a partitioned folder in
    a temporary folder (:mod:`solver.mpi.on_the_fly`) whose Krylov
    friction runs unchanged (:class:`PartitionedPlan`), the same answer
    as the folder run; the folder is removed at the end. ``converted``
    gives the folder's plan for as long as the caller needs the folder
    (the command line writes the ranks' pieces from it)."""

    def __init__(self, problem, case, settings, given):
        from .. import mpi

        reason = mpi.missing()
        if reason:
            raise SolverError(reason)
        self.problem, self.case, self.settings = problem, case, settings
        self.friction = settings["friction"]
        check_friction(problem, self.friction, settings["steps"])
        # the folder's options: gap and rollers went into the conversion
        self.options = {name: value for name, value in given.items()
                        if name not in ("gap", "rollers")}

    def source(self):
        """The ``.npz`` to convert, streamed (its path), when the problem
        is that file's; else the problem in memory."""
        import os

        path = self.problem.source
        if isinstance(path, str) and os.path.isfile(path):
            return path
        return self.problem

    def converted(self, workdir=None):
        """Context manager: convert into a temporary folder under
        ``workdir`` (``$TMPDIR`` when None), yield (the folder's
        :class:`PartitionedPlan`, the conversion's ``info``), remove the
        folder on leaving."""
        import contextlib
        import os

        from ..mpi.on_the_fly import converted_folder
        from ..problem import load_problem

        @contextlib.contextmanager
        def block():
            source = self.source()
            name = os.path.splitext(os.path.basename(
                self.problem.source or "problem"))[0]
            with converted_folder(source, self.settings["gap"], workdir,
                                  name) as (folder, info):
                plan = prepare(load_problem(folder), **self.options)
                yield plan, info
        return block()

    def run(self, outdir=None, progress=None, workdir=None):
        """Convert, solve on the ranks, remove the folder; the result
        (``"converted"``: what was converted). Its pieces are written
        while the folder exists: give ``outdir`` (each step's pieces in
        ``outdir/steps/``, u in ``outdir/result-RANK.vtu``)."""
        with self.converted(workdir) as (plan, info):
            result = plan.run(outdir=outdir, progress=progress)
            if outdir is not None:
                result.write_pieces(outdir)
        result["converted"] = info
        return result


def prepare(problem, **options):
    """Check a call of :func:`solve` (same arguments) and make what it
    needs before any solving: the case, its settings, the engine, the contact
    geometry and (serial full system) the check that K is positive definite.
    Every input error surfaces here; :meth:`Plan.run` then solves."""
    clock = time.perf_counter()
    given = dict(DEFAULTS)
    unknown = set(options) - set(DEFAULTS)
    if unknown:
        raise SolverError(f"unknown option(s) {sorted(unknown)}: "
                          f"solve takes {sorted(DEFAULTS)}")
    given.update(options)
    friction = given["friction"]
    case = case_of(problem, friction, given["engine"])
    settings = resolve(case, given)
    if case.bodies == "partitioned":
        return PartitionedPlan(problem, case, settings, friction)
    if converted(case, settings):  # friction, full system, petsc: a folder
        return ConvertedPlan(problem, case, settings, given)
    if auto_eligible(case, given) and problem.kind == "mesh":
        settings = _choose_path(problem, case, given, settings)
    if settings["backend"] == "amg":
        settings.setdefault("linear_solver_reason", "backend='amg' given")
    if friction is not None:
        check_friction(problem, friction, given["steps"])
    engine = make_engine(given["engine"], settings)
    mapping, target = None, problem
    if case.bodies == "two-body":
        mapping = TwoBodyMap(problem, given["variant"] or "mortar",
                             friction=friction is not None)
        target = mapping.equivalent
    if given["search_interval"] is not None:
        problem.set_search_interval(*given["search_interval"])
    geometry = given["geometry"]
    if geometry is None:
        geometry = contact_geometry(target, settings["gap"],
                                    rollers=settings["rollers"])
        if mapping is not None:
            mapping.mark_uncovered(geometry)
    check_geometry_rules(case, settings, geometry)
    if case.support == "floating" and friction is not None:
        check_floating_friction(target, geometry, friction,  # none holds?
                                settings["coulomb"], given["steps"])
    if not settings["condense"] and case.engine == "serial" \
            and settings["backend"] != "amg":  # CG reports a K not SPD
        target.check_stiffness()  # before anything is written
    return Plan(problem, case, settings, engine, geometry, mapping, target,
                clock)


def _choose_path(problem, case, given, settings):
    """``backend="auto"``: the iterative path when a factorisation of K
    would not fit the memory (:func:`solver.linalg.amg.direct_fits`) and
    pyamg is installed; ``linear_solver_reason`` says why."""
    from ..linalg import amg

    fits, reason = amg.direct_fits(problem.K)
    if not fits and amg.available():
        settings = resolve(case, dict(given, backend="amg"))
    elif not fits:
        reason += (f" (not installed: pip install "
                   f"'contact-ssn[{amg.EXTRA}]'; factorising)")
    settings["linear_solver_reason"] = reason
    return settings


def _warn_excluded(problem, result):
    """A :class:`~solver.errors.PenetrationWarning` naming the nodes left
    out of contact (supports) that penetrate the obstacle at the answer."""
    import warnings

    from ..errors import PenetrationWarning

    excluded = (result.get("verification") or {}).get("excluded") or {}
    where = excluded.get("penetrating") or []
    if not where:
        return
    ids = problem.contact_nodes[where] if problem.kind == "mesh" else where
    names = ", ".join(str(int(i)) for i in ids[:5]) + \
        (", ..." if len(ids) > 5 else "")
    several = len(ids) > 1
    other = "the other body" if problem.is_mortar else "the obstacle"
    warnings.warn(
        f"{len(ids)} contact node{'s' if several else ''} left out of "
        f"contact as support{'s' if several else ''} ({names}) "
        f"penetrate{'' if several else 's'} {other} at the answer "
        f"(deepest {excluded['max_depth']:.3g}): a prescribed displacement "
        f"moves {'them' if several else 'it'} there; let "
        f"{'them' if several else 'it'} take part (rollers=True) or "
        "correct the supports", PenetrationWarning, stacklevel=3)


def _warn_kinematics(result):
    """A :class:`~solver.errors.KinematicsWarning` for each breach of the
    model's kinematic assumptions (:mod:`solver.contact.kinematics`), for
    a converged answer only: a failed solve says why in its one error line
    (its breaches stay in ``verification['kinematics']``)."""
    import warnings

    from ..errors import KinematicsWarning

    if not result.get("success", False):
        return
    for message in (result.get("verification") or {}).get("kinematics", []):
        warnings.warn(message, KinematicsWarning, stacklevel=3)


def _chain(first, then):
    return lambda fields: then(first(fields))


def make_engine(engine, settings):
    """The engine object of ``engine`` ("serial", "petsc", None or an
    engine object)."""
    if (engine is None or engine == "serial") \
            and settings["backend"] == "amg":
        return IterativeEngine(settings.get("linear_solver_reason"))
    if engine is None or engine == "serial":
        return SerialEngine(settings["backend"])
    if engine == "petsc":
        from .. import mpi

        reason = mpi.missing()
        if reason:
            raise SolverError(reason)
        from ..mpi.engine import PetscEngine

        return PetscEngine(settings["ksp"] or "mumps")
    if isinstance(engine, str):
        raise SolverError(f"engine must be one of ('serial', 'petsc') or an "
                          f"engine object, got {engine!r}")
    return engine


def _compatible(problem, condense=None, **options):
    """The old keyword ``condense`` (True/False/None) as ``system``."""
    if condense is not None:
        options["system"] = "condensed" if condense else "full"
    return options


def solve_frictionless(problem, method="min", gap=None, tol=1e-10,
                       max_iter=100, **options):
    """Frictionless contact: :func:`solve` without ``friction`` (kept for
    compatibility; ``condense=True``/``False`` is ``system=``)."""
    return solve(problem, method=method, gap=gap, tol=tol,
                 max_iter=max_iter, **_compatible(problem, **options))


def solve_friction(problem, friction, steps=None, **options):
    """Coulomb friction in load steps: :func:`solve` with ``friction``
    (kept for compatibility; ``condense=`` is ``system=``)."""
    return solve(problem, friction=friction, steps=steps,
                 **_compatible(problem, **options))


def solve_two_body(problem, friction=None, variant="mortar", **options):
    """Two elastic bodies: :func:`solve` (kept for compatibility)."""
    return solve(problem, friction=friction, variant=variant,
                 **_compatible(problem, **options))
