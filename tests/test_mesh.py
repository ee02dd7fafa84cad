"""Boundary topology helpers of solver.geometry.mesh, on hand-made meshes."""

import numpy as np
import pytest

from solver.geometry.mesh import boundary_edges, is_boundary_chain, order_along_boundary


def grid(nx, ny):
    """Structured triangulation of [0, nx] x [0, ny], node id = j*(nx+1)+i."""
    x, y = np.meshgrid(np.arange(nx + 1.0), np.arange(ny + 1.0))
    nodes = np.c_[x.ravel(), y.ravel()]
    cells = []
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i
            b, c, d = a + 1, a + nx + 2, a + nx + 1
            cells += [[a, b, c], [a, c, d]]
    return nodes, np.array(cells)


def test_boundary_edges_of_grid():
    nodes, cells = grid(3, 2)
    edges = boundary_edges(cells)
    assert len(edges) == 2 * (3 + 2)  # perimeter of a 3 x 2 grid
    mid = nodes[edges].mean(axis=1)
    on_boundary = ((mid[:, 0] == 0) | (mid[:, 0] == 3) | (mid[:, 1] == 0)
                   | (mid[:, 1] == 2))
    assert on_boundary.all()


def test_order_along_right_edge_from_shuffled_nodes():
    nodes, cells = grid(3, 4)
    right = np.flatnonzero(nodes[:, 0] == 3)
    shuffled = np.random.default_rng(0).permutation(right)
    chain = order_along_boundary(shuffled, cells, nodes)
    np.testing.assert_array_equal(nodes[chain, 1], [0, 1, 2, 3, 4])
    assert is_boundary_chain(chain, cells)
    assert not is_boundary_chain(chain[[0, 2, 1, 3, 4]], cells)


def test_chain_around_a_corner():
    nodes, cells = grid(2, 2)
    piece = np.flatnonzero((nodes[:, 0] == 2) | (nodes[:, 1] == 2))
    chain = order_along_boundary(piece, cells, nodes)
    np.testing.assert_array_equal(nodes[chain],
                                  [[2, 0], [2, 1], [2, 2], [1, 2], [0, 2]])


def test_not_a_chain():
    nodes, cells = grid(2, 2)
    with pytest.raises(ValueError, match="open chain"):
        order_along_boundary([0, 2], cells, nodes)  # not joined
    with pytest.raises(ValueError, match="open chain"):
        order_along_boundary(np.flatnonzero(
            (nodes[:, 0] % 2 == 0) | (nodes[:, 1] % 2 == 0)), cells)  # closed
    center = 4
    assert not is_boundary_chain([3, center, 5], cells)  # interior node
