"""The dimension-free contact core in 3D (issue 18, parts 1 and 6).

The problems are P1 tetrahedral blocks assembled here (tests/tet_elasticity.py,
independent of SfePy and of the solver) with gaps and normals given
directly, so that these tests do not depend on the 3D obstacle surfaces.
Independent references, each named where it is used: the exact linear
field of a uniaxially pressed block (patch test), Clarabel (an interior-
point QP solver sharing no code with ours), the 2D P1 triangle problem
solved by the 2D path, and the 2D answers computed on main before the
change.
"""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

from tet_elasticity import (box, extrude, mesh_problem, rectangle,  # noqa: E402
                            stiffness)
from test_linalg_backends import require  # noqa: E402
from solver import solve_frictionless  # noqa: E402
from solver.contact import ContactGeometry
from solver.contact.strategies.candidates import (enlarge_candidates,  # noqa: E402
                                       initial_candidates)
from solver.contact.geometry import rotation  # noqa: E402
from solver.errors import SolverError  # noqa: E402
from solver.geometry.frames import frames, tangent_basis  # noqa: E402

METHODS = ("min", "fb")


def bottom_faces(ids):
    """The bottom (z = 0) triangles of a box's node grid ``ids`` (nx+1,
    ny+1, nz+1), oriented with the outward normal −z."""
    a, b = ids[:-1, :-1, 0].ravel(), ids[1:, :-1, 0].ravel()
    c, d = ids[1:, 1:, 0].ravel(), ids[:-1, 1:, 0].ravel()
    return np.concatenate([np.stack([a, c, b], 1), np.stack([a, d, c], 1)])


def pressed_block(n=(4, 3, 3), E=200.0, nu=0.3, dz=0.01):
    """A unit block on the rigid plane z = 0 (gaps 0, ν = −z), its top face
    moved by the exact uniaxial field u = (ν dz x, ν dz y, −dz z)."""
    nodes, tets = box(n)
    x, y, z = nodes.T
    prescribed = np.full(nodes.shape, np.nan)
    top = np.isclose(z, 1.0)
    prescribed[top] = np.column_stack([nu * dz * x, nu * dz * y,
                                       -dz * z])[top]
    ids = np.arange(len(nodes)).reshape(tuple(m + 1 for m in n))
    problem = mesh_problem(nodes, tets, stiffness(nodes, tets, E, nu),
                           prescribed, np.flatnonzero(np.isclose(z, 0.0)),
                           bottom_faces(ids))
    free = np.flatnonzero((problem.contact_dofs >= 0).all(axis=1))
    m = len(free)
    geometry = ContactGeometry(free, problem.contact_dofs[free], np.zeros(m),
                               np.tile([0.0, 0.0, -1.0], (m, 1)))
    return problem, geometry, E * dz


def dome_block(n=(10, 10, 3), curvature=0.5, dz=0.05):
    """A block clamped at its top (pushed down by dz) onto a paraboloid
    bump z = −κ r² under it: gaps κ r², normals tilted with the bump's
    slope (ν = (h_x, h_y, −1)/|·|, h = −κ r²), so only a patch touches."""
    nodes, tets = box(n)
    x, y, z = nodes.T
    prescribed = np.full(nodes.shape, np.nan)
    top = np.isclose(z, 1.0)
    prescribed[top] = 0.0
    prescribed[top, 2] = -dz
    ids = np.arange(len(nodes)).reshape(tuple(m + 1 for m in n))
    problem = mesh_problem(nodes, tets, stiffness(nodes, tets, 100.0, 0.3),
                           prescribed, np.flatnonzero(np.isclose(z, 0.0)),
                           bottom_faces(ids))
    free = np.flatnonzero((problem.contact_dofs >= 0).all(axis=1))
    px, py = nodes[problem.contact_nodes[free], :2].T - 0.5
    normal = np.column_stack([-2 * curvature * px, -2 * curvature * py,
                              -np.ones(len(free))])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    geometry = ContactGeometry(free, problem.contact_dofs[free],
                               curvature * (px ** 2 + py ** 2), normal)
    return problem, geometry


# --- frames -----------------------------------------------------------

def test_tangent_basis_2d_is_the_thesis_gamma():
    nu = np.array([[0.6, -0.8], [0.0, 1.0]])
    np.testing.assert_array_equal(tangent_basis(nu)[:, 0],
                                  [[0.8, 0.6], [-1.0, 0.0]])


