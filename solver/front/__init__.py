"""The public front: :func:`solve` for every case (:mod:`.solve`) and the
table of what works where (:mod:`.cases`)."""

from .cases import Case, RULES, support_table
from .solve import (ConvertedPlan, Plan, make_engine, prepare, solve, solve_friction,
                    solve_frictionless, solve_two_body)

__all__ = ["solve", "prepare", "Plan", "ConvertedPlan", "solve_frictionless", "solve_friction",
           "solve_two_body", "make_engine", "Case", "RULES",
           "support_table"]
