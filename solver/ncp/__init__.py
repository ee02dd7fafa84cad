"""Nonlinear complementarity problems: NCP functions and semismooth Newton.

Nothing here knows about finite elements: the methods take residual and
Jacobian callables. See :func:`solve_ncp`."""

from .functions import NCP_FUNCTIONS, derivative_weights, phi
from .newton import DEFAULT_OPTIONS, MESSAGES, solve_ncp, stable_norm

__all__ = ["solve_ncp", "phi", "derivative_weights", "NCP_FUNCTIONS",
           "MESSAGES", "DEFAULT_OPTIONS", "stable_norm"]
