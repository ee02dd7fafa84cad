"""Two elastic bodies by dual mortar (solver.contact.two_body) on problems
assembled here without SfePy (tests/tri_elasticity.py).

References: the patch test's pressure is the closed form of two
plane-strain layers in series (σ_xx = 0) and the top reaction of the full
K; the QP cross-check solves the same K, f, D, M with Clarabel, in u, with
no change of variables; full slip is Coulomb's law on the totals."""

import clarabel
import numpy as np
import pytest
import scipy.sparse as sp

from solver import load_problem, save_problem, solve_two_body
from solver.contact.two_body import equivalent_problem, interface_coupling
from tri_elasticity import stacked_blocks, top_reaction, uniform_pressure

MATERIALS = ((1.0, 0.3), (3.0, 0.2))


def patch(slave):
    """Upper block 4 × 2 cells, lower 9 × 3: non-matching interface."""
    return stacked_blocks(n_upper=(4, 2), n_lower=(9, 3),
                          materials=MATERIALS, slave=slave)


@pytest.mark.parametrize("slave", ["upper", "lower"])  # coarse / fine slave
@pytest.mark.parametrize("method", ["min", "fb"])
@pytest.mark.parametrize("condense", [True, False])
def test_patch_test_non_matching(slave, method, condense):
    """Uniform pressure = applied (top reaction / width = closed form) at
    every slave node to 1e-10 relative, fine slave on coarse master and
    the reverse."""
    problem, K, prescribed = patch(slave)
    result = solve_two_body(problem, method=method, condense=condense,
                            tol=1e-12)
    assert result.success
    exact = uniform_pressure((1.0, 1.0), MATERIALS, 1e-3)
    applied = -top_reaction(K, problem, result.u, prescribed) / 1.0
    assert abs(applied - exact) <= 1e-10 * exact
    p = result.contact_pressure
    assert len(p) == (5 if slave == "upper" else 10)
    assert np.abs(p - applied).max() <= 1e-10 * applied
    # the traction on the slave, −λ n: up on the upper block, down on the
    # lower one
    up = 1.0 if slave == "upper" else -1.0
    assert np.allclose(result.traction, [[0, up * applied]] * len(p),
                       rtol=1e-10, atol=0)


@pytest.mark.parametrize("slave", ["upper", "lower"])
def test_node_to_segment_fails_the_patch_test(slave):
    """The same problems with node-to-segment: the pressure is not uniform
    (Taylor & Papadopoulos 1991): ≥ 2 % off somewhere."""
    problem, K, prescribed = patch(slave)
    result = solve_two_body(problem, variant="node-to-segment", tol=1e-12)
    assert result.success
    exact = uniform_pressure((1.0, 1.0), MATERIALS, 1e-3)
    deviation = np.abs(result.contact_pressure / exact - 1).max()
    assert deviation > 0.02, deviation


def clarabel_two_body(problem, coupling):
    """min ½uᵀKu − fᵀu s.t. g̃⁰_j − n_j·(D_jj u_j − Σ_k M_jk u_k) ≥ 0 at
    the covered slave nodes (free DOFs only here), by Clarabel."""
    n = problem.n_dofs
    reduced = np.full(problem.nodes.shape, -1)
    reduced[problem.dof_map[:, 0], problem.dof_map[:, 1]] = np.arange(n)
    covered = np.flatnonzero(np.abs(coupling.coverage - 1) < 1e-8)
    rows, cols, vals = [], [], []
    M = coupling.M.tocoo()
    for c in range(2):
        j = np.arange(len(coupling.D))
        rows += [j, M.row]
        cols += [reduced[coupling.slave_nodes, c], reduced[M.col, c]]
        vals += [coupling.D * coupling.normal[:, c],
                 -M.data * coupling.normal[M.row, c]]
    rows, cols, vals = map(np.concatenate, (rows, cols, vals))
    assert (cols >= 0).all()
    A = sp.csr_matrix((vals, (rows, cols)), shape=(len(coupling.D), n))
    A = A[covered].tocsc()
    # units: u = L x with L = max|f| / k̄, objective / (k̄ L²) (the same
    # minimiser; unscaled Clarabel stops at "AlmostSolved")
    k = problem.K.diagonal().mean()
    L = np.abs(problem.f).max() / k
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = settings.tol_gap_rel = 1e-13
    settings.tol_feas = 1e-13
    settings.max_iter = 400
    solver = clarabel.DefaultSolver(
        sp.triu(problem.K / k).tocsc(), -problem.f / (k * L), A,
        coupling.gap[covered] / L, [clarabel.NonnegativeConeT(len(covered))],
        settings)
    solution = solver.solve()
    assert str(solution.status) == "Solved", solution.status
    return L * np.asarray(solution.x)


