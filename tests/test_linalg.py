"""solver.linalg: nested dissection, the LDLᵀ factorisation, condensation
onto Γc, and the condensed contact solves against the full systems."""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from solver import load_problem, solve_friction, solve_frictionless
from solver.contact import contact_geometry
from solver.errors import ProblemError
from solver.linalg import (Condensation, Factorization, dof_ordering,
                           nested_dissection)


@pytest.fixture(scope="module")
def refined(refined_block):
    """The 1878 block refined once (7668 DOFs), exported by SfePy."""
    return refined_block(1)


def grid(n):
    """Nodes and edges of an n×n grid graph."""
    x, y = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    points = np.column_stack([x.ravel(), y.ravel()]).astype(float)
    ids = np.arange(n * n).reshape(n, n)
    edges = np.concatenate([
        np.column_stack([ids[:-1].ravel(), ids[1:].ravel()]),
        np.column_stack([ids[:, :-1].ravel(), ids[:, 1:].ravel()])])
    return points, edges


def laplacian(n_nodes, edges):
    i, j = edges.T
    A = sp.coo_matrix((np.full(len(i), -1.0), (i, j)),
                      shape=(n_nodes, n_nodes))
    A = (A + A.T).tocsr()
    return (A + sp.diags(-np.asarray(A.sum(axis=1)).ravel() + 0.1)).tocsc()


def test_nested_dissection_is_a_permutation_with_separators_last():
    points, edges = grid(40)
    order = nested_dissection(points, edges, leaf=16)
    assert np.array_equal(np.sort(order), np.arange(len(points)))
    # the first bisection of the 40×40 square cuts it in two halves of 20
    # columns or rows; its separator (a line of 40 nodes) is ordered last
    last = points[order[-40:]]
    assert len(np.unique(last[:, 0])) == 1 or len(np.unique(last[:, 1])) == 1


def test_nested_dissection_ignores_repeated_edges_and_loops():
    """Mesh cells list each interior edge twice (once per triangle), in
    either direction: the order depends on the graph only."""
    points, edges = grid(30)
    n = len(points)
    noisy = np.concatenate([edges, edges[:, ::-1], edges,
                            np.column_stack([np.arange(n), np.arange(n)])])
    np.random.default_rng(1).shuffle(noisy)
    for leaf in (1, 4, 16):
        assert np.array_equal(nested_dissection(points, noisy, leaf),
                              nested_dissection(points, edges, leaf))


def test_nested_dissection_fill_beats_natural_and_rcm():
    """Fill of the 5-point Laplacian on a 60×60 grid: nested dissection
    needs fewer factor nonzeros than the natural (banded) order and than
    reverse Cuthill-McKee (the George 1973 result, O(n log n) vs n^1.5)."""
    points, edges = grid(60)
    A = laplacian(len(points), edges)

    def fill(order):
        lu = sla.splu(A[order][:, order].tocsc(), permc_spec="NATURAL",
                      diag_pivot_thresh=0.0, options={"SymmetricMode": True})
        return lu.nnz

    import scipy.sparse.csgraph as csgraph
    nd = fill(nested_dissection(points, edges))
    assert nd < 0.7 * fill(np.arange(len(points)))
    assert nd < 0.7 * fill(csgraph.reverse_cuthill_mckee(A, True))


def test_block_ordering_fill_beats_colamd(refined):
    """On the refined thesis block, our ordering needs fewer factor
    nonzeros than SciPy's default (SuperLU's COLAMD): the reason it is
    the project's linear solver (benchmarks/ measures the time)."""
    ours = Factorization(refined.K, dof_ordering(refined)).nnz
    colamd = sla.splu(refined.K.tocsc()).nnz
    assert ours < colamd


def test_factorization_solves_and_keeps_last_dofs_last(refined):
    geometry = contact_geometry(refined)
    last = geometry.dofs.ravel()
    order = dof_ordering(refined, last=last)
    assert np.array_equal(np.sort(order), np.arange(refined.n_dofs))
    assert np.array_equal(order[-len(last):], last)
    factorization = Factorization(refined.K, order)
    reference = sla.spsolve(refined.K.tocsc(), refined.f)
    u = factorization.solve(refined.f)
    np.testing.assert_allclose(u, reference, rtol=0,
                               atol=1e-10 * np.abs(reference).max())
    # several right-hand sides at once
    B = np.column_stack([refined.f, 2 * refined.f])
    np.testing.assert_allclose(factorization.solve(B)[:, 1], 2 * u,
                               rtol=0, atol=1e-10 * np.abs(u).max())


@pytest.mark.parametrize("matrix, message", [
    (np.array([[1.0, 2.0], [2.0, 1.0]]), "negative eigenvalue"),
    (np.array([[1.0, 1.0], [1.0, 1.0]]), "not positive definite"),
    (np.array([[0.0, 1.0], [1.0, 0.0]]), "not positive definite")])
def test_factorization_refuses_non_positive_definite(matrix, message):
    with pytest.raises(ProblemError, match=message):
        Factorization(sp.csr_matrix(matrix), np.arange(2))


