r"""The PETSc engine's condensations, with the interfaces of
:class:`solver.linalg.Condensation` (:class:`PetscCondensation`) and
:class:`solver.contact.strategies.candidates.NormalCondensation`
(:class:`PetscNormalCondensation`) on one distributed MUMPS factorisation
in its Schur mode, so that the serial drivers and strategies run
unchanged on them."""

import numpy as np

from ..contact.geometry import rotate_stiffness, rotation
from ..linalg import Condensation
from .factor import SCHUR_BLOCK, PetscFactor

__all__ = ["PetscCondensation", "PetscNormalCondensation"]


class PetscCondensation(Condensation):
    """:class:`~solver.linalg.Condensation` of ``problem.K`` (or of
    ``stiffness``: a matrix of its size, or a function returning one, held
    only while padded) onto ``dofs`` whose factorisation is a
    :class:`PetscFactor` (all ranks); ``load`` and ``displacement`` are
    Condensation's own."""

    def __init__(self, svc, layout, problem, dofs,
                 stiffness=None):  # noqa: D107
        dofs = np.asarray(dofs, np.int64).ravel()
        A = problem.K if stiffness is None else stiffness
        super().__init__(problem, dofs, "petsc-mumps",
                         PetscFactor(svc, layout, A, dofs))


class PetscNormalCondensation:
    """:class:`solver.contact.strategies.candidates.NormalCondensation`'s
    interface on one distributed MUMPS factor: K̂ = RKRᵀ is built and
    scattered once (:meth:`rotated`); each round's candidate set is a new
    Schur-mode factorisation (``block`` None) or only new solves (``block``
    = k)."""

    def __init__(self, svc, layout, problem, geometry, block=SCHUR_BLOCK):
        self.svc, self.layout, self.block = svc, layout, block
        self.R = rotation(problem.n_dofs, geometry)[0]
        self.problem = problem
        self.f = self.R @ problem.f
        self.normal_rows = geometry.dofs[:, -1]
        self.free_dofs = geometry.free_dofs()
        self.factor, self.nodes = None, None

    def rotated(self):
        """K̂ = RKRᵀ (:func:`~solver.contact.geometry.rotate_stiffness`;
        built when scattered: rank 0 holds it only while padding, not
        under MUMPS's factor)."""
        K = rotate_stiffness(self.problem.K, self.R, self.free_dofs)
        self.svc.mark("rotate")
        return K

    def factorize(self, nodes):
        """(S, g̃, w_c) on the normal rows c of ``nodes``, w = K̂⁻¹f̂: g̃ from
        one interior solve of the Schur-mode factor, w_c = S⁻¹g̃ (w itself
        never formed: :meth:`displacement` back-substitutes with f̂)."""
        self.nodes = np.asarray(nodes, np.int64)
        c = self.normal_rows[self.nodes]
        if self.factor is None:
            self.factor = PetscFactor(self.svc, self.layout, self.rotated,
                                      c, block=self.block)
        else:
            self.factor.schur(c)
        S = self.factor.S
        if not len(c):
            self.w = self.factor.solve(self.f)
            return S, np.zeros(0), np.zeros(0)
        g = self.factor.condensed_rhs(self.f)
        return S, g, self.factor.solve_schur(g)

    def displacement(self, u_n):
        """(u, u_n at every free contact node): one back-substitution."""
        c = self.normal_rows[self.nodes]
        u_hat = self.w if not len(c) else self.factor.back_substitute(
            self.f, np.asarray(u_n, float))
        return self.R.T @ u_hat, u_hat[self.normal_rows]
