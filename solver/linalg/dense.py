"""Dense factorisations of the Newton systems on a contact zone.

The condensed Newton systems (:mod:`solver.contact.frictionless.newton`,
:mod:`solver.contact.friction.newton`) are dense, of the size of the
contact zone: LAPACK's Cholesky where the matrix is symmetric positive
definite (the primal-dual active set structure makes it so for φ_min and
φ_FB with the lagged bound), else its LU."""

import warnings

import numpy as np
import scipy.linalg as sla

__all__ = ["factorize"]


def factorize(A, symmetric):
    """Cholesky of A if ``symmetric`` and it is positive definite, else LU;
    None if A is (numerically) singular. Returns a solve callable."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sla.LinAlgWarning)
        if symmetric:
            try:
                factor = sla.cho_factor(A, check_finite=False)
                return lambda b: sla.cho_solve(factor, b,
                                               check_finite=False)
            except np.linalg.LinAlgError:
                pass
        lu, piv = sla.lu_factor(A, check_finite=False)
        if not np.all(np.diagonal(lu)):
            return None
        return lambda b: sla.lu_solve((lu, piv), b, check_finite=False)
