"""Quadrilateral and hexahedral meshes through the rigid-obstacle pipeline
(issue 35, point 1).

Independent references: the closed-form uniaxial compression of a block on
rollers pressed by a rigid plane (``sfepy_problems/squeezed_block.py``:
uniform pressure p = E'δ/L, a linear displacement field that first-order
elements of every kind reproduce to round-off), frictionless and, with
ν = 0 (no Poisson sliding along the plane), with Coulomb friction; the
area of the contact face (Σ M); the same nodes cut into triangles or
tetrahedra (``solver.geometry.cells.simplices``), which must give the same
body normals and the same patch answer; hand-made bad cells for the
validation.
"""

import numpy as np
import pytest

from conftest import MESHES, ROOT, load_script
from test_export import export_module

import solver
from solver.errors import InitialPenetrationWarning, ProblemError
from solver.geometry.cells import cell_edges, face_triangles, simplices
from solver.geometry.curves.normals import boundary_normals
from solver.geometry.surfaces.normals import surface_normals
from solver.problem import load_problem, validate_arrays

# meshes/ stays off sys.path: its hertz_sphere.py would shadow the problem
# file of that name when SfePy imports it.
structured = load_script("_contact_ssn_structured", MESHES / "structured.py")

SQUEEZED = ROOT / "sfepy_problems" / "squeezed_block.py"
E, DELTA = 100.0, 1e-3


def export_box(tmp_path, dim, n, cut, nu=0.3):
    """The squeezed unit box, n cells per side, cells or simplices."""
    nodes, cells = structured.box(n, dim)
    mesh = tmp_path / f"box{dim}_{n}_{int(cut)}.mesh"
    structured.write(mesh, nodes, cells, cut)
    out = tmp_path / (mesh.stem + ".npz")
    export_module().export_only(SQUEEZED, mesh=str(mesh), output=str(out),
                                E=E, nu=nu, delta=DELTA)
    return load_problem(out)


def exact(problem, nu):
    """Pressure and displacement of uniaxial compression (module doc)."""
    dim = problem.dim
    e_mod, nu_side = (E, nu) if dim == 3 else (E / (1 - nu ** 2),
                                               nu / (1 - nu))
    x = problem.nodes
    u = np.empty_like(x)
    u[:, 0] = -DELTA * x[:, 0]
    u[:, 1] = nu_side * DELTA * x[:, 1]
    if dim == 3:
        u[:, 2] = nu * DELTA * x[:, 2]
    return e_mod * DELTA, u


@pytest.mark.parametrize("dim, n", [(2, 4), (3, 3)])
@pytest.mark.parametrize("cut", [False, True], ids=["cells", "simplices"])
def test_squeezed_block_is_uniaxial_compression(tmp_path, dim, n, cut):
    problem = export_box(tmp_path, dim, n, cut)
    assert problem.cells.shape[1] == (dim + 1 if cut else 2 ** dim)
    assert problem.M.sum() == pytest.approx(1.0, rel=1e-12)  # |Γc| = 1
    p, u_exact = exact(problem, 0.3)
    for options in ({}, dict(system="full"), dict(gap="body")):
        with pytest.warns(InitialPenetrationWarning):  # the plane enters
            result = solver.solve(problem, **options)
        assert result.success, result.message
        free = ~np.isnan(result.gap)
        np.testing.assert_allclose(result.contact_pressure[free], p,
                                   rtol=1e-10)
        np.testing.assert_allclose(problem.full_displacement(result.u),
                                   u_exact, rtol=0, atol=1e-10 * DELTA)


@pytest.mark.parametrize("dim, n", [(2, 4), (3, 2)])
def test_squeezed_block_with_friction(tmp_path, dim, n):
    """ν = 0: nothing slides along the plane, friction carries nothing and
    the answer is the frictionless closed form in every load step."""
    problem = export_box(tmp_path, dim, n, False, nu=0.0)
    p, u_exact = exact(problem, 0.0)
    with pytest.warns(InitialPenetrationWarning):
        result = solver.solve(problem, friction=0.3, steps=2,
                              formulation="projection")
    assert result.success, result.message
    np.testing.assert_allclose(np.atleast_2d(result.contact_pressure)[-1],
                               p, rtol=1e-10)
    np.testing.assert_allclose(
        problem.full_displacement(np.atleast_2d(result.u)[-1]), u_exact,
        rtol=0, atol=1e-10 * DELTA)


