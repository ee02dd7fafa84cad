"""PERF17 (issue 17's timing targets): the faster paths give the same answers
and the same Newton counts as the paths they replace."""

import numpy as np
import pytest
import scipy.linalg as sla

from solver import load_problem, solve_frictionless
from solver.contact import FrictionlessSystem
from solver.contact import contact_geometry
from solver.contact.strategies.reduction import condense_onto_contact
from solver.geometry.curves.normals import outward_sign
from solver.linalg import available_backends
from solver.linalg.base import Factor
from solver.linalg.threads import _libraries, single_blas_thread
from solver.ncp.functions import derivative_weights

#: Newton counts (njev, nfev) of the default 2D solve (condensed, nested
#: start, c = k̄, SuperLU) on the thesis blocks of 118, 454 and 1878
#: triangles, per level (coarsest first) and in total: recorded on main at
#: 0e99ad8 before PERF17 (issue 8's and 17's benchmark tables show the same
#: totals: φ_min 4/7, 6/10, 9/14; φ_FB 12/15, 18/22, 29/35), where every
#: Newton system was the assembled Jacobian factorised by LU.
COUNTS = {
    (118, "min"): (4, 7, [3, 1]), (118, "fb"): (12, 15, [7, 5]),
    (454, "min"): (6, 10, [3, 1, 2]), (454, "fb"): (18, 22, [7, 5, 6]),
    (1878, "min"): (9, 14, [4, 2, 1, 2]),
    (1878, "fb"): (29, 35, [12, 6, 5, 6]),
}


@pytest.mark.parametrize("key", list(COUNTS))
def test_newton_counts_on_the_thesis_blocks_unchanged(exported, key):
    triangles, method = key
    problem = load_problem(exported(triangles)[0])
    result = solve_frictionless(problem, method, backend="superlu")
    njev, nfev, levels = COUNTS[key]
    assert result.success
    assert (result.njev, result.nfev) == (njev, nfev)
    assert [level["njev"] for level in result.levels] == levels


@pytest.mark.parametrize("method", ["min", "fb"])
def test_reduced_direction_solves_the_assembled_jacobian(exported, method):
    """The structured Jacobian's direction against LAPACK's solve of the
    whole Jacobian [XRS; diag(w_a)(−YRS) + diag(w_b)(−cYR)] assembled
    densely (thesis (67)): backward error at round-off, for weights with
    fixed rows (w_a = 0) and mixed rows (φ_FB)."""
    problem = load_problem(exported(454)[0])
    geometry = contact_geometry(problem, "obstacle")
    condensation, local = condense_onto_contact(problem, geometry, "superlu")
    S = condensation.S
    g, w = condensation.load(problem.f)
    system = FrictionlessSystem(S, g, local, gap_scale=2.5e3)
    jac = system.jacobian(None)
    assert hasattr(jac, "combine")  # the reduced path is taken on dense S
    rng = np.random.default_rng(5)
    x = w[condensation.dofs] + 1e-3 * rng.standard_normal(len(g))
    E, A, B = system.residual(x)
    wa, wb, _ = derivative_weights(A, B, method, None, None)
    if method == "min":
        assert 0 < np.count_nonzero(wa == 0) < len(wa)  # both kinds of row
    J = np.vstack([system._JE, wa[:, None] * system._JA
                   + wb[:, None] * system._JB])
    F = rng.standard_normal(len(g))
    d = jac.combine(wa, wb).direction(F)
    backward = np.abs(J @ d + F).max() / (np.abs(J).max() *
                                          np.abs(d).max() + np.abs(F).max())
    assert backward < 1e-14
    assert np.allclose(d, sla.solve(J, -F), rtol=1e-9, atol=0)
    grad = jac.combine(wa, wb).rmatvec(F)
    assert np.allclose(grad, J.T @ F, rtol=1e-12,
                       atol=1e-12 * np.abs(J.T @ F).max())


@pytest.mark.parametrize("method", ["min", "fb"])
def test_normal_complement_direction_equals_unreduced(exported, method):
    """The direction after eliminating the rows X once (the normal
    complement N = T_YY − T_YX T_XX⁻¹ T_XY) against the direction on all
    free components, the path it replaces: the same vector to round-off,
    for φ_min's fixed rows and φ_FB's mixed rows."""
    problem = load_problem(exported(454)[0])
    geometry = contact_geometry(problem, "obstacle")
    condensation, local = condense_onto_contact(problem, geometry, "superlu")
    g, w = condensation.load(problem.f)
    system = FrictionlessSystem(condensation.S, g, local, gap_scale=2.5e3)
    jac = system.jacobian(None)
    assert jac.normal_complement() is not None  # the reduced path runs
    rng = np.random.default_rng(11)
    x = w[condensation.dofs] + 1e-3 * rng.standard_normal(len(g))
    _, A, B = system.residual(x)
    wa, wb, _ = derivative_weights(A, B, method, None, None)
    combined = jac.combine(wa, wb)
    F = rng.standard_normal(len(g))
    h = -combined._natural(F)
    fixed = wa == 0.0
    v_K = h[jac.y_rows[fixed]] / (-jac.c * wb[fixed])
    h[jac.y_rows[~fixed]] /= -wa[~fixed]
    reference = combined._unreduced(h, fixed, v_K)
    d = combined.direction(F)
    assert np.abs(d - reference).max() <= 1e-10 * np.abs(reference).max()


