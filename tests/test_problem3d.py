"""The .npz format version 3 in 3D: round trip, the 2D versions 1 and 2 read
unchanged, and every new key's malformed values refused in one line.

The 3D problem is built here without SfePy: the unit cube cut into 2×2×2
cubes of 6 tetrahedra (Kuhn's split), clamped on top, its bottom z = 0 the
contact surface (8 triangles oriented outward, normal −z) above the plane
z = −0.01. K and M are stand-ins (symmetric positive definite; the format
checks no more of them).
"""

import json

import numpy as np
import pytest
import scipy.sparse as sp

from solver.errors import ProblemError
from solver.problem import (FORMAT_VERSION, ContactProblem, load_problem,
                            save_problem, validate_arrays)

PLANE = {"kind": "plane", "point": [0.0, 0.0, -0.01],
         "normal": [0.0, 0.0, 1.0]}

#: Kuhn's split of the cube with corners numbered by (i, j, k) bits.
KUHN = [(0, 1, 3, 7), (0, 1, 5, 7), (0, 2, 3, 7), (0, 2, 6, 7),
        (0, 4, 5, 7), (0, 4, 6, 7)]


def cube_mesh(n=2):
    """Nodes (n+1)³ of the unit cube, Kuhn tetrahedra of positive volume."""
    g = np.linspace(0.0, 1.0, n + 1)
    z, y, x = np.meshgrid(g, g, g, indexing="ij")
    nodes = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    idx = np.arange((n + 1) ** 3).reshape(n + 1, n + 1, n + 1)  # [k, j, i]
    tets = []
    for k in range(n):
        for j in range(n):
            for i in range(n):
                corner = [idx[k + (c >> 2 & 1), j + (c >> 1 & 1),
                              i + (c & 1)] for c in range(8)]
                tets += [[corner[c] for c in t] for t in KUHN]
    tets = np.array(tets)
    e = nodes[tets[:, 1:]] - nodes[tets[:, :1]]
    neg = np.einsum("ij,ij->i", e[:, 0], np.cross(e[:, 1], e[:, 2])) < 0
    tets[neg, 1], tets[neg, 2] = tets[neg, 2], tets[neg, 1].copy()
    return nodes, tets


def boundary_faces(tets, nodes, keep):
    """Faces of the tetrahedra on one boundary (all vertices ``keep``),
    oriented outward (right-hand normal away from the fourth vertex)."""
    faces = []
    for t in tets:
        for o in range(4):
            f = [v for v in t if v != t[o]]
            if keep[f].all():
                a, b, c = nodes[f]
                if np.cross(b - a, c - a) @ (nodes[t[o]] - a) > 0:
                    f = [f[0], f[2], f[1]]
                faces.append(f)
    return np.array(faces)


@pytest.fixture(scope="module")
def cube():
    """The 3D problem's arrays (format version 3)."""
    nodes, cells = cube_mesh()
    top = nodes[:, 2] == 1.0
    bottom = nodes[:, 2] == 0.0
    faces = boundary_faces(cells, nodes, bottom)
    free = np.flatnonzero(~top)
    dof_map = np.column_stack([np.repeat(free, 3),
                               np.tile(np.arange(3), len(free))])
    n = len(dof_map)
    K = sp.diags([-1.0, 4.0, -1.0], [-1, 0, 1], shape=(n, n), format="csr")
    contact_nodes = np.flatnonzero(bottom)
    lookup = {tuple(r): i for i, r in enumerate(dof_map)}
    contact_dofs = np.array([[lookup[(v, c)] for c in range(3)]
                             for v in contact_nodes])
    M = sp.identity(len(contact_nodes), format="csr") / len(contact_nodes)
    u_prescribed = np.zeros((len(nodes), 3))
    u_prescribed[top, 2] = -0.02
    problem = ContactProblem(
        K=K, f=np.linspace(-1.0, 1.0, n), M=M, contact_dofs=contact_dofs,
        meta={"E": 1.0, "nu": 0.3, "load": "top moved by -0.02",
              "mesh": "unit cube 2x2x2, Kuhn"},
        nodes=nodes, cells=cells, dof_map=dof_map,
        u_prescribed=u_prescribed, contact_nodes=contact_nodes,
        contact_faces=faces, obstacle=dict(PLANE))
    return problem.to_arrays()


