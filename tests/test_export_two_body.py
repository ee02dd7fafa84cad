"""The two-body SfePy problem files (issue 19) export format v4 files.

Independent references: the closed-form P1 plane-strain element matrices
(K of each body with its own E, ν: tests/test_problem_two_body.py), the
exact uniform-stress solution of the patch test (σ_yy = −p in both blocks,
p = δ / Σ h_b/E'_b), the analytic P1 edge mass matrix (M), the circles'
gap formula (R1 − √(R1² − x²)) + (R2 − √(R2² − x²)) for the cylinders,
the rigid-obstacle export of the same block (block_obstacle.py), and a
node-to-segment frictionless solve by scipy's NNLS for the cylinders'
contact width. The mortar solutions' physics (patch test to 1e-10, Hertz,
Cattaneo–Mindlin, rigid limit) is tested with solver.contact.
"""

import subprocess
import sys

import numpy as np
import pytest
import scipy.sparse.linalg as sla

from conftest import ROOT
from solver.problem import load_problem
from test_export import export_module, p1_edge_mass
from test_problem_two_body import _stiffness

PROBLEMS = ROOT / "sfepy_problems"
MESHES = ROOT / "meshes"


def export(tmp_path, filename, name, **define):
    """Export a problem file in-process (no SfePy solve) and load it."""
    path = tmp_path / f"{name}.npz"
    export_module().export_only(PROBLEMS / filename, output=str(path),
                                **define)
    return load_problem(path)


def outward(problem, segments):
    """Unit outward normals (t_y, −t_x)/|t| of segments (the contract)."""
    t = problem.nodes[segments[:, 1]] - problem.nodes[segments[:, 0]]
    return np.stack([t[:, 1], -t[:, 0]], axis=1) \
        / np.hypot(t[:, 0], t[:, 1])[:, None]


def assert_block_diagonal_spd(problem):
    of = problem.body[problem.dof_map[:, 0]]
    coo = problem.K.tocoo()
    assert (of[coo.row] == of[coo.col]).all()
    smallest = sla.eigsh(problem.K.tocsc(), k=1, sigma=0, which="LM",
                         return_eigenvectors=False)[0]
    assert smallest > 0


# -- patch test ---------------------------------------------------------

@pytest.fixture(scope="module", params=["upper", "lower"])
def patch(request, tmp_path_factory):
    folder = tmp_path_factory.mktemp("patch")
    return export(folder, "two_body_patch.py", f"patch_{request.param}",
                  mesh=str(MESHES / "two_body_patch.mesh"),
                  slave=request.param)


def test_patch_bodies_and_interface(patch):
    slave_body = patch.meta["slave_body"]
    assert patch.is_mortar and patch.n_bodies == 2 and patch.obstacle is None
    assert patch.meta["master_body"] == 1 - slave_body
    # body 0 is the lower block, 1 the upper (cell groups 1, 2)
    centre = patch.nodes[patch.cells].mean(axis=1)[:, 1]
    np.testing.assert_array_equal(patch.body[patch.cells[:, 0]],
                                  (centre > 0.5).astype(int))
    on = np.flatnonzero(patch.nodes[:, 1] == 0.5)
    slave = on[patch.body[on] == slave_body]
    master = on[patch.body[on] != slave_body]
    assert len(slave) == (9 if slave_body == 1 else 6)  # 8 and 5 segments
    assert sorted(patch.contact_nodes) == sorted(slave)
    assert (patch.contact_dofs >= 0).all()  # the x pins are off Γc
    assert sorted(np.unique(patch.mortar_master)) == sorted(master)
    # the body on the left: upper bottom left to right, lower top reverse
    sign = -1 if slave_body == 1 else 1
    np.testing.assert_allclose(outward(patch, patch.mortar_slave),
                               [[0, sign]] * len(patch.mortar_slave))
    np.testing.assert_allclose(outward(patch, patch.mortar_master),
                               [[0, -sign]] * len(patch.mortar_master))
    x = patch.nodes[patch.contact_nodes, 0]
    assert (np.diff(x) * sign < 0).all()  # the chain in segment direction
    M = p1_edge_mass(x * -sign)
    np.testing.assert_allclose(patch.M.toarray(), M, rtol=1e-12, atol=1e-15)


