"""Command line interface: ``python -m solver PROBLEM.npz [options]``.

A thin layer over the library: it parses arguments, calls the public API,
prints and writes the result files. Errors caused by the input end with a
one-line message on stderr and exit code 2 (``--debug`` shows the traceback
instead).

Exit codes: 0 converged (or ``--info``), 2 bad input or usage, 3 not
converged (the outputs are still written, marked not converged).
"""

import argparse
import json
import os
import sys
import tempfile
import traceback

from . import __version__
from .errors import SolverError
from .problem import FORMAT_VERSION, load_problem

EXIT_OK, EXIT_INPUT, EXIT_NOT_CONVERGED = 0, 2, 3


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2 (argparse's own code)
        self.exit(EXIT_INPUT, f"{self.prog}: error: {message}\n")


def build_parser():
    parser = _Parser(
        prog="python -m solver",
        description="Contact of an elastic body with a rigid obstacle "
                    "(semismooth Newton). Reads a problem file written by "
                    "sfepy_problems/*.py (format version "
                    f"{FORMAT_VERSION}).")
    parser.add_argument("problem", help="problem file (.npz)")
    parser.add_argument("--method", choices=("min", "fb"), default=None,
                        help="semismooth Newton method: damped Newton with "
                             "the min function (thesis §2.2.1) or the "
                             "Fischer-Burmeister method of De Luca, "
                             "Facchinei and Kanzow (§2.2.2); default min "
                             "without friction, fb with friction (as the "
                             "thesis)")
    parser.add_argument("--gap", choices=("obstacle", "body"),
                        default="obstacle",
                        help="gaps and normals from the obstacle's normals "
                             "(§2.1.1) or from the body's spline normals "
                             "(§2.1.2-2.1.3); default obstacle")
    parser.add_argument("--search-interval", nargs=2, type=_real,
                        metavar=("T0", "T1"),
                        help="obstacle parameter interval searched for the "
                             "gaps; default: the problem file's, else found "
                             "from the body's extent")
    parser.add_argument("-o", "--outdir", metavar="OUTDIR",
                        help="folder for summary.json, result.npz, "
                             "result.vtu and figures; default: beside the "
                             "problem, named PROBLEM-METHOD-GAP")
    parser.add_argument("--tol", type=_positive_float, default=1e-10,
                        help="stop when ||Phi|| <= TOL * max(||f||, 1); "
                             "default 1e-10")
    parser.add_argument("--max-iter", type=_positive_int, default=100,
                        help="maximum number of Newton iterations; "
                             "default 100")
    parser.add_argument("--gap-scale", type=_positive_float,
                        help="scale c of the gap rows, B = c (s - YRu): "
                             "same solution, other Newton path; default 1 "
                             "(the thesis) on the full system and with "
                             "friction, the contact stiffness (gaps in "
                             "force units) on the condensed frictionless "
                             "system")
    parser.add_argument("--system", choices=("auto", "condensed", "full"),
                        default="auto",
                        help="condensed: factorise K once and iterate on the "
                             "system condensed exactly onto the contact "
                             "boundary (same solution, much faster); full: "
                             "the thesis's system in all unknowns, one "
                             "sparse LU per Newton iteration (faithful mode: "
                             "the iteration counts of Tables 1 and 2); "
                             "default auto = condensed, except full for the "
                             "thesis's friction formulation")
    parser.add_argument("--start", choices=("nested", "free"),
                        help="start of a condensed frictionless solve: "
                             "nested = solve on ever coarser subsets of the "
                             "contact nodes first (Newton iterations on the "
                             "finest that do not grow with the mesh); "
                             "free = from no contact force, u = K^-1 f; "
                             "default nested (the full system starts from "
                             "the thesis's u = 0)")
    friction = parser.add_argument_group(
        "Coulomb friction by load steps (thesis §5)")
    friction.add_argument("--friction", type=_nonnegative_float,
                          metavar="F_C",
                          help="coefficient of friction f_c >= 0; without "
                               "it the problem is frictionless")
    friction.add_argument("--steps", type=_positive_int, default=None,
                          help="number of load steps; step k applies "
                               "k/steps * f (default 100; a problem with a "
                               "load path uses its own stages and steps)")
    friction.add_argument("--formulation", choices=("thesis", "projection"),
                          default="thesis",
                          help="thesis: the split tangential increment of "
                               "(110)/(111) (singular where p = 0, the min "
                               "method fails on it); projection: "
                               "g_t = proj(g_t - c du_t), non-degenerate "
                               "(default thesis)")
    friction.add_argument("--coulomb", choices=("lagged", "implicit"),
                          default="lagged",
                          help="friction bound from the previous step's "
                               "normal force (thesis) or the current one's "
                               "(default lagged)")
    parser.add_argument("--plots", action="store_true",
                        help="also write PNG figures (deformed body, "
                             "displacements, convergence, contact "
                             "pressure)")
    parser.add_argument("--info", action="store_true",
                        help="load and validate the problem, print a "
                             "summary and stop")
    parser.add_argument("--json", action="store_true",
                        help="with --info: print the summary as JSON")
    parser.add_argument("--debug", action="store_true",
                        help="show tracebacks of errors")
    parser.add_argument("--version", action="version",
                        version=f"%(prog)s {__version__}")
    return parser


def _finite_float(text, allow_zero):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    low_ok = value >= 0 if allow_zero else value > 0
    if not (low_ok and value < float("inf")):
        rule = ">= 0" if allow_zero else "positive"
        raise argparse.ArgumentTypeError(f"must be {rule} and finite: "
                                         f"{text!r}")
    return value


def _real(text):
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None


def _positive_float(text):
    return _finite_float(text, allow_zero=False)


def _nonnegative_float(text):
    return _finite_float(text, allow_zero=True)


def _positive_int(text):
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") \
            from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1: {text!r}")
    return value


