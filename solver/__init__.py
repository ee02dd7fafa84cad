"""Contact of a 2D elastic body with a rigid obstacle, by semismooth Newton.

A Python reproduction of the bachelor thesis "Numerical solution of the
contact problem of elastic bodies" (Plzeň, 2017). The finite element model
(K, f, M) is exported by the SfePy problem files in ``sfepy_problems/`` to an
``.npz`` file (:mod:`solver.problem`); this package reads it and never
imports SfePy.

Public API
----------
load_problem, save_problem, ContactProblem, FORMAT_VERSION
    The ``.npz`` problem format (:mod:`solver.problem`).
ParametricCurve, parse_expression
    Rigid obstacles given by safe expressions in t (:mod:`solver.obstacle`).
two_dof_bar
    The thesis's §6 two-DOF bar system (:mod:`solver.examples`).
SolverError, ProblemError, ExpressionError
    Errors caused by bad input (:mod:`solver.errors`).
"""

from .errors import ExpressionError, ProblemError, SolverError
from .examples import two_dof_bar
from .obstacle import ParametricCurve, parse_expression
from .problem import (FORMAT_VERSION, ContactProblem, load_problem,
                      save_problem)

__version__ = "0.1.0"

__all__ = ["FORMAT_VERSION", "ContactProblem", "load_problem",
           "save_problem", "ParametricCurve", "parse_expression",
           "two_dof_bar", "SolverError", "ProblemError", "ExpressionError",
           "__version__"]
