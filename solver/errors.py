"""Exceptions raised by the :mod:`solver` package.

All errors a user can cause by bad input derive from :class:`SolverError`, so
that the command line can turn them into a one-line message and exit code 2
instead of a traceback.
"""

__all__ = ["SolverError", "ProblemError", "ExpressionError"]


class SolverError(Exception):
    """Base class of every error caused by the user's input."""


class ProblemError(SolverError, ValueError):
    """A problem file (``.npz``) or a problem object is malformed.

    The message starts with the offending key, e.g.
    ``"K_indices: index 12 out of range [0, 10)"``.
    """


class ExpressionError(ProblemError):
    """An obstacle expression is malformed or uses something not allowed."""