def test_patch_K_is_the_two_bodies_stiffness(patch):
    """K = the free rows and columns of the closed-form P1 assembly with
    each block's own E, ν; block-diagonal and positive definite."""
    bodies = patch.meta["bodies"]
    K = 0
    for b in (0, 1):
        cells = patch.cells[patch.body[patch.cells[:, 0]] == b]
        K = K + _stiffness(patch.nodes, cells, bodies[b]["E"],
                           bodies[b]["nu"])
    free = 2 * patch.dof_map[:, 0] + patch.dof_map[:, 1]
    reference = K[free][:, free]
    assert abs(patch.K - reference).max() <= 1e-10 * abs(reference).max()
    assert_block_diagonal_spd(patch)


def test_patch_exact_solution_balances_at_the_interface(patch):
    """The uniform uniaxial stress σ_yy = −p (u_x = 0 on x = 0, u_y = 0
    on y = 0, u_y = −δ on y = 1) satisfies the exported K u = f except at
    the interface nodes, where the residual is the contact force: p per
    unit width, pushing the blocks apart (up on the upper block)."""
    meta = patch.meta
    p, delta = meta["p_exact"], meta["delta"]
    (E0, nu0), (E1, nu1) = ((b["E"], b["nu"]) for b in meta["bodies"])
    strain = [p * (1 - nu ** 2) / E for E, nu in ((E0, nu0), (E1, nu1))]
    lateral = [p * nu * (1 + nu) / E for E, nu in ((E0, nu0), (E1, nu1))]
    x, y = patch.nodes[:, 0], patch.nodes[:, 1]
    upper = patch.body == 1
    u = np.zeros_like(patch.nodes)
    u[:, 0] = np.where(upper, lateral[1], lateral[0]) * x
    u[:, 1] = np.where(upper, -strain[0] * 0.5 - strain[1] * (y - 0.5),
                       -strain[0] * y)
    assert u[y == 1.0, 1] == pytest.approx(-delta, rel=1e-12)
    np.testing.assert_allclose(patch.u_prescribed[y == 1.0, 1], -delta)
    residual = patch.K @ u[patch.dof_map[:, 0], patch.dof_map[:, 1]] \
        - patch.f
    node = patch.dof_map[:, 0]
    interface = y[node] == 0.5
    scale = p  # force per unit width
    assert abs(residual[~interface]).max() <= 1e-9 * scale
    vertical = patch.dof_map[:, 1] == 1
    for b, sign in ((1, 1), (0, -1)):  # K u - f = the contact force
        mine = interface & vertical & (patch.body[node] == b)
        assert residual[mine].sum() == pytest.approx(sign * p, rel=1e-9)
        assert (sign * residual[mine] > 0).all()


def test_patch_slide_load_path(tmp_path):
    """load='slide': the lower bottom clamped, the upper top clamped and
    moved to (0, -δ) frictionless, then to (shift, -δ) with friction."""
    problem = export(tmp_path, "two_body_patch.py", "slide", load="slide",
                     mesh=str(MESHES / "two_body_patch.mesh"))
    np.testing.assert_array_equal(problem.load_path_friction, [0, 1])
    np.testing.assert_array_equal(problem.load_path_steps, [5, 10])
    y = problem.nodes[:, 1]
    delta, shift = problem.meta["delta"], problem.meta["load"]["shift"]
    top = problem.load_path_prescribed[:, y == 1.0]
    np.testing.assert_allclose(top[0], [[0, -delta]] * (y == 1.0).sum())
    np.testing.assert_allclose(top[1], [[shift, -delta]] * (y == 1.0).sum())
    fixed = np.ones(problem.nodes.shape, bool)
    fixed[problem.dof_map[:, 0], problem.dof_map[:, 1]] = False
    np.testing.assert_array_equal(fixed.all(axis=1), (y == 0) | (y == 1))
    assert "p_exact" not in problem.meta
    assert (problem.contact_dofs >= 0).all()


# -- two cylinders ------------------------------------------------------

@pytest.fixture(scope="module")
def cylinders(tmp_path_factory):
    return export(tmp_path_factory.mktemp("cyl"), "two_cylinders.py",
                  "two_cylinders",
                  mesh=str(MESHES / "two_body_cylinders.mesh"))


@pytest.fixture(scope="module")
def cylinders_cm(tmp_path_factory):
    return export(tmp_path_factory.mktemp("cm"), "two_cylinders.py",
                  "two_cylinders_cm",
                  mesh=str(MESHES / "two_body_cylinders_identical.mesh"),
                  identical=True, load="cattaneo")


