"""Two bodies' frictionless candidates condensed from K's own factor
(solver.contact.strategies.bordered, solver.linalg.pardiso.BorderedFactor)
against independent computations: B K⁻¹ Bᵀ and K⁻¹(b − Bᵀμ) against
SciPy's SuperLU of K, and the condensed S, g̃, w_c and the displacements
against the factorisation of the glued K̂ = RK̃Rᵀ with the Schur set
(strategies.candidates.NormalCondensation, the path it replaces) on the
non-matching stacked boxes of the 3D patch test."""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from solver.contact import TwoBodyMap, contact_geometry
from solver.contact.engine import SerialEngine
from solver.contact.strategies.bordered import BorderedCondensation
from solver.contact.strategies.candidates import NormalCondensation
from solver.errors import ProblemError
from solver.linalg import pardiso
from tet_two_body import stacked_boxes

pytestmark = pytest.mark.skipif(not pardiso.available(),
                                reason="PARDISO (mkl) not installed")


def test_bordered_factor_against_superlu():
    """C = B K⁻¹ Bᵀ, K⁻¹b and K⁻¹(b − Bᵀμ) to 1e-12 (relative) on the
    stacked boxes' K, B 30 random sparse rows."""
    problem, _, _ = stacked_boxes()
    K = problem.K.tocsc()
    n = K.shape[0]
    B = sp.random(30, n, density=0.05, random_state=2, format="csr")
    factor = pardiso.factorize_bordered(K, B)
    lu = sla.splu(K)
    C = B @ lu.solve(B.T.toarray())
    assert np.abs(factor.C - C).max() <= 1e-12 * np.abs(C).max()
    rng = np.random.default_rng(0)
    b, mu = rng.standard_normal(n), rng.standard_normal(30)
    for x, exact in ((factor.solve(b), lu.solve(b)),
                     (factor.solve(b, mu), lu.solve(b - B.T @ mu))):
        assert np.abs(x - exact).max() <= 1e-12 * np.abs(exact).max()


def test_bordered_factor_refuses_an_indefinite_K():
    """A K with a negative pivot: the one-line ProblemError of every
    backend, not a wrong C."""
    K = sp.diags([2.0, 1.0, -1.0, 3.0]).tocsr()
    B = sp.csr_matrix(np.array([[1.0, 0, 0, 1.0]]))
    with pytest.raises(ProblemError, match="not positive definite"):
        pardiso.factorize_bordered(K, B)


def _nodewise(slave="upper"):
    problem, _, _ = stacked_boxes(slave=slave)
    mapping = TwoBodyMap(problem)
    equivalent = mapping.equivalent
    return problem, equivalent, contact_geometry(equivalent, "obstacle",
                                                 rollers=True)


@pytest.mark.parametrize("slave", ["upper", "lower"])
def test_same_condensation_as_the_glued_factor(slave):
    """Every other slave node a candidate: S, g̃ = S w_c, w_c, and v and
    the normal displacements from the same candidates' u_n, equal to the
    glued K̂'s to 1e-10 (relative)."""
    _, equivalent, geometry = _nodewise(slave)
    nodes = np.arange(0, len(geometry.gap), 2)
    glued = NormalCondensation(equivalent, geometry, "pardiso")
    bordered = BorderedCondensation(equivalent, geometry, "pardiso")
    u_n = np.random.default_rng(1).standard_normal(len(nodes)) * 1e-3
    for a, b in zip(glued.factorize(nodes), bordered.factorize(nodes)):
        assert np.abs(a - b).max() <= 1e-10 * np.abs(a).max()
    for a, b in zip(glued.displacement(u_n), bordered.displacement(u_n)):
        assert np.abs(a - b).max() <= 1e-10 * np.abs(a).max()


def test_the_engine_chooses_it_for_two_bodies_on_pardiso():
    """PARDISO: the bordered condensation; CHOLMOD (no bordered factor) and
    a body held by contact only (K singular): the glued K̂."""
    _, equivalent, geometry = _nodewise()
    assert isinstance(SerialEngine("pardiso").normal_condensation(
        equivalent, geometry), BorderedCondensation)
    assert isinstance(SerialEngine("cholmod").normal_condensation(
        equivalent, geometry), NormalCondensation)
    floating, _, _ = stacked_boxes(pressure=1e-3)
    held = TwoBodyMap(floating).equivalent
    assert getattr(held, "change_of_variables", None) is None