@pytest.mark.parametrize("method", ["min", "fb"])
def test_qp_cross_check(method):
    """A curved upper block pressed on a flat one (partial contact): the
    same u as Clarabel's QP in u to 1e-8."""
    problem, K, _ = stacked_blocks(n_upper=(16, 3), n_lower=(11, 3),
                                   materials=MATERIALS, curvature=0.05,
                                   squeeze=2e-3)
    result = solve_two_body(problem, method=method, tol=1e-12)
    assert result.success
    assert 2 <= result.n_contact < problem.n_contact - 2
    reference = clarabel_two_body(problem, interface_coupling(problem))
    err = np.abs(result.u - reference).max() / np.abs(reference).max()
    assert err <= 1e-8, err


def test_equivalent_problem_is_the_same_energy():
    """K̃ = T⁻ᵀKT⁻¹, f̃ = T⁻ᵀf: the energies of v and u = T⁻¹v agree."""
    problem, _, _ = patch("lower")
    equivalent, T_inv, _ = equivalent_problem(problem,
                                              interface_coupling(problem))
    v = np.random.default_rng(0).normal(size=problem.n_dofs)
    u = T_inv @ v
    assert np.isclose(v @ equivalent.K @ v, u @ problem.K @ u, rtol=1e-12)
    assert np.isclose(equivalent.f @ v, problem.f @ u, rtol=1e-12)


@pytest.mark.parametrize("formulation", ["projection", "thesis"])
@pytest.mark.parametrize("coulomb", ["lagged", "implicit"])
def test_full_slip_friction_force(formulation, coulomb):
    """A block squeezed on a block, then its top shifted far: every node
    slips and the total friction force Σ D_jj g_t,j = f_c Σ D_jj λ_j
    (to 1e-8 relative)."""
    problem, _, _ = stacked_blocks(n_upper=(5, 2), n_lower=(7, 2),
                                   materials=MATERIALS, squeeze=1e-3,
                                   shift=5e-3)
    fc = 0.3
    result = solve_two_body(problem, friction=fc, formulation=formulation,
                            coulomb=coulomb, method="fb", tol=1e-12)
    assert result.success, result.message
    D = result.mortar_D
    # the bound used: f_c × this step's λ (implicit), the previous one's
    # (lagged)
    normal_force = D @ result.contact_pressure[-1 if coulomb == "implicit"
                                                 else -2]
    friction_force = D @ result.friction_traction[-1]
    assert normal_force > 0
    assert result.slip[-1].sum() == result.in_contact[-1].sum() > 0
    assert abs(abs(friction_force) - fc * normal_force) <= \
        1e-8 * fc * normal_force


def test_prescribed_master_displacement_shifts_the_gaps(tmp_path):
    """A rigid master (every DOF prescribed) moved by u_D = (−0.02, 0)
    gives the same u as the master's nodes moved there with u_D = 0:
    s_j gains n_j·Σ_k P_jk u_D,k (module docstring of two_body)."""
    from tri_elasticity import block_on_parabola_body

    moved = block_on_parabola_body(1, mesh="block_118.mesh", rigid=True)
    n0 = int((moved.body == 0).sum())
    moved.u_prescribed[n0:] = [-0.02, 0.0]
    placed = block_on_parabola_body(1, mesh="block_118.mesh", rigid=True)
    placed.nodes[n0:] += [-0.02, 0.0]
    a = solve_two_body(moved, tol=1e-12)
    b = solve_two_body(placed, tol=1e-12)
    assert a.success and b.success and a.n_contact > b.n_contact - 1 > 0
    assert np.abs(a.u - b.u).max() <= 1e-12 * np.abs(b.u).max()
    # a rigid master has nodes but no free DOFs: its file loads back (the
    # archive's size bounds once capped the nodes by the free DOFs)
    save_problem(tmp_path / "moved.npz", moved)
    again = solve_two_body(load_problem(tmp_path / "moved.npz"), tol=1e-12)
    assert np.abs(again.u - a.u).max() <= 1e-14 * np.abs(a.u).max()
    # and the friction runs refuse it (their steps would scale it)
    from solver.errors import SolverError

    with pytest.raises(SolverError, match="prescribed displacements"):
        solve_two_body(moved, friction=0.3, steps=2)


