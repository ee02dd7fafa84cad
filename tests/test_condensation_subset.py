"""K condensed onto a subset of a condensation's DOFs from its S
(:class:`solver.linalg.SubCondensation`), and the friction screening
condensed onto every DOF of its candidates
(:class:`solver.contact.strategies.candidates.NodalCondensation`), so that
a 3D friction run factorises K once (issue 33, point 2).

References, each independent of what is tested:

* the Schur complement S = K_kk − K_ki K_ii⁻¹ K_ik and g̃ = f_k −
  K_ki K_ii⁻¹ f_i computed directly by SciPy's spsolve on the sparse K
  (as tests/test_linalg.py does for :class:`~solver.linalg.Condensation`),
  and K u = f + Pᵀr with r on the kept DOFs only;
* :class:`~solver.contact.strategies.candidates.NormalCondensation`, the
  screening before: K̂ = RKRᵀ factorised with its own Schur set on the
  candidates' normal rows;
* the 3D friction run with the screening's factorisation not reused
  (:data:`solver.linalg.condensation.SUBSET_FRACTION` = −1: a second
  factorisation, the path before).
"""

import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse.linalg as sla

sys.path.insert(0, str(Path(__file__).resolve().parent))

from test_rollers import dragged_3d  # noqa: E402
from solver import load_problem, solve  # noqa: E402
from solver.contact import contact_geometry  # noqa: E402
from solver.contact.strategies.candidates import (  # noqa: E402
    NodalCondensation, NormalCondensation)
from solver.linalg import Condensation, SubCondensation, get_backend, \
    resolve  # noqa: E402
from solver.linalg import condensation as condensation_module  # noqa: E402


def direct_schur(problem, k):
    """(S, g̃) of K onto the DOFs k by spsolve on the interior."""
    i = np.setdiff1d(np.arange(problem.n_dofs), k)
    K = problem.K.tocsc()
    Kii, Kik = K[i][:, i].tocsc(), K[i][:, k].toarray()
    S = K[k][:, k].toarray() - Kik.T @ sla.spsolve(Kii, Kik)
    g = problem.f[k] - Kik.T @ sla.spsolve(Kii, problem.f[i])
    return S, g


def test_subset_is_the_schur_complement_of_k(exported):
    """Condensation.of onto most of a made condensation's DOFs (in another
    order) derives it from S: S, g̃ equal the direct Schur complement, and
    u from u_k carries forces on k only."""
    problem = load_problem(exported(454)[0])
    c = contact_geometry(problem).dofs.ravel()
    parent = Condensation.of(problem, c)
    k = np.random.default_rng(1).permutation(c)[:int(0.85 * len(c))]
    sub = Condensation.of(problem, k)
    assert isinstance(sub, SubCondensation) and sub.parent is parent
    S, g_direct = direct_schur(problem, k)
    np.testing.assert_allclose(sub.S, S, rtol=0,
                               atol=1e-10 * np.abs(S).max())
    g, w = sub.load(problem.f)
    np.testing.assert_allclose(g, g_direct, rtol=0,
                               atol=1e-10 * np.abs(g_direct).max())
    u_k = 1e-3 * np.random.default_rng(0).standard_normal((len(k), 2))
    u = sub.displacement(u_k, np.column_stack([w, w]))  # two columns
    np.testing.assert_allclose(u[k], u_k, rtol=0, atol=1e-14)
    r = problem.K @ u - problem.f[:, None]
    rest = np.setdiff1d(np.arange(problem.n_dofs), k)
    assert np.abs(r[rest]).max() <= 1e-9 * np.abs(problem.f).max()
    np.testing.assert_allclose(r[k], sub.S @ u_k - g[:, None], rtol=0,
                               atol=1e-9 * np.abs(r[k]).max())
    assert Condensation.of(problem, k) is sub  # kept
    assert Condensation.of(problem, c) is parent  # and so is its parent
    shuffled = Condensation.of(problem, c[::-1])  # the same DOFs, reordered
    np.testing.assert_array_equal(shuffled.S, parent.S[::-1, ::-1])
    np.testing.assert_allclose(shuffled.displacement(w[c[::-1]], w), w,
                               rtol=0, atol=1e-12 * np.abs(w).max())