def spec_of(obstacle):
    return obstacle.spec() if hasattr(obstacle, "spec") else obstacle


def test_cube_fixture_is_what_it_claims(cube):
    """27 nodes, 48 tetrahedra filling the unit cube, 8 bottom faces of
    total area 1 with normals −z."""
    nodes, cells = cube["nodes"], cube["cells"]
    assert nodes.shape == (27, 3) and cells.shape == (48, 4)
    e = nodes[cells[:, 1:]] - nodes[cells[:, :1]]
    vol = np.einsum("ij,ij->i", e[:, 0], np.cross(e[:, 1], e[:, 2])) / 6
    assert vol.sum() == pytest.approx(1.0, rel=1e-14) and (vol > 0).all()
    f = nodes[cube["contact_faces"]]
    normal = np.cross(f[:, 1] - f[:, 0], f[:, 2] - f[:, 0])
    assert normal[:, 2].min() < 0 and np.allclose(normal[:, :2], 0)
    assert -normal[:, 2].sum() / 2 == pytest.approx(1.0, rel=1e-14)


def test_round_trip_3d(cube, tmp_path):
    problem = validate_arrays(cube)
    assert problem.dim == 3 and problem.kind == "mesh"
    path = save_problem(tmp_path / "cube.npz", problem)
    with np.load(path, allow_pickle=False) as archive:
        assert int(archive["format_version"]) == FORMAT_VERSION >= 3
        assert json.loads(str(archive["obstacle_surface"])) == PLANE
    again = load_problem(path)
    assert again.dim == 3
    for name in ("f", "contact_dofs", "nodes", "cells", "dof_map",
                 "u_prescribed", "contact_nodes", "contact_faces"):
        np.testing.assert_array_equal(getattr(again, name),
                                      getattr(problem, name))
    assert (again.K != problem.K).nnz == 0 and (again.M != problem.M).nnz == 0
    assert spec_of(again.obstacle) == PLANE
    # to_arrays of the loaded problem gives the same arrays again
    arrays = again.to_arrays()
    for key, value in cube.items():
        if key != "meta":
            np.testing.assert_array_equal(arrays[key], value, err_msg=key)


def test_dim_repr_summary_full_displacement(cube):
    problem = validate_arrays(cube)
    text = repr(problem)
    assert "dim=3" in text and "tetrahedra=48" in text
    assert "contact_faces=8" in text and "plane" in text.lower()
    assert "\n" not in text and len(text) < 400
    info = problem.summary()
    assert info["dim"] == 3 and info["tetrahedra"] == 48
    assert info["contact_faces"] == 8 and info["nodes"] == 27
    assert info["obstacle"] == PLANE  # the spec, shim or Surface
    json.dumps(info)  # --info --json must be able to print it
    u = np.arange(problem.n_dofs, dtype=float)
    full = problem.full_displacement(u)
    assert full.shape == (27, 3)
    np.testing.assert_array_equal(full[problem.dof_map[:, 0],
                                       problem.dof_map[:, 1]], u)
    top = problem.nodes[:, 2] == 1.0
    np.testing.assert_array_equal(full[top], [[0.0, 0.0, -0.02]] * 9)
    with pytest.raises(ProblemError, match="search interval: a 3D"):
        problem.set_search_interval(0.0, 1.0)


