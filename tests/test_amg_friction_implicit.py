"""Coulomb friction with the implicit bound f_c p(u) on the iterative path
(issue 33 point 1): each Newton system of the active set method carries
D g·ŵ = −f_c r_n(u) in the slip rows, a nonsymmetric system solved by
right-preconditioned GMRES with the eliminated V-cycle of its symmetric
part (``backend="amg", coulomb="implicit"``,
:mod:`solver.contact.friction.active_set`).

Independent references: the factorisation path with the same bound (the
default: condensed onto Γc, semismooth Newton on the projection
formulation) on the thesis's §4 block (2D) and the a/h 4 Hertz sphere
with rollers (3D); Coulomb's law at full slip against the current normal
force (Σ D g_t = f_c Σ λ D); SciPy's sparse LU for the GMRES itself.
"""

import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as sla

sys.path.insert(0, str(Path(__file__).resolve().parent))

from test_amg import hertz_sphere  # noqa: E402
from test_amg_friction import (block_454, full_slip,  # noqa: E402,F401
                               pytestmark, same_answer)
from solver import solve  # noqa: E402
from solver.linalg import amg  # noqa: E402


def test_projected_gmres_equals_the_direct_solve():
    """A nonsymmetric A with constraints C x = C x0 (disjoint rows, here
    unit rows): GMRES with restarts gives the LU answer on the free DOFs
    to 1e-9 and keeps the constraints exactly."""
    n = 300
    rng = np.random.default_rng(3)
    A = (sp.diags([-1.0, 2.5, -1.2], [-1, 0, 1], shape=(n, n))
         + 0.2 * sp.random(n, n, 0.01, random_state=4)).tocsr()
    f = rng.standard_normal(n)
    fixed = np.array([5, 60, 120, 250])
    C = sp.csr_matrix((np.ones(4), (np.arange(4), fixed)), shape=(4, n))
    x0 = np.zeros(n)
    x0[fixed] = [1.0, -2.0, 0.5, 3.0]
    diagonal = 1.0 / A.diagonal()
    result = amg.projected_gmres(A, f, lambda v: diagonal * v, x0, C,
                                 atol=1e-12 * np.linalg.norm(f), restart=15)
    assert result.converged and result.method == "GMRES"
    assert result.iterations > 15  # it restarted
    keep = np.ones(n, bool)
    keep[fixed] = False
    exact = x0.copy()
    exact[keep] = sla.spsolve(A[keep][:, keep].tocsc(), (f - A @ x0)[keep])
    assert np.linalg.norm(result.x - exact) <= 1e-9 * np.linalg.norm(exact)
    np.testing.assert_array_equal(result.x[fixed], x0[fixed])


@pytest.mark.parametrize("fc", [0.05, 0.3])
def test_block_2d_equals_the_factorisation(block_454, fc):
    """The thesis's block, 10 load steps, implicit bound: the same u (to
    1e-7; measured 2e-12) and sets in every step as the factorisation."""
    direct = solve(block_454, friction=fc, steps=10, coulomb="implicit")
    iterative = solve(block_454, friction=fc, steps=10, coulomb="implicit",
                      backend="amg")
    assert same_answer(iterative, direct) < 1e-8
    assert iterative.slip[-1].any()
    assert all(r["krylov"] >= r["njev"] for r in iterative.records)


def test_sphere_3d_equals_the_factorisation(tmp_path_factory):
    """The a/h 4 Hertz sphere (rollers on x = 0 and y = 0), f_c = 0.3,
    10 load steps, implicit bound: the same u (measured 5e-11) and sets,
    stick and slip nodes both present."""
    sphere = hertz_sphere(tmp_path_factory, 4)
    direct = solve(sphere, friction=0.3, steps=10, coulomb="implicit")
    iterative = solve(sphere, friction=0.3, steps=10, coulomb="implicit",
                      backend="amg")
    assert same_answer(iterative, direct) < 1e-8
    assert iterative.stick[-1].sum() >= 5 and iterative.slip[-1].sum() >= 2
    assert max(r["njev"] for r in iterative.records) <= 10


@pytest.mark.parametrize("theta", [30.0, 120.0])
def test_full_slip_friction_is_fc_times_the_current_normal_force(theta):
    """A block pressed, then dragged: every node in contact slips, the
    bound is f_c times the normal force of this step's answer (not the
    last step's), and Σ D g_t = f_c × Σ D λ to 1e-8 against the drag;
    the factorisation's u to 1e-7."""
    result, _, normal = full_slip(theta, "implicit")
    assert normal == pytest.approx(result.contact_force[-1].sum(),
                                   rel=1e-10)


def test_projected_path_equals_the_eliminated(block_454, monkeypatch):
    """Where R is not orthogonal the implicit bound's systems are solved
    by projected GMRES with K's own V-cycle (forced here by declaring R
    not orthogonal): the same u to 1e-8 and the same sets as the
    eliminated systems, f_c = 0.3, 10 steps."""
    from solver.contact.friction import active_set

    eliminated = solve(block_454, friction=0.3, steps=10,
                       coulomb="implicit", backend="amg")
    monkeypatch.setattr(active_set, "is_orthogonal", lambda R: False)
    projected = solve(block_454, friction=0.3, steps=10, coulomb="implicit",
                      backend="amg")
    for result in (eliminated, projected):
        assert result.success and result.verification["passed"]
    for a, b in zip(eliminated.displacement, projected.displacement):
        assert np.linalg.norm(a - b) <= 1e-8 * np.linalg.norm(b)
    for key in ("in_contact", "stick", "slip"):
        for a, b in zip(getattr(eliminated, key), getattr(projected, key)):
            assert np.array_equal(a, b), key
