r"""The one interface of the sparse direct solvers, and the choice of one.

A backend module (:mod:`~solver.linalg.superlu`, :mod:`~solver.linalg.pardiso`,
:mod:`~solver.linalg.cholmod`) has ``NAME``, ``EXTRA`` (its pip extra),
``LICENCE``, ``USES_ORDER`` (whether it takes our fill-reducing order),
``available()`` and ``factorize(A, order=None, schur=None, name="K",
check=True)``, which returns a :class:`Factor` of the SPD A: solves
A x = b and, factorised with ``schur=c``, gives the Schur complement

.. math:: S = A_{cc} − A_{ci} A_{ii}^{-1} A_{ic}  \quad (dense, m×m),

the condensed right-hand side g̃ = b_c − A_ci A_ii⁻¹ b_i and the
back-substitution u_i = A_ii⁻¹(b_i − A_ic u_c). Positive definiteness is
checked from the pivots of the factorisation (Sylvester's law of inertia,
:func:`check_pivots`). ``auto`` (:func:`resolve`) takes the first
installed of :data:`AUTO_ORDER`: PARDISO (S inside the factorisation, the
fastest), CHOLMOD, SuperLU (no extra dependency); nothing is timed at run
time."""

import importlib

import numpy as np

from ..errors import ProblemError, SolverError

__all__ = ["PIVOT_RTOL", "BACKENDS", "ITERATIVE", "AUTO_ORDER", "Factor",
           "check_pivots",
           "available_backends", "get_backend", "resolve", "factorize"]

#: A pivot below this fraction of the largest counts as zero.
PIVOT_RTOL = 1e-10

#: Every backend, by name (module ``solver.linalg.<name>``).
BACKENDS = ("superlu", "pardiso", "cholmod")

#: The iterative path, by name (:mod:`solver.linalg.amg`; no factorisation,
#: so not a backend of :func:`factorize`).
ITERATIVE = ("amg",)

#: ``auto`` picks the first installed of these (fastest first).
AUTO_ORDER = ("pardiso", "cholmod", "superlu")


def check_pivots(pivots, name="K"):
    """Raise :class:`ProblemError` unless every LDLᵀ pivot is positive and
    above :data:`PIVOT_RTOL` of the largest. For a positive definite A every
    pivot is at least λ_min(A); a body without supports gives pivots of
    round-off size (~1e-14 of the largest, one per rigid body mode)."""
    key = f"{name}_data"
    singular = not_positive_definite(name, singular=True)
    pivots = np.asarray(pivots, float)
    if not np.isfinite(pivots).all() or pivots.max(initial=0.0) <= 0:
        raise ProblemError(f"{key}: {name} is not positive definite (its "
                           "LDLᵀ factorisation has no positive pivot)")
    ratio = pivots.min() / pivots.max()
    if ratio < -PIVOT_RTOL:
        negative = int(np.count_nonzero(pivots < -PIVOT_RTOL * pivots.max()))
        raise ProblemError(f"{key}: {name} is not positive definite: it has "
                           f"{negative} negative eigenvalue(s) (LDLᵀ pivot "
                           f"ratio {ratio:.2g})")
    if ratio <= PIVOT_RTOL:
        small = int(np.count_nonzero(pivots <= PIVOT_RTOL * pivots.max()))
        raise ProblemError(f"{key}: {singular}: {small} pivot(s) of its LDLᵀ "
                           f"factorisation at round-off level ({ratio:.2g} "
                           "of the largest)")


def not_positive_definite(name="K", singular=False):
    """The start of the refusal message for A = ``name``."""
    if not singular:
        return f"{name} is not positive definite"
    return (f"{name} is not positive definite (singular " +
            ("stiffness: is the body supported?)" if name == "K"
             else "matrix)"))


class Factor:
    """A factorisation of an SPD matrix (module docstring): ``backend``,
    ``n``, ``nnz`` (factor nonzeros or None), ``schur_dofs`` (c or None), ``S``
    (the dense Schur complement on c, or None). Subclasses implement
    :meth:`solve`; the Schur methods below use only ``solve`` and ``S``."""

    backend = None
    nnz = None
    schur_dofs = S = None

    def solve(self, b):
        """A⁻¹b for b of shape (n,) or (n, k)."""
        raise NotImplementedError

    def condensed_rhs(self, b):
        """g̃ = b_c − A_ci A_ii⁻¹ b_i = S (A⁻¹b)_c, shape (m,) or (m, k)."""
        return self.S @ self.solve(b)[self.schur_dofs]

    def back_substitute(self, b, u_c):
        """u with u_c on c and A_ii u_i = b_i − A_ic u_c:
        u = A⁻¹(b + Pᵀ S (u_c − (A⁻¹b)_c)); b = 0 costs one solve."""
        c = self.schur_dofs
        u_c = np.asarray(u_c, float)
        if b is None or not np.any(b):
            r = np.zeros((self.n,) + u_c.shape[1:])
            r[c] = self.S @ u_c
            return self.solve(r)
        x = self.solve(b)
        r = np.zeros_like(x)
        r[c] = self.S @ (u_c - x[c])
        return x + self.solve(r)


def _module(name):
    return importlib.import_module(f"{__package__}.{name}")


def available_backends():
    """The names of the installed backends, in :data:`AUTO_ORDER`."""
    return [name for name in AUTO_ORDER if _module(name).available()]


def get_backend(name):
    """The backend module ``name`` (not "auto"); :class:`SolverError`
    naming the pip extra if it is unknown or not installed."""
    if name not in BACKENDS:
        raise SolverError(f"linear solver must be one of "
                          f"{('auto',) + BACKENDS}, got {name!r}")
    module = _module(name)
    if not module.available():
        raise SolverError(f"linear solver {name!r} is not installed: "
                          f"pip install 'contact-ssn[{module.EXTRA}]' "
                          f"({module.REQUIRES})")
    return module


def resolve(name="auto"):
    """The backend name that ``name`` stands for ("auto" → the first
    installed of :data:`AUTO_ORDER`)."""
    if name in (None, "auto"):
        return available_backends()[0]
    return get_backend(name).NAME


def factorize(A, order=None, schur=None, name="K", check=True,
              backend="auto"):
    """Factorise the SPD matrix A with ``backend`` (see the module)."""
    return get_backend(resolve(backend)).factorize(A, order, schur, name,
                                                   check)
