"""Exceptions and warnings of the :mod:`solver` package.

All errors a user can cause by bad input derive from :class:`SolverError`, so
that the command line can turn them into a one-line message and exit code 2
instead of a traceback. Warnings about questionable but solvable input
derive from :class:`SolverWarning`; library code never prints, it warns.
:data:`STOP_SIGNALS` are the signals that stop the command line (exit
128 + the signal, solver/cli/codes.py) and that the converter holds
while it makes a temporary folder."""

import signal

__all__ = ["SolverError", "ProblemError", "ExpressionError",
           "GeometryError", "SolverWarning", "InitialPenetrationWarning",
           "STOP_SIGNALS"]

#: The signals that stop a run or a conversion (exit code 128 + the
#: signal's number).
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


class SolverError(Exception):
    """Base class of every error caused by the user's input."""


class ProblemError(SolverError, ValueError):
    """A problem file (``.npz``) or a problem object is malformed; the
    message starts with the offending key, e.g. ``"K_indices: index 12 out of
    range [0, 10)"``."""


class ExpressionError(ProblemError):
    """An obstacle expression is malformed or uses something not allowed."""


class GeometryError(ProblemError):
    """The contact geometry is degenerate: a contact boundary of one node,
    coincident contact nodes, a zero-area triangle on Γc, coordinates out of
    the range double precision can resolve. The message names the nodes."""


class SolverWarning(UserWarning):
    """Base class of the warnings about questionable but solvable input."""


class InitialPenetrationWarning(SolverWarning):
    """The obstacle already penetrates the undeformed body (negative initial
    gaps, thesis §2.1: allowed, but rarely what a problem meant); the message
    names the nodes and the deepest penetration."""


class PenetrationWarning(SolverWarning):
    """A node of Γc that took no part in contact (a support: its
    displacement is prescribed) penetrates the obstacle at the answer. The
    solver cannot move it; the message names the nodes and the depth."""


class WeaklyHeldWarning(SolverWarning):
    """A rigid-body motion of a body held by contact only moves its contact
    nodes almost only along the contact surface (a round body spinning on
    a round body without friction): the contact normals see it through
    the mesh's facets alone, so the answer's share along it is set by the
    discretisation. Raised before solving; the message names the motion
    and says how to hold it (:func:`solver.problem.rigid.weakly_held`)."""


class KinematicsWarning(SolverWarning):
    """The answer breaks an assumption of the geometrically linear model
    (:mod:`solver.contact.kinematics`): sliding of more than one element
    of Γc along a curved obstacle, or an initial overlap larger than a tenth
    of the body; the message says which and where."""
