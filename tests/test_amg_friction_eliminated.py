"""Friction's Newton systems on the eliminated K̂ (issue 33): the active
normals and the stick tangentials fixed in y = R u, the slip springs a
low-rank change of K̂ on the slip rows, in the operator and in the first
coarse operator of :meth:`solver.linalg.amg.Multigrid.eliminated`
(:mod:`solver.contact.friction.active_set`).

Independent references: the Galerkin product P̂_Fᵀ (K̂ + S)_FF P̂_F formed
directly and SciPy's sparse LU of the same system; the projected CG with
K's own V-cycle (the path before the elimination, still taken where R is
not orthogonal) on the a/h 4 Hertz sphere with rollers, whose answer
tests/test_amg_friction.py pins to the factorisation's.
"""

import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

sys.path.insert(0, str(Path(__file__).resolve().parent))

from test_amg import hertz_sphere  # noqa: E402
from solver import contact_geometry, solve  # noqa: E402
from solver.linalg import amg  # noqa: E402

pytestmark = pytest.mark.skipif(not amg.available(),
                                reason="pyamg not installed (.[amg])")


@pytest.fixture(scope="module")
def sphere_8(tmp_path_factory):
    return hertz_sphere(tmp_path_factory, 8)


@pytest.fixture(scope="module")
def sphere_4(tmp_path_factory):
    return hertz_sphere(tmp_path_factory, 4)


def test_springs_in_the_eliminated_hierarchy(sphere_8):
    """Fixed: the normals of the 40 nodes nearest the obstacle and the
    tangentials of 20 of them (stick); rank-one springs k e eᵀ on the
    tangent rows of 25 other nodes (slip). (a) The first coarse operator,
    updated through the fixed and spring rows only, is P̂_Fᵀ (K̂ + S)_FF
    P̂_F formed directly; (b) CG with that hierarchy reaches SciPy's LU
    answer of (K̂ + S)_FF y_F = (R f − K̂ y_E)_F to 1e-8."""
    from solver.contact.frictionless.active_set import eliminated_step
    from solver.contact.geometry import rotate_stiffness, rotation

    problem = sphere_8
    K, f, n = sp.csr_matrix(problem.K), problem.f, problem.n_dofs
    geometry = contact_geometry(problem, "obstacle")
    R, _, tangent_rows, normal_rows = rotation(n, geometry)
    K_hat = rotate_stiffness(K, R, geometry.free_dofs())
    mg = amg.Multigrid(K, amg.rigid_body_modes(
        problem.nodes[problem.dof_map[:, 0]], problem.dof_map[:, 1]))
    assert mg.levels >= 2
    order = np.argsort(geometry.gap)
    tangents = tangent_rows.reshape(-1, 2)
    stick, slip = order[:20], order[40:65]
    stick = stick[(tangents[stick] >= 0).all(axis=1)]
    slip = slip[(tangents[slip] >= 0).all(axis=1)]
    assert len(stick) >= 10 and len(slip) >= 10
    fixed = np.concatenate([normal_rows[order[:40]],
                            tangents[stick].ravel()])
    keep = np.ones(n, bool)
    keep[fixed] = False
    angle = np.linspace(0.0, np.pi, len(slip))
    across = np.column_stack([np.cos(angle), np.sin(angle)])
    E = sp.csr_matrix((across.ravel(), (np.repeat(np.arange(len(slip)), 2),
                                        tangents[slip].ravel())),
                      shape=(len(slip), n))
    k = K.diagonal().mean() * np.linspace(0.1, 100.0, len(slip))
    S = (E.T @ sp.diags(k) @ E).tocsr()
    reduced = mg.eliminated(K_hat, R, keep, S)
    A = (K_hat + S)[keep][:, keep]
    P = sp.csr_matrix(R @ mg.prolongators()[0])[keep]
    galerkin = (P.T @ A @ P).toarray()
    updated = reduced.operators()[1].toarray()
    assert np.abs(updated - galerkin).max() < 1e-12 * np.abs(galerkin).max()
    without = mg.eliminated(K_hat, R, keep).operators()[1].toarray()
    assert np.abs(without - galerkin).max() > 1e-3 * np.abs(galerkin).max()
    # the system from u = 0 moved onto the fixed values (gaps, 0)
    start = R[normal_rows[order[:40]]].T @ geometry.gap[order[:40]]
    y = R @ start
    rhs = (R @ f - K_hat @ np.where(keep, 0.0, y))[keep]
    exact = spla.spsolve(sp.csc_matrix(A), rhs)
    atol = 1e-10 * np.linalg.norm(rhs - A @ y[keep])
    krylov, u = eliminated_step(K_hat, R @ f, R, mg, fixed, start, atol, S)
    assert krylov.converged
    assert np.linalg.norm((R @ u)[keep] - exact) < 1e-8 * np.linalg.norm(exact)
    assert np.abs((R @ u)[fixed] - y[fixed]).max() < 1e-12


def test_friction_eliminated_against_projected(sphere_4, monkeypatch):
    """The a/h 4 sphere, f_c = 0.3, 10 load steps: the eliminated Newton
    systems (the default where R is orthogonal) and the projected ones
    (forced by declaring R not orthogonal) give the same u to 1e-8 and the
    same stick and slip sets up to nodes on the cone's edge (|g| = b to
    1e-6: stick with |g| = b and slip with no slide are the same state;
    the projected path ends a step with a node there, |g|/b = 1.000,
    since a 3D slip node turned back twice is stuck); the eliminated CG
    needs fewer iterations in all."""
    from solver.contact.friction import active_set

    eliminated = solve(sphere_4, friction=0.3, steps=10, backend="amg")
    monkeypatch.setattr(active_set, "is_orthogonal", lambda R: False)
    projected = solve(sphere_4, friction=0.3, steps=10, backend="amg")
    for result in (eliminated, projected):
        assert result.success and result.verification["passed"]
    for a, b in zip(eliminated.displacement, projected.displacement):
        assert np.linalg.norm(a - b) <= 1e-8 * np.linalg.norm(b)
    for step in range(len(eliminated.displacement)):
        g = np.linalg.norm(np.reshape(
            eliminated.friction_traction[step],
            (len(eliminated.stick[step]), -1)), axis=1)
        edge = g >= (1 - 1e-6) * eliminated.friction_bound[step]
        for key in ("stick", "slip"):
            a, b = (getattr(r, key)[step] for r in (eliminated, projected))
            assert np.array_equal(a[~edge], b[~edge]), (key, step)
    cg = [sum(r["krylov"] for r in result.records)
          for result in (eliminated, projected)]
    assert cg[0] < cg[1]