def test_three_blocks_two_pairs():
    """Three stacked blocks, two contact pairs (top on middle, middle on
    bottom), non-matching meshes: the pressure is uniform and equal to the
    closed form of three layers in series on both interfaces."""
    from tet_elasticity import mesh_problem, rectangle, stiffness
    from tri_elasticity import attach_interface

    layers = [((3, 2), (1.0, 0.3)), ((5, 2), (2.0, 0.25)),
              ((4, 2), (1.5, 0.2))]                       # top to bottom
    blocks, offset = [], 0
    for i, (cells_xy, _) in enumerate(layers):
        nodes, tri = rectangle(cells_xy, (1.0, 1.0))
        blocks.append((nodes + [0.0, 2.0 - i], tri, offset))
        offset += len(nodes)
    nodes = np.concatenate([b[0] for b in blocks])
    cells = np.concatenate([b[1] + b[2] for b in blocks])
    body = np.concatenate([np.full(len(b[0]), i) for i, b in enumerate(blocks)])
    K = sp.block_diag([stiffness(b[0], b[1], *layers[i][1])
                       for i, b in enumerate(blocks)]).tocsr()
    prescribed = np.full(nodes.shape, np.nan)
    top, bottom = np.isclose(nodes[:, 1], 3.0), np.isclose(nodes[:, 1], 0.0)
    prescribed[top, 1], prescribed[bottom, 1] = -1e-3, 0.0
    left = np.isclose(nodes[:, 0], 0)
    prescribed[top & left, 0] = prescribed[bottom & left, 0] = 0.0
    # the middle block would float (its K singular): hold its mid-height
    # left node at the exact solution's values (σ_yy uniform, σ_xx = 0,
    # u_x = ε_xx x)
    exact = uniform_pressure([1.0] * 3, [m for _, m in layers], 1e-3)
    strain = [exact * (1 - nu ** 2) / E for _, (E, nu) in layers]
    middle = (body == 1) & left & np.isclose(nodes[:, 1], 1.5)
    prescribed[middle] = [0.0, -(strain[2] + strain[1] / 2)]
    # and u_x = 0 at its top-left node (no rotation; a master node of the
    # top pair, so a Dirichlet master DOF in the gaps)
    prescribed[(body == 1) & left & np.isclose(nodes[:, 1], 2.0), 0] = 0.0

    def edge(b, y, forward):
        ids = np.flatnonzero((body == b) & np.isclose(nodes[:, 1], y))
        ids = ids[np.argsort(nodes[ids, 0] * (1 if forward else -1))]
        return np.c_[ids[:-1], ids[1:]]

    slave = [edge(0, 2.0, True), edge(1, 1.0, True)]     # bottoms: +x
    master = [edge(1, 2.0, False), edge(2, 1.0, False)]  # tops: −x
    contact = np.concatenate([np.r_[s[:, 0], s[-1, 1]] for s in slave])
    problem = mesh_problem(nodes, cells, K, prescribed, contact,
                           np.concatenate(slave))
    attach_interface(problem, body, np.concatenate(slave),
                     np.concatenate(master),
                     [{"name": f"layer {i}", "E": m[0], "nu": m[1]}
                      for i, (_, m) in enumerate(layers)], 0)
    problem.mortar_slave_pair = np.repeat([0, 1], [len(s) for s in slave])
    problem.mortar_master_pair = np.repeat([0, 1], [len(m) for m in master])
    problem.meta.update(slave_body=[0, 1], master_body=[1, 2])
    problem.validate()  # the format-v4 loader's checks
    result = solve_two_body(problem, tol=1e-12)
    assert result.success
    assert len(result.contact_pressure) == 4 + 6
    assert np.abs(result.contact_pressure / exact - 1).max() <= 1e-10
