"""The two jobs of the command line: a frictionless solve and a friction
run, each checking its inputs before it makes the output folder, then
solving, writing the outputs and printing the summary (called by
:func:`solver.cli.run.run`, which maps every outcome to an exit code)."""

import os
import sys
import time

from .run import EXIT_NOT_CONVERGED, EXIT_OK

__all__ = ["frictionless", "friction", "two_body", "default_outdir"]


def default_outdir(args, problem):
    """PROBLEM-METHOD-GAP (or the friction options) beside the problem."""
    stem = os.path.splitext(args.problem)[0]
    gap = args.gap if problem.kind == "mesh" else "given"
    if getattr(problem, "is_mortar", False):
        gap = "mortar"
    if args.friction is not None:
        steps = "path" if problem.load_path is not None else \
            f"{args.steps or 100}steps"
        return (f"{stem}-fc{args.friction:g}-{steps}-"
                f"{args.formulation}-{args.coulomb}-{args.method}")
    return f"{stem}-{args.method}-{gap}"


def _condense(args):
    """``condense`` of the solvers from ``--system`` (None = auto)."""
    return {"auto": None, "condensed": True, "full": False}[args.system]


def _geometry(args, problem):
    """Every input error that can be found before solving: the linear
    solver installed, K positive definite on the full system, gaps and
    normals (GapError)."""
    from ..contact import contact_geometry
    from ..linalg import resolve

    resolve(args.linear_solver)  # not installed: SolverError, exit 2
    if _condense(args) is False and _engine(args) == "serial":
        problem.check_stiffness()  # else by the solve's factorisation (the
        # petsc engine's on all ranks: a serial one took 19 s at 9.2·10⁵)
    # contact nodes on symmetry planes (rollers) take part in contact; 2D
    # friction runs (the thesis's) keep them supports, as solve_friction
    from ..contact.geometry import problem_dim

    return contact_geometry(problem, args.gap, rollers=args.friction is None
                            or problem_dim(problem) == 3)


def _engine(args):
    """"serial" or "petsc" (``--engine``; solver.mpi)."""
    return getattr(args, "engine", "serial")


def _failure_line(message, nit, history, tail=""):
    values = ", ".join(f"{r:.3e}" for r in history)
    return (f"error: {message} after {nit} iterations; residual history "
            f"||Phi||: [{values}]{tail}")


def frictionless(args, problem, open_folder, emit, write_summary):
    """Solve (67), write summary.json, result.npz, result.vtu, figures."""
    if getattr(problem, "is_mortar", False):
        return two_body(args, problem, open_folder, emit, write_summary)
    args.gap = getattr(args, "gap", None) or "obstacle"
    from ..contact import solve_frictionless
    from ..output import summary_of, write_result, write_vtk

    if _engine(args) == "petsc":
        from ..mpi.jobs import solvers
        solve_frictionless = solvers(args)[0]
    from ..output.report import format_result

    args.method = args.method or "min"
    geometry = _geometry(args, problem)
    folder = open_folder(args.outdir or default_outdir(args, problem))
    result = solve_frictionless(problem, method=args.method, gap=args.gap,
                                tol=args.tol, max_iter=args.max_iter,
                                gap_scale=args.gap_scale, geometry=geometry,
                                condense=_condense(args), start=args.start,
                                backend=args.linear_solver)
    summary = summary_of(result, problem, tol=args.tol,
                         max_iter=args.max_iter)
    if "engine" in result:
        summary["engine"] = result["engine"]
    write_result(folder.file("result.npz"), result, problem)
    if problem.kind == "mesh":
        write_vtk(folder.file("result.vtu"), result, problem)
    if args.plots:
        for path in _figures(folder.path, problem, result).values():
            folder.file(os.path.basename(path))
    write_summary(summary)
    emit(format_result(summary, folder.path))
    if not result.success:
        print(_failure_line(result.message, result.nit,
                            summary["residual_history"]), file=sys.stderr)
        return EXIT_NOT_CONVERGED
    return EXIT_OK


def _figures(folder, problem, result):
    """``--plots`` of a frictionless solve: the thesis's figures in 2D; in
    3D the convergence and the pressure against the radius, with Hertz's
    profile when the problem's meta names R, E and nu (a Hertz export)."""
    if getattr(problem, "dim", 2) == 2:
        from ..output.figures import write_figures

        return write_figures(folder, problem, result)
    from ..output.figures3d import write_figures3d

    center = (problem.meta or {}).get("contact_center")
    return write_figures3d(folder, problem, result,
                           *_hertz_reference(problem, result), center=center)


