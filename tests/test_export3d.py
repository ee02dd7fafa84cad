"""SfePy export in 3D: the Hertz quarter sphere and the extruded block.

Independent references: the rigid body motions of 3D elasticity (the
stiffness without supports must annihilate all six, the supports must
remove all six), the volume of the quarter half-ball, πR³/6, within the
chord error of the inscribed mesh, the sphere's outward normal (x − c)/R,
the area of the contact triangles (Σ M), and the 2D block of the thesis
for the plane-strain slab.
"""

import subprocess
import sys

import numpy as np
import pytest
import scipy.sparse.linalg as sla

from conftest import MESHES, ROOT
from test_export import export_module
from solver.linalg import factorize
from solver.problem import load_problem

SPHERE = ROOT / "sfepy_problems" / "hertz_sphere.py"
BLOCK3D = ROOT / "sfepy_problems" / "block3d_obstacle.py"


@pytest.fixture(scope="module")
def sphere(tmp_path_factory):
    """(loaded problem, SfePy problem) of the a/h = 4 quarter sphere."""
    path = tmp_path_factory.mktemp("sphere") / "hertz_sphere_4.npz"
    _, pb = export_module().export_only(
        SPHERE, mesh=str(MESHES / "hertz_sphere_4.mesh"), output=str(path))
    return load_problem(path), pb


def rigid_modes(nodes):
    """The six rigid motions of the nodes, (3 n, 6), DOF 3 node + comp."""
    n = len(nodes)
    modes = np.zeros((n, 3, 6))
    for c in range(3):
        modes[:, c, c] = 1.0
    x, y, z = nodes.T
    modes[:, :, 3] = np.column_stack([-y, x, 0 * x])
    modes[:, :, 4] = np.column_stack([0 * x, -z, y])
    modes[:, :, 5] = np.column_stack([z, 0 * x, -x])
    return modes.reshape(3 * n, 6)


def test_sphere_K_spd_and_rigid_modes_removed(sphere):
    problem, pb = sphere
    K = problem.K
    assert problem.dim == 3 and problem.n_dofs == 2443
    assert abs(K - K.T).max() <= 1e-12 * abs(K).max()
    factor = factorize(K, backend="superlu")  # Cholesky/LDLᵀ: refuses
    x = factor.solve(problem.f)               # a matrix that is not SPD
    assert np.linalg.norm(K @ x - problem.f) <= 1e-10 * np.linalg.norm(
        problem.f)
    # The stiffness without supports annihilates the rigid motions ...
    stiffness = "dw_lin_elastic.i.Omega(solid.D, v, u)"
    K_full = export_module().full_stiffness(pb, stiffness)
    R = rigid_modes(problem.nodes)
    assert np.abs(K_full @ R).max() <= 1e-9 * abs(K_full).max()
    # ... and the Dirichlet DOFs (symmetry planes, top) leave none free.
    fixed = np.ones(3 * len(problem.nodes), bool)
    fixed[3 * problem.dof_map[:, 0] + problem.dof_map[:, 1]] = False
    assert np.linalg.matrix_rank(R[fixed]) == 6
    # The top is moved down by delta, nothing else is prescribed.
    top = problem.nodes[:, 2] == 1.0
    assert top.sum() > 10
    np.testing.assert_array_equal(problem.u_prescribed[top, 2],
                                  -problem.meta["delta"])
    assert not problem.u_prescribed[~top].any()


def test_sphere_volume_is_the_quarter_half_ball(sphere):
    """Σ tetrahedron volumes = πR³/6 minus the chord error of the
    inscribed surface triangles (at most area × longest edge² / (8R))."""
    problem, _ = sphere
    p = problem.nodes[problem.cells]
    e = p[:, 1:] - p[:, :1]
    volume = np.einsum("ij,ij->i", e[:, 0], np.cross(e[:, 1], e[:, 2])) / 6
    assert (volume > 0).all()
    exact = np.pi / 6  # R = 1
    centre = np.array([0.0, 0.0, 1.0])
    on_sphere = np.abs(np.linalg.norm(problem.nodes - centre, axis=1)
                       - 1) < 1e-9
    edges = np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2).max()
    bound = (np.pi / 2) * edges ** 2 / 8  # quarter-hemisphere area π/2
    assert on_sphere.sum() > 100
    assert 0 < exact - volume.sum() <= bound
    assert (exact - volume.sum()) / exact < 0.01