def test_cylinders_interface_geometry(cylinders, cylinders_cm):
    """Slave nodes on the upper arc, master segments on the lower arc,
    outward normals facing each other, and the initial vertical gap from
    the master segments = the circles' gap up to the chord error."""
    for problem in (cylinders, cylinders_cm):
        m = problem.meta
        R1, R2 = m["R1"], m["R2"]
        assert m["slave_body"] == 1 and m["master_body"] == 0
        s = problem.nodes[problem.contact_nodes]
        np.testing.assert_allclose(np.hypot(s[:, 0], s[:, 1] - R1), R1,
                                   rtol=1e-12)
        a, b = (problem.nodes[problem.mortar_master[:, k]] for k in (0, 1))
        for end in (a, b):
            np.testing.assert_allclose(np.hypot(end[:, 0], end[:, 1] + R2),
                                       R2, rtol=1e-12)
        assert (problem.body[problem.contact_nodes] == 1).all()
        assert (problem.body[problem.mortar_master] == 0).all()
        assert (outward(problem, problem.mortar_slave)[:, 1] < 0).all()
        assert (outward(problem, problem.mortar_master)[:, 1] > 0).all()
        # the vertical gap of every slave node to the master polygon
        lo, hi = np.minimum(a[:, 0], b[:, 0]), np.maximum(a[:, 0], b[:, 0])
        x = s[:, 0]
        k = np.argmax((lo[None] <= x[:, None]) & (x[:, None] <= hi[None]),
                      axis=1)
        w = (x - a[k, 0]) / (b[k, 0] - a[k, 0])
        gap = s[:, 1] - (a[k, 1] + w * (b[k, 1] - a[k, 1]))
        exact = (R1 - np.sqrt(R1 ** 2 - x ** 2)) \
            + (R2 - np.sqrt(R2 ** 2 - x ** 2))
        # linear interpolation of y(x) = -R2 + sqrt(R2² - x²): error <=
        # Δx²/8 max |y''|, |y''| = R2²/(R2² - x²)^(3/2)
        edge = np.maximum(abs(lo[k]), abs(hi[k]))
        bound = (hi[k] - lo[k]) ** 2 / 8 * R2 ** 2 \
            / (R2 ** 2 - edge ** 2) ** 1.5
        assert (abs(gap - exact) <= bound * (1 + 1e-6) + 1e-14).all()
        assert abs(gap - exact)[abs(x) < 0.1].max() < 1e-5
        # the slave mesh resolves the expected contact: >= 40 nodes in
        # |x| < a_target (issue 19)
        assert (abs(x) < m["a_target"]).sum() >= 40
        assert_block_diagonal_spd(problem)


def test_cylinders_default_delta_puts_40_slave_nodes_in_contact(cylinders):
    """An independent frictionless solve of the exported cylinders: the
    vertical gaps of the slave nodes to the master polygon (node to
    segment, small deformation), condensed on them (A = B K⁻¹ Bᵀ) and
    solved as min ½λᵀAλ + qᵀλ, λ >= 0 by scipy's NNLS. The default δ
    (from a_target = 0.1) gives P within 10 % of the estimate, Hertz's a
    of that P within 5 % of a_target, and >= 40 slave nodes in contact."""
    import scipy.sparse as sp
    from scipy.optimize import nnls
    from scipy.sparse.linalg import splu

    p, m = cylinders, cylinders.meta
    dof = -np.ones(p.nodes.shape, int)
    dof[p.dof_map[:, 0], p.dof_map[:, 1]] = np.arange(p.n_dofs)
    S = p.contact_nodes[abs(p.nodes[p.contact_nodes, 0]) < 0.3]
    a, b = (p.nodes[p.mortar_master[:, k]] for k in (0, 1))
    lo, hi = np.minimum(a[:, 0], b[:, 0]), np.maximum(a[:, 0], b[:, 0])
    x = p.nodes[S, 0]
    k = np.argmax((lo[None] <= x[:, None]) & (x[:, None] <= hi[None]),
                  axis=1)
    w = (x - a[k, 0]) / (b[k, 0] - a[k, 0])
    g0 = p.nodes[S, 1] - (a[k, 1] + w * (b[k, 1] - a[k, 1]))
    cols = np.stack([dof[S, 1], dof[p.mortar_master[k, 0], 1],
                     dof[p.mortar_master[k, 1], 1]], axis=1)
    vals = np.stack([np.ones(len(S)), w - 1, -w], axis=1)
    B = sp.csr_matrix((vals.ravel(), (np.repeat(np.arange(len(S)), 3),
                                      cols.ravel())), (len(S), p.n_dofs))
    lu = splu(p.K.tocsc())
    A = B @ lu.solve(B.T.toarray())
    L = np.linalg.cholesky(0.5 * (A + A.T))
    q = g0 + B @ lu.solve(p.f)
    lam = nnls(L.T, -np.linalg.solve(L, q), maxiter=10000)[0]
    P = lam.sum()
    a_hertz = 2 * np.sqrt(P * m["R_star"] / (np.pi * m["E_star"]))
    assert P == pytest.approx(m["P_estimate"], rel=0.1)
    assert a_hertz == pytest.approx(m["a_target"], rel=0.05)
    assert (lam > 1e-12 * lam.max()).sum() >= 40


