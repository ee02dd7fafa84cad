"""The solve job of the command line: the parsed arguments become the
options of :func:`solver.solve`, checked (:func:`solver.front.prepare`)
before the output folder is made; then solve, write the outputs
(:func:`solver.output.write_all`) and print the summary. Called by
:func:`solver.cli.run.run`, which maps every outcome to an exit code."""

import os
import re
import sys
import time

from ..errors import SolverError
from .codes import EXIT_NOT_CONVERGED, EXIT_OK

__all__ = ["solve_job", "options_of", "default_outdir", "Progress",
           "command_line_message"]

#: Options of solve() by their command-line names, where they differ.
FLAGS = {"backend": "--linear-solver", "search_interval": "--search-interval",
         "max_iter": "--max-iter", "gap_scale": "--gap-scale"}


def options_of(args):
    """The :func:`solver.solve` options of the parsed ``args`` (those left
    at their defaults are not passed, so that the front can tell what was
    given)."""
    options = dict(
        friction=args.friction, method=args.method, system=args.system,
        start=args.start, formulation=args.formulation, coulomb=args.coulomb,
        steps=args.steps, gap=args.gap, backend=args.linear_solver,
        engine=None if args.engine == "serial" else args.engine,
        ksp=args.ksp, tol=args.tol, max_iter=args.max_iter,
        gap_scale=args.gap_scale, variant=args.variant,
        search_interval=(None if args.search_interval is None
                         else tuple(args.search_interval)))
    return options


def command_line_message(message):
    """A refusal of the front in the command line's words: every
    ``option=value`` of solve()'s becomes ``--option value``."""
    from ..front.cases import DEFAULTS

    def flag(match):
        name, value = match.group(1), match.group(2).strip("'")
        if name not in DEFAULTS:
            return match.group(0)
        return f"{FLAGS.get(name, '--' + name.replace('_', '-'))} {value}"
    return re.sub(r"\b(\w+)=(\([^)]*\)|'[^']*'|[^\s,;)]+)", flag, message)


def default_outdir(args, plan):
    """PROBLEM-METHOD-GAP or PROBLEM-fcF-STEPS-FORMULATION-COULOMB-METHOD
    beside the problem, then every other option given that changes the run,
    so that different runs write different folders."""
    s, case = plan.settings, plan.case
    stem = os.path.splitext(args.problem)[0]
    gap = {"rigid": s["gap"], "two-body": s["variant"] or "mortar",
           "discrete": "given"}[case.bodies]
    if plan.friction is not None:
        steps = "path" if plan.problem.load_path is not None else \
            f"{s['steps'] or 100}steps"
        name = (f"{stem}-fc{plan.friction:g}-{steps}-{s['formulation']}-"
                f"{s['coulomb']}-{s['method']}")
        if case.bodies != "rigid":
            name += f"-{gap}"
    else:
        name = f"{stem}-{s['method']}-{gap}"
    extras = [("system", args.system != "auto", args.system),
              ("start", args.start is not None, args.start),
              ("solver", args.linear_solver != "auto", args.linear_solver),
              ("engine", args.engine != "serial", args.engine),
              ("ksp", args.ksp is not None, args.ksp),
              ("tol", args.tol != 1e-10, f"tol{args.tol:g}"),
              ("iter", args.max_iter != 100, f"maxiter{args.max_iter}"),
              ("scale", args.gap_scale is not None,
               f"c{args.gap_scale:g}" if args.gap_scale else ""),
              ("search", args.search_interval is not None, "search")]
    for _, given, text in extras:
        if given:
            name += f"-{text}"
    return name


def _failure_line(message, nit, history, tail=""):
    values = ", ".join(f"{r:.3e}" for r in history)
    return (f"error: {message} after {nit} iterations; residual history "
            f"||Phi||: [{values}]{tail}")


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


def solve_job(args, problem, open_folder, emit, write_summary):
    """Check, solve, write summary.json, result.npz, result.vtu (friction:
    result.pvd and steps/), figures; print the summary."""
    from ..front import ConvertedPlan, prepare
    from ..output import StepOutputs, write_all
    from ..output.report import format_friction_result, format_result

    try:
        plan = prepare(problem, **options_of(args))
    except SolverError as exc:
        raise type(exc)(command_line_message(str(exc))) from None
    if plan.case.bodies == "partitioned":
        from .partitioned import partitioned_job

        return partitioned_job(args, plan, open_folder, emit, write_summary,
                               Progress)
    if isinstance(plan, ConvertedPlan):  # a .npz's friction, full, petsc
        from .partitioned import converted_job

        return converted_job(args, plan, open_folder(
            args.outdir or default_outdir(args, plan)), emit, write_summary,
            Progress)
    folder = open_folder(args.outdir or default_outdir(args, plan))
    result = None
    if plan.friction is None:
        result = plan.run()
    else:
        outputs = StepOutputs(folder, problem,
                              problem.n_load_steps(args.steps),
                              geometry=plan.geometry)
        progress = Progress(problem.n_load_steps(args.steps))
        try:
            result = plan.run(progress=progress, on_step=outputs,
                              keep_steps=False)
        finally:
            progress.close()
            folder.extra = {"steps_completed": outputs.count}
            outputs.finish(plan.geometry, result)
    summary = write_all(folder, problem, result, plots=args.plots,
                        tol=args.tol, max_iter=args.max_iter)
    write_summary(summary)
    emit((format_result if plan.friction is None else
          format_friction_result)(summary, folder.path))
    if not result.success:  # in the command line's words
        message = command_line_message(result.message)
        if plan.friction is None:
            line = _failure_line(message, result.nit,
                                 summary["residual_history"])
        elif result.records and "residual_history" in result.records[-1]:
            failed = result.records[-1]
            line = _failure_line(message, failed["nit"],
                                 failed["residual_history"],
                                 f"; {result.steps_completed} completed "
                                 f"steps kept in {folder.path}/")
        else:
            line = f"error: {message}"
        print(line, file=sys.stderr)
        return EXIT_NOT_CONVERGED
    return EXIT_OK