def format_summary(info):
    """The ``--info`` summary as readable lines."""
    meta = info["meta"]
    lines = [f"problem kind      {info['kind']}",
             f"reduced DOFs      {info['dofs']}",
             f"contact nodes Nc  {info['contact_nodes']} "
             f"({info['contact_nodes_free']} free, "
             f"{info['contact_nodes'] - info['contact_nodes_free']} "
             "supported)",
             f"K                 nnz {info['K_nnz']}, "
             f"‖K‖_F = {info['K_norm_fro']:.6g}, "
             f"max |K_ij| = {info['K_norm_max']:.6g}",
             f"‖f‖               {info['f_norm']:.6g}",
             f"sum of M          {info['M_sum']:.12g}"]
    if info["kind"] == "mesh":
        x, y = info["obstacle"]
        rng = info["obstacle_t_range"]
        lines += [f"mesh              {meta.get('mesh')}: "
                  f"{info['triangles']} triangles, {info['nodes']} nodes",
                  f"material          E = {meta['E']:g}, nu = {meta['nu']:g},"
                  f" plane {meta['plane']}",
                  f"obstacle          x(t) = {x}, y(t) = {y}"
                  + ("" if rng is None else f", t in [{rng[0]}, {rng[1]}]")]
    else:
        lines += [f"description       {meta['description']}",
                  f"gaps s            {info['gap']}",
                  f"normals           {info['normal']}"]
    if "load" in meta:
        lines.append(f"load              {json.dumps(meta['load'])}")
    return "\n".join(lines)


