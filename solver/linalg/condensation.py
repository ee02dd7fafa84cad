r"""K condensed onto the contact DOFs, on any backend's Schur complement.

With c = the DOFs of the free contact nodes and i the others, K u = f + Pᵀr
(r: forces acting on the c DOFs only) is equivalent to

.. math:: S u_c = g̃ + r, \qquad S = K_{cc} − K_{ci}K_{ii}^{-1}K_{ic},
          \quad g̃ = f_c − K_{ci}K_{ii}^{-1}f_i,

the stiffness of the body seen from Γc (its inverse is the Neumann-to-
Dirichlet map). Contact acts only on these DOFs, so the thesis's systems
(67) and (110)/(111) are *exactly* the same with K → S (dense, 2Nc×2Nc)
and f → g̃: one factorisation of K, with its S, serves every Newton
iteration and every load step (Wriggers, *Computational Contact
Mechanics*, 2006, §6.2.2; Dostál, *Optimal Quadratic Programming
Algorithms*, 2009).

K condensed onto a subset k of the DOFs of a condensation made already is
the Schur complement of its S on k (the quotient property of Schur
complements, Crabtree & Haynsworth, Proc. AMS 22 (1969) 364-366),

.. math:: S_k = S_{kk} − S_{ko} S_{oo}^{-1} S_{ok},

o the DOFs dropped: no second factorisation of K when the set shrinks
(the friction candidates within the frictionless screening's,
:mod:`solver.contact.strategies.friction_candidates`)."""

import weakref

import numpy as np

from .base import get_backend, resolve
from .dense import DenseSchur
from .threads import single_blas_thread
from .ordering import dof_ordering

__all__ = ["Condensation", "SubCondensation", "SUBSET_FRACTION"]

_MADE = {}  # id(K) -> the last Condensation of that K (dropped with K)

#: A subset k of a made condensation's DOFs is condensed from its S
#: (module docstring) when the DOFs dropped are at most this fraction of
#: those kept: its dense cost, |o|³/3 + |o|·|k|², then stays below the
#: |k|³ of the friction run's flexibility on k, and far below a
#: factorisation of K with a Schur set.
SUBSET_FRACTION = 0.25


class Condensation:
    r"""K of ``problem`` condensed onto the DOFs ``dofs`` (in the order
    wanted), factorised by ``backend`` (the factorisation checks that K is
    positive definite) or given as ``factorization`` (K factorised with
    ``dofs`` last: the PETSc engine's). Attributes: ``S`` (m, m),
    ``factorization``, ``backend``, ``n_solves`` (solves with K so far)."""

    def __init__(self, problem, dofs, backend="auto", factorization=None):
        self.dofs = np.asarray(dofs, np.int64).ravel()
        if factorization is None:  # K with ``backend``, self.dofs last
            self.backend = resolve(backend)
            module = get_backend(self.backend)
            order = dof_ordering(problem, last=self.dofs) \
                if module.USES_ORDER else None
            factorization = module.factorize(problem.K, order, self.dofs,
                                             "K", True)
        else:  # made elsewhere (the PETSc engine's): ``backend`` names it
            self.backend = backend
        self.factorization = factorization
        self.S = self.factorization.S
        self._solved = []  # up to two recent (f, K⁻¹f)
        self._gram = None  # their loads' Gram matrix
        self.n_solves = 0

    @classmethod
    def of(cls, problem, dofs, backend="auto"):
        """The condensation of ``problem.K`` onto ``dofs``, made once per K
        object, set of DOFs and backend: repeated solves of one problem
        (other methods, gap modes, starts) reuse its factorisation and S.
        Replace ``problem.K`` rather than modify it in place."""
        K, dofs, backend = problem.K, np.asarray(dofs).ravel(), \
            resolve(backend)
        made = _MADE.get(id(K))
        for parent in (made, getattr(made, "parent", None)):
            if parent is None or parent.backend != backend:
                continue
            if np.array_equal(parent.dofs, dofs):
                return parent
            if parent.covers(dofs):  # the Schur complement of its S
                _MADE[id(K)] = made = SubCondensation(parent, dofs)
                return made
        if id(K) not in _MADE:
            weakref.finalize(K, _MADE.pop, id(K), None)
        _MADE[id(K)] = made = cls(problem, dofs, backend)
        return made

    def covers(self, dofs):
        """Whether K condensed onto ``dofs`` is best made from this S: all
        of them among this condensation's DOFs, and at most
        :data:`SUBSET_FRACTION` of those kept dropped."""
        dofs = np.asarray(dofs).ravel()
        dropped = len(self.dofs) - len(dofs)
        return 0 < len(dofs) and 0 <= dropped <= SUBSET_FRACTION * len(dofs) \
            and len(np.unique(dofs)) == len(dofs) \
            and np.isin(dofs, self.dofs).all()

    def load(self, f):
        """(g̃, w): the condensed load g̃ = S (K⁻¹f)_c and w = K⁻¹f; a
        combination a f₁ + b f₂ of the last two loads reuses their solutions
        (proportional loads and piecewise linear load paths cost no solve)."""
        w = self._solution(f)
        return self.S @ w[self.dofs], w

    def _solution(self, f):
        """w = K⁻¹f, from the stored solutions where f is in their span."""
        f = np.asarray(f, dtype=np.float64)
        w = self._combination(f)
        if w is None:
            w = self.factorization.solve(f)
            self.n_solves += 1
            self._solved = (self._solved + [(f.copy(), w)])[-2:]
            self._gram = None
        return w

    def _combination(self, f):
        """K⁻¹f from the stored solutions if f is in their span, else None
        (least squares by the 2×2 normal equations; the residual is then
        checked directly)."""
        loads = [g for g, _ in self._solved]
        if not loads:
            return None
        with single_blas_thread():  # vector ops: threads only wait here
            if self._gram is None:  # the loads' Gram matrix, once per pair
                self._gram = np.array([[a @ b for b in loads]
                                       for a in loads])
            rhs = [a @ f for a in loads]
            try:
                coef = np.linalg.solve(self._gram, rhs)
            except np.linalg.LinAlgError:  # two parallel loads
                coef = np.linalg.lstsq(self._gram, rhs, rcond=None)[0]
            residual = f - sum(c * g for c, g in zip(coef, loads))
            if np.linalg.norm(residual) > 1e-13 * np.linalg.norm(f):
                return None
            return sum(c * v for c, (_, v) in zip(coef, self._solved))

    def displacement(self, u_c, w):
        """The full u with contact DOFs u_c, given w = K⁻¹f from
        :meth:`load`: u = w + (the interior response to u_c − w_c), one
        back-substitution. Several at once: u_c and w of shape (m, k) and
        (n, k), one sweep with k right-hand sides."""
        self.n_solves += 1
        return w + self.factorization.back_substitute(
            None, np.asarray(u_c, float) - w[self.dofs])