def test_outputs_keep_the_cells(tmp_path):
    """result.vtu has VTK_HEXAHEDRON (12) cells; the report names them."""
    import meshio

    problem = export_box(tmp_path, 3, 2, False)
    with pytest.warns(InitialPenetrationWarning):
        result = solver.solve(problem)
    from solver.output.vtk import write_vtk

    path = tmp_path / "result.vtu"
    write_vtk(path, result, problem)
    mesh = meshio.read(path)
    assert [c.type for c in mesh.cells] == ["hexahedron"]
    assert "hexahedra=8" in repr(problem)
    assert problem.summary()["hexahedra"] == 8


def test_quad_block_exports_and_draws(tmp_path):
    """The thesis block on 10 × 20 quads: Γc is the 21 nodes of x = 5 in
    order, Σ M = 20, the quads are drawn (40 + 200 + ... edges)."""
    from conftest import solve_block

    solve_block(MESHES / "block_quad_200.mesh", tmp_path / "q.npz")
    problem = load_problem(tmp_path / "q.npz")
    assert problem.cells.shape == (200, 4)
    assert np.allclose(problem.nodes[problem.contact_nodes, 0], 5.0)
    assert np.all(np.diff(problem.nodes[problem.contact_nodes, 1]) > 0)
    assert problem.M.sum() == pytest.approx(20.0, rel=1e-12)
    assert len(cell_edges(problem.cells)) == 10 * 21 + 11 * 20
    result = solver.solve(problem)
    assert result.success
    from solver.output.figures import plot_deformed

    plot_deformed(problem, result, path=tmp_path / "deformed.png")
    assert (tmp_path / "deformed.png").stat().st_size > 0


def test_normals_do_not_depend_on_the_cut():
    """2D: the boundary normals of the quads and of their triangles are the
    same; 3D: the angle-weighted normals of quad faces of a curved surface
    equal those of the same faces given as triangles."""
    nodes, quads = structured.block(3, 4)
    chain = np.flatnonzero(np.isclose(nodes[:, 0], 5.0))
    np.testing.assert_array_equal(boundary_normals(nodes, quads, chain),
                                  boundary_normals(nodes, simplices(quads),
                                                   chain))
    xyz, hexes = structured.box(3, 3)
    xyz = xyz.copy()
    xyz[:, 2] += 0.1 * np.sin(xyz[:, 0] * 2) * np.cos(xyz[:, 1])
    top = np.flatnonzero(np.isclose(structured.box(3, 3)[0][:, 2], 1.0))
    faces = hexes[:, [4, 5, 6, 7]]  # the top face of every hexahedron
    faces = faces[np.isin(faces, top).all(axis=1)]
    for weighting in ("angle", "area"):
        np.testing.assert_allclose(
            surface_normals(xyz, faces, top, weighting),
            surface_normals(xyz, face_triangles(faces), top, weighting),
            atol=1e-14)
    assert (surface_normals(xyz, faces, top)[:, 2] > 0.9).all()  # outward


def _bad(arrays, **changes):
    with pytest.raises(ProblemError) as info:
        validate_arrays(dict(arrays, **changes))
    return str(info.value)


@pytest.fixture(scope="module")
def hex_arrays(tmp_path_factory):
    problem = export_box(tmp_path_factory.mktemp("hex"), 3, 2, False)
    return problem.to_arrays()


@pytest.fixture(scope="module")
def quad_arrays(tmp_path_factory):
    problem = export_box(tmp_path_factory.mktemp("quad"), 2, 2, False)
    return problem.to_arrays()


def test_bad_quadrilaterals_are_refused_in_one_line(quad_arrays):
    cells = quad_arrays["cells"]
    text = _bad(quad_arrays, cells=cells[:, ::-1])
    assert text.startswith("cells: quadrilateral 0 (nodes") \
        and "clockwise" in text
    twisted = cells.copy()
    twisted[0] = twisted[0, [0, 2, 1, 3]]
    assert "not convex or self-intersecting" in _bad(quad_arrays,
                                                     cells=twisted)


