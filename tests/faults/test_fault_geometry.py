"""Degenerate geometry (issue 16, class 2).

Each case is refused with one :class:`~solver.errors.SolverError` line that
names the nodes, or solved correctly: a contact boundary of one node,
coincident contact nodes, a zero-area triangle on Γc, coordinates scaled by
1e±300 or shifted by 1e17, every contact node supported, and a contact
boundary that turns a corner of the body. Reference values are analytic
(distances to straight obstacle lines; dimensional analysis of the scaled
block: in plane elasticity K does not change with the length unit, f and
the gaps scale with it) or from SciPy's sparse direct solver.
"""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from fault_tools import assert_one_error_line, run_cli, write
from fault_tools import block  # noqa: F401  (the fixture)
from solver.contact import contact_geometry
from solver.errors import GeometryError, ProblemError, SolverError
from solver.examples import two_dof_bar
from solver.geometry.curves import GapError, gap_from_obstacle
from solver.geometry.curves.normals import boundary_normals, outward_sign, spline_tangents
from solver.geometry.curves.parametric import ParametricCurve
from solver.geometry.curves.polyline import PolylineCurve
from solver.problem import ContactProblem, load_problem, save_problem


def refused(path, phrase):
    with pytest.raises(ProblemError) as info:
        load_problem(path)
    assert "\n" not in str(info.value) and phrase in str(info.value), \
        str(info.value)


def csr_keys(name, A):
    A = sp.csr_matrix(A)
    return {f"{name}_data": A.data, f"{name}_indices": A.indices,
            f"{name}_indptr": A.indptr,
            f"{name}_shape": np.array(A.shape)}


def opposite_vertex(arrays, a, b):
    """The third vertex of the triangle on the boundary edge (a, b)."""
    cells = arrays["cells"]
    has = np.isin(cells, [a, b]).sum(axis=1) == 2
    cell = cells[np.flatnonzero(has)[0]]
    return int(cell[~np.isin(cell, [a, b])][0])


# --------------------------------------------------------------------------
# refused, naming the nodes

def test_contact_boundary_of_one_node(block, tmp_path):
    c = block["contact_nodes"]
    arrays = dict(block, contact_nodes=c[5:6],
                  contact_dofs=block["contact_dofs"][5:6],
                  **csr_keys("M", [[1.0]]))
    refused(write(tmp_path, arrays), f"contact_nodes: the contact boundary "
                                     f"Γc is the single node {c[5]}")


def test_coincident_contact_nodes(block, tmp_path, capsys):
    c = block["contact_nodes"]
    nodes = block["nodes"].copy()
    nodes[c[4]] = nodes[c[3]]
    path = write(tmp_path, dict(block, nodes=nodes))
    refused(path, f"contact nodes {c[3]} and {c[4]} coincide")
    assert_one_error_line(*run_cli([path], capsys), "coincide")


def test_zero_area_triangle_on_the_contact_boundary(block, tmp_path):
    c = block["contact_nodes"]
    inner = opposite_vertex(block, c[3], c[4])
    nodes = block["nodes"].copy()
    nodes[inner] = (nodes[c[3]] + nodes[c[4]]) / 2 - [0.0, 0.1]
    nodes[inner, 0] = 5.0  # on the line x = 5 of the edge: zero area
    refused(write(tmp_path, dict(block, nodes=nodes)), "has zero area")


@pytest.mark.parametrize("factor, shift, phrase", [
    (1e300, 0.0, "out of the supported range"),
    (1e-300, 0.0, "double precision cannot resolve it"),
    (1.0, 1e17, "double precision cannot resolve it"),
    (1e40, 0.0, "out of the supported range"),
])
def test_coordinates_double_precision_cannot_hold(block, tmp_path, capsys,
                                                  factor, shift, phrase):
    path = write(tmp_path, dict(block, nodes=block["nodes"] * factor
                                + shift))
    refused(path, phrase)
    assert_one_error_line(*run_cli([path], capsys), phrase)


def test_api_errors_are_solver_errors():
    """The gap and normal functions raise SolverErrors (one line), not bare
    ValueErrors, on bad points."""
    with pytest.raises(SolverError, match="shape"):
        gap_from_obstacle(np.zeros(3), PolylineCurve([[0, 0], [1, 0]]),
                          (0, 1))
    with pytest.raises(GeometryError, match="coincide"):
        spline_tangents([[0.0, 0.0], [0.0, 0.0], [1.0, 0.0]])
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    cells = np.array([[0, 1, 2], [0, 2, 3]])
    with pytest.raises(GeometryError, match=r"1 node \(node 2\)"):
        outward_sign(square, cells, [2])
    flat = square.copy()
    flat[2] = [1.0, 0.0]
    with pytest.raises(GeometryError, match="contact nodes 1 and 2 coincide"):
        boundary_normals(flat, cells, [0, 1, 2])