def test_reduced_direction_singular_row():
    """A row with w_a = w_b = 0 makes J singular: no direction."""
    from solver.contact.frictionless.newton import CondensedJacobian
    import scipy.sparse as sp

    S = np.array([[2.0, -1.0], [-1.0, 2.0]])
    jac = CondensedJacobian(S, sp.identity(2, format="csr"), np.array([0]),
                            np.array([1]), -S[[1]], -np.eye(2)[[1]], 1.0)
    assert jac.combine(np.zeros(1), np.zeros(1)).direction(
        np.ones(2)) is None


@pytest.mark.skipif("cholmod" not in available_backends(),
                    reason="kvxopt (CHOLMOD) not installed")
def test_cholmod_backward_sweep_back_substitution(exported):
    """CHOLMOD's back-substitution by the backward sweep alone against the
    generic one (a full solve of K with the right-hand side PᵀS u_c)."""
    problem = load_problem(exported(1878)[0])
    geometry = contact_geometry(problem, "obstacle")
    condensation, _ = condense_onto_contact(problem, geometry, "cholmod")
    factor = condensation.factorization
    assert factor._L22 is not None  # read in place: the fast path runs
    m = len(condensation.dofs)
    rng = np.random.default_rng(3)
    for shape in ((m,), (m, 4)):
        u_c = rng.standard_normal(shape)
        fast = factor.back_substitute(None, u_c)
        generic = Factor.back_substitute(factor, None, u_c)
        scale = np.abs(generic).max()
        assert np.abs(fast - generic).max() <= 1e-10 * scale
        assert np.abs(fast[condensation.dofs] - u_c).max() <= 1e-12 * \
            np.abs(u_c).max()


def _outward_sign_all_sides(nodes, cells, chain):
    """The reference: the opposite vertex of each chain edge by a Python
    search over every triangle."""
    signs = []
    for a, b in zip(chain[:-1], chain[1:]):
        owners = [c for c in cells if a in c and b in c]
        assert len(owners) == 1
        c = [v for v in owners[0] if v not in (a, b)][0]
        e, i = nodes[b] - nodes[a], nodes[c] - nodes[a]
        signs.append(np.sign(i[0] * e[1] - i[1] * e[0]))
    return 1 if all(s < 0 for s in signs) else -1


def test_outward_sign_restricted_to_chain_triangles():
    """A structured triangulation of [0, 4]×[0, 2]; the chain along the
    bottom edge in both directions and along the top edge."""
    nx, ny = 5, 3
    X, Y = np.meshgrid(np.arange(nx, dtype=float), np.arange(ny, dtype=float))
    nodes = np.column_stack([X.ravel(), Y.ravel()])
    cells = []
    for j in range(ny - 1):
        for i in range(nx - 1):
            p = j * nx + i
            cells += [[p, p + 1, p + nx + 1], [p, p + nx + 1, p + nx]]
    cells = np.array(cells)
    bottom = np.arange(nx)
    top = (ny - 1) * nx + np.arange(nx)
    for chain in (bottom, bottom[::-1], top, top[::-1]):
        assert outward_sign(nodes, cells, chain) == \
            _outward_sign_all_sides(nodes, cells, chain)
    from solver.geometry.curves.normals import GeometryError

    with pytest.raises(GeometryError, match="not a boundary edge"):
        outward_sign(nodes, cells, np.array([nx + 1, nx + 2]))  # interior


def test_single_blas_thread_restores_the_thread_counts():
    before = [get() for get, _ in _libraries()]
    with single_blas_thread():
        assert all(get() == 1 for get, _ in _libraries())
    assert [get() for get, _ in _libraries()] == before


def test_large_dense_factorisation_gets_the_threads_back():
    """Inside single_blas_thread, blas_threads_for(order) restores the
    outer counts for orders >= THREADED_ORDER only, and one thread after."""
    from solver.linalg.threads import THREADED_ORDER, blas_threads_for

    before = [get() for get, _ in _libraries()]
    with single_blas_thread():
        with blas_threads_for(THREADED_ORDER):
            assert [get() for get, _ in _libraries()] == before
        with blas_threads_for(THREADED_ORDER - 1):
            assert all(get() == 1 for get, _ in _libraries())
        assert all(get() == 1 for get, _ in _libraries())
    with blas_threads_for(THREADED_ORDER):  # outside: nothing changes
        assert [get() for get, _ in _libraries()] == before
    assert [get() for get, _ in _libraries()] == before


def test_stable_norm_of_a_long_vector_single_threaded(monkeypatch):
    """A mesh-sized vector is normed with one BLAS thread (FRIC17B): the
    value against math.fsum's correctly rounded sum of squares, the
    thread counts restored, and the short vectors of the Newton loops
    never switch threads."""
    import math

    from solver.ncp import newton

    rng = np.random.default_rng(7)
    v = rng.standard_normal(newton.SINGLE_THREAD_NORM + 5)
    before = [get() for get, _ in _libraries()]
    entered = []
    original = newton.single_blas_thread

    def spy():
        entered.append(True)
        return original()

    monkeypatch.setattr(newton, "single_blas_thread", spy)
    reference = math.sqrt(math.fsum(v * v))
    assert abs(newton.stable_norm(v) - reference) <= 1e-14 * reference
    assert entered == [True]
    newton.stable_norm(v[:100])
    assert entered == [True]
    assert [get() for get, _ in _libraries()] == before