def _hertz_reference(problem, result):
    """(a, p0) of Hertz's point contact for the total contact force of the
    solve (×4 for a quarter model), or (None, None) without R, E, nu."""
    import numpy as np

    from ..verification import hertz_point_contact

    meta = problem.meta or {}
    if not all(isinstance(meta.get(k), (int, float)) for k in ("R", "E",
                                                                 "nu")):
        return None, None
    force = np.nansum(np.asarray(result.contact_force, float))
    if force <= 0:
        return None, None
    return hertz_point_contact(force * (4 if meta.get("quarter") else 1),
                               meta["R"], meta["E"], meta["nu"])


class Progress:
    """Progress of the load steps on stderr: a bar on a terminal, else a
    line per 10 % of the steps (step, J, stopping measure, elapsed)."""

    def __init__(self, total):
        self.total, self.done, self.start = total, 0, time.perf_counter()
        self.bar = None
        if sys.stderr.isatty():
            from tqdm import tqdm

            self.bar = tqdm(total=total, desc="load steps", unit="step",
                            file=sys.stderr)
        self.every = max(1, total // 10)

    def __call__(self, record):
        self.done += 1
        if self.bar is not None:
            self.bar.set_postfix(J=record["njev"],
                                 contact=record["n_contact"],
                                 slip=record["n_slip"])
            self.bar.update()
        elif self.done % self.every == 0 or self.done == self.total:
            print(f"load step {self.done}/{self.total} "
                  f"({100 * self.done // self.total} %): J {record['njev']},"
                  f" stopping measure {record['error']:.2e}, "
                  f"{record['n_contact']} in contact, elapsed "
                  f"{time.perf_counter() - self.start:.1f} s",
                  file=sys.stderr, flush=True)

    def close(self):
        if self.bar is not None:
            self.bar.close()


def friction(args, problem, open_folder, emit, write_summary):
    """Load steps with Coulomb friction; every completed step is written at
    once (steps/*.vtu and scratch arrays), result.npz at the end, also when
    the run stops early."""
    from ..contact import solve_friction
    from ..contact.friction.driver import default_method
    from ..contact.friction.stream import MAX_LOAD_STEPS

    if _engine(args) == "petsc":
        from ..mpi.jobs import solvers
        solve_friction = solvers(args)[1]
    from ..errors import SolverError
    from ..output import StepWriter, friction_summary_of
    from ..output.report import format_friction_result

    if getattr(problem, "is_mortar", False):
        return two_body(args, problem, open_folder, emit, write_summary)
    args.method = args.method or default_method(args.formulation)
    total = problem.n_load_steps(args.steps)
    if total > MAX_LOAD_STEPS:
        raise SolverError(f"the load path has {total} load steps; at most "
                          f"{MAX_LOAD_STEPS} are supported")
    args.gap = getattr(args, "gap", None) or "obstacle"
    geometry = _geometry(args, problem)
    folder = open_folder(args.outdir or default_outdir(args, problem))
    writer = StepWriter(folder, problem, total)
    progress = Progress(total)
    result = None
    try:
        result = solve_friction(
            problem, args.friction, steps=args.steps,
            formulation=args.formulation, coulomb=args.coulomb,
            method=args.method, gap=args.gap, tol=args.tol,
            max_iter=args.max_iter, gap_scale=args.gap_scale,
            progress=progress, geometry=geometry, condense=_condense(args),
            on_step=writer, keep_steps=False, backend=args.linear_solver)
    finally:
        progress.close()
        folder.extra = {"steps_completed": writer.count}
        _finish_steps(writer, problem, geometry, result)
    summary = friction_summary_of(result, problem, tol=args.tol,
                                  max_iter=args.max_iter)
    if "engine" in result:
        summary["engine"] = result["engine"]
    if args.plots and result.steps_completed:
        from ..output.friction_figures import write_friction_figures

        steps = _load_steps(folder, result)
        for path in write_friction_figures(folder.path, problem,
                                           steps).values():
            folder.file(os.path.basename(path))
    write_summary(summary)
    emit(format_friction_result(summary, folder.path))
    if not result.success:
        failed = result.records[-1]
        print(_failure_line(result.message, failed["nit"],
                            failed["residual_history"],
                            f"; {result.steps_completed} completed steps "
                            f"kept in {folder.path}/"), file=sys.stderr)
        return EXIT_NOT_CONVERGED
    return EXIT_OK


def _finish_steps(writer, problem, geometry, result):
    """result.npz and result.pvd of the completed steps (also after an
    interrupt, when ``result`` is None)."""
    import numpy as np

    nc = problem.n_contact
    normal = np.full((nc, geometry.normal.shape[1]), np.nan)
    normal[geometry.index] = geometry.normal
    gap = np.full(nc, np.nan)
    gap[geometry.index] = geometry.gap
    records = [] if result is None else result.records
    extra = dict(
        contact_nodes=(problem.contact_nodes if problem.kind == "mesh"
                       else np.arange(nc)),
        gap=gap, normal=normal,
        step_njev=np.array([r["njev"] for r in records[:writer.count]],
                           dtype=np.int64),
        step_nfev=np.array([r["nfev"] for r in records[:writer.count]],
                           dtype=np.int64),
        converged=np.array(result is not None and bool(result.success)),
        steps_completed=np.array(writer.count))
    if writer.count == 0:
        writer.close()
        return
    writer.finish(extra)


def _load_steps(folder, result):
    """The written result.npz with the run's settings, for the figures."""
    import numpy as np
    from scipy.optimize import OptimizeResult

    with np.load(os.path.join(folder.path, "result.npz")) as data:
        steps = OptimizeResult({key: data[key] for key in data.files})
    steps.update({key: result[key] for key in (
        "steps", "friction", "formulation", "coulomb", "method",
        "steps_completed", "records")})
    return steps


def two_body(args, problem, open_folder, emit, write_summary):
    """Two elastic bodies (dual mortar, :mod:`solver.contact.two_body`),
    frictionless or with ``--friction``: summary.json, result.npz,
    result.vtu (cell data ``body``), ``--plots`` interface.png and
    bodies.png. Options of a rigid obstacle (``--gap``) are refused."""
    from ..contact.friction.driver import default_method
    from ..contact.two_body import solve_two_body
    from ..errors import SolverError
    from ..linalg import resolve
    from ..output import friction_summary_of, summary_of
    from ..output.report import format_friction_result, format_result
    from ..output.two_body import (write_two_body_figures,
                                  write_two_body_result, write_two_body_vtk)

    if getattr(args, "gap", None) is not None:
        raise SolverError("--gap applies to a rigid obstacle; two bodies "
                          "use the mortar's weighted gaps")
    friction = args.friction is not None
    args.method = args.method or (default_method(args.formulation)
                                  if friction else "min")
    resolve(args.linear_solver)  # not installed: SolverError, exit 2
    options = dict(method=args.method, tol=args.tol, max_iter=args.max_iter,
                   gap_scale=args.gap_scale, condense=_condense(args),
                   backend=args.linear_solver)
    if friction:
        options.update(steps=args.steps, formulation=args.formulation,
                       coulomb=args.coulomb)
    else:
        options.update(start=args.start)
    folder = open_folder(args.outdir or default_outdir(args, problem))
    if friction:
        progress = Progress(problem.n_load_steps(args.steps))
        try:
            result = solve_two_body(problem, friction=args.friction,
                                    progress=progress, **options)
        finally:
            progress.close()
        summary = friction_summary_of(result, problem, tol=args.tol,
                                      max_iter=args.max_iter)
    else:
        result = solve_two_body(problem, **options)
        summary = summary_of(result, problem, tol=args.tol,
                             max_iter=args.max_iter)
    summary.update(_interface_summary(problem, result))
    write_two_body_result(folder.file("result.npz"), result, problem)
    if friction and not result.steps_completed:
        pass  # nothing to draw
    else:
        write_two_body_vtk(folder.file("result.vtu"), result, problem)
        if args.plots:
            for path in write_two_body_figures(folder.path, problem,
                                               result).values():
                folder.file(os.path.basename(path))
    write_summary(summary)
    emit((format_friction_result if friction else format_result)(
        summary, folder.path))
    if not result.success:
        print(f"error: {result.message}", file=sys.stderr)
        return EXIT_NOT_CONVERGED
    return EXIT_OK


def _interface_summary(problem, result):
    """The interface's figures for summary.json (last step of friction)."""
    import numpy as np

    pressure = np.asarray(result.contact_pressure)
    pressure = pressure[-1] if pressure.ndim == 2 else pressure
    D = np.asarray(result.mortar_D)
    meta = problem.meta or {}
    return {"coupling": result.variant,
            "bodies": meta.get("bodies"),
            "slave_body": meta.get("slave_body"),
            "master_body": meta.get("master_body"),
            "slave_nodes": int(len(D)),
            "slave_nodes_covered": int(np.sum(result.covered)),
            "interface_normal_force": float(D @ pressure),
            "max_interface_pressure": float(pressure.max(initial=0.0))}
