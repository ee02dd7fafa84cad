"""The iterative path (issue 33): the active set method on the full primal
system, its Newton systems by AMG-preconditioned projected CG
(``backend="amg"``, :mod:`solver.linalg.amg`,
:mod:`solver.contact.frictionless.active_set`).

Independent references: the kernel of linear elasticity (rigid motions
have no strain, so K times a rigid-body mode vanishes on every row whose
node's neighbours are all free), the saddle-point system of a constrained
quadratic problem solved densely by NumPy, and the factorisation path
(condensed onto Γc, another algorithm and another linear solver) on the
thesis's §4 block (2D) and the a/h 4 Hertz sphere (3D, with rollers).
"""

import json

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from conftest import MESHES, run_cli
from test_export import export_module
from test_export3d import SPHERE
from solver import contact_geometry, solve
from solver.errors import SolverError
from solver.contact.frictionless.active_set import START_FRACTION, hertz_start
from solver.linalg import amg
from solver.problem import load_problem

pytestmark = pytest.mark.skipif(not amg.available(),
                                reason="pyamg not installed (.[amg])")


@pytest.fixture(scope="module")
def block_454(exported):
    return load_problem(exported(454)[0])


def hertz_sphere(tmp_path_factory, a_over_h):
    """The committed quarter Hertz sphere of ``a_over_h``, exported."""
    name = f"hertz_sphere_{a_over_h}"
    path = tmp_path_factory.mktemp("sphere") / f"{name}.npz"
    export_module().export_only(SPHERE, mesh=str(MESHES / f"{name}.mesh"),
                                output=str(path))
    return load_problem(path)


@pytest.fixture(scope="module")
def sphere_4(tmp_path_factory):
    """The a/h = 4 quarter Hertz sphere (2443 DOFs, rollers on x = 0 and
    y = 0)."""
    return hertz_sphere(tmp_path_factory, 4)


@pytest.fixture(scope="module")
def sphere_8(tmp_path_factory):
    """The a/h = 8 quarter Hertz sphere (5961 DOFs, 75 nodes in contact)."""
    return hertz_sphere(tmp_path_factory, 8)


@pytest.mark.parametrize("name", ["block_454", "sphere_4"])
def test_rigid_body_modes_are_the_kernel_of_elasticity(name, request):
    """K B = 0 on the rows whose columns' nodes have all their DOFs free
    (there K is the unconstrained stiffness, which annihilates rigid
    motions); 3 modes in 2D, 6 in 3D."""
    problem = request.getfixturevalue(name)
    node, comp = problem.dof_map[:, 0], problem.dof_map[:, 1]
    B = amg.rigid_body_modes(problem.nodes[node], comp)
    d = problem.dim
    assert B.shape == (problem.n_dofs, 3 if d == 2 else 6)
    free = np.bincount(node, minlength=len(problem.nodes)) == d
    cells = np.asarray(problem.cells)
    near = np.zeros(len(problem.nodes), bool)  # shares a cell with a
    near[cells[(~free[cells]).any(axis=1)]] = True  # prescribed DOF
    inner = ~near[node]
    assert inner.sum() > 0.3 * problem.n_dofs
    KB = problem.K @ B
    scale = abs(problem.K).sum(axis=1).max() * np.abs(B).max(axis=0)
    assert np.abs(KB[inner]).max(axis=0).max() < 1e-10 * scale.max()
    assert np.linalg.matrix_rank(B) == B.shape[1]