def test_sphere_contact_faces_outward(sphere):
    """Every contact triangle's right-hand normal is the sphere's outward
    normal (x − c)/R to within the facet's tilt; near the contact it points
    to −z."""
    problem, _ = sphere
    f = problem.nodes[problem.contact_faces]
    normal = np.cross(f[:, 1] - f[:, 0], f[:, 2] - f[:, 0])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    radial = f.mean(axis=1) - [0.0, 0.0, 1.0]
    radial /= np.linalg.norm(radial, axis=1)[:, None]
    assert np.einsum("ij,ij->i", normal, radial).min() > 0.95
    near = np.hypot(*f.mean(axis=1)[:, :2].T) < 0.2
    assert near.sum() > 10 and (normal[near, 2] < -0.9).all()
    # Γc: the sphere below z = 0.2 R, no facet of the symmetry planes.
    xyz = problem.nodes[problem.contact_nodes]
    assert xyz[:, 2].max() <= 0.2 + 1e-12
    assert (np.abs(np.linalg.norm(xyz - [0, 0, 1], axis=1) - 1)
            < 1e-9).all()
    assert not (f[:, :, 0] == 0).all(axis=1).any()
    assert not (f[:, :, 1] == 0).all(axis=1).any()
    # Σ M = the area of the contact triangles (P1 mass matrix).
    area = np.linalg.norm(np.cross(f[:, 1] - f[:, 0], f[:, 2] - f[:, 0]),
                          axis=1).sum() / 2
    assert problem.M.sum() == pytest.approx(area, rel=1e-12)
    # Inscribed in the cap z < 0.2 (area 2πRh/4), covering the cap below
    # z = 0.2 − (longest edge): Γc takes whole facets only.
    longest = np.linalg.norm(f - np.roll(f, 1, axis=1), axis=2).max()
    assert np.pi * (0.2 - longest) / 2 < area < np.pi * 0.2 / 2


def test_sphere_meta_and_dofs(sphere):
    problem, _ = sphere
    meta = problem.meta
    for key in ("R", "E", "nu", "E_star", "delta", "a_target", "a_h"):
        assert key in meta
    assert meta["E_star"] == pytest.approx(2e5 / (1 - 0.3 ** 2))
    assert meta["a_h"] == pytest.approx(4.0, rel=0.15)  # 4.42: few triangles
    assert problem.obstacle == {"kind": "plane", "point": [0.0, 0.0, 0.0],
                                "normal": [0.0, 0.0, 1.0]} \
        or problem.obstacle.spec()["kind"] == "plane"
    # Contact nodes keep a free z DOF except on the top (none here); the
    # symmetry planes fix u_x (x = 0) and u_y (y = 0).
    xyz = problem.nodes[problem.contact_nodes]
    assert ((problem.contact_dofs[:, 0] < 0) == (xyz[:, 0] == 0)).all()
    assert ((problem.contact_dofs[:, 1] < 0) == (xyz[:, 1] == 0)).all()
    assert (problem.contact_dofs[:, 2] >= 0).all()


def sfepy_run():
    from pathlib import Path
    script = Path(sys.executable).parent / "sfepy-run"
    return str(script) if script.exists() else "sfepy-run"