@pytest.mark.parametrize("argv, phrase", [
    (["--search-interval", "1", "0"], "need finite t0 < t1"),
    (["--search-interval", "nan", "1"], "need finite t0 < t1"),
    (["--search-interval", "1", "inf"], "need finite t0 < t1"),
    (["--search-interval", "x", "1"], "not a number"),
])
def test_bad_search_interval(block, tmp_path, capsys, argv, phrase):
    path = write(tmp_path, block)
    assert_one_error_line(*run_cli([path, *argv], capsys), phrase)


def test_search_interval_of_a_discrete_problem(tmp_path, capsys):
    path = save_problem(tmp_path / "bar.npz", two_dof_bar())
    assert_one_error_line(*run_cli([path, "--search-interval", "0", "1"],
                                   capsys), "--search-interval (0.0, 1.0) "
                                            "is not supported for 2D, "
                                            "discrete")


# --------------------------------------------------------------------------
# valid: solved correctly

def test_scaled_and_shifted_block_gives_scaled_gaps(block, tmp_path):
    """Lengths in other units (×1e-3, ×1e3) and a body shifted by 1e4:
    the gaps scale with the unit, the shift changes nothing."""
    base = contact_geometry(load_problem(write(tmp_path, block)))
    for factor, shift in ((1e-3, 0.0), (1e3, 0.0), (1.0, 1e4)):
        arrays = dict(block, nodes=block["nodes"] * factor + shift,
                      obstacle_x=np.array(f"{shift!r} + {factor!r}*(5.05 + "
                                          f"0.005*(t/{factor!r})**2)"),
                      obstacle_y=np.array(f"{shift!r} + t"))
        geometry = contact_geometry(load_problem(write(tmp_path, arrays,
                                                       "s.npz")))
        np.testing.assert_allclose(geometry.gap, factor * base.gap,
                                   rtol=1e-9, atol=1e-12 * factor)
        np.testing.assert_allclose(geometry.normal, base.normal, atol=1e-9)


def test_every_contact_node_supported_is_a_trivial_solve(block, tmp_path,
                                                         capsys):
    """All contact nodes clamped (their DOFs eliminated): no contact
    unknowns; the solution is u = K⁻¹f (SciPy's spsolve)."""
    K = sp.csr_matrix((block["K_data"], block["K_indices"],
                       block["K_indptr"]), shape=tuple(block["K_shape"]))
    c = block["contact_nodes"]
    dof_map = block["dof_map"]
    keep = ~np.isin(dof_map[:, 0], c)
    K2 = K[keep][:, keep]
    f2 = block["f"][keep]
    arrays = dict(block, **csr_keys("K", K2), f=f2, dof_map=dof_map[keep],
                  contact_dofs=np.full((len(c), 2), -1))
    path = write(tmp_path, arrays)
    problem = load_problem(path)
    assert contact_geometry(problem).gap.shape == (0,)
    code, out, err = run_cli([path, "-o", tmp_path / "out"], capsys)
    assert code == 0, err
    with np.load(tmp_path / "out" / "result.npz") as result:
        u = result["u"]
    np.testing.assert_allclose(u, sla.spsolve(K2.tocsc(), f2), rtol=1e-10,
                               atol=1e-12 * np.abs(u).max())


# --------------------------------------------------------------------------
# a contact boundary around a corner

def square_problem(n=6, gap=0.1, chain=None, obstacle=None):
    """The unit square, n×n cells of two triangles, clamped on x = 0; Γc
    runs along the bottom edge and turns up the right edge at (1, 0) (or
    follows ``chain``, a function of the (n+1)×(n+1) node numbers). The
    obstacle is the L-shaped polyline a distance ``gap`` outside both
    edges (or ``obstacle``). K is an SPD stand-in (only the geometry is
    tested)."""
    x, y = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1))
    nodes = np.column_stack([x.ravel(), y.ravel()])
    k = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = (k[:-1, :-1].ravel(), k[:-1, 1:].ravel(), k[1:, 1:].ravel(),
                  k[1:, :-1].ravel())
    cells = np.concatenate([np.column_stack([a, b, c]),
                            np.column_stack([a, c, d])])
    free = np.flatnonzero(nodes[:, 0] > 0)
    dof_map = np.column_stack([np.repeat(free, 2),
                               np.tile([0, 1], len(free))])
    chain = np.r_[k[0, 1:], k[1:, -1]] if chain is None else chain(k)
    lookup = {(int(p), int(q)): i for i, (p, q) in enumerate(dof_map)}
    contact_dofs = np.array([[lookup.get((int(p), 0), -1),
                              lookup.get((int(p), 1), -1)] for p in chain])
    if obstacle is None:
        obstacle = PolylineCurve([[-1.0, -gap], [1 + gap, -gap],
                                  [1 + gap, 2.0]])
    m = len(dof_map)
    return ContactProblem(
        K=sp.identity(m, format="csr"), f=np.zeros(m),
        M=sp.identity(len(chain), format="csr"), contact_dofs=contact_dofs,
        meta={"E": 1.0, "nu": 0.3, "plane": "strain", "load": {},
              "mesh": "unit square"},
        nodes=nodes, cells=cells, dof_map=dof_map,
        u_prescribed=np.zeros_like(nodes), contact_nodes=chain,
        obstacle=obstacle), n