def test_projected_cg_solves_the_constrained_problem():
    """min ½uᵀKu − fᵀu subject to C u = s, C rows of disjoint support (the
    normals of nodes): u equals the dense KKT solve [K Cᵀ; C 0]."""
    rng = np.random.default_rng(3)
    n = 60
    A = rng.standard_normal((n, n))
    K = sp.csr_matrix(A @ A.T + n * np.eye(n))
    f = rng.standard_normal(n)
    normals = rng.standard_normal((4, 3))
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    rows = np.repeat(np.arange(4), 3)
    cols = np.arange(12) + 10
    C = sp.csr_matrix((normals.ravel(), (rows, cols)), shape=(4, n))
    s = rng.standard_normal(4)
    kkt = np.block([[K.toarray(), C.T.toarray()], [C.toarray(),
                                                    np.zeros((4, 4))]])
    exact = np.linalg.solve(kkt, np.concatenate([f, s]))[:n]
    start = C.T @ s  # C Cᵀ = I: on the constraints
    out = amg.projected_cg(K, f, lambda r: r / K.diagonal(), start, C,
                           atol=1e-12 * np.linalg.norm(f))
    assert out.converged and 0 < out.iterations < n
    assert np.abs(out.x - exact).max() < 1e-10 * np.abs(exact).max()
    assert np.abs(C @ out.x - s).max() < 1e-13


@pytest.mark.parametrize("name", ["block_454", "sphere_4"])
def test_amg_equals_the_factorisation(name, request):
    """The iterative answer is the direct one to 1e-7 (relative), passes
    the same verification on every node, and touches the same nodes."""
    problem = request.getfixturevalue(name)
    direct = solve(problem)
    iterative = solve(problem, backend="amg")
    assert direct.success and iterative.success, iterative.message
    assert iterative.verification["passed"]
    assert iterative.linear_solver == "amg" and not iterative.condensed
    assert iterative.linear_solver_reason == "backend='amg' given"
    assert iterative.krylov >= iterative.njev > 0
    assert len(iterative.history["krylov"]) == iterative.njev
    error = np.linalg.norm(iterative.u - direct.u) / np.linalg.norm(direct.u)
    assert error < 1e-7
    assert np.array_equal(iterative.in_contact, direct.in_contact)
    assert iterative.engine["levels"] >= 2


@pytest.mark.parametrize("options, reason", [
    (dict(friction=0.3, formulation="thesis"), "projection formulation"),
    (dict(method="fb"), "φ_min"),
    (dict(system="condensed"), "condensing onto Γc factorises K"),
    (dict(options={"alpha_min": 0.5}), "full steps"),
    (dict(start="nested"), "nested start needs the condensed system"),
    (dict(engine="petsc"), "backend"),
])
def test_amg_refusals(block_454, options, reason):
    """What the iterative path does not do is refused in one line naming
    why (front/cases.py RULES)."""
    with pytest.raises(SolverError, match=reason) as info:
        solve(block_454, backend="amg", **options)
    assert "\n" not in str(info.value)


def test_auto_takes_amg_when_the_factor_does_not_fit(block_454,
                                                     monkeypatch):
    """``backend="auto"``: with (pretend) 100 kB available the CHOLMOD
    estimate of the factor exceeds the budget, so the iterative path runs
    and the result says why; with the machine's memory it factorises."""
    default = solve(block_454)
    assert default.linear_solver != "amg"
    assert default.get("linear_solver_reason") is None  # n²/2 fits
    monkeypatch.setattr(amg, "available_memory", lambda: 1e5)
    chosen = solve(block_454)
    assert chosen.linear_solver == "amg" and chosen.success
    assert "CHOLMOD" in chosen.linear_solver_reason \
        or "kvxopt" in chosen.linear_solver_reason
    assert np.linalg.norm(chosen.u - default.u) < \
        1e-7 * np.linalg.norm(default.u)


def test_factor_memory_bounds(block_454):
    """The symbolic estimate lies between the nonzeros of K's lower
    triangle and the dense triangle n(n+1)/2 (8-byte values)."""
    size = amg.factor_memory(block_454.K)
    if size is None:
        pytest.skip("kvxopt not installed")
    n = block_454.n_dofs
    lower = (sp.tril(block_454.K).nnz)
    assert 8 * lower <= size <= 8 * n * (n + 1) / 2