def test_tangent_basis_3d_orthonormal_right_handed():
    rng = np.random.default_rng(0)
    nu = rng.normal(size=(500, 3))
    nu[:4] = [[0, 0, 1], [0, 0, -1], [1, 0, 0], [0, 1e-17, -1]]
    nu /= np.linalg.norm(nu, axis=1)[:, None]
    Q = frames(nu)
    eye = np.broadcast_to(np.eye(3), Q.shape)
    np.testing.assert_allclose(Q @ Q.transpose(0, 2, 1), eye, atol=1e-15)
    np.testing.assert_allclose(np.linalg.det(Q), 1.0, atol=1e-14)
    np.testing.assert_array_equal(Q[:, 2], nu)


def test_rotation_rows_are_tangents_then_normal():
    problem, geometry = dome_block((2, 2, 1))
    R, other, t_rows, n_rows = rotation(problem.n_dofs, geometry)
    np.testing.assert_array_equal(n_rows, geometry.dofs[:, 2])
    np.testing.assert_array_equal(t_rows, geometry.dofs[:, :2].ravel())
    u = np.random.default_rng(1).normal(size=problem.n_dofs)
    Ru = R @ u
    np.testing.assert_allclose(Ru[n_rows], (geometry.normal
                                            * u[geometry.dofs]).sum(1))
    np.testing.assert_allclose(Ru[other], u[other])
    np.testing.assert_allclose((R @ R.T).toarray(), np.eye(problem.n_dofs),
                               atol=1e-15)


# --- patch test ---------------------------------------------------------

@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("path", ["candidates", "contact", "full"])
def test_patch_uniform_pressure(method, path):
    """Reference: the exact linear field u = (ν dz x, ν dz y, −dz z) of a
    block in uniaxial compression (P1 reproduces it), p = E dz / H."""
    problem, geometry, p = pressed_block()
    kw = dict(candidates=dict(candidates=True), contact=dict(
        candidates=False), full=dict(condense=False))[path]
    result = solve_frictionless(problem, method=method, geometry=geometry,
                                tol=1e-12, **kw)
    assert result.success, result.message
    assert result.condensation == {"candidates": "normal candidates",
                                   "contact": "contact",
                                   "full": "none"}[path]
    for pressure in (result.contact_pressure,
                     result.contact_pressure_consistent):
        assert np.abs(pressure / p - 1).max() <= 1e-10
    assert result.n_contact == problem.n_contact
    assert result.displacement.shape == (len(problem.nodes), 3)
    assert result.normal.shape == (problem.n_contact, 3)


# --- a curved contact: paths, candidates, Clarabel --------------------

@pytest.fixture(scope="module")
def dome():
    problem, geometry = dome_block()
    reference = solve_frictionless(problem, "min", geometry=geometry,
                                   condense=False, tol=1e-13)
    assert reference.success
    return problem, geometry, reference


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("kw", [dict(), dict(candidates=False)],
                         ids=["normal candidates", "all of Γc"])
def test_condensed_agrees_with_full(dome, method, kw):
    """Condensed (normal candidates, or every DOF of Γc) and full system:
    the same answer to 1e-10."""
    problem, geometry, reference = dome
    result = solve_frictionless(problem, method, geometry=geometry,
                                tol=1e-13, **kw)
    assert result.success, result.message
    assert result.verification["passed"]
    scale = np.abs(reference.u).max()
    assert np.abs(result.u - reference.u).max() <= 1e-10 * scale
    lam = np.abs(reference.contact_force).max()
    assert np.abs(result.contact_force
                  - reference.contact_force).max() <= 1e-10 * lam
    assert 0 < result.n_contact < problem.n_contact  # a patch, not all


@pytest.mark.parametrize("backend", ["superlu", "pardiso", "cholmod"])
def test_candidates_on_every_backend(dome, backend):
    """The Schur complement on the candidates' normal rows of K̂ = RKRᵀ,
    from each backend (SuperLU/CHOLMOD with dof_ordering, PARDISO's Schur
    mode): the answer of the full system to 1e-10."""
    require(backend)
    problem, geometry, reference = dome
    result = solve_frictionless(problem, geometry=geometry, tol=1e-13,
                                backend=backend)
    assert result.success and result.linear_solver == backend
    scale = np.abs(reference.u).max()
    assert np.abs(result.u - reference.u).max() <= 1e-10 * scale


def test_default_3d_path(dome):
    problem, geometry, _ = dome
    result = solve_frictionless(problem, geometry=geometry)
    assert result.condensation == "normal candidates"
    assert result.start == "free"
    screening = result.candidates
    assert not screening["exhausted"]
    assert screening["rounds"][-1]["penetrating"] == 0
    assert screening["n_candidates"] < problem.n_contact
    with pytest.raises(SolverError, match="nested start"):
        solve_frictionless(problem, geometry=geometry, start="nested")