def test_bad_hexahedra_and_faces_are_refused_in_one_line(hex_arrays):
    cells, faces = hex_arrays["cells"], hex_arrays["contact_faces"]
    twisted = cells.copy()
    twisted[0] = twisted[0, [0, 1, 2, 3, 5, 4, 7, 6]]
    assert "twisted or not in VTK node order" in _bad(hex_arrays,
                                                      cells=twisted)
    inverted = cells.copy()
    inverted[0] = inverted[0, [4, 5, 6, 7, 0, 1, 2, 3]]
    assert "inverted: 1 of 8 hexahedra" in _bad(hex_arrays, cells=inverted)
    assert _bad(hex_arrays, contact_faces=face_triangles(faces)).startswith(
        "contact_faces: expected shape (?, 4)")
    assert "is oriented inwards" in _bad(hex_arrays,
                                         contact_faces=faces[:, ::-1])
    assert "is shared by two hexahedra (an interior face" in _bad(
        hex_arrays, cells=np.r_[cells, cells[1:2]])  # cell 1 touches x = 1
    repeated = faces.copy()  # the centre node (on all 4 faces) replaced
    k = int(np.argmax(np.isin(faces[0], faces[1:])))
    repeated[0, k] = repeated[0, (k + 1) % 4]
    assert "repeats a vertex" in _bad(hex_arrays, contact_faces=repeated)


def test_two_body_files_refuse_hexahedra(hex_arrays):
    """Quadrilaterals take two bodies (tests/test_two_body_quads.py);
    hexahedra not: the 3D mortar has no dual basis of bilinear faces."""
    arrays = dict(hex_arrays, mortar_slave=np.array([[0, 1, 2]]),
                  mortar_master=np.array([[1, 2, 3]]))
    arrays = {k: v for k, v in arrays.items()
              if not k.startswith("obstacle") and k != "contact_faces"}
    assert _bad(arrays).startswith("cells: a 3D two-body file (mortar_slave) "
                                   "needs tetrahedra")


def test_readme_quadrilateral_rows_are_what_the_solver_counts(tmp_path):
    """The README's quadrilateral Table 1 rows (thesis's system, u = 0)
    and the total contact forces, on the quads and on the same nodes cut
    into triangles."""
    from conftest import solve_block

    section = (ROOT / "README.md").read_text().split(
        "### Quadrilaterals: Table 1 on the block", 1)[1].split("\n### ")[0]
    rows = [[c.strip() for c in line.strip("|").split("|")]
            for line in section.splitlines() if line.startswith("| φ")]
    nodes, quads = structured.block(10, 20)
    meshes = {"200 quadrilaterals": MESHES / "block_quad_200.mesh",
              "the same nodes, 400 triangles": tmp_path / "tri.mesh"}
    structured.write(meshes["the same nodes, 400 triangles"], nodes, quads,
                     cut=True)
    checked = 0
    for name, mesh in meshes.items():
        out = tmp_path / (mesh.stem + ".npz")
        solve_block(mesh, out)
        problem = load_problem(out)
        for method, label in (("fb", "φ_FB"), ("min", "φ_min")):
            row = next(r for r in rows if r[0] == label and r[1] == name)
            counts = []
            for gap in ("obstacle", "body"):
                result = solver.solve(problem, method=method, gap=gap,
                                      system="full")
                assert result.success
                counts.append(f"{result.njev} / {result.nfev}")
                if gap == "obstacle":
                    force = f"{np.nansum(result.contact_force):.1f}"
            assert row[2:] == counts + [force], (row, counts, force)
            checked += 1
    assert checked == 4


def test_sfepys_own_hexahedral_cube(tmp_path):
    """SfePy's ``meshes/3d/cube_medium_hexa.mesh`` (the mesh of its contact
    examples, issue 35: 1000 hexahedra on [−½, ½]³) as it ships: the
    squeezed-block pressure E δ / L to 1e-10 on all 121 nodes of Γc."""
    import sfepy

    mesh = ROOT.joinpath(sfepy.data_dir, "meshes", "3d",
                         "cube_medium_hexa.mesh")
    out = tmp_path / "cube.npz"
    export_module().export_only(SQUEEZED, mesh=str(mesh), output=str(out),
                                E=E, nu=0.3, delta=DELTA)
    problem = load_problem(out)
    assert problem.cells.shape == (1000, 8)
    with pytest.warns(InitialPenetrationWarning):
        result = solver.solve(problem)
    assert result.success and result.n_contact == 121
    np.testing.assert_allclose(result.contact_pressure, E * DELTA,
                               rtol=1e-10)