def test_discrete_3d_round_trip(tmp_path):
    """A discrete problem of one node with three DOFs and an oblique
    normal."""
    normal = np.array([[1.0, 2.0, 2.0]]) / 3.0
    problem = ContactProblem(
        K=sp.identity(3, format="csr") * 2.0, f=np.array([1.0, 0.0, 0.0]),
        M=sp.identity(1, format="csr"), contact_dofs=np.array([[0, 1, 2]]),
        gap=np.array([0.1]), normal=normal,
        meta={"description": "one node in 3D"})
    again = load_problem(save_problem(tmp_path / "d.npz", problem))
    assert again.dim == 3 and again.kind == "discrete"
    np.testing.assert_array_equal(again.normal, normal)
    assert "dim=3" in repr(again)
    bad = dict(problem.to_arrays(), normal=np.array([[1.0, 1.0, 0.0]]))
    with pytest.raises(ProblemError, match=r"^normal: row 0 has length"):
        validate_arrays(bad)


@pytest.fixture(scope="module")
def arrays_2d(tmp_path_factory):
    """A 2D mesh problem as written by this version (block, 118 triangles)."""
    from conftest import MESHES, solve_block

    path = tmp_path_factory.mktemp("v") / "block_118.npz"
    solve_block(MESHES / "block_118.mesh", path)
    with np.load(path, allow_pickle=False) as archive:
        return {k: archive[k] for k in archive.files}


@pytest.mark.parametrize("version", [1, 2, 3])
def test_2d_files_of_every_version_load_unchanged(arrays_2d, bar_problem,
                                                  version):
    """A 2D file marked 1, 2 or 3 loads to the same arrays: version 3 adds
    keys for 3D only."""
    reference = validate_arrays(arrays_2d)
    old = validate_arrays(dict(arrays_2d,
                               format_version=np.array(version)))
    assert old.dim == 2
    for name in ("f", "contact_dofs", "nodes", "cells", "dof_map",
                 "u_prescribed", "contact_nodes"):
        np.testing.assert_array_equal(getattr(old, name),
                                      getattr(reference, name))
    assert (old.K != reference.K).nnz == 0
    assert old.obstacle.x_text == reference.obstacle.x_text
    assert old.contact_faces is None
    bar = dict(bar_problem.to_arrays(), format_version=np.array(version))
    np.testing.assert_array_equal(validate_arrays(bar).normal,
                                  bar_problem.normal)


def test_3d_needs_version_3(cube):
    with pytest.raises(ProblemError) as info:
        validate_arrays(dict(cube, format_version=np.array(1)))
    assert str(info.value) == ("format_version: a 3D problem needs version "
                               "3, the file has 1")


def _swap(a, row, i, j):
    a = a.copy()
    a[row, [i, j]] = a[row, [j, i]]
    return a


def _edit(key, change):
    return lambda a: dict(a, **{key: change(a[key])})


def _drop(key):
    return lambda a: {k: v for k, v in a.items() if k != key}


def _not_a_face(a):
    """Triangle 0 replaced by three bottom corners: no tetrahedron's
    face."""
    faces = a["contact_faces"].copy()
    corners = [i for i in a["contact_nodes"]
               if a["nodes"][i, 0] in (0.0, 1.0)
               and a["nodes"][i, 1] in (0.0, 1.0)]
    faces[0] = corners[:3]
    return faces