def test_sfepy_run_exports_without_solving(tmp_path):
    """The docstring's sfepy-run command prints the export line only (past
    SfePy's jax notice) and writes no SfePy solution."""
    out = tmp_path / "hs4.npz"
    result = subprocess.run(
        [sfepy_run(), str(SPHERE), "-d",
         f"mesh='{MESHES / 'hertz_sphere_4.mesh'}', output='{out}'"],
        cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr[-2000:]
    printed = export_module().JAX_NOTICE.sub("", result.stdout)
    assert printed == f"exported 2443 DOFs, 172 contact nodes -> {out}\n"
    assert list(tmp_path.iterdir()) == [out]


@pytest.fixture(scope="module")
def slab(tmp_path_factory):
    path = tmp_path_factory.mktemp("slab") / "slab.npz"
    export_module().export_only(
        BLOCK3D, mesh=str(MESHES / "block3d_118_slab.mesh"),
        output=str(path), slab=True)
    return load_problem(path)


def test_block_slab_is_the_2d_block_in_plane_strain(slab, exported):
    """The one-layer slab: u_z = 0 everywhere, the load F per unit
    thickness, Γc the face x = 5 (normals +x); its unconstrained
    displacements are those of the 2D thesis block to within the extra
    freedom of the tetrahedra (softer, < 1 % of the largest)."""
    assert slab.n_dofs == 2 * 138  # the 2D block's DOFs, twice
    assert (slab.contact_dofs[:, 2] == -1).all()
    assert slab.f.sum() == pytest.approx(4000.0 * slab.meta["thickness"])
    f = slab.nodes[slab.contact_faces]
    normal = np.cross(f[:, 1] - f[:, 0], f[:, 2] - f[:, 0])
    assert (normal[:, 0] > 0).all() and np.allclose(normal[:, 1:], 0)
    assert (slab.nodes[slab.contact_nodes, 0] == 5.0).all()
    plane = load_problem(exported(118)[0])
    u3 = slab.full_displacement(sla.spsolve(slab.K.tocsc(), slab.f))
    u2 = plane.full_displacement(sla.spsolve(plane.K.tocsc(), plane.f))
    n = len(plane.nodes)
    np.testing.assert_array_equal(slab.nodes[:n, :2], plane.nodes)
    scale = np.abs(u2).max()
    for layer in (u3[:n, :2], u3[n:, :2]):
        assert 1e-5 < np.abs(layer - u2).max() / scale < 0.01
    # Softer: the 3D space holds every z-independent 2D field (with the 2D
    # energy times T), so the compliance f·u per unit thickness is larger.
    T = slab.meta["thickness"]
    compliance_3d = slab.f @ sla.spsolve(slab.K.tocsc(), slab.f) / T
    compliance_2d = plane.f @ sla.spsolve(plane.K.tocsc(), plane.f)
    assert compliance_2d < compliance_3d < 1.01 * compliance_2d


def test_block3d_parabolic_cylinder(tmp_path):
    """The extruded block: its obstacle is the thesis parabola swept in z
    (parametric spec, normal towards the body), the load totals F·T."""
    path = tmp_path / "b.npz"
    problem, _ = export_module().export_only(
        BLOCK3D, mesh=str(MESHES / "block3d_454x5.mesh"), output=str(path))
    problem = load_problem(path)
    spec = problem.obstacle if isinstance(problem.obstacle, dict) \
        else problem.obstacle.spec()
    assert spec == {"kind": "parametric", "x": "5.05 + 0.005*t**2",
                    "y": "t", "z": "s", "s_range": [-1.0, 11.0],
                    "t_range": [-20.0, 20.0]}
    assert problem.f.sum() == pytest.approx(40000.0)
    assert problem.n_contact == 20 * 6  # 20 nodes on x = 5, 6 levels
    K = problem.K
    assert abs(K - K.T).max() <= 1e-12 * abs(K).max()
    factorize(K, backend="superlu")


@pytest.mark.parametrize("script, args, committed", [
    ("hertz_sphere.py", ["--a-over-h", "4"], "hertz_sphere_4.mesh"),
    ("hertz_sphere.py", ["--a-over-h", "8"], "hertz_sphere_8.mesh"),
    ("block3d.py", ["--base", "454", "--layers", "5", "--thickness", "10"],
     "block3d_454x5.mesh"),
    ("block3d.py", ["--base", "118", "--layers", "1", "--thickness", "1"],
     "block3d_118_slab.mesh"),
])
def test_committed_3d_meshes_are_reproducible(tmp_path, script, args,
                                              committed):
    """The scripts rebuild the committed meshes byte for byte (Delaunay
    3D, one thread, fixed seed; the extrusion needs no gmsh)."""
    pytest.importorskip("gmsh")
    out = tmp_path / committed
    subprocess.run([sys.executable, str(MESHES / script), *args, "-o",
                    str(out)], check=True, capture_output=True, timeout=300)
    assert out.read_bytes() == (MESHES / committed).read_bytes()


def test_extruded_block_is_conforming():
    """Every face of the extruded block is shared by two tetrahedra or on
    the box's surface; the volume is 10 × 20 × 10."""
    import meshio

    mesh = meshio.read(MESHES / "block3d_454x5.mesh")
    nodes, tets = mesh.points, mesh.cells_dict["tetra"]
    faces = np.sort(np.concatenate([tets[:, [1, 2, 3]], tets[:, [0, 2, 3]],
                                    tets[:, [0, 1, 3]], tets[:, [0, 1, 2]]]),
                    axis=1)
    unique, count = np.unique(faces, axis=0, return_counts=True)
    assert count.max() == 2
    single = nodes[unique[count == 1]]
    on_box = ((np.abs(single[:, :, 0]) == 5).all(axis=1)
              | (np.abs(single[:, :, 1]) == 10).all(axis=1)
              | np.isin(single[:, :, 2], (0.0, 10.0)).all(axis=1))
    assert on_box.all()
    e = nodes[tets[:, 1:]] - nodes[tets[:, :1]]
    volume = np.einsum("ij,ij->i", e[:, 0], np.cross(e[:, 1], e[:, 2])) / 6
    assert (volume > 0).all()
    assert volume.sum() == pytest.approx(2000.0, rel=1e-12)
