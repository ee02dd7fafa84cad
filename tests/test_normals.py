"""Outward normals of Γc from the parametric natural cubic spline (§2.1.3).

Reference normals are analytic: radial directions on circular arcs, the
constant normal of a straight edge.
"""

import numpy as np
import pytest

from solver.geometry.curves.normals import (boundary_normals, chord_parameters,
                            outward_sign, spline_normals, spline_tangents)

UNIT_SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
SQUARE_CELLS = np.array([[0, 1, 2], [0, 2, 3]])


def arc(n, spacing="graded"):
    """``n`` nodes on the unit circle, angles -60°..60°, counter-clockwise.

    ``"graded"``: the spacing varies smoothly (u + 0.15 sin(pi u)); on a
    uniformly spaced circle the interior normals would be exact by symmetry
    up to the end effect, which hides the interior convergence order.
    ``"rough"``: every other interior node is shifted by 0.3 h, so the
    spacing jumps from node to node (as on an unstructured mesh).
    """
    u = np.linspace(0.0, 1.0, n)
    if spacing == "graded":
        u = u + 0.15 * np.sin(np.pi * u)
    else:
        u[1:-1:2] += 0.3 / (n - 1)
    angle = np.radians(-60.0 + 120.0 * u)
    return np.column_stack([np.cos(angle), np.sin(angle)])


def arc_errors(n, spacing="graded"):
    points = arc(n, spacing)
    # Counter-clockwise chain with the disc on its left: outward is the
    # tangent rotated clockwise, sign = 1; the exact normal is the point.
    error = np.linalg.norm(spline_normals(points, 1) - points, axis=1)
    u = np.linspace(0.0, 1.0, n)
    middle = (u >= 0.25) & (u <= 0.75)
    return error[middle].max(), max(error[0], error[-1])


def test_arc_normals_converge():
    sizes = [17, 33, 65, 129]
    errors = np.array([arc_errors(n) for n in sizes])
    h = 1.0 / (np.array(sizes) - 1)
    order = np.log(errors[:-1] / errors[1:]) \
        / np.log(h[:-1] / h[1:])[:, None]
    interior, ends = order[:, 0], order[:, 1]
    # Middle half of the chain: measured orders 9.1 (pre-asymptotic, the
    # end effect still decaying), 4.6, 4.0 -> fourth order.
    assert (interior >= 3.5).all(), interior
    assert errors[-1, 0] < 2e-9
    # End nodes: the natural condition X'' = 0 is wrong on a curved
    # boundary, measured order 1.00 (error about 0.9 h).
    assert np.allclose(ends, 1.0, atol=0.05), ends
    assert errors[-1, 1] < 0.01


def test_arc_normals_rough_spacing_third_order():
    sizes = [33, 65, 129]
    errors = np.array([arc_errors(n, "rough") for n in sizes])
    order = np.log2(errors[:-1] / errors[1:])  # h halves
    # Measured: interior 3.03, 3.00; ends 1.00, 1.00.
    assert (order[:, 0] > 2.8).all() and np.allclose(order[:, 1], 1, atol=.05)


def test_end_error_decays_into_the_chain():
    # The natural-end error decays by about 2 - sqrt(3) = 0.27 per node.
    points = arc(65)
    error = np.linalg.norm(spline_normals(points, 1) - points, axis=1)
    ratio = error[1:4] / error[:3]
    assert np.allclose(ratio, 2 - np.sqrt(3), atol=0.03), ratio


def test_straight_chain_is_exact():
    direction = np.array([3.0, 4.0]) / 5.0
    s = np.array([0.0, 0.1, 0.35, 0.4, 1.2, 1.25, 2.0])
    points = np.array([1.0, -2.0]) + s[:, None] * direction
    normals = spline_normals(points, 1)
    assert np.allclose(normals, [4.0 / 5.0, -3.0 / 5.0], atol=1e-14)
    assert np.allclose(spline_normals(points, -1), -normals, atol=0)


