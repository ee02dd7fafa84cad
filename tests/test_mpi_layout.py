"""The PETSc engine's padded numbering (solver/mpi/layout.py) without MPI:
the padded CSR against the padded matrix written out densely entry by
entry (P[pad(i), pad(j)] = A[i, j], P[d, d] = mean diag A at a Dirichlet
row d), for the row copy (the nodes' order kept) and the COO fallback (any
other numbering), 2D and 3D."""

import types

import numpy as np
import pytest
import scipy.sparse as sp

from solver import load_problem
from solver.mpi.layout import Layout


def dense_padded(layout, A):
    A = sp.csr_matrix(A).toarray()
    P = np.zeros((layout.n, layout.n))
    P[np.ix_(layout.red_to_pad, layout.red_to_pad)] = A
    P[layout.dirichlet, layout.dirichlet] = np.mean(np.diag(A))
    return P


def synthetic(dim, n_nodes, seed, shuffle):
    """A problem-like object: some DOFs prescribed, a random symmetric
    sparse A on the others; ``shuffle`` numbers the free DOFs out of the
    nodes' order."""
    rng = np.random.default_rng(seed)
    pairs = np.array([(i, c) for i in range(n_nodes) for c in range(dim)])
    free = pairs[rng.random(len(pairs)) > 0.2]
    if shuffle:
        free = free[rng.permutation(len(free))]
    m = len(free)
    B = sp.random(m, m, density=0.2, random_state=seed, format="csr")
    A = (B + B.T + 4 * sp.identity(m)).tocsr()
    problem = types.SimpleNamespace(dim=dim, nodes=np.zeros((n_nodes, dim)),
                                    dof_map=free)
    return problem, A


@pytest.mark.parametrize("dim,shuffle", [(2, False), (3, False), (2, True),
                                         (3, True)])
def test_padded_matrix_is_the_dense_padding(dim, shuffle):
    problem, A = synthetic(dim, 17, 3 + dim, shuffle)
    layout = Layout(problem, 2)
    P = layout.matrix(A)
    assert P.has_sorted_indices
    assert np.array_equal(P.toarray(), dense_padded(layout, A))


def test_unsorted_duplicated_input(exported):
    """A CSR whose rows list their columns backwards and every entry twice
    (half the value each, as an unsummed sum of element matrices) pads to
    the padding of the summed matrix, exactly (x/2 + x/2 = x)."""
    p = load_problem(exported(118)[0])
    layout = Layout(p, 3)
    K = p.K.tocsr()
    rows = np.repeat(np.arange(K.shape[0]), np.diff(K.indptr))
    order = np.lexsort((-K.indices, rows))
    messy = sp.csr_matrix((np.repeat(K.data[order] / 2, 2),
                           np.repeat(K.indices[order], 2), 2 * K.indptr),
                          shape=K.shape)
    assert not messy.has_canonical_format
    P = layout.matrix(messy)
    assert P.has_sorted_indices
    assert np.array_equal(P.toarray(), dense_padded(layout, K))


def test_thesis_block_padding(exported):
    """The exported 454 block (nodes' order kept: the row copy)."""
    p = load_problem(exported(454)[0])
    layout = Layout(p, 2)
    assert np.all(np.diff(layout.red_to_pad) > 0)
    P = layout.matrix(p.K)
    assert P.indices.dtype == np.int32
    assert np.array_equal(P.toarray(), dense_padded(layout, p.K))