def test_corner_normals_are_one_sided(tmp_path):
    problem, n = square_problem()
    normals = boundary_normals(problem.nodes, problem.cells,
                               problem.contact_nodes)
    corner = n - 1  # position of (1, 0) in the chain
    np.testing.assert_array_equal(normals[:corner], [[0.0, -1.0]] * corner)
    np.testing.assert_array_equal(normals[corner + 1:],
                                  [[1.0, 0.0]] * (len(normals) - corner - 1))
    np.testing.assert_allclose(normals[corner], [2 ** -0.5, -2 ** -0.5])


@pytest.mark.parametrize("mode", ["obstacle", "body"])
def test_corner_gaps_have_the_right_sign_and_size(tmp_path, mode):
    """Through a problem file: every gap is the analytic distance 0.1 to
    the L-shaped obstacle (0.1·√2 along the bisector at the corner)."""
    problem, n = square_problem()
    problem = load_problem(save_problem(tmp_path / "sq.npz", problem))
    geometry = contact_geometry(problem, mode)
    expected = np.full(len(problem.contact_nodes), 0.1)
    if mode == "body":
        expected[n - 1] = 0.1 * np.sqrt(2)
    np.testing.assert_allclose(geometry.gap, expected, atol=1e-12)


def test_api_bad_values_are_solver_errors():
    """Text, empty meshes and ragged shapes through the public geometry
    functions: SolverErrors, never a bare ValueError."""
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    cases = [
        lambda: gap_from_obstacle([["a", "b"]], PolylineCurve(
            [[0, 0], [1, 0]]), (0, 1)),
        lambda: gap_from_obstacle([[0.0, 1.0]], PolylineCurve(
            [[0, 0], [1, 0]]), ("x", 1)),
        lambda: boundary_normals(square, np.zeros((0, 3), int), [0, 1]),
        lambda: boundary_normals(square, [[0, 1]], [0, 1]),
        lambda: outward_sign(square, [[0, 1, 2]], [0, 7]),
    ]
    for case in cases:
        with pytest.raises(SolverError):
            case()


def test_nodes_past_a_corner_keep_the_sign_of_their_gap(tmp_path):
    """Γc up the right edge x = 1 and on along the top edge y = 1 towards
    x = 0; the obstacle x = 1.05 + 0.2 (t - 0.5)², y = t lies right of the
    body. The top-edge nodes are outside the obstacle: their nearest
    obstacle points (dense brute-force search, the reference) are at a
    positive distance, though their outward normal (0, 1) points away from
    the obstacle's. The gaps from the obstacle equal those distances."""
    n = 6
    curve = ParametricCurve("1.05 + 0.2*(t - 0.5)**2", "t")
    problem, _ = square_problem(
        n, chain=lambda k: np.r_[k[:, -1], k[-1, -2:0:-1]], obstacle=curve)
    problem = load_problem(save_problem(tmp_path / "top.npz", problem))
    geometry = contact_geometry(problem, "obstacle")
    points = problem.nodes[problem.contact_nodes[geometry.index]]
    ts = np.linspace(-3, 4, 700001)
    dense = curve.point(ts)
    distance = np.min(np.hypot(dense[None, :, 0] - points[:, None, 0],
                               dense[None, :, 1] - points[:, None, 1]),
                      axis=1)
    top = points[:, 1] == 1.0
    assert top.sum() >= n - 1 and (geometry.gap > 0).all()
    np.testing.assert_allclose(geometry.gap, distance, atol=1e-8)
    # along the body's normals the top-edge nodes see no obstacle: refused
    with pytest.raises(GapError, match="misses the obstacle"):
        contact_geometry(problem, "body")