BAD_3D = [
    ("contact_dofs 4 columns",
     _edit("contact_dofs", lambda v: np.hstack([v, v[:, :1]])),
     "contact_dofs: expected 2 or 3 columns (the dimension), got shape "
     "(9, 4)"),
    ("nodes 2 columns", _edit("nodes", lambda v: v[:, :2]),
     "nodes: expected shape (?, 3), got (27, 2)"),
    ("nodes NaN", _edit("nodes", lambda v: np.where(
        np.arange(v.size).reshape(v.shape) == 5, np.nan, v)),
     "nodes: 1 entries are NaN or infinite (first at index [1, 2])"),
    ("nodes far", _edit("nodes", lambda v: v + 1e31),
     "nodes: node 0 at (1e+31, 1e+31, 1e+31) is out of the supported range "
     "|x|, |y|, |z| <= 1e+30 (rescale the units)"),
    ("cells triangles", _edit("cells", lambda v: v[:, :3]),
     "cells: expected shape (?, 4) or (?, 8) (tetrahedra or hexahedra), got (48, 3)"),
    ("cells float", _edit("cells", lambda v: v.astype(float)),
     "cells: expected integers, got dtype float64"),
    ("cells out of range", _edit("cells", lambda v: np.where(v == 26, 27, v)),
     "cells: index 27 out of range [0, 27)"),
    ("flat tetrahedron", _edit("cells", lambda v: np.vstack(
        [v[:5], [[v[5, 0], v[5, 1], v[5, 2], v[5, 2]]], v[6:]])),
     "cells: tetrahedron 5 (nodes"),
    ("inverted tetrahedron", _edit("cells", lambda v: _swap(v, 7, 1, 2)),
     "cells: tetrahedron 7 (nodes"),
    ("no contact_faces", _drop("contact_faces"),
     "contact_faces: missing (required in a 3D 'mesh' problem file)"),
    ("contact_faces float", _edit("contact_faces",
                                  lambda v: v.astype(float)),
     "contact_faces: expected integers, got dtype float64"),
    ("contact_faces quads", _edit("contact_faces",
                                  lambda v: np.hstack([v, v[:, :1]])),
     "contact_faces: expected shape (?, 3), got (8, 4)"),
    ("contact_faces empty", _edit("contact_faces", lambda v: v[:0]),
     "contact_faces: no triangles"),
    ("contact_faces out of range",
     _edit("contact_faces", lambda v: np.where(v == v.max(), 99, v)),
     "contact_faces: index 99 out of range [0, 27)"),
    ("contact_faces negative",
     _edit("contact_faces", lambda v: np.where(v == v.max(), -1, v)),
     "contact_faces: index -1 out of range [0, 27)"),
    ("face vertex off Γc", _edit("contact_faces", lambda v: np.vstack(
        [[[v[0, 0], v[0, 1], 26]], v[1:]])),
     "contact_faces: triangle 0 has vertex 26, which is not in "
     "contact_nodes"),
    ("repeated vertex", _edit("contact_faces", lambda v: np.vstack(
        [[[v[0, 0], v[0, 0], v[0, 1]]], v[1:]])),
     "contact_faces: triangle 0 (nodes"),
    ("inward face", _edit("contact_faces", lambda v: _swap(v, 3, 1, 2)),
     "contact_faces: triangle 3 (nodes"),
    ("face twice", _edit("contact_faces",
                         lambda v: np.vstack([v, v[2:3]])),
     "contact_faces: triangle 8 (nodes"),
    ("not a face", lambda a: dict(a, contact_faces=_not_a_face(a)),
     "contact_faces: triangle 0 (nodes"),
    ("lonely contact node", _edit("contact_faces", lambda v: v[
        ~(v == v.min()).any(axis=1)]),
     "contact_nodes: node 0 is a vertex of no contact face"),
    ("no obstacle_surface", _drop("obstacle_surface"),
     "obstacle_surface: missing (required in a 3D 'mesh' problem file)"),
    ("obstacle_surface not JSON",
     lambda a: dict(a, obstacle_surface=np.array("{plane")),
     "obstacle_surface: not valid JSON"),
    ("obstacle_surface a list",
     lambda a: dict(a, obstacle_surface=np.array("[1, 2]")),
     "obstacle_surface: must be a JSON object"),
    ("obstacle_surface NaN",
     lambda a: dict(a, obstacle_surface=np.array(
         '{"kind": "sphere", "center": [0, 0, NaN], "radius": 1}')),
     "obstacle_surface: NaN is not a number in JSON"),
    ("obstacle_surface unknown kind",
     lambda a: dict(a, obstacle_surface=np.array('{"kind": "torus"}')),
     "obstacle_surface: 'kind' must be one of plane, sphere, graph, "
     "parametric, rectangle, polygon, several, got 'torus'"),
    ("obstacle_surface no kind",
     lambda a: dict(a, obstacle_surface=np.array('{"point": [0, 0, 0]}')),
     "obstacle_surface: 'kind' must be one of"),
    ("obstacle_surface numeric",
     lambda a: dict(a, obstacle_surface=np.array(3.0)),
     "obstacle_surface: expected a text scalar"),
    ("2D obstacle in 3D", lambda a: dict(a, obstacle_x=np.array("t")),
     "obstacle_x: unexpected key in a 3D 'mesh' problem file"),
    ("u_prescribed 2 columns", _edit("u_prescribed", lambda v: v[:, :2]),
     "u_prescribed: expected shape (27, 3), got (27, 2)"),
    ("dof_map component 3", _edit("dof_map", lambda v: np.column_stack(
        [v[:, 0], np.where(np.arange(len(v)) == 4, 3, v[:, 1])])),
     "dof_map: index 3 out of range [0, 3)"),
    ("contact_dofs disagree", _edit("contact_dofs", lambda v: v[:, [1, 0, 2]]),
     "contact_dofs: does not match dof_map and contact_nodes"),
    ("load_path_prescribed 2D", lambda a: dict(
        a, load_path=a["f"][None, :], load_path_steps=np.array([2]),
        load_path_friction=np.array([1.0]),
        load_path_prescribed=a["u_prescribed"][None, :, :2]),
     "load_path_prescribed: expected shape (1, 27, 3), got (1, 27, 2)"),
    ("meta E missing", lambda a: dict(a, meta=np.array(json.dumps(
        {"nu": 0.3, "load": "", "mesh": ""}))),
     "meta: field 'E' missing"),
]


