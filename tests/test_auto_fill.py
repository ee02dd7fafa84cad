"""``backend="auto"``'s choice between factorising K and the AMG path from
the fill estimate (issue 33 point 3, :func:`solver.linalg.amg.direct_fits`),
with the machine's memory and the factor's size mocked: the decision is
the arithmetic of its docstring (need = FACTOR_OVERHEAD × factor values +
K's values and column indices, against MEMORY_SHARE × available), checked
here on both sides of the budget. The estimate itself is compared with the
nested-dissection bound of a 2D grid (George 1973: the factor of an
N × N grid has Θ(N² log N) nonzeros)."""

import numpy as np
import pytest
import scipy.sparse as sp

from solver.linalg import amg


def grid_stiffness(n):
    """The 5-point Laplacian of an n × n grid plus a shift (SPD)."""
    one = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)],
                   [-1, 0, 1])
    eye = sp.identity(n)
    return (sp.kron(one, eye) + sp.kron(eye, one)
            + 1e-3 * sp.identity(n * n)).tocsr()


def need(K, values):
    return amg.FACTOR_OVERHEAD * values + K.data.nbytes + K.indices.nbytes


def test_small_K_fits_by_the_dense_bound(monkeypatch):
    """n²/2 values within the budget: no symbolic analysis at all."""
    K = grid_stiffness(10)
    monkeypatch.setattr(amg, "available_memory", lambda: 1e9)

    def unexpected(K):
        raise AssertionError("factor_memory called")

    monkeypatch.setattr(amg, "factor_memory", unexpected)
    assert amg.direct_fits(K) == (True, None)


@pytest.mark.parametrize("side", [-1, 1])
def test_choice_on_each_side_of_the_budget(monkeypatch, side):
    """A factor whose need is 1 % under (over) MEMORY_SHARE of the
    available memory is factorised (goes to AMG), and the reason says
    so with the GB it compared."""
    K = grid_stiffness(200)  # n = 40,000: the dense bound (6.4 GB) fails
    values = 3e8
    free = need(K, values) / amg.MEMORY_SHARE * (1 - 0.01 * side)
    monkeypatch.setattr(amg, "available_memory", lambda: free)
    monkeypatch.setattr(amg, "factor_memory", lambda K: values)
    fits, reason = amg.direct_fits(K)
    assert fits == (side < 0)
    assert f"≈ {need(K, values) / 1e9:.3g} GB" in reason
    assert f"{free / 1e9:.3g} GB available" in reason
    assert reason.endswith("factorise" if side < 0 else
                           "AMG-preconditioned CG instead")


def test_unknown_memory_or_no_analysis_factorises(monkeypatch):
    K = grid_stiffness(200)
    monkeypatch.setattr(amg, "available_memory", lambda: None)
    assert amg.direct_fits(K)[0]
    monkeypatch.setattr(amg, "available_memory", lambda: 1e6)
    monkeypatch.setattr(amg, "factor_memory", lambda K: None)
    fits, reason = amg.direct_fits(K)
    assert fits and "kvxopt" in reason


def test_estimate_grows_like_nested_dissection():
    """CHOLMOD's estimate for 2D grids: above K's lower triangle, below
    the dense triangle, and growing from N = 100 to 200 (4× the unknowns)
    by 4·log(200)/log(100) ≈ 4.6× within a factor 1.5 (the N² log N law;
    the n^1.5 of 3D-like fill would give 8×)."""
    sizes = []
    for N in (100, 200):
        K = grid_stiffness(N)
        size = amg.factor_memory(K)
        if size is None:
            pytest.skip("kvxopt not installed")
        n = K.shape[0]
        assert 8 * sp.tril(K).nnz < size < 8 * n * (n + 1) / 2
        sizes.append(size)
    growth = sizes[1] / sizes[0]
    law = 4 * np.log(200) / np.log(100)
    assert law / 1.5 < growth < law * 1.5
