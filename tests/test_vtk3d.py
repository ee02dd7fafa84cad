"""VTU output of tetrahedral meshes (solver/output/vtk.py): written, read
back with meshio (the reference reader), types and values compared."""

from itertools import permutations
from types import SimpleNamespace

import meshio
import numpy as np

from solver.output.vtk import step_mesh, write_pvd, write_vtk


def kuhn_cube():
    """The unit cube split into 6 positively oriented tetrahedra along its
    diagonal (Kuhn/Freudenthal)."""
    corners = np.array([[x, y, z] for z in (0, 1) for y in (0, 1)
                        for x in (0, 1)], float)
    tets = []
    for order in permutations(range(3)):
        path = [0]
        for axis in order:
            path.append(path[-1] + 2 ** axis)
        tets.append(path)
    tets = np.array(tets)
    a, b, c, d = (corners[tets[:, k]] for k in range(4))
    negative = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) < 0
    tets[negative] = tets[negative][:, [1, 0, 2, 3]]
    return corners, tets


def problem_and_result():
    nodes, cells = kuhn_cube()
    problem = SimpleNamespace(nodes=nodes, cells=cells,
                              contact_nodes=np.array([0, 1, 2, 3]))
    rng = np.random.default_rng(0)
    result = SimpleNamespace(displacement=rng.normal(size=(8, 3)),
                             contact_pressure=np.array([0.0, 1.5, 2.5, 0.0]),
                             in_contact=np.array([False, True, True, False]),
                             gap=np.array([0.1, 0.0, 0.0, 0.2]))
    return problem, result


def test_tetra_vtu_round_trip(tmp_path):
    problem, result = problem_and_result()
    path = tmp_path / "result.vtu"
    write_vtk(path, result, problem)
    mesh = meshio.read(path)
    assert [block.type for block in mesh.cells] == ["tetra"]
    np.testing.assert_array_equal(mesh.cells[0].data, problem.cells)
    np.testing.assert_array_equal(mesh.points, problem.nodes)
    data = mesh.point_data
    assert data["u"].shape == (8, 3)
    np.testing.assert_array_equal(data["u"], result.displacement)
    np.testing.assert_array_equal(data["contact_pressure"],
                                  [0, 1.5, 2.5, 0, 0, 0, 0, 0])
    np.testing.assert_array_equal(data["in_contact"],
                                  [0, 1, 1, 0, 0, 0, 0, 0])
    assert data["in_contact"].dtype == np.int32
    np.testing.assert_array_equal(data["initial_gap"][:4], result.gap)
    assert np.isnan(data["initial_gap"][4:]).all()


def test_friction_step_with_traction_vectors(tmp_path):
    problem, result = problem_and_result()
    traction = np.arange(12.0).reshape(4, 3)
    fields = {"displacement": result.displacement,
              "contact_pressure": result.contact_pressure,
              "friction_traction": traction,
              "in_contact": result.in_contact,
              "stick": np.array([0, 1, 0, 0]), "slip": np.array([0, 0, 1, 0])}
    path = tmp_path / "step_0001.vtu"
    meshio.write(path, step_mesh(problem, fields), file_format="vtu")
    write_pvd(tmp_path / "result.pvd", [(1.0, "step_0001.vtu")])
    mesh = meshio.read(path)
    assert mesh.cells[0].type == "tetra"
    t = mesh.point_data["friction_traction"]
    assert t.shape == (8, 3)
    np.testing.assert_array_equal(t[:4], traction)
    np.testing.assert_array_equal(t[4:], 0)
    np.testing.assert_array_equal(mesh.point_data["slip"][:4], [0, 0, 1, 0])


def test_two_dimensional_output_keeps_triangles_and_padded_u(tmp_path):
    nodes = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    problem = SimpleNamespace(nodes=nodes, cells=np.array([[0, 1, 2],
                                                           [1, 3, 2]]),
                              contact_nodes=np.array([0, 1]))
    result = SimpleNamespace(displacement=np.ones((4, 2)),
                             contact_pressure=np.array([1.0, 2.0]),
                             in_contact=np.array([True, True]),
                             gap=np.zeros(2))
    write_vtk(tmp_path / "r.vtu", result, problem)
    mesh = meshio.read(tmp_path / "r.vtu")
    assert mesh.cells[0].type == "triangle"
    np.testing.assert_array_equal(mesh.points[:, 2], 0)
    np.testing.assert_array_equal(mesh.point_data["u"],
                                  np.c_[np.ones((4, 2)), np.zeros(4)])