def test_cli_linear_solver_amg(exported, tmp_path, capsys):
    """``python -m solver FILE --linear-solver amg``: converged, and
    summary.json and the printout name the path and why."""
    path = exported(454)[0]
    code, out, err = run_cli([path, "--linear-solver", "amg", "-o",
                              tmp_path / "out"], capsys)
    assert code == 0, err
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["linear_solver"] == "amg" and summary["converged"]
    assert summary["linear_solver_reason"] == "backend='amg' given"
    assert summary["krylov_iterations"] > 0
    assert "AMG-preconditioned CG" in out
    assert "linear solver     amg (backend='amg' given)" in out


def test_cli_auto_says_why(exported, tmp_path, capsys, monkeypatch):
    """``--linear-solver auto`` with (pretend) 100 kB available: the
    printout and summary.json name the AMG path and the estimate."""
    monkeypatch.setattr(amg, "available_memory", lambda: 1e5)
    code, out, err = run_cli([exported(454)[0], "-o", tmp_path / "out"],
                             capsys)
    assert code == 0, err
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["linear_solver"] == "amg"
    assert summary["linear_solver_reason"].startswith("auto: ")
    assert f"linear solver     amg ({summary['linear_solver_reason']})" \
        in out


def test_hertz_start_is_the_hertz_contact_circle():
    """On a paraboloid pressed by δ into a rigid plane, the free
    interference is d = δ − r²/(2R); Hertz's contact radius is a = √(Rδ)
    (Johnson, Contact mechanics, 1985, eq. 4.22 with a rigid plane), where
    d = δ/2. The first set is the disc r ≤ a, not the penetrated disc
    r < √(2Rδ); with nothing penetrating there is no first set."""
    R, delta = 1.0, 2.43e-3
    x, y = np.meshgrid(np.linspace(0, 0.1, 101), np.linspace(0, 0.1, 101))
    r = np.hypot(x, y).ravel()
    r = r[np.abs(r - np.sqrt(R * delta)) > 1e-6]  # none on the edge
    first = hertz_start(delta - r ** 2 / (2 * R))
    assert START_FRACTION == 0.5
    assert np.array_equal(first, r <= np.sqrt(R * delta))
    assert (delta - r ** 2 / (2 * R) > 0).sum() > 1.9 * first.sum()
    assert hertz_start(-r) is None


def test_amg_first_active_set_on_the_sphere(sphere_8):
    """The a/h 8 sphere on the iterative path: the set after the free
    solution is within a ring of the answer's contact set (Hertz's radius;
    the free solution penetrates twice its area, 1.5 times its nodes at
    this a/h, which the method's own rule would take), so the Newton systems are few (4 measured, 7
    from the penetrated set; benchmarks/README.md); the answer is the
    factorisation's to 1e-7 and touches the same nodes."""
    problem = sphere_8
    direct = solve(problem)
    iterative = solve(problem, backend="amg")
    assert iterative.success and iterative.verification["passed"]
    error = np.linalg.norm(iterative.u - direct.u) / np.linalg.norm(direct.u)
    assert error < 1e-7
    assert np.array_equal(iterative.in_contact, direct.in_contact)
    n_contact = int(direct.in_contact.sum())
    sizes = iterative.history["active"]
    assert sizes[0] == 0  # the free solution first
    assert abs(sizes[1] - n_contact) <= 0.1 * n_contact
    geometry = contact_geometry(problem, "obstacle")
    free = np.append(spla.spsolve(sp.csc_matrix(problem.K), problem.f), 0)
    u_n = np.einsum("ij,ij->i", free[geometry.node_dofs],  # −1: roller's
                    geometry.normal)  # prescribed component, 0
    assert (u_n > geometry.gap).sum() > 1.4 * n_contact  # 111 against 75
    assert iterative.njev <= 5


