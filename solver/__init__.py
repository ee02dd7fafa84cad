"""Contact of a 2D elastic body with a rigid obstacle, by semismooth Newton.

A Python reproduction of the bachelor thesis "Numerical solution of the
contact problem of elastic bodies" (Plzeň, 2017). The finite element model
(K, f, M) is exported by the SfePy problem files in ``sfepy_problems/`` to an
``.npz`` file (:mod:`solver.problem`); this package reads it and never
imports SfePy.

Public API
----------
solve
    Every contact problem (:mod:`solver.front`): 2D or 3D, a rigid
    obstacle or two elastic bodies, frictionless (thesis (67)) or Coulomb
    friction in load steps (§5), on the serial or the PETSc engine.
    ``solve_frictionless``, ``solve_friction`` and ``solve_two_body`` are
    the same front under their earlier names.
ContactResult
    What :func:`solve` returns (a ``scipy.optimize.OptimizeResult``).
load_problem, save_problem, ContactProblem, FORMAT_VERSION
    The ``.npz`` problem format (:mod:`solver.problem`).
ParametricCurve, parse_expression
    Rigid obstacles given by safe expressions in t
    (:mod:`solver.geometry.curves.parametric`).
two_dof_bar
    The thesis's §6 two-DOF bar system (:mod:`solver.examples`).
contact_geometry
    Gaps and per-node frames of a problem (:mod:`solver.contact.geometry`).
solve_ncp, DEFAULT_OPTIONS
    Semismooth Newton methods for mixed NCPs, FE-free (:mod:`solver.ncp`),
    and their default options.
support_table
    What works where: the combinations :func:`solve` refuses.
SolverError, ProblemError, ExpressionError, GapError
    Errors caused by bad input (:mod:`solver.errors`).
"""

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