def main(argv=None):
    """Run the command line; return the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.start is not None and args.friction is not None:
        parser.error("--start applies to frictionless solves only (friction "
                     "steps start from the previous step)")
    if args.start == "nested" and args.system == "full":
        parser.error("--start nested needs the condensed system, not "
                     "--system full")
    try:
        problem = load_problem(args.problem)
        if args.search_interval is not None:
            problem.set_search_interval(*args.search_interval)
        if args.info:
            info = problem.summary()
            print(json.dumps(info, indent=2) if args.json
                  else format_summary(info))
            return EXIT_OK
        return _solve(args, problem)
    except SolverError as exc:
        _remove_created_dirs(args)
        if args.debug:
            traceback.print_exc()
        print(f"error: {_one_line(exc)}", file=sys.stderr)
        return EXIT_INPUT
    except OSError as exc:  # output folder not writable, disk full, ...
        _remove_created_dirs(args)
        if args.debug:
            traceback.print_exc()
        where = f" {exc.filename}" if exc.filename else ""
        print(f"error: cannot write{where}: "
              f"{_one_line(exc.strerror or exc)}", file=sys.stderr)
        return EXIT_INPUT
    except BaseException:
        _remove_created_dirs(args)
        raise


def _one_line(message):
    """The message on one line (a file name may hold a newline)."""
    return " ".join(str(message).split("\n"))


def _default_outdir(args, problem):
    stem = os.path.splitext(args.problem)[0]
    gap = args.gap if problem.kind == "mesh" else "given"
    if args.friction is not None:
        steps = "path" if problem.load_path is not None else \
            f"{args.steps or 100}steps"
        return (f"{stem}-fc{args.friction:g}-{steps}-"
                f"{args.formulation}-{args.coulomb}-{args.method}")
    return f"{stem}-{args.method}-{gap}"


def _prepare_outdir(args, problem):
    """Create the output folder (and missing parents) and check that a file
    can be written there. The folders created are remembered in
    ``args.created_dirs`` so that :func:`_remove_created_dirs` can take them
    back if the run fails before writing anything."""
    outdir = args.outdir or _default_outdir(args, problem)
    missing, folder = [], os.path.abspath(outdir)
    while folder and not os.path.exists(folder):
        missing.append(folder)
        folder = os.path.dirname(folder)
    os.makedirs(outdir, exist_ok=True)
    args.created_dirs = missing  # innermost first
    try:  # a real test (os.access is always true for root)
        fd, probe = tempfile.mkstemp(prefix=".tmp-", dir=outdir)
    except OSError as exc:
        raise PermissionError(exc.errno, exc.strerror or "cannot write",
                              outdir) from None
    os.close(fd)
    os.unlink(probe)
    return outdir


def _remove_created_dirs(args):
    """Remove the folders this run created, if they are still empty."""
    for folder in getattr(args, "created_dirs", []):
        try:
            os.rmdir(folder)  # only ever removes an empty folder
        except OSError:
            break
    args.created_dirs = []


def _condense(args):
    """``condense`` of the solvers from ``--system`` (None = auto)."""
    return {"auto": None, "condensed": True, "full": False}[args.system]


def _check_inputs(args, problem):
    """Find every input error that can be found before solving, then make
    the output folder: an error never leaves a new (empty) folder behind.

    Returns the contact geometry (gaps and normals, which may raise
    GapError) and the output folder.
    """
    from .contact import contact_geometry

    if _condense(args) is False:  # else checked by the solve's factorisation
        problem.check_stiffness()  # K positive definite (one factorisation)
    geometry = contact_geometry(problem, args.gap)
    return geometry, _prepare_outdir(args, problem)


def _solve(args, problem):
    if args.friction is not None:
        return _solve_friction(args, problem)
    from .contact import solve_frictionless
    from .output import summary_of, write_result, write_summary, write_vtk

    args.method = args.method or "min"
    geometry, outdir = _check_inputs(args, problem)
    result = solve_frictionless(problem, method=args.method, gap=args.gap,
                                tol=args.tol, max_iter=args.max_iter,
                                gap_scale=args.gap_scale, geometry=geometry,
                                condense=_condense(args), start=args.start)
    summary = summary_of(result, problem, tol=args.tol,
                         max_iter=args.max_iter)
    write_result(os.path.join(outdir, "result.npz"), result, problem)
    if problem.kind == "mesh":
        write_vtk(os.path.join(outdir, "result.vtu"), result, problem)
    if args.plots:
        from .output.figures import write_figures

        write_figures(outdir, problem, result)
    write_summary(os.path.join(outdir, "summary.json"), summary)
    print(format_result(summary, outdir))
    if not result.success:
        history = ", ".join(f"{r:.3e}" for r in result.history["residual"])
        print(f"error: {result.message} after {result.nit} iterations; "
              f"residual history ||Phi||: [{history}]", file=sys.stderr)
        return EXIT_NOT_CONVERGED
    return EXIT_OK


def _solve_friction(args, problem):
    from tqdm import tqdm

    from .contact import solve_friction
    from .output import (friction_summary_of, write_friction_result,
                         write_summary, write_vtk_series)

    args.method = args.method or "fb"
    geometry, outdir = _check_inputs(args, problem)
    total = problem.n_load_steps(args.steps)
    with tqdm(total=total, desc="load steps", unit="step",
              file=sys.stderr, disable=None) as bar:
        def progress(record):
            bar.set_postfix(J=record["njev"], contact=record["n_contact"],
                            slip=record["n_slip"])
            bar.update()

        result = solve_friction(
            problem, args.friction, steps=args.steps,
            formulation=args.formulation, coulomb=args.coulomb,
            method=args.method, gap=args.gap, tol=args.tol,
            max_iter=args.max_iter, gap_scale=args.gap_scale,
            progress=progress, geometry=geometry,
            condense=_condense(args))
    summary = friction_summary_of(result, problem, tol=args.tol,
                                  max_iter=args.max_iter)
    if result.steps_completed:
        write_friction_result(os.path.join(outdir, "result.npz"), result,
                              problem)
        if problem.kind == "mesh":
            write_vtk_series(outdir, result, problem)
        if args.plots:
            from .output.figures import write_friction_figures

            write_friction_figures(outdir, problem, result)
    write_summary(os.path.join(outdir, "summary.json"), summary)
    print(format_friction_result(summary, outdir))
    if not result.success:
        failed = result.records[-1]
        history = ", ".join(f"{r:.3e}" for r in failed["residual_history"])
        print(f"error: {result.message} after {failed['nit']} iterations; "
              f"residual history ||Phi||: [{history}]; "
              f"{result.steps_completed} completed steps kept in {outdir}/",
              file=sys.stderr)
        return EXIT_NOT_CONVERGED
    return EXIT_OK


def format_friction_result(summary, outdir):
    """A readable summary of a friction run."""
    state = "converged" if summary["converged"] else "NOT CONVERGED"
    lines = [
        f"f_c = {summary['friction']:g}, {summary['steps']} load steps, "
        f"{summary['formulation']} formulation, {summary['coulomb']} "
        f"normal force, {summary['method']} method: {state}",
        f"steps completed   {summary['steps_completed']} of "
        f"{summary['steps']}",
        f"evaluations       J {summary['n_jacobian']}, F "
        f"{summary['n_residual']} in total (thesis Table 2 metrics)",
        f"system            {_system_text(summary)}",
        f"gradient steps    {summary['gradient_steps']}"]
    if summary["steps_completed"]:
        lines += [
            f"last step         {summary['final_n_contact']} nodes in "
            f"contact: {summary['final_n_stick']} stick, "
            f"{summary['final_n_slip']} slip; max pressure "
            f"{summary['final_max_contact_pressure']:.6g}"]
    lines += [f"reduced DOFs      {summary['n_dof']}",
              f"wall time         {summary['wall_time']:.3f} s",
              f"outputs           {outdir}/"]
    return "\n".join(lines)


def _system_text(summary):
    if summary["system"] == "full":
        return "full (the thesis's, in all unknowns)"
    text = "condensed onto the contact boundary (--system full: the thesis's)"
    levels = summary.get("levels") or []
    if len(levels) > 1:
        text += (f"\nnested start      {len(levels)} levels of "
                 f"{levels[0]['n_nodes']}..{levels[-1]['n_nodes']} contact "
                 f"nodes; J per level {[lv['njev'] for lv in levels]}")
    return text


def format_result(summary, outdir):
    """A readable summary of a solve."""
    state = "converged" if summary["converged"] else "NOT CONVERGED"
    return "\n".join([
        f"{summary['method']} method, gap from {summary['gap']}: {state} "
        f"({summary['message']})",
        f"iterations        {summary['iterations']}",
        f"evaluations       J {summary['n_jacobian']}, F "
        f"{summary['n_residual']}  ("
        + ("thesis Table 1 metrics)" if summary["system"] == "full" else
           "all levels; Table 1's: --system full)"),
        f"system            {_system_text(summary)}",
        f"final ||Phi||     {summary['residual']:.3e} (stopping measure "
        f"{summary['error']:.3e})",
        f"complementarity   max|min(lambda, s - u_n)| = "
        f"{summary['complementarity']:.3e}",
        f"contact nodes     {summary['n_contact_nodes']} of "
        f"{summary['n_contact_candidates']}",
        f"max pressure      {summary['max_contact_pressure']:.6g}",
        f"reduced DOFs      {summary['n_dof']}",
        f"wall time         {summary['wall_time']:.3f} s",
        f"outputs           {outdir}/"])