def test_condensation_is_the_schur_complement(exported):
    """S = K_cc − K_ci K_ii⁻¹ K_ic and g̃ = f_c − K_ci K_ii⁻¹ f_i, computed
    directly with SciPy's spsolve (independent of the trailing-block
    read-out), and u recovered from u_c solves K u = f + Pᵀ r."""
    problem = load_problem(exported(454)[0])
    geometry = contact_geometry(problem)
    c = geometry.dofs.ravel()
    i = np.setdiff1d(np.arange(problem.n_dofs), c)
    K = problem.K.tocsc()
    Kii, Kic = K[i][:, i].tocsc(), K[i][:, c].toarray()
    S_direct = K[c][:, c].toarray() - Kic.T @ sla.spsolve(Kii, Kic)
    g_direct = problem.f[c] - Kic.T @ sla.spsolve(Kii, problem.f[i])
    condensation = Condensation(problem, c)
    scale = np.abs(S_direct).max()
    np.testing.assert_allclose(condensation.S, S_direct, rtol=0,
                               atol=1e-10 * scale)
    g, w = condensation.load(problem.f)
    np.testing.assert_allclose(g, g_direct, rtol=0,
                               atol=1e-10 * np.abs(g_direct).max())
    rng = np.random.default_rng(0)
    u_c = 1e-3 * rng.standard_normal(len(c))
    u = condensation.displacement(u_c, w)
    np.testing.assert_allclose(u[c], u_c, rtol=0, atol=1e-14)
    r = K @ u - problem.f  # forces only on the condensed DOFs
    assert np.abs(r[i]).max() <= 1e-9 * np.abs(problem.f).max()
    np.testing.assert_allclose(r[c], condensation.S @ u_c - g, rtol=0,
                               atol=1e-9 * np.abs(r[c]).max())


def test_proportional_loads_reuse_solves(exported):
    problem = load_problem(exported(118)[0])
    c = contact_geometry(problem).dofs.ravel()
    condensation = Condensation(problem, c)
    g1, w1 = condensation.load(problem.f)
    other = np.roll(problem.f, 3)
    condensation.load(other)
    assert condensation.n_solves == 2
    g, w = condensation.load(0.3 * problem.f - 2.0 * other)  # no solve
    assert condensation.n_solves == 2
    reference = sla.spsolve(problem.K.tocsc(), 0.3 * problem.f - 2 * other)
    np.testing.assert_allclose(w, reference, rtol=0,
                               atol=1e-12 * np.abs(reference).max())
    condensation.load(problem.f + np.roll(problem.f, 7))  # a new direction
    assert condensation.n_solves == 3


@pytest.mark.parametrize("n", [118, 454, 1878])
@pytest.mark.parametrize("gap", ["obstacle", "body"])
@pytest.mark.parametrize("method", ["min", "fb"])
def test_condensed_frictionless_equals_full(exported, n, gap, method):
    """The condensed system is the thesis's (67), exactly: the same u and
    λ as the full system, and the full residual's KKT conditions hold."""
    problem = load_problem(exported(n)[0])
    geometry = contact_geometry(problem, gap)
    full = solve_frictionless(problem, method=method, geometry=geometry,
                              condense=False)
    ours = solve_frictionless(problem, method=method, geometry=geometry,
                              condense=True)
    assert full.success and ours.success and ours.condensed
    scale = np.abs(full.u).max()
    assert np.abs(ours.u - full.u).max() <= 1e-9 * scale
    force = np.abs(full.contact_force).max()
    assert np.abs(ours.contact_force - full.contact_force).max() \
        <= 1e-8 * force
    # equilibrium away from Γc's free nodes, from the full K
    r = problem.K @ ours.u - problem.f
    interior = np.setdiff1d(np.arange(problem.n_dofs), geometry.dofs)
    assert np.abs(r[interior]).max() <= 1e-9 * np.abs(problem.f).max()


def test_condensed_frictionless_on_refined_mesh(refined):
    """Also where the Newton path differs most (7668 DOFs): same solution
    as the full system."""
    geometry = contact_geometry(refined)
    full = solve_frictionless(refined, geometry=geometry, condense=False)
    ours = solve_frictionless(refined, geometry=geometry)
    assert np.abs(ours.u - full.u).max() <= 1e-9 * np.abs(full.u).max()
    np.testing.assert_array_equal(ours.in_contact, full.in_contact)


@pytest.mark.parametrize("coulomb, method", [("lagged", "fb"),
                                             ("implicit", "min")])
def test_condensed_friction_equals_full(exported, coulomb, method):
    problem = load_problem(exported(454)[0])
    kwargs = dict(steps=20, formulation="projection", coulomb=coulomb,
                  method=method)
    full = solve_friction(problem, 0.3, condense=False, **kwargs)
    ours = solve_friction(problem, 0.3, **kwargs)
    assert full.success and ours.success and ours.condensed
    assert np.abs(ours.u - full.u).max() <= 1e-9 * np.abs(full.u).max()
    scale = np.abs(full.friction_traction).max()
    assert np.abs(ours.friction_traction - full.friction_traction).max() \
        <= 1e-7 * scale
    np.testing.assert_array_equal(ours.in_contact, full.in_contact)


def test_singular_stiffness_refused_by_the_condensed_solve(exported):
    """The condensed solve's factorisation is the positive definiteness
    check: K made singular (K·1 = 0, by moving each row's sum onto the
    diagonal) is refused with the loader's message, before any iteration."""
    problem = load_problem(exported(118)[0])
    geometry = contact_geometry(problem)
    K = problem.K.tolil()
    K.setdiag(K.diagonal() - np.asarray(K.sum(axis=1)).ravel())
    problem.K = K.tocsr()
    with pytest.raises(ProblemError, match="K_data: K is not positive "
                                           "definite"):
        solve_frictionless(problem, geometry=geometry)