@pytest.mark.parametrize("method", METHODS)
def test_candidate_enlargement(dome, method):
    """Too small a margin (only the apex is a candidate): the rounds grow
    the set until no other node penetrates, with the same answer."""
    problem, geometry, reference = dome
    result = solve_frictionless(problem, method, geometry=geometry,
                                tol=1e-13, margin=0.0)
    assert result.success, result.message
    rounds = result.candidates["rounds"]
    assert rounds[0]["n_candidates"] < reference.n_contact
    assert rounds[0]["penetrating"] > 0
    assert result.candidates["enlarged"] >= 1
    assert rounds[-1]["penetrating"] == 0
    assert sum(r["nit"] for r in rounds) == result.nit
    scale = np.abs(reference.u).max()
    assert np.abs(result.u - reference.u).max() <= 1e-10 * scale


def test_candidate_rules():
    gap = np.array([0.0, 0.1, 0.2, 1.0, 2.0])
    nodes, delta = initial_candidates(gap)
    assert delta == pytest.approx(0.1) and list(nodes) == [0, 1]
    assert list(initial_candidates(gap, 0.5)[0]) == [0, 1, 2]
    assert list(initial_candidates(np.zeros(3))[0]) == [0, 1, 2]
    remaining = np.array([0.0, 0.0, -0.3, 0.2, 0.4])
    assert list(enlarge_candidates(np.array([0, 1]), remaining, 1e-9)) == \
        [0, 1, 2, 3]
    assert enlarge_candidates(np.array([0, 1]), np.abs(remaining),
                              1e-9) is None


def clarabel_solution(problem, geometry):
    """min ½uᵀKu − fᵀu s.t. ν_i·u_i ≤ s_i, by Clarabel (objective / k̄, as
    in tests/test_qp_crosscheck.py)."""
    clarabel = pytest.importorskip("clarabel")
    import scipy.sparse as sp

    n, (m, d) = problem.n_dofs, geometry.dofs.shape
    k = problem.K.diagonal().mean()
    C = sp.csc_matrix((geometry.normal.ravel(),
                       (np.repeat(np.arange(m), d), geometry.dofs.ravel())),
                      shape=(m, n))
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = settings.tol_gap_rel = 1e-13
    settings.tol_feas = 1e-13
    settings.max_iter = 400
    solver = clarabel.DefaultSolver(sp.triu(problem.K / k).tocsc(),
                                    -problem.f / k, C, geometry.gap,
                                    [clarabel.NonnegativeConeT(m)], settings)
    solution = solver.solve()
    assert str(solution.status) == "Solved", solution.status
    return np.asarray(solution.x)


@pytest.mark.parametrize("method", METHODS)
def test_clarabel_crosscheck_3d(dome, method):
    problem, geometry, _ = dome
    ours = solve_frictionless(problem, method, geometry=geometry, tol=1e-12)
    assert ours.success
    reference = clarabel_solution(problem, geometry)
    err = np.abs(ours.u - reference).max() / np.abs(reference).max()
    assert err <= 1e-8, err


# --- 2D as a special case: a slab of one element thickness ----------------

