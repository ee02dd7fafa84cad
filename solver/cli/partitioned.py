"""The command line on a partitioned problem (a folder written by
``python -m solver convert X.npz DIR``): ``mpiexec -n N python -m solver
DIR --engine petsc`` goes through the front as every run
(:func:`solver.front.prepare` checks it against the rules of
:mod:`solver.front.cases`; :func:`solver.cli.run.run` locks the output
folder, marks it "running" and turns every outcome into an exit code);
:func:`partitioned_job` writes its outputs. And the converter itself."""

import argparse
import os
import signal
import sys

import numpy as np

from ..errors import STOP_SIGNALS, SolverError
from .codes import EXIT_INPUT, EXIT_NOT_CONVERGED, EXIT_OK, EXIT_OUTPUT

__all__ = ["partitioned_job", "converted_job", "convert_main"]


def _one_line(text):
    return " ".join(str(text).split())


def partitioned_job(args, plan, open_folder, emit, write_summary,
                    progress_bar=None):
    """Solve the checked ``plan`` on the ranks; write, each under a
    temporary name renamed when complete, the pieces ``result-RANK.vtu``
    (every rank its own), ``contact.npz``, ``result.pvtu`` and last
    ``summary.json``; with friction also each step's pieces
    (``steps/step_KKKK-RANK.vtu``, ``steps/step_KKKK.pvtu``, written as the
    steps complete) and ``result.pvd``, the steps' progress shown by
    ``progress_bar(total)`` (:class:`solver.cli.jobs.Progress`); print
    the summary line."""
    from ..mpi.distributed import write_pvtu
    from ..problem.partitioned import original_nodes
    from ..output.folder import atomic_path
    from ..output.vtk import write_pvd

    name = os.path.normpath(args.problem)
    if plan.friction is not None:  # beside the frictionless run's
        name += f"-fc{plan.friction:g}-{args.steps or 100}steps"
    outdir = args.outdir or name + "-result"
    folder = open_folder(outdir)
    if plan.friction is None:
        result = plan.run()
    else:
        progress = progress_bar(plan.problem.n_load_steps(args.steps))
        try:
            result = plan.run(outdir=folder.path, progress=progress)
        finally:  # the steps' pieces listed also when a signal ends the run
            progress.close()
            steps = os.path.join(folder.path, "steps")
            for name in sorted(os.listdir(steps)) if os.path.isdir(
                    steps) else ():
                if name.startswith("step_"):
                    folder.file(os.path.join("steps", name))
    for name in result.piece_names():  # listed if interrupted once written
        folder.file(name)
    pieces = result.write_pieces(folder.path)
    contact = dict(result.contact)  # the .npz's node numbers
    contact["node"] = original_nodes(result.folder, contact["node"])
    with atomic_path(folder.file("contact.npz")) as tmp:
        np.savez(tmp, **contact)
    with atomic_path(folder.file("result.pvtu")) as tmp:
        write_pvtu(tmp, pieces, bool(result.meta.get("mortar")))
    if plan.friction is not None and result.timesteps:
        with atomic_path(folder.file("result.pvd")) as tmp:
            write_pvd(tmp, result.timesteps)
    summary = dict(result)
    write_summary(summary)
    v = summary["verification"]
    if plan.friction is None:
        emit(f"{summary['status']}: {summary['nit']} Newton iterations on "
             f"{summary['n_contact_dofs']} contact DOFs of "
             f"{summary['n_dofs']} ({summary['engine']['ranks']} ranks), "
             f"{summary['n_in_contact']} nodes in contact, max penetration "
             f"{v['max_penetration']:.1e}, interior equilibrium "
             f"{v['interior_equilibrium']:.1e}; {folder.path}/result.pvtu")
    else:
        emit(f"{summary['status']}: {summary['steps_completed']} of "
             f"{summary['steps']} load steps, f_c {summary['friction']:g}, "
             f"{summary['njev']} Jacobians on {summary['n_contact_dofs']} "
             f"contact DOFs of {summary['n_dofs']} "
             f"({summary['engine']['ranks']} ranks); last step "
             f"{summary['n_in_contact']} in contact, {summary['n_stick']} "
             f"stick, {summary['n_slip']} slip; max penetration "
             f"{v.get('max_penetration', float('nan')):.1e}, friction bound "
             f"violation {v.get('friction_bound_violation', float('nan')):.1e}"
             f", interior equilibrium "
             f"{v.get('interior_equilibrium', float('nan')):.1e}; "
             f"{folder.path}/result.pvd")
    if not result.success:
        print(f"error: not converged: {_one_line(summary['message'])}",
              file=sys.stderr)
        return EXIT_NOT_CONVERGED
    return EXIT_OK


