r"""The Newton direction: J d = −Φ by SuperLU for a sparse J, by LAPACK
for a dense one (a system condensed onto Γc: at most the size of its Schur
complement), or by a structured Jacobian's own ``direction``
(:mod:`solver.contact.friction.newton`); None when J is singular."""

import warnings

import numpy as np
import scipy.linalg as sla_dense
import scipy.sparse as sp
import scipy.sparse.linalg as sla

__all__ = ["DENSE_FRACTION", "DENSE_MIN_SIZE", "newton_direction"]

#: Jacobians with more than this fraction of nonzeros (and at least
#: DENSE_MIN_SIZE rows: those of the condensed systems) are factorised by
#: LAPACK, several times faster than SuperLU on dense blocks.
DENSE_FRACTION = 0.2
DENSE_MIN_SIZE = 64


def newton_direction(J, F):
    """Solve J d = −F (SuperLU, or LAPACK for a dense J, or the
    structured Jacobian's own ``direction``); None if J is (numerically)
    singular."""
    if hasattr(J, "direction"):
        return J.direction(F)
    n = J.shape[0]
    dense = isinstance(J, np.ndarray)
    nnz = np.count_nonzero(J) if dense else J.nnz
    if n >= DENSE_MIN_SIZE and nnz > DENSE_FRACTION * n * n:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", sla_dense.LinAlgWarning)
            lu, piv = sla_dense.lu_factor(J if dense else J.toarray(),
                                          overwrite_a=dense,
                                          check_finite=False)
            if not np.all(np.diagonal(lu)):
                return None
            d = sla_dense.lu_solve((lu, piv), -F, check_finite=False)
    else:
        try:
            d = sla.splu(sp.csc_matrix(J) if dense else J).solve(-F)
        except RuntimeError:  # "Factor is exactly singular"
            return None
    return d if np.all(np.isfinite(d)) else None
