"""Sparse direct linear algebra for the contact solvers: one interface
(:mod:`.base`: factorise with a positive-definiteness check, solve, Schur
complement on an index set) over three backends (:mod:`.superlu`,
:mod:`.pardiso`, :mod:`.cholmod`), the fill-reducing orderings
(:mod:`.ordering`), the condensation onto Γc (:mod:`.condensation`) and
the dense factorisations of the Newton systems (:mod:`.dense`); beside
them the iterative path, algebraic multigrid for K (:mod:`.amg`)."""

from .base import (AUTO_ORDER, BACKENDS, ITERATIVE, PIVOT_RTOL, Factor,
                   available_backends, check_pivots, factorize, get_backend,
                   resolve)
from .condensation import Condensation, SubCondensation
from .ordering import LEAF_SIZE, dof_ordering, nested_dissection
from .superlu import Factorization

__all__ = ["PIVOT_RTOL", "BACKENDS", "ITERATIVE", "AUTO_ORDER", "Factor",
           "factorize",
           "available_backends", "get_backend", "resolve", "check_pivots",
           "LEAF_SIZE", "nested_dissection", "dof_ordering", "Factorization",
           "Condensation", "SubCondensation"]