def converted_job(args, plan, folder, emit, write_summary,
                  progress_bar=None):
    """Friction on the full system of a ``.npz`` on the petsc engine
    (:class:`solver.front.ConvertedPlan`): say which path runs, convert
    into a temporary folder beside the output folder ``folder`` (opened
    and locked, so that a full disk during the conversion is an output
    error, exit 4), run :func:`partitioned_job` on it, and remove it
    however the run ends (:mod:`solver.mpi.on_the_fly`). ``summary.json``
    says what was converted (``"converted"``)."""
    workdir = os.path.dirname(os.path.abspath(folder.path))
    ksp = plan.settings["ksp"]
    emit(f"path: friction on the full system by Krylov (CG/GMRES + {ksp}) "
         f"on the ranks' rows of a partitioned folder converted on the "
         f"fly from {args.problem} (in {workdir}/, removed at the end)")
    with plan.converted(workdir) as (folder_plan, info):
        info["folder"] = os.path.relpath(info["folder"], workdir)

        def summary_with_conversion(summary):
            summary.update(problem=args.problem, converted=info)
            write_summary(summary)
        local = argparse.Namespace(**dict(vars(args), outdir=folder.path))
        return partitioned_job(local, folder_plan, lambda outdir: folder,
                               emit, summary_with_conversion, progress_bar)


class _Stopped(BaseException):
    """A signal of :data:`~solver.errors.STOP_SIGNALS` arrived during
    the conversion (the converter's ``finally`` clauses then remove its
    temporary files; cli/run.py's ``Interrupted`` is not imported: run
    imports this module's job)."""

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


def _stop(signum, frame):
    for other in STOP_SIGNALS:  # once: the clean-up runs unbroken
        signal.signal(other, signal.SIG_IGN)
    raise _Stopped(signum)


def convert_main(argv):
    """``python -m solver convert X.npz DIR [--gap obstacle|body]
    [--no-renumber]``. SIGINT, SIGTERM and SIGHUP end it as they end a
    run (exit 128 + the signal, one line), after the converter has
    removed its temporary files and any ``problem.json``."""
    parser = argparse.ArgumentParser(
        prog="python -m solver convert",
        description="Write a rigid-obstacle or two-body (dual mortar) "
                    "problem file as the partitioned folder that mpiexec -n N python -m solver DIR --engine "
                    "petsc reads in part: K and f in PETSc's binary format, "
                    "the mesh as .npy, the contact geometry as contact.npz "
                    "(docs/npz-format.md, 'The partitioned problem').")
    parser.add_argument("problem", help="problem file (.npz)")
    parser.add_argument("folder", help="the partitioned problem's folder")
    parser.add_argument("--gap", choices=("obstacle", "body"),
                        default="obstacle",
                        help="gaps and normals as the solver's --gap")
    parser.add_argument("--renumber", action=argparse.BooleanOptionalAction,
                        default=True,
                        help="number the nodes in reverse Cuthill-McKee "
                             "order, so that each rank's node range is a "
                             "compact piece of the body (the default; "
                             "streamed, K never in memory); outputs keep "
                             "the .npz's node numbers. --no-renumber keeps "
                             "the file's order")
    args = parser.parse_args(argv)
    from ..mpi.convert import CUT_WARN, convert

    saved = {signum: signal.signal(signum, _stop)
             for signum in STOP_SIGNALS}
    try:
        meta = convert(args.problem, args.folder, args.gap, args.renumber)
    except KeyboardInterrupt:
        print("error: interrupted by SIGINT", file=sys.stderr)
        return 128 + signal.SIGINT
    except _Stopped as exc:
        print(f"error: interrupted by {signal.Signals(exc.signum).name}",
              file=sys.stderr)
        return 128 + exc.signum
    except SolverError as exc:
        print(f"error: {_one_line(exc)}", file=sys.stderr)
        return EXIT_INPUT
    except OSError as exc:
        print(f"error: cannot write {exc.filename or args.folder}: "
              f"{_one_line(exc.strerror or exc)}", file=sys.stderr)
        return EXIT_OUTPUT
    finally:
        for signum, handler in saved.items():
            signal.signal(signum, handler)
    print(f"{args.folder}: {meta['n']} rows ({meta['n_free']} free DOFs), "
          f"{meta['nnz']} nonzeros, {meta['n_nodes']} nodes"
          + (", renumbered" if meta["renumbered"] else ""))
    if not meta["renumbered"] and meta["cut_cells"] > CUT_WARN:
        print(f"note: {100 * meta['cut_cells']:.0f} % of the cells have "
              f"nodes in both halves of the node numbering, so on 2 ranks "
              f"or more each rank's rows of K couple to most of the others' "
              f"and its memory grows with the whole problem: convert "
              f"without --no-renumber for the Krylov path (--system full)")
    return EXIT_OK
