"""The command line on a partitioned problem (a folder written by
``python -m solver convert X.npz DIR``): ``mpiexec -n N python -m solver
DIR --engine petsc`` (:mod:`solver.mpi.distributed`), and the converter
itself. Each outcome is an exit code of :mod:`~solver.cli.codes` and at
most one line on stderr, as the ``.npz`` runs."""

import argparse
import os
import sys
import traceback

from ..errors import SolverError
from .codes import (EXIT_INPUT, EXIT_INTERNAL, EXIT_NOT_CONVERGED, EXIT_OK,
                    EXIT_OUTPUT)

__all__ = ["run_partitioned", "convert_main", "REFUSED"]

#: Options of the ``.npz`` runs a partitioned run refuses (frictionless,
#: rigid obstacle, condensed system, gaps fixed by the conversion):
#: attribute -> (value that is accepted, option); ``--system condensed``
#: is accepted too (what it runs).
REFUSED = {"friction": (None, "--friction"), "steps": (None, "--steps"),
           "formulation": (None, "--formulation"),
           "coulomb": (None, "--coulomb"), "gap": (None, "--gap"),
           "search_interval": (None, "--search-interval"),
           "gap_scale": (None, "--gap-scale"),
           "system": ("auto", "--system"), "variant": (None, "--variant"),
           "start": (None, "--start"),
           "linear_solver": ("auto", "--linear-solver"),
           "ksp": (None, "--ksp"), "plots": (False, "--plots"),
           "info": (False, "--info")}


def _one_line(text):
    return " ".join(str(text).split())


def run_partitioned(args, svc):
    """(rank 0) Solve the partitioned problem ``args.problem`` on the
    service's ranks; return the exit code."""
    from ..mpi.distributed import solve_partitioned
    from ..mpi.service import EngineError

    try:
        given = [option for name, (default, option) in REFUSED.items()
                 if getattr(args, name, default) not in (default, None)
                 and not (name == "system" and args.system == "condensed")]
        if given:
            raise SolverError(
                f"{', '.join(given)}: not for a partitioned problem (the "
                "distributed solve is frictionless, on the system condensed "
                "onto Γc, with the gaps of the conversion); run the .npz "
                "for these")
        outdir = args.outdir or os.path.normpath(args.problem) + "-result"
        summary = solve_partitioned(svc, args.problem, args.method or "min",
                                    args.tol, args.max_iter, outdir)
    except SolverError as exc:
        return _fail(args, f"error: {_one_line(exc)}", EXIT_INPUT)
    except EngineError as exc:
        return _fail(args, f"error: {_one_line(exc)}", EXIT_INTERNAL)
    except OSError as exc:
        return _fail(args, f"error: cannot write {exc.filename or ''}: "
                     f"{_one_line(exc.strerror or exc)}", EXIT_OUTPUT)
    except Exception as exc:  # a bug: one line, the traceback with --debug
        return _fail(args, f"error: internal error: {_one_line(repr(exc))} "
                     "(run with --debug for the traceback and report it)",
                     EXIT_INTERNAL)
    v = summary["verification"]
    print(f"{summary['status']}: {summary['nit']} Newton iterations on "
          f"{summary['n_contact_dofs']} contact DOFs of "
          f"{summary['n_dofs']} ({svc.size} ranks), "
          f"{summary['n_in_contact']} nodes in contact, max penetration "
          f"{v['max_penetration']:.1e}, interior equilibrium "
          f"{v['interior_equilibrium']:.1e}; {outdir}/result.pvtu")
    sys.stdout.flush()
    if not summary["converged"]:
        print(f"error: not converged: {_one_line(summary['message'])}",
              file=sys.stderr)
        return EXIT_NOT_CONVERGED
    return EXIT_OK


def _fail(args, line, code):
    if getattr(args, "debug", False):
        traceback.print_exc()
    print(line, file=sys.stderr)
    return code


def convert_main(argv):
    """``python -m solver convert X.npz DIR [--gap obstacle|body]``."""
    parser = argparse.ArgumentParser(
        prog="python -m solver convert",
        description="Write a rigid-obstacle problem file as the partitioned "
                    "folder that mpiexec -n N python -m solver DIR --engine "
                    "petsc reads in part: K and f in PETSc's binary format, "
                    "the mesh as .npy, the contact geometry as contact.npz "
                    "(docs/npz-format.md, 'The partitioned problem').")
    parser.add_argument("problem", help="problem file (.npz)")
    parser.add_argument("folder", help="the partitioned problem's folder")
    parser.add_argument("--gap", choices=("obstacle", "body"),
                        default="obstacle",
                        help="gaps and normals as the solver's --gap")
    args = parser.parse_args(argv)
    from ..mpi.convert import convert

    try:
        meta = convert(args.problem, args.folder, args.gap)
    except SolverError as exc:
        print(f"error: {_one_line(exc)}", file=sys.stderr)
        return EXIT_INPUT
    except OSError as exc:
        print(f"error: cannot write {exc.filename or args.folder}: "
              f"{_one_line(exc.strerror or exc)}", file=sys.stderr)
        return EXIT_OUTPUT
    print(f"{args.folder}: {meta['n']} rows ({meta['n_free']} free DOFs), "
          f"{meta['nnz']} nonzeros, {meta['n_nodes']} nodes")
    return EXIT_OK
