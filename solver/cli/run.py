"""One run of the command line: load, solve, write, and say how it ended.

:func:`run` turns every outcome into an exit code (:mod:`~solver.cli.codes`)
and at most one line on stderr. The output folder is locked for the run,
cleared of an earlier run's files, and its ``summary.json`` says
``"running"`` until the run ends, then the final status and the files the
run wrote."""

import json
import os
import signal
import stat
import sys
import traceback
import warnings

from ..errors import STOP_SIGNALS, SolverError
from .codes import (EXIT_CODES_TEXT, EXIT_INPUT, EXIT_INTERNAL,
                    EXIT_NOT_CONVERGED, EXIT_OK, EXIT_OUTPUT, EXIT_PIPE,
                    MAX_ITER, MAX_STEPS, MIN_TOL)
from ..output.folder import OutputFolder

__all__ = ["run", "Interrupted", "EXIT_OK", "EXIT_INTERNAL", "EXIT_INPUT",
           "EXIT_NOT_CONVERGED", "EXIT_OUTPUT", "EXIT_PIPE", "MAX_STEPS",
           "MAX_ITER", "MIN_TOL", "EXIT_CODES_TEXT", "emit"]


class Interrupted(BaseException):
    """SIGINT, SIGTERM or SIGHUP arrived; ``signum`` says which."""

    def __init__(self, signum):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def _raise_interrupted(signum, frame):
    """Stop the run, once: later signals are ignored, so that a second one
    cannot cut short the writing of the completed work (which may still need
    the petsc engine's ranks)."""
    for stop in STOP_SIGNALS:
        signal.signal(stop, signal.SIG_IGN)
    raise Interrupted(signum)


def _one_line(message):
    """The message on one line (a file name may hold a newline)."""
    return " ".join(str(message).split())


def _show_warning(message, category, filename, lineno, file=None,
                  line=None):
    print(f"warning: {_one_line(message)}", file=sys.stderr)


def _setup(args):
    """Signals become exceptions (so that the run can mark its outputs);
    a file-size limit gives an error, not a kill; warnings one line each."""
    for signum in STOP_SIGNALS:
        signal.signal(signum, _raise_interrupted)
    if hasattr(signal, "SIGXFSZ"):
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    warnings.showwarning = _show_warning
    if not args.verbose:
        warnings.filterwarnings("ignore")
        from .. import errors

        if hasattr(errors, "SolverWarning"):  # ours: always shown
            warnings.filterwarnings("always", category=errors.SolverWarning)


def _check_input_file(path):
    """A regular file (a FIFO or device would be read twice or hang)."""
    try:
        mode = os.stat(path).st_mode
    except OSError as exc:
        raise SolverError(f"{path}: {exc.strerror.lower()}") from None
    if stat.S_ISDIR(mode):
        raise SolverError(f"{path}: is a directory, not a problem file (a "
                          "partitioned problem folder runs with --engine "
                          "petsc, under mpiexec)")
    if not stat.S_ISREG(mode):
        raise SolverError(f"{path}: not a regular file (a FIFO or device "
                          "cannot be read as a problem)")


def run(args):
    """Run the parsed command line ``args``; return the exit code."""
    signals = [s for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP,
                           getattr(signal, "SIGXFSZ", None)) if s]
    saved = {s: signal.getsignal(s) for s in signals}
    try:
        with warnings.catch_warnings():  # the caller's filters come back
            _setup(args)
            return _guarded(args)
    finally:  # so do the caller's signal handlers
        for signum, handler in saved.items():
            signal.signal(signum, handler)


def _guarded(args):
    state = {"folder": None, "summary": None}
    try:
        try:
            code = _run(args, state)
            sys.stdout.flush()
            return code
        except KeyboardInterrupt:
            raise Interrupted(signal.SIGINT) from None
    except Interrupted as exc:
        for signum in STOP_SIGNALS:
            signal.signal(signum, signal.SIG_IGN)  # finish the marking
        _finish(state, "interrupted", f"interrupted by {exc}")
        print(f"error: interrupted by {exc}"
              + (f"; completed work kept in {state['folder'].path}/"
                 if state["folder"] else ""), file=sys.stderr)
        return 128 + exc.signum
    except SolverError as exc:
        _finish(state, "failed", str(exc), remove=True)
        _report(args, f"error: {_one_line(exc)}")
        return EXIT_INPUT
    except OSError as exc:
        if _is_stdout(exc):
            return _stdout_failed(exc)
        _finish(state, "failed", f"cannot write: {exc}")
        where = f" {exc.filename}" if exc.filename else ""
        _report(args, f"error: cannot write{where}: "
                      f"{_one_line(exc.strerror or exc)}")
        return EXIT_OUTPUT if state["folder"] else EXIT_INPUT
    except Exception as exc:  # a bug: one line, the traceback with --debug
        _finish(state, "failed", f"internal error: {exc!r}")
        _report(args, f"error: internal error: {_one_line(repr(exc))} "
                      "(run with --debug for the traceback and report it)")
        return EXIT_INTERNAL
    finally:
        if state["folder"] is not None:
            state["folder"].release()


