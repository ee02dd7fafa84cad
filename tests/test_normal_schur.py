"""Rank 0's condensation of Γc's Schur complement onto the normal rows
(solver/mpi/distributed.py, ``NormalSchur``), in process (no PETSc).

References, independent of the class's block elimination: the Schur
complement of an SPD matrix on a set N is the inverse of the N block of
its inverse, (Ŝ⁻¹)_NN⁻¹ with Ŝ = R S Rᵀ (thesis (58)-(60), node frames of
:func:`solver.contact.geometry.rotation`); and the recovered u must leave
no force on the tangential rows, R (S u − g̃) = 0 there, with the normal
rows' force S_n u_n − g_n."""

import numpy as np
import pytest

from solver.contact.geometry import ContactGeometry, rotation
from solver.errors import ProblemError
from solver.mpi.distributed import Ledger, NormalSchur


def geometry(m_nodes, dim, seed):
    """Contact nodes with oblique unit normals, DOFs 0 … d·m − 1."""
    rng = np.random.default_rng(seed)
    normal = rng.standard_normal((m_nodes, dim))
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    dofs = np.arange(dim * m_nodes).reshape(m_nodes, dim)
    return ContactGeometry(np.arange(m_nodes), dofs,
                           rng.uniform(0.0, 1e-3, m_nodes), normal)


@pytest.mark.parametrize("dim", [2, 3])
def test_normal_rows_schur_complement_and_recovery(dim):
    local = geometry(7, dim, 4 + dim)
    m = dim * 7
    rng = np.random.default_rng(dim)
    A = rng.standard_normal((m, m))
    S = A @ A.T + m * np.eye(m)
    g = rng.standard_normal(m)
    ledger = Ledger()
    work = dict(S=S.copy())
    normal = NormalSchur(work, g, local, 1.0, ledger)
    assert "S" not in work  # S handed over, freed there
    R = rotation(m, local)[0].toarray()
    N = local.dofs[:, -1]
    hat = R @ S @ R.T
    expected = np.linalg.inv(np.linalg.inv(hat)[np.ix_(N, N)])
    assert np.allclose(normal.S, expected, rtol=1e-12, atol=1e-12 * m)
    # the free start is the N rows of Ŝ⁻¹ĝ (no force anywhere)
    free = np.linalg.solve(hat, R @ g)
    assert np.allclose(normal.start, free[N], rtol=1e-10, atol=1e-14)
    # any u_n: no force on the tangential rows, S_n u_n − g_n on N
    u_n = rng.standard_normal(7)
    u = normal.displacement(u_n)
    force = R @ (S @ u - g)
    T = np.setdiff1d(np.arange(m), N)
    assert np.abs(force[T]).max() <= 1e-10 * np.abs(force).max()
    assert np.allclose(force[N], normal.S @ u_n - normal.g, rtol=1e-10)
    assert np.allclose((R @ u)[N], u_n, rtol=1e-13)
    # rank 0's ledger: nothing beyond (m/d)² once S is gone
    assert ledger.shapes["S_n"] == [7, 7]


def test_not_positive_definite_is_one_line():
    """An indefinite S (K not SPD) is refused by the pivot check of
    ``schur_cholesky``, as before the condensation."""
    local = geometry(4, 2, 1)
    S = -np.eye(8)
    with pytest.raises(ProblemError, match="not positive definite"):
        NormalSchur(dict(S=S), np.ones(8), local, 1.0, Ledger())
