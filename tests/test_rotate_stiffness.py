"""K̂ = R K Rᵀ by rows and columns of the contact DOFs only
(:func:`solver.contact.geometry.rotate_stiffness`, used by the candidates'
condensation and the PETSc engine) against the two sparse products
½(RKRᵀ + (RKRᵀ)ᵀ) it replaced: the thesis block (2D), the 3D quarter
block with rollers on its two symmetry planes, and a non-symmetric K."""

import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

sys.path.insert(0, str(Path(__file__).parent))
from test_rollers import block_3d  # noqa: E402

from solver import load_problem  # noqa: E402
from solver.contact.geometry import (contact_geometry,  # noqa: E402
                                     rotate_stiffness, rotation)


def products(K, R):
    A = (R @ K @ R.T).tocsr()
    return 0.5 * (A + A.T)


def check(K, geometry):
    R = rotation(K.shape[0], geometry)[0]
    c = geometry.free_dofs()
    K_hat = rotate_stiffness(K, R, c)
    ref = products(K, R)
    scale = abs(ref).max()
    assert abs(K_hat - ref).max() <= 1e-14 * scale
    # the rotated rows and columns exactly symmetric, the others K's own
    assert (K_hat[c] != K_hat[:, c].T).nnz == 0
    others = np.setdiff1d(np.arange(K.shape[0]), c)
    assert (K_hat[others][:, others] != sp.csr_matrix(K)[others][:, others]
            ).nnz == 0
    return K_hat


def test_thesis_block(exported):
    p = load_problem(exported(454)[0])
    check(p.K, contact_geometry(p, "obstacle"))


def test_quarter_block_with_rollers():
    p = block_3d("quarter")
    g = contact_geometry(p, "obstacle", rollers=True)
    assert g.has_rollers
    check(p.K, g)


@pytest.mark.parametrize("seed", [0, 1])
def test_nonsymmetric_k_keeps_its_entries_off_the_contact_dofs(exported,
                                                              seed):
    """A K with a rounding-sized asymmetry (as assembled K has, 1e-15
    relative): K̂ agrees with the products' symmetric part to that size."""
    p = load_problem(exported(118)[0])
    K = p.K.tocsr().copy()
    K.data *= 1 + 1e-15 * np.random.default_rng(seed).standard_normal(
        K.nnz)
    check(K, contact_geometry(p, "obstacle"))