def test_subset_too_small_or_outside_factorises_anew(exported):
    """Dropping more than SUBSET_FRACTION of the kept DOFs, or a DOF
    outside the made set: a factorisation of its own."""
    problem = load_problem(exported(454)[0])
    c = contact_geometry(problem).dofs.ravel()
    Condensation.of(problem, c)
    few = c[:len(c) // 2]
    assert type(Condensation.of(problem, few)) is Condensation
    Condensation.of(problem, c)
    outside = np.append(c[1:], np.setdiff1d(np.arange(problem.n_dofs),
                                            c)[0])
    assert type(Condensation.of(problem, outside)) is Condensation


@pytest.fixture(scope="module")
def quarter():
    """tests/test_rollers.py's quarter block on a paraboloid: rollers on
    two symmetry planes."""
    return dragged_3d("quarter", 0.02)


def test_nodal_screening_equals_the_normal_one(quarter):
    """NodalCondensation's normal S, g̃, w_c and recovered u equal
    NormalCondensation's (K̂ factorised on the normal rows), rollers
    among the candidates."""
    geometry = contact_geometry(quarter, "obstacle", rollers=True)
    assert geometry.has_rollers
    nodes = np.arange(len(geometry.gap))
    backend = resolve("auto")
    normal = NormalCondensation(quarter, geometry, backend)
    nodal = NodalCondensation(quarter, geometry, backend)
    (S0, g0, w0), (S1, g1, w1) = normal.factorize(nodes), \
        nodal.factorize(nodes)
    np.testing.assert_allclose(S1, S0, rtol=0, atol=1e-10 * np.abs(S0).max())
    np.testing.assert_allclose(g1, g0, rtol=0, atol=1e-10 * np.abs(g0).max())
    np.testing.assert_allclose(w1, w0, rtol=0, atol=1e-10 * np.abs(w0).max())
    u_n = w0 - 1e-3 * np.abs(w0).max() * np.linspace(0, 1, len(w0))
    (u0, n0), (u1, n1) = normal.displacement(u_n), nodal.displacement(u_n)
    np.testing.assert_allclose(u1, u0, rtol=0, atol=1e-10 * np.abs(u0).max())
    np.testing.assert_allclose(n1, n0, rtol=0, atol=1e-10 * np.abs(n0).max())


def test_friction_run_factorises_once(quarter, monkeypatch):
    """The default 3D friction run (screening, then friction on
    candidates) factorises K once, and its answer equals the run that
    factorises again (SUBSET_FRACTION < 0) to 1e-10, same stick set. On
    this small block the friction candidates (4) are far fewer than the
    screening's, so SUBSET_FRACTION (a cost rule) is raised to take them
    from the screening's S all the same."""
    module = get_backend(resolve("auto"))
    calls = []
    factorize = module.factorize

    def counted(*args, **kwargs):
        calls.append(1)
        return factorize(*args, **kwargs)

    monkeypatch.setattr(module, "factorize", counted)
    monkeypatch.setattr(condensation_module, "SUBSET_FRACTION", 100.0)
    problem = dragged_3d("quarter", 0.02)  # a K of its own: nothing cached
    reused = solve(problem, friction=0.3, formulation="projection",
                   tol=1e-13)
    assert reused.success and reused.condensation == "candidates"
    assert len(calls) == 1
    monkeypatch.setattr(condensation_module, "SUBSET_FRACTION", -1.0)
    problem = dragged_3d("quarter", 0.02)
    again = solve(problem, friction=0.3, formulation="projection",
                  tol=1e-13)
    assert len(calls) == 3  # the screening's and the friction run's
    assert np.abs(reused.u - again.u).max() <= 1e-10 * np.abs(again.u).max()
    np.testing.assert_array_equal(reused.stick, again.stick)
    np.testing.assert_array_equal(reused.in_contact, again.in_contact)