def test_eliminated_hierarchy_on_the_sphere(sphere_8):
    """The Newton system on an active set A in y = R u: the fixed DOFs are
    the active normals, the others solve K̂_FF y_F = (R f − K̂ y_A)_F.
    (a) Its hierarchy's first coarse operator, updated through the rows of
    A only, is the Galerkin product P̂_Fᵀ K̂_FF P̂_F formed directly;
    (b) CG with it reaches SciPy's sparse LU answer of the same system
    (another solver) to 1e-8, in fewer iterations than the projected CG
    with K's own V-cycle, P M P (the count that grew 1.88× from a/h 16 to
    64: benchmarks/README.md)."""
    from solver.contact.frictionless.active_set import (eliminated_step,
                                                        is_orthogonal)
    from solver.contact.geometry import rotate_stiffness, rotation

    problem = sphere_8
    K, f, n = sp.csr_matrix(problem.K), problem.f, problem.n_dofs
    geometry = contact_geometry(problem, "obstacle")
    R, _, _, normal_rows = rotation(n, geometry)
    assert is_orthogonal(R)
    K_hat = rotate_stiffness(K, R, geometry.free_dofs())
    mg = amg.Multigrid(K, amg.rigid_body_modes(
        problem.nodes[problem.dof_map[:, 0]], problem.dof_map[:, 1]))
    assert mg.levels >= 2
    active = np.argsort(geometry.gap)[:75]  # about the contact set
    fixed = normal_rows[active]
    keep = np.ones(n, bool)
    keep[fixed] = False
    reduced = mg.eliminated(K_hat, R, keep)
    P = sp.csr_matrix(R @ mg.prolongators()[0])[keep]
    galerkin = (P.T @ K_hat[keep][:, keep] @ P).toarray()
    updated = reduced.operators()[1].toarray()
    assert np.abs(updated - galerkin).max() < 1e-12 * np.abs(galerkin).max()
    assert np.abs(mg.operators()[1].toarray() - galerkin).max() > \
        1e-3 * np.abs(galerkin).max()  # the update changed something
    # the system: the active normals at their gaps, from u = 0 moved there
    C = R[normal_rows].tocsr()[active]
    start = C.T @ geometry.gap[active]
    y = R @ start
    rhs = (R @ f - K_hat @ np.where(keep, 0.0, y))[keep]
    exact = spla.spsolve(sp.csc_matrix(K_hat[keep][:, keep]), rhs)
    atol = 1e-10 * np.linalg.norm(rhs - K_hat[keep][:, keep] @ y[keep])
    krylov, u = eliminated_step(K_hat, R @ f, R, mg, fixed, start, atol)
    assert krylov.converged and krylov.initial > krylov.residual
    assert np.linalg.norm((R @ u)[keep] - exact) < 1e-8 * np.linalg.norm(exact)
    assert np.abs(C @ u - geometry.gap[active]).max() < 1e-12
    projected = amg.projected_cg(K, f, mg, start, C, atol=atol)
    assert projected.converged
    assert np.linalg.norm(projected.x - u) < 1e-8 * np.linalg.norm(u)
    assert krylov.iterations < projected.iterations


def test_amg_projected_fallback(sphere_4, monkeypatch):
    """Where R is not orthogonal (a roller whose normal leaves its free
    plane) the Newton systems stay projected (P M P, no eliminated
    hierarchy): forced here, the answer is still the factorisation's to
    1e-7, with no hierarchy set up per system."""
    from solver.contact.frictionless import active_set

    direct = solve(sphere_4)
    monkeypatch.setattr(active_set, "ORTHOGONAL_TOL", -1.0)
    iterative = solve(sphere_4, backend="amg")
    assert iterative.success and iterative.verification["passed"]
    assert iterative.history["setup"] == [0.0] * iterative.njev
    error = np.linalg.norm(iterative.u - direct.u) / np.linalg.norm(direct.u)
    assert error < 1e-7
    monkeypatch.undo()
    eliminated = solve(sphere_4, backend="amg")
    assert max(eliminated.history["setup"]) > 0