def test_cylinders_parameters(cylinders, cylinders_cm):
    m = cylinders.meta
    assert (m["R1"], m["R2"]) == (1.0, 1.5)
    assert (m["E1"], m["nu1"]) != (m["E2"], m["nu2"])
    assert m["bodies"][1] == {"name": "upper cylinder", "E": m["E1"],
                              "nu": m["nu1"]}
    # Hertz: 1/R* = 1/R1 + 1/R2, 1/E* = Σ (1 - ν²)/E (plane strain)
    assert m["R_star"] == pytest.approx(0.6, rel=1e-14)
    assert 1 / m["E_star"] == pytest.approx(
        (1 - 0.3 ** 2) / 2e5 + (1 - 0.25 ** 2) / 1.2e5, rel=1e-14)
    top = cylinders.nodes[:, 1] == 1.0
    np.testing.assert_allclose(cylinders.u_prescribed[top, 1], -m["delta"])
    bottom = cylinders.nodes[:, 1] == -1.5
    fixed = np.ones(cylinders.nodes.shape, bool)
    fixed[cylinders.dof_map[:, 0], cylinders.dof_map[:, 1]] = False
    assert fixed[bottom].all() and fixed[top, 1].all()
    assert fixed[top, 0].sum() == 1  # u_x pinned at (0, R1) only
    c = cylinders_cm.meta
    assert c["identical"] and (c["R1"], c["E1"], c["nu1"]) == \
        (c["R2"], c["E2"], c["nu2"])
    assert cylinders_cm.load_path is not None
    np.testing.assert_array_equal(cylinders_cm.load_path_friction, [0, 1])
    top = cylinders_cm.nodes[:, 1] == 1.0
    stages = cylinders_cm.load_path_prescribed[:, top]
    np.testing.assert_allclose(stages[0], [[0, -c["delta"]]] * top.sum())
    np.testing.assert_allclose(stages[1], [[c["load"]["shift"],
                                            -c["delta"]]] * top.sum())


# -- the block on an elastic parabola ------------------------------------

@pytest.fixture(scope="module")
def elastic_blocks(tmp_path_factory):
    folder = tmp_path_factory.mktemp("beo")
    return {ratio: export(folder, "block_elastic_obstacle.py",
                          f"block_{ratio:g}", E_ratio=ratio,
                          mesh=str(MESHES / "two_body_block_454.mesh"))
            for ratio in (1e2, 1e4)}


def test_block_is_the_rigid_case_block(elastic_blocks, exported):
    """The block's nodes, DOFs, K, f, M and Γc are those of the rigid
    obstacle export of the same mesh (block_obstacle.py)."""
    rigid = load_problem(exported(454)[0])
    problem = elastic_blocks[1e4]
    n = len(rigid.nodes)
    np.testing.assert_array_equal(problem.nodes[:n], rigid.nodes)
    assert (problem.body[:n] == 0).all() and (problem.body[n:] == 1).all()
    block = problem.dof_map[:, 0] < n
    np.testing.assert_array_equal(problem.dof_map[block], rigid.dof_map)
    assert abs(problem.K[block][:, block] - rigid.K).max() == 0
    np.testing.assert_array_equal(problem.f[block], rigid.f)
    assert (problem.f[~block] == 0).all()
    np.testing.assert_array_equal(problem.contact_nodes, rigid.contact_nodes)
    np.testing.assert_array_equal(problem.contact_dofs, rigid.contact_dofs)
    assert abs(problem.M - rigid.M).max() == 0
    np.testing.assert_allclose(outward(problem, problem.mortar_slave),
                               [[1, 0]] * 19)


