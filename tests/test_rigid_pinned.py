"""The cheap test of a supported body (``solver.linalg.kernel.pinned``):
the rigid motions restricted to the Dirichlet DOFs have full rank, so K
has no rigid-body mode, without the product K·G and its SVD that
``rigid_modes`` makes (issue 32: that check cost 0.2-0.7 s of every
two-body solve at 10⁵ DOFs).

Reference: the numerical kernel test itself (``rigid_modes``: the
singular values of K G, an independent computation from K), on K of
elastic tetrahedra with supports chosen so that zero, one and six rigid
motions stay free (statics: two pinned points leave the rotation about
the line through them, three non-collinear ones none)."""

import numpy as np

from solver.linalg.kernel import pinned, rigid_modes
from tet_two_body import stacked_boxes


def _held(K, nodes, fixed):
    """K of the box's DOFs with the DOFs ``fixed`` (node, component)
    removed: (K_ff, points of the free DOFs, their components, points and
    components of the fixed ones)."""
    node = np.repeat(np.arange(len(nodes)), 3)
    comp = np.tile(np.arange(3), len(nodes))
    held = np.zeros(len(node), bool)
    for n, c in fixed:
        held[3 * n + c] = True
    free = ~held
    return (K[free][:, free], nodes[node[free]], comp[free],
            nodes[node[held]], comp[held])


def test_pinned_agrees_with_the_kernel_of_K():
    problem, K, _ = stacked_boxes()  # K of all DOFs; the lower box alone
    lower = np.flatnonzero(problem.body == 1)
    nodes = problem.nodes[lower]
    dofs = (3 * lower[:, None] + np.arange(3)).ravel()
    K_low = K[dofs][:, dofs]
    bottom = np.flatnonzero(np.isclose(nodes[:, 2], 0.0))
    corners = [bottom[np.argmin(nodes[bottom, :2].sum(axis=1))],
               bottom[np.argmax(nodes[bottom, 0] - nodes[bottom, 1])],
               bottom[np.argmax(nodes[bottom, :2].sum(axis=1))]]
    cases = {  # supports: rigid motions left free
        "three corners": ([(n, c) for n in corners for c in range(3)], 0),
        "two corners": ([(n, c) for n in corners[::2] for c in range(3)],
                        1),
        "none": ([], 6)}
    for name, (fixed, free_motions) in cases.items():
        K_ff, points, comp, fixed_points, fixed_comp = _held(K_low, nodes,
                                                             fixed)
        R, _ = rigid_modes(K_ff, points, comp)
        assert R.shape[1] == free_motions, name
        assert pinned(fixed_points, fixed_comp) == (free_motions == 0), name


def test_problems_modes_unchanged_by_the_shortcut():
    """The supported stacked boxes take the shortcut (no modes, as the
    SVD says); the upper box pressed by a load keeps its six modes."""
    supported, _, _ = stacked_boxes()
    groups = supported.body[supported.dof_map[:, 0]]
    numeric, _ = rigid_modes(supported.K, supported.dof_points(),
                             supported.dof_map[:, 1], groups=groups)
    assert numeric.shape[1] == 0
    assert supported.rigid_modes()[0].shape[1] == 0
    assert not supported.floating
    floating, _, _ = stacked_boxes(pressure=1e-3)
    assert floating.rigid_modes()[0].shape[1] == 6