def slab_pair(nx, ny, E=100.0, nu=0.3, curvature=0.5, dz=0.03):
    """The 2D P1 plane-strain block [0, 2]×[0, 1] (thickness h = 1/ny)
    pressed by its top (u = (0, −dz)) onto a parabolic bump, gaps κ(x−1)²
    and normals (h'(x), −1)/|·| given; and the same block as a 3D slab of
    one layer of prisms (3 tetrahedra each), u_z = 0 except at the contact
    nodes (a contact node with a Dirichlet DOF is a support). Returns the
    2D nodal contact forces and the 3D ones summed over the two faces."""
    h = 1.0 / ny
    nodes2, tris = rectangle((nx, ny), (2.0, 1.0))
    x, y = nodes2.T
    bottom = np.flatnonzero(np.isclose(y, 0.0))
    bottom = bottom[np.argsort(x[bottom])]

    def given(problem, coords, d):
        free = np.flatnonzero((problem.contact_dofs >= 0).all(axis=1))
        px = coords[problem.contact_nodes[free], 0] - 1.0
        normal = np.zeros((len(free), d))
        normal[:, 0], normal[:, 1] = -2 * curvature * px, -1.0
        normal /= np.linalg.norm(normal, axis=1)[:, None]
        return ContactGeometry(free, problem.contact_dofs[free],
                               curvature * px ** 2, normal)

    prescribed = np.full(nodes2.shape, np.nan)
    prescribed[np.isclose(y, 1.0)] = [0.0, -dz]
    p2 = mesh_problem(nodes2, tris, h * stiffness(nodes2, tris, E, nu),
                      prescribed, bottom,
                      np.stack([bottom[1:], bottom[:-1]], 1))
    r2 = solve_frictionless(p2, geometry=given(p2, nodes2, 2), tol=1e-12)
    nodes3, tets = extrude(nodes2, tris, h)
    n = len(nodes2)
    prescribed = np.full(nodes3.shape, np.nan)
    prescribed[:, 2] = 0.0
    prescribed[np.isclose(nodes3[:, 1], 1.0)] = [0.0, -dz, 0.0]
    contact = np.concatenate([bottom, bottom + n])
    prescribed[contact, 2] = np.nan
    a, b = bottom[:-1], bottom[1:]
    faces = np.concatenate([np.stack([a, b, b + n], 1),
                            np.stack([a, b + n, a + n], 1)])
    p3 = mesh_problem(nodes3, tets, stiffness(nodes3, tets, E, nu),
                      prescribed, contact, faces)
    r3 = solve_frictionless(p3, geometry=given(p3, nodes3, 3), tol=1e-12)
    assert r2.success and r3.success
    assert r3.condensation == "normal candidates"
    m = len(bottom)
    return r2.contact_force, r3.contact_force[:m] + r3.contact_force[m:]


def test_slab_reproduces_2d_to_discretisation_error():
    """Reference: the 2D P1 triangle problem, solved by the 2D path.

    Not to 1e-8: one layer of prisms split into 3 tetrahedra is not the P1
    triangle discretisation. The split is not symmetric in z, so the two
    faces' nodes move differently and the in-plane field of a tetrahedron
    depends on z (a different, stiffer element), and the contact nodes keep
    u_z free. Measured: the total contact force differs by 1.8 %, 1.2 %,
    0.65 % on 16×8, 32×16, 64×32 cells (O(h)), the nodal forces by ≤ 2.6 %
    of the largest. Checked: 32×16 within 1.5 % (total) and 3 % (nodal),
    and the difference shrinks from 16×8 to 32×16."""
    differences = []
    for nx, ny in ((16, 8), (32, 16)):
        lam2, lam3 = slab_pair(nx, ny)
        differences.append(abs(lam3.sum() / lam2.sum() - 1))
        nodal = np.abs(lam3 - lam2).max() / np.abs(lam2).max()
    assert differences[1] <= 0.015
    assert nodal <= 0.03
    assert differences[1] < 0.8 * differences[0]


# --- 2D unchanged ------------------------------------------------------------

#: Reference: computed with the code of main at 8ef49e1 (this branch's base,
#: before the dimension-free core) on block_454 exported by
#: sfepy_problems/block_obstacle.py, SuperLU backend: (njev, nfev) and the
#: in-contact nodal forces λ[10:14], printed with repr. The same numbers
#: (and sha256 of u, λ and the verification of 22 configurations: both gap
#: modes and methods, nested/free/full, SuperLU and PARDISO, friction)
#: were checked equal bit for bit by hand when the change was made; another
#: BLAS may change the last bits of both. Since PERF17 the condensed Newton
#: systems are solved on their free components by Cholesky
#: (:mod:`solver.contact.frictionless.newton`) instead of an LU of the whole
#: Jacobian: the same iterates up to round-off, so λ is compared to 1e-13
#: (measured 1.4e-15) and the counts still exactly.
BEFORE = {
    ("obstacle", "min", "nested"): (6, 10, [978.8525727410013,
                                            1768.1995460526564,
                                            1693.201690174197,
                                            437.00687207107296]),
    ("obstacle", "fb", "nested"): (18, 22, [978.8525727456226,
                                            1768.1995460537144,
                                            1693.2016901747393,
                                            437.00687207149775]),
    ("body", "fb", "free"): (11, 12, [1089.8132857567446, 1806.9718036758222,
                                      1689.9914188272112, 325.64517277432094]),
    ("obstacle", "fb", "full"): (25, 113, [978.8525727411516,
                                           1768.199546052716,
                                           1693.201690174282,
                                           437.0068720713677]),
}