@pytest.mark.parametrize("name, edit, message", BAD_3D,
                         ids=[b[0] for b in BAD_3D])
def test_bad_3d_inputs(cube, name, edit, message):
    """Each malformed 3D key: a one-line ProblemError starting with it."""
    with pytest.raises(ProblemError) as info:
        validate_arrays(edit(dict(cube)))
    text = str(info.value)
    assert text.startswith(message), text
    assert "\n" not in text


def test_bad_3d_messages_name_the_element(cube):
    """The geometric refusals say what is wrong with which element."""
    cases = {
        "flat tetrahedron": "has zero volume",
        "inverted tetrahedron": "is inverted: 1 of 48 tetrahedra have the "
                                "other orientation",
        "repeated vertex": "repeats a vertex",
        "inward face": "is oriented inwards (its right-hand normal points "
                       "into the body); 1 of 8 are",
        "face twice": "appears twice",
        "not a face": "is not a face of any tetrahedron",
    }
    for name, edit, _message in BAD_3D:
        if name in cases:
            with pytest.raises(ProblemError) as info:
                validate_arrays(edit(dict(cube)))
            assert cases[name] in str(info.value)


def test_2d_file_refuses_3d_keys(arrays_2d, cube):
    for key in ("contact_faces", "obstacle_surface"):
        with pytest.raises(ProblemError) as info:
            validate_arrays(dict(arrays_2d, **{key: cube[key]}))
        assert str(info.value) == (f"{key}: unexpected key in a 2D 'mesh' "
                                   "problem file")


def test_3d_file_through_load_problem(cube, tmp_path):
    """The safe reader's size limits admit 3 coordinates and 4 vertices
    per cell, and refuse a bad key from a file in one line."""
    path = tmp_path / "cube.npz"
    np.savez(path, **cube)
    assert load_problem(path).dim == 3
    np.savez(path, **dict(cube, contact_faces=cube["contact_faces"][:, ::-1]))
    with pytest.raises(ProblemError, match=r"^contact_faces: triangle 0 "):
        load_problem(path)