class SubCondensation(Condensation):
    r"""K condensed onto ``dofs``, a subset of the DOFs of the condensation
    ``parent``, from its S (module docstring): S = S_kk − S_ko S_oo⁻¹ S_ok
    and, for :meth:`displacement`, X = S_oo⁻¹ S_ok, the response of the
    dropped DOFs o (no force on them) to the kept ones. Loads and
    back-substitutions go through the parent's factorisation."""

    def __init__(self, parent, dofs):
        self.parent = parent
        self.dofs = np.asarray(dofs, np.int64).ravel()
        self.backend, self.factorization = parent.backend, \
            parent.factorization
        position = np.full(int(parent.dofs.max()) + 1, -1)
        position[parent.dofs] = np.arange(len(parent.dofs))
        self.keep = position[self.dofs]
        dropped = np.ones(len(parent.dofs), bool)
        dropped[self.keep] = False
        self.drop = np.flatnonzero(dropped)
        S, k, o = parent.S, self.keep, self.drop
        if len(o):  # X = S_oo⁻¹S_ok as L⁻ᵀW (DenseSchur)
            self.schur = DenseSchur(S, k, o)
            self.S = self.schur.S
        else:  # the same DOFs in another order
            self.schur, self.S = None, S[np.ix_(k, k)]
        self._solved, self._gram = [], None
        self.n_solves = 0

    def load(self, f):
        """(g̃, w) as :meth:`Condensation.load`, through the parent (its
        stored solutions shared)."""
        w = self.parent._solution(f)
        return self.S @ w[self.dofs], w

    def displacement(self, u_c, w):
        """u with u_c on the kept DOFs: the dropped ones at w_o −
        X (u_c − w_k), then the parent's back-substitution."""
        self.n_solves += 1
        u_c = np.asarray(u_c, float)
        full = np.empty((len(self.parent.dofs),) + u_c.shape[1:])
        full[self.keep] = u_c
        if not len(self.drop):
            full[self.keep] = u_c
            return self.parent.displacement(full, w)
        full[self.drop] = w[self.parent.dofs[self.drop]] \
            - self.schur.response(u_c - w[self.dofs])
        return self.parent.displacement(full, w)