def _report(args, line):
    if args.debug:
        traceback.print_exc()
    print(line, file=sys.stderr)


def _is_stdout(exc):
    return isinstance(exc, BrokenPipeError) or getattr(
        exc, "_stdout", False)


def _stdout_failed(exc):
    """Standard output is closed or full: the outputs on disk are complete;
    say so once (not for a closed pipe, as Unix tools) and exit."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())  # no second error at exit
    if isinstance(exc, BrokenPipeError):
        return EXIT_PIPE
    print(f"error: cannot write to standard output: "
          f"{_one_line(exc.strerror or exc)}", file=sys.stderr)
    return EXIT_OUTPUT


def emit(text):
    """Print ``text`` to stdout and flush, marking a failure as stdout's."""
    try:
        print(text)
        sys.stdout.flush()
    except OSError as exc:
        exc._stdout = True
        raise


def _finish(state, status, message, remove=False):
    """Mark an ended run in its summary.json (or, with ``remove`` and
    nothing written yet, take the new folder back)."""
    folder = state["folder"]
    if folder is None:
        return
    folder.sweep_temporaries()
    if remove and not folder.files[1:]:  # only the "running" summary
        try:
            os.unlink(os.path.join(folder.path, "summary.json"))
        except OSError:
            pass
        folder.release(remove_created=True)
        state["folder"] = None
        return
    summary = dict(state["summary"] or {})
    summary.update(getattr(folder, "extra", {}))
    summary.update(status=status, converged=False, message=message)
    try:
        _write_summary(folder, summary)
    except OSError:
        pass  # the "running" summary stays: still marked incomplete


def _write_summary(folder, summary):
    from ..output.files import write_summary

    path = folder.file("summary.json")
    summary["files"] = sorted(  # written completely (not cut short)
        name for name in folder.files if name == "summary.json"
        or os.path.exists(os.path.join(folder.path, name)))
    write_summary(path, summary)


def _run(args, state):
    from ..problem import load_problem

    if os.path.isdir(args.problem) and args.engine == "petsc":
        if args.info or args.plots:  # a partitioned problem (a folder)
            raise SolverError(f"{'--info' if args.info else '--plots'}: "
                              "not for a partitioned problem (a folder); "
                              "run the .npz for it")
    else:
        _check_input_file(args.problem)
    problem = load_problem(args.problem)
    if args.info:  # with what a solve would refuse: exit 2 then
        from .jobs import command_line_message

        if args.search_interval is not None:
            problem.set_search_interval(*args.search_interval)
        info = problem.summary(check=True, gap=args.gap)
        info["refusals"] = [command_line_message(line)  # flags, not API
                            for line in info["refusals"]]
        if args.json:
            emit(json.dumps(info, indent=2, allow_nan=False))
        else:
            from ..output.report import format_summary

            emit(format_summary(info))
        if info["refusals"]:
            raise SolverError("; ".join(info["refusals"]))
        return EXIT_OK
    from .jobs import solve_job

    return solve_job(args, problem, lambda outdir: _open_folder(
        args, problem, state, outdir), emit, lambda summary: _write_summary(
        state["folder"], summary))


def _open_folder(args, problem, state, outdir):
    """Lock and clear the output folder; write the "running" summary."""
    folder = OutputFolder(outdir, inputs=[args.problem])
    state["folder"] = folder
    folder.clear_stale()
    state["summary"] = {"problem": problem.source, "status": "running",
                        "converged": False, "pid": os.getpid(),
                        "argv": sys.argv[1:]}
    _write_summary(folder, dict(state["summary"]))
    return folder