@pytest.mark.parametrize("key", list(BEFORE))
def test_2d_unchanged_bit_for_bit(exported, key):
    from solver.problem import load_problem

    problem = load_problem(exported(454)[0])
    gap, method, start = key
    kw = dict(condense=False) if start == "full" else dict(start=start)
    result = solve_frictionless(problem, method, gap=gap, backend="superlu",
                                **kw)
    njev, nfev, lam = BEFORE[key]
    assert (result.njev, result.nfev) == (njev, nfev)
    np.testing.assert_allclose(result.contact_force[10:14], lam, rtol=1e-13)
    assert result.condensation == ("none" if start == "full" else "contact")
    assert result.candidates is None


# --- contact_geometry in 3D (through the contract's interfaces) -----------

class _Plane:
    """Stand-in for GEOM3D's plane surface z = 0 (the obstacle below):
    the contract's two gap methods, written out for this test."""

    def gap_along_obstacle_normal(self, points):
        nu = np.tile([0.0, 0.0, -1.0], (len(points), 1))
        return points[:, 2], nu, points * [1.0, 1.0, 0.0]

    def gap_along_rays(self, points, directions):
        t = -points[:, 2] / directions[:, 2]
        return t, points + t[:, None] * directions


def test_contact_geometry_3d_modes(monkeypatch):
    """Both gap modes through the contract: "obstacle" takes the surface's
    closest point and −its normal; "body" the ray along the body normals
    (solver.geometry.surfaces.normals, stubbed here with tilted normals)."""
    import types

    from solver.contact import contact_geometry

    nodes = np.array([[0.0, 0, 0.1], [1, 0, 0.2], [0, 1, 0.3], [1, 1, 0.4]])
    contact_dofs = np.array([[0, 1, 2], [3, 4, 5], [-1, 6, 7], [8, 9, 10]])
    problem = types.SimpleNamespace(
        kind="mesh", dim=3, nodes=nodes, contact_nodes=np.arange(4),
        contact_faces=np.array([[0, 2, 1], [1, 2, 3]]),
        contact_dofs=contact_dofs, obstacle=_Plane())
    tilted = np.array([[0.6, 0.0, -0.8]] * 4)
    stub = types.ModuleType("solver.geometry.surfaces.normals")
    stub.surface_normals = lambda nodes, faces, contact: tilted[contact]
    monkeypatch.setitem(sys.modules, "solver.geometry.surfaces.normals", stub)
    for mode, gap, normal in (
            ("obstacle", [0.1, 0.2, 0.4], [[0.0, 0.0, -1.0]] * 3),
            ("body", [0.125, 0.25, 0.5], tilted[:3])):
        geometry = contact_geometry(problem, mode)
        assert geometry.dim == 3 and geometry.mode == mode
        np.testing.assert_array_equal(geometry.index, [0, 1, 3])
        np.testing.assert_array_equal(geometry.dofs, contact_dofs[[0, 1, 3]])
        np.testing.assert_allclose(geometry.gap, gap)
        np.testing.assert_allclose(geometry.normal, normal)
        assert geometry.tangents.shape == (3, 2, 3)
        np.testing.assert_allclose(
            np.einsum("mkd,md->mk", geometry.tangents, geometry.normal), 0,
            atol=1e-16)
        assert geometry.foot.shape == (3, 3)


@pytest.mark.parametrize("backend", ["superlu", "pardiso", "cholmod"])
def test_candidates_empty_sets(backend):
    """No free contact node, and a margin below every gap (round 0 without
    candidates): a plain factorisation, then the rounds as usual."""
    require(backend)
    problem, geometry = dome_block((4, 4, 2))
    none = solve_frictionless(problem, geometry=geometry.subset(
        np.arange(0)), backend=backend)
    assert none.success and none.n_contact == 0
    late = solve_frictionless(problem, geometry=geometry, margin=-1.0,
                              backend=backend)
    early = solve_frictionless(problem, geometry=geometry, backend=backend)
    assert late.success and late.candidates["rounds"][0]["n_candidates"] == 0
    assert late.candidates["enlarged"] >= 1
    np.testing.assert_allclose(late.u, early.u, rtol=0,
                               atol=1e-10 * np.abs(early.u).max())


def test_candidates_exhausted_is_reported(dome, monkeypatch):
    """Out of rounds with a non-candidate still penetrating: not success,
    status 6 (verification: penetration), and the message says why."""
    import solver.contact.strategies.candidates as candidates

    problem, geometry, _ = dome
    monkeypatch.setattr(candidates, "MAX_ROUNDS", 1)
    result = solve_frictionless(problem, geometry=geometry, margin=0.0)
    assert not result.success and result.status == 6
    assert result.candidates["exhausted"]
    assert "max penetration" in result.message
    assert "larger margin" in result.message
