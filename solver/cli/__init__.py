"""Command line interface: ``python -m solver PROBLEM.npz [options]``.

A thin layer over the library: it parses and checks the arguments, then
:mod:`solver.cli.run` solves and writes the outputs. Nothing it does ends in
a traceback (``--debug`` shows one); each outcome has its exit code
(:data:`~solver.cli.codes.EXIT_CODES_TEXT`, the table of ``--help``)."""

import argparse

from ..version import __version__
from ..problem import FORMAT_VERSION
from .codes import (EXIT_CODES_TEXT, EXIT_INPUT, MAX_ITER, MAX_STEPS,
                     MIN_TOL)
from .run import run


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2 (argparse's own code)
        self.exit(EXIT_INPUT, None if _mpi_rank() else
                  f"{self.prog}: error: {message}\n")


def _mpi_rank():
    """This process's rank under mpiexec (0 otherwise): only rank 0 prints."""
    import os

    for name in ("OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"):
        if os.environ.get(name, "").isdigit():
            return int(os.environ[name])
    return 0


def build_parser():
    parser = _Parser(
        prog="python -m solver",
        description="Contact of an elastic body with a rigid obstacle, "
                    "or of two elastic bodies (dual mortar), by "
                    "semismooth Newton. Reads a problem file written by "
                    "sfepy_problems/*.py (format version "
                    f"{FORMAT_VERSION}).",
        epilog=EXIT_CODES_TEXT,
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("problem", help="problem file (.npz)")
    parser.add_argument("--method", choices=("min", "fb"), default=None,
                        help="semismooth Newton method: damped Newton with "
                             "the min function (thesis §2.2.1) or the "
                             "Fischer-Burmeister method of De Luca, "
                             "Facchinei and Kanzow (§2.2.2); default min, "
                             "fb with --formulation thesis (as the thesis; "
                             "with the projection formulation min needs "
                             "fewer Jacobians, benchmarks/README.md)")
    parser.add_argument("--gap", choices=("obstacle", "body"),
                        default=None,
                        help="gaps and normals from the obstacle's normals "
                             "(§2.1.1) or from the body's spline normals "
                             "(§2.1.2-2.1.3); default obstacle; not for "
                             "two bodies (mortar weighted gaps)")
    parser.add_argument("--search-interval", nargs=2, type=_real,
                        metavar=("T0", "T1"),
                        help="obstacle parameter interval searched for the "
                             "gaps; default: the problem file's, else found "
                             "from the body's extent")
    parser.add_argument("-o", "--outdir", metavar="OUTDIR",
                        help="folder for summary.json, result.npz, "
                             "result.vtu and figures; default: beside the "
                             "problem, named PROBLEM-METHOD-GAP")
    parser.add_argument("--tol", type=_tolerance, default=1e-10,
                        help="relative tolerance of the stopping test "
                             f"(scale-invariant, in [{MIN_TOL:g}, 0.1]); "
                             "summary.json records the test applied; "
                             "default 1e-10")
    parser.add_argument("--max-iter", type=_bounded_int(MAX_ITER),
                        default=100,
                        help="maximum number of Newton iterations (all "
                             f"levels of a nested start; at most {MAX_ITER}"
                             "); default 100")
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
    parser.add_argument("--variant", choices=("mortar", "node-to-segment"),
                        default=None,
                        help="coupling of two bodies: mortar (dual mortar, "
                             "weighted gaps; passes the patch test) or "
                             "node-to-segment (each slave node against the "
                             "master surface; for comparison); default "
                             "mortar")
    parser.add_argument("--start", choices=("nested", "free"),
                        help="start of a condensed frictionless solve: "
                             "nested = solve on ever coarser subsets of the "
                             "contact nodes first (Newton iterations on the "
                             "finest that do not grow with the mesh); "
                             "free = from no contact force, u = K^-1 f; "
                             "default nested (the full system starts from "
                             "the thesis's u = 0)")
    parser.add_argument("--linear-solver",
                        choices=("auto", "superlu", "pardiso", "cholmod",
                                 "amg"),
                        default="auto",
                        help="sparse direct solver of the condensed system "
                             "(factorisation of K and its Schur complement "
                             "on the contact DOFs): superlu (SciPy, always "
                             "there), pardiso (pip install '.[mkl]'), "
                             "cholmod (pip install '.[cholmod]'); or amg: "
                             "no factorisation, the active set method with "
                             "AMG-preconditioned CG (frictionless, one body; "
                             "pip install '.[amg]'); default auto = the "
                             "first installed of pardiso, cholmod, superlu, "
                             "or amg when a factorisation would not fit the "
                             "memory; summary.json records it and why")
    friction = parser.add_argument_group(
        "Coulomb friction by load steps (thesis §5)")
    friction.add_argument("--friction", type=_nonnegative_float,
                          metavar="F_C",
                          help="coefficient of friction f_c >= 0; without "
                               "it the problem is frictionless")
    friction.add_argument("--steps", type=_bounded_int(MAX_STEPS),
                          default=None,
                          help="number of load steps, at most "
                               f"{MAX_STEPS}; step k applies k/steps * f "
                               "(default 100; a problem with a load path "
                               "uses its own stages and steps)")
    friction.add_argument("--formulation", choices=("projection", "thesis"),
                          default=None,
                          help="projection: g_t = proj(g_t - c du_t), "
                               "non-degenerate, 2D and 3D; thesis: the split "
                               "tangential increment of (110)/(111), as in "
                               "Table 2 (2D only; singular where p = 0, it "
                               "fails on fine meshes) (default projection)")
    friction.add_argument("--coulomb", choices=("lagged", "implicit"),
                          default=None,
                          help="friction bound from the previous step's "
                               "normal force (thesis) or the current one's "
                               "(default lagged)")
    engine = parser.add_argument_group(
        "PETSc engine, under mpiexec (pip install '.[petsc]'; docs/mpi.md)")
    engine.add_argument("--engine", choices=("serial", "petsc"),
                        default="serial",
                        help="petsc: the same solves with PETSc (MUMPS, "
                             "KSP) on the MPI ranks of mpiexec -n N; "
                             "default serial")
    engine.add_argument("--ksp", choices=("mumps", "gamg", "hypre"), default=None,
                        help="with --engine petsc --system full: each Newton "
                             "system by MUMPS, by CG + GAMG (rigid-body "
                             "near-null space) or by CG + hypre's "
                             "BoomerAMG; default mumps (a partitioned "
                             "folder: gamg or hypre)")
    parser.add_argument("--plots", action="store_true",
                        help="also write PNG figures (deformed body, "
                             "displacements, convergence, contact "
                             "pressure)")
    parser.add_argument("--info", action="store_true",
                        help="load and validate the problem, print a "
                             "summary and stop")
    parser.add_argument("--json", action="store_true",
                        help="with --info: print the summary as JSON")
    parser.add_argument("-v", "--verbose", action="store_true",
                        help="also show the warnings of the libraries "
                             "used (the solver's own warnings are always "
                             "shown, one line each)")
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


def _tolerance(text):
    value = _positive_float(text)
    if not MIN_TOL <= value <= 0.1:
        raise argparse.ArgumentTypeError(
            f"must be between {MIN_TOL:g} and 0.1 (a relative tolerance; "
            f"below {MIN_TOL:g} round-off decides): {text!r}")
    return value


def _bounded_int(largest):
    def parse(text):
        digits = text.strip().lstrip("+")
        if not digits.isdigit() or len(digits) > 12:
            raise argparse.ArgumentTypeError(
                f"not an integer between 1 and {largest}: {text[:40]!r}")
        value = int(digits)
        if not 1 <= value <= largest:
            raise argparse.ArgumentTypeError(
                f"must be between 1 and {largest}: {text!r}")
        return value
    return parse


def main(argv=None):
    """Run the command line; return the exit code. Under ``mpiexec`` with
    ``--engine petsc`` every rank calls it: rank 0 runs the command line,
    the others serve the engine's work (:func:`solver.mpi.engine.spmd`)."""
    import sys

    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] == ["convert"]:  # python -m solver convert X.npz DIR
        from .partitioned import convert_main

        return convert_main(argv[1:])
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.json and not args.info:
        parser.error("--json goes with --info")
    if args.engine == "petsc":
        from .. import mpi

        reason = mpi.missing()
        if reason:
            parser.error(reason)
        from ..mpi.engine import service

        svc = service()
        if not svc.root:
            return svc.serve()  # rank 0's exit code
        code = 1
        try:
            code = run(args)
        finally:
            svc.stop(code)
        return code
    return run(args)
