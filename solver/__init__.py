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
    Rigid obstacles given by safe expressions in t (:mod:`solver.geometry.curves.parametric`).
two_dof_bar
    The thesis's §6 two-DOF bar system (:mod:`solver.examples`).
solve_frictionless, contact_geometry
    Frictionless contact, thesis (67) (:mod:`solver.contact`), condensed
    onto Γc with a nested start (:mod:`solver.contact.strategies.nested`) or in all
    unknowns as in the thesis.
solve_friction
    Coulomb friction by load steps, thesis (110)/(111) and a projection
    formulation (:mod:`solver.contact.friction.driver`).
solve_ncp
    Semismooth Newton methods for mixed NCPs, FE-free (:mod:`solver.ncp`).
Factorization, Condensation, nested_dissection
    One LDLᵀ factorisation of K per solve, condensation onto Γc
    (:mod:`solver.linalg`).
SolverError, ProblemError, ExpressionError, GapError
    Errors caused by bad input (:mod:`solver.errors`, :mod:`solver.geometry.curves`).
"""

from .errors import ExpressionError, ProblemError, SolverError
from .geometry.curves import GapError
from .contact import contact_geometry, solve_friction, solve_frictionless
from .examples import two_dof_bar
from .ncp import solve_ncp
from .geometry.curves.parametric import ParametricCurve, parse_expression
from .problem import (FORMAT_VERSION, ContactProblem, load_problem,
                      save_problem)

__version__ = "0.1.0"

__all__ = ["FORMAT_VERSION", "ContactProblem", "load_problem",
           "save_problem", "ParametricCurve", "parse_expression",
           "two_dof_bar", "solve_frictionless", "solve_friction", "contact_geometry",
           "solve_ncp", "SolverError", "ProblemError", "ExpressionError", "GapError",
           "__version__"]
