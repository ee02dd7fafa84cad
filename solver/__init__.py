"""Contact of elastic bodies with a rigid obstacle or with each other,
by semismooth Newton.

A Python reproduction of the bachelor thesis "Numerical solution of the
contact problem of elastic bodies" (Plzeň, 2017). The finite element model
(K, f, M) is exported by the SfePy problem files in ``sfepy_problems/`` to
an ``.npz`` file (:mod:`solver.problem`); this package reads it and never
imports SfePy. The entry point is :func:`solve` (:mod:`solver.front`;
``solve_frictionless``, ``solve_friction`` and ``solve_two_body`` are it
under earlier names); ``__all__`` lists the rest of the public API."""

from .errors import ExpressionError, ProblemError, SolverError
from .geometry.curves import GapError
from .contact import ContactResult, contact_geometry
from .examples import two_dof_bar
from .front import (solve, solve_friction, solve_frictionless,
                    solve_two_body, support_table)
from .ncp import DEFAULT_OPTIONS, solve_ncp
from .geometry.curves.parametric import ParametricCurve, parse_expression
from .problem import (FORMAT_VERSION, ContactProblem, load_problem,
                      save_problem)
from .version import __version__


__all__ = ["solve", "ContactResult", "FORMAT_VERSION", "ContactProblem",
           "load_problem", "save_problem", "ParametricCurve",
           "parse_expression", "two_dof_bar", "solve_frictionless",
           "solve_friction", "solve_two_body", "contact_geometry",
           "solve_ncp", "DEFAULT_OPTIONS", "support_table", "SolverError",
           "ProblemError", "ExpressionError", "GapError", "__version__"]