def test_obstacle_body_is_the_parabola_scaled_by_E_ratio(elastic_blocks):
    soft, stiff = elastic_blocks[1e2], elastic_blocks[1e4]
    master = np.unique(stiff.mortar_master)
    x, y = stiff.nodes[master].T
    np.testing.assert_allclose(x, 5.05 + 0.005 * y ** 2, rtol=0, atol=1e-14)
    assert y.min() == -11 and y.max() == 11 and len(master) == 89
    assert (outward(stiff, stiff.mortar_master)[:, 0] < 0).all()
    assert stiff.meta["bodies"][1]["E"] == 1e4 * stiff.meta["E"]
    obstacle = stiff.dof_map[:, 0] >= 257
    K_soft = soft.K[obstacle][:, obstacle]
    K_stiff = stiff.K[obstacle][:, obstacle]
    assert abs(K_stiff - 100 * K_soft).max() <= 1e-12 * abs(K_stiff).max()
    far = stiff.nodes[:, 0] == 10.0
    fixed = np.ones(stiff.nodes.shape, bool)
    fixed[stiff.dof_map[:, 0], stiff.dof_map[:, 1]] = False
    assert fixed[far].all() and far.sum() > 5
    assert_block_diagonal_spd(stiff)


# -- meshes and commands --------------------------------------------------

def test_patch_mesh_is_reproducible(tmp_path):
    """The mesh script makes the committed file byte for byte (gmsh)."""
    pytest.importorskip("gmsh")
    out = tmp_path / "patch.mesh"
    subprocess.run([sys.executable, str(MESHES / "two_body.py"), "patch",
                    "-o", str(out)], check=True, capture_output=True)
    assert out.read_bytes() == (MESHES / "two_body_patch.mesh").read_bytes()


def test_sfepy_run_command_of_the_docstring(tmp_path):
    """The patch file's ``sfepy-run`` command (its docstring) exports."""
    from test_export import sfepy_run

    out = tmp_path / "patch.npz"
    proc = subprocess.run(
        [sfepy_run(), str(PROBLEMS / "two_body_patch.py"), "-d",
         f"mesh='meshes/two_body_patch.mesh', output='{out}', "
         "slave='lower'"], cwd=ROOT, capture_output=True, text=True,
        timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert f"exported 110 DOFs, 6 contact nodes -> {out}" in proc.stdout
    assert load_problem(out).meta["slave_body"] == 0
    doc = (PROBLEMS / "two_body_patch.py").read_text()
    assert "sfepy-run sfepy_problems/two_body_patch.py" in doc


def test_cylinders_under_a_force(tmp_path):
    """``load='force'``: the upper cylinder held in y by the contact only
    (one rigid mode), P given. The contact forces balance P (the
    equilibrium the floating solve imposes), and Hertz for two cylinders
    (a = 2√(P R*/(π E*)), p₀ = 2P/(πa); Johnson §4.3): a within 1 %
    (second moment of the pressure), p₀ within 3 % (measured −0.46 %,
    +0.36 %, 51 slave nodes in contact)."""
    from solver import solve

    problem = export(tmp_path, "two_cylinders.py", "force", load="force",
                     mesh=str(MESHES / "two_body_cylinders.mesh"))
    m = problem.meta
    assert m["P"] == m["P_estimate"] and m["load"]["force_y"] == -m["P"]
    result = solve(problem)
    assert result.success and result.rigid_body["modes"] == 1
    np.testing.assert_allclose(result.total_contact_force, [0, m["P"]],
                               rtol=0, atol=1e-10 * m["P"])
    lam, D = result.contact_pressure, result.mortar_D
    x = problem.nodes[problem.contact_nodes, 0]
    a = 2 * np.sqrt((D * lam * x ** 2).sum() / (D * lam).sum())
    a_hertz = 2 * np.sqrt(m["P"] * m["R_star"] / (np.pi * m["E_star"]))
    p0_hertz = 2 * m["P"] / (np.pi * a_hertz)
    assert result.n_contact >= 40
    assert abs(a / a_hertz - 1) <= 0.01
    assert abs(lam.max() / p0_hertz - 1) <= 0.03