def test_two_points_give_the_segment_normal():
    tangents = spline_tangents([[0.0, 0.0], [2.0, 2.0]])
    assert np.allclose(tangents, np.sqrt(0.5), atol=1e-15)
    assert np.allclose(spline_normals([[0.0, 0.0], [2.0, 2.0]], 1),
                       [np.sqrt(0.5), -np.sqrt(0.5)], atol=1e-15)


def test_chord_parameters_and_bad_input():
    assert np.allclose(chord_parameters([[0, 0], [3, 4], [3, 5]]),
                       [0, 5, 6])
    with pytest.raises(ValueError, match="coincide"):
        spline_normals([[0, 0], [1, 1], [1, 1]])
    with pytest.raises(ValueError, match="at least 2"):
        spline_normals([[0, 0]])
    with pytest.raises(ValueError, match="sign"):
        spline_normals([[0, 0], [1, 1]], 0)


def test_unit_square_right_edge():
    assert outward_sign(UNIT_SQUARE, SQUARE_CELLS, [1, 2]) == 1
    assert outward_sign(UNIT_SQUARE, SQUARE_CELLS, [2, 1]) == -1
    for chain in ([1, 2], [2, 1]):
        normals = boundary_normals(UNIT_SQUARE, SQUARE_CELLS, chain)
        assert np.array_equal(normals, [[1.0, 0.0], [1.0, 0.0]])
    # Around a corner: bottom then right edge.
    # Around a corner (bottom edge, then right edge): the spline rounds the
    # corner symmetrically, so the corner normal is the diagonal.
    normals = boundary_normals(UNIT_SQUARE, SQUARE_CELLS, [0, 1, 2])
    assert np.allclose(normals[1], [np.sqrt(0.5), -np.sqrt(0.5)])
    assert normals[0] @ [0.0, -1.0] > 0.5 and normals[2] @ [1.0, 0.0] > 0.5


def block_mesh(nx=3, ny=8):
    """Structured triangles on the thesis block [-5, 5] x [-10, 10]."""
    x, y = np.meshgrid(np.linspace(-5, 5, nx + 1),
                       np.linspace(-10, 10, ny + 1))
    nodes = np.column_stack([x.ravel(), y.ravel()])
    k = np.arange((nx + 1) * (ny + 1)).reshape(ny + 1, nx + 1)
    a, b, c, d = (k[:-1, :-1].ravel(), k[:-1, 1:].ravel(), k[1:, 1:].ravel(),
                  k[1:, :-1].ravel())
    cells = np.concatenate([np.column_stack([a, b, c]),
                            np.column_stack([a, c, d])])
    return nodes, cells, k[:, -1]  # right edge, bottom -> top


def test_thesis_block_right_edge_is_exactly_one_zero():
    nodes, cells, chain = block_mesh()
    assert outward_sign(nodes, cells, chain) == 1
    for order in (chain, chain[::-1]):
        normals = boundary_normals(nodes, cells, order)
        assert np.array_equal(normals, np.tile([1.0, 0.0], (len(chain), 1)))


def test_fan_on_an_arc_reversed_chain_still_outward():
    arc_points = arc(33)
    nodes = np.vstack([[0.0, 0.0], arc_points])
    cells = np.column_stack([np.zeros(32, int), np.arange(1, 33),
                             np.arange(2, 34)])
    chain = np.arange(1, 34)
    forward = boundary_normals(nodes, cells, chain)
    backward = boundary_normals(nodes, cells, chain[::-1])[::-1]
    assert np.allclose(forward, backward, atol=1e-12)
    assert (np.sum(forward * arc_points, axis=1) > 0.99).all()


def test_outward_sign_rejects_bad_chains():
    with pytest.raises(ValueError, match="2 triangles"):
        outward_sign(UNIT_SQUARE, SQUARE_CELLS, [0, 2])  # the diagonal
    with pytest.raises(ValueError, match="0 triangles"):
        outward_sign(UNIT_SQUARE, SQUARE_CELLS, [1, 3])
    with pytest.raises(ValueError, match="left of 1 and right of 1"):
        outward_sign(UNIT_SQUARE, SQUARE_CELLS, [1, 2, 1])
    with pytest.raises(ValueError, match="at least 2"):
        outward_sign(UNIT_SQUARE, SQUARE_CELLS, [1])
