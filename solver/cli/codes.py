"""The command line's exit codes and limits, in one place for the parser
(whose ``--help`` ends with :data:`EXIT_CODES_TEXT`), the run and the
job."""

import signal

__all__ = ["EXIT_OK", "EXIT_INTERNAL", "EXIT_INPUT", "EXIT_NOT_CONVERGED",
           "EXIT_OUTPUT", "EXIT_PIPE", "MAX_STEPS", "MAX_ITER", "MIN_TOL",
           "EXIT_CODES_TEXT"]

EXIT_OK, EXIT_INTERNAL, EXIT_INPUT, EXIT_NOT_CONVERGED, EXIT_OUTPUT = \
    0, 1, 2, 3, 4
EXIT_PIPE = 128 + signal.SIGPIPE
MAX_STEPS, MAX_ITER, MIN_TOL = 100_000, 100_000, 1e-15

EXIT_CODES_TEXT = """exit codes:
  0    converged (or --info printed)
  1    internal error (a bug: please report it with --debug's output)
  2    bad input or usage: nothing written
  3    not converged: outputs written, summary.json "status": "not_converged"
  4    an output could not be written (disk full, permission, stdout)
  130  interrupted (Ctrl-C; 143 SIGTERM, 129 SIGHUP): completed work kept,
       summary.json "status": "interrupted"
  141  standard output closed early"""
