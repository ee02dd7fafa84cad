"""Sparse direct linear algebra for the contact solvers.

One factorisation of the stiffness matrix K serves a whole contact solve,
through one interface (:mod:`solver.linalg.base`: factorise with a
positive-definiteness check, solve, Schur complement on an index set) and
three backends, each its own module: :mod:`~solver.linalg.superlu` (SciPy,
always there), :mod:`~solver.linalg.pardiso` (oneMKL, ``pip install
'.[mkl]'``) and :mod:`~solver.linalg.cholmod` (SuiteSparse via kvxopt,
``pip install '.[cholmod]'``). :func:`resolve` says which one "auto" takes.
:mod:`~solver.linalg.ordering` holds the fill-reducing orderings,
:mod:`~solver.linalg.condensation` condenses K onto Γc and
:mod:`~solver.linalg.cholmod_struct` reads CHOLMOD's factor in place.
"""

from .base import (AUTO_ORDER, BACKENDS, PIVOT_RTOL, Factor,
                   available_backends, check_pivots, factorize, get_backend,
                   resolve)
from .condensation import Condensation
from .ordering import LEAF_SIZE, dof_ordering, nested_dissection
from .superlu import Factorization

__all__ = ["PIVOT_RTOL", "BACKENDS", "AUTO_ORDER", "Factor", "factorize",
           "available_backends", "get_backend", "resolve", "check_pivots",
           "LEAF_SIZE", "nested_dissection", "dof_ordering", "Factorization",
           "Condensation"]
