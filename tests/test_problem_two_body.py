"""Format version 4 (issue 19): two elastic bodies in one 2D mesh file.

A small two-body problem is built here without SfePy: two stacked unit
blocks with non-matching interface meshes, plane-strain P1 stiffness
assembled from the closed-form element matrix (area · Bᵀ D B), the lower
bottom and the upper top clamped (so each body's K is positive definite).
The upper body (1) is the slave, its bottom edge running left to right
(body on the left); the lower body's top edge, the master, runs right to
left. Every refusal of the loader is checked for its one-line message
naming the key; versions 1–3 still load.
"""

import json

import numpy as np
import pytest
import scipy.sparse as sp

from solver.errors import ProblemError
from solver.problem import (FORMAT_VERSION, KEYS, load_problem,
                            save_problem, validate_arrays)
from solver.problem.format import TWO_BODY

E0, NU0, E1, NU1 = 2e5, 0.3, 7e4, 0.25


def _grid(x0, y0, width, height, nx, ny, offset):
    """Nodes and counter-clockwise triangles of a structured rectangle."""
    x, y = np.meshgrid(np.linspace(x0, x0 + width, nx + 1),
                       np.linspace(y0, y0 + height, ny + 1))
    nodes = np.stack([x.ravel(), y.ravel()], axis=1)
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    p = (j * (nx + 1) + i).ravel() + offset
    q, r, s = p + 1, p + nx + 2, p + nx + 1
    cells = np.concatenate([np.stack([p, q, r], 1), np.stack([p, r, s], 1)])
    return nodes, cells


def _stiffness(nodes, cells, E, nu):
    """Plane-strain P1 stiffness over all 2·n_nodes DOFs (2·node + comp)."""
    x, y = nodes[cells, 0], nodes[cells, 1]
    b = np.stack([y[:, 1] - y[:, 2], y[:, 2] - y[:, 0], y[:, 0] - y[:, 1]], 1)
    c = np.stack([x[:, 2] - x[:, 1], x[:, 0] - x[:, 2], x[:, 1] - x[:, 0]], 1)
    area = 0.5 * (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0])
    B = np.zeros((len(cells), 3, 6))
    B[:, 0, 0::2], B[:, 1, 1::2] = b, c
    B[:, 2, 0::2], B[:, 2, 1::2] = c, b
    B /= 2 * area[:, None, None]
    D = E / ((1 + nu) * (1 - 2 * nu)) * np.array(
        [[1 - nu, nu, 0], [nu, 1 - nu, 0], [0, 0, (1 - 2 * nu) / 2]])
    Ke = area[:, None, None] * np.einsum("eki,kl,elj->eij", B, D, B)
    dofs = (2 * cells[:, :, None] + np.arange(2)).reshape(-1, 6)
    rows = np.repeat(dofs, 6, axis=1).ravel()
    cols = np.tile(dofs, (1, 6)).ravel()
    n = 2 * len(nodes)
    return sp.csr_matrix((Ke.ravel(), (rows, cols)), shape=(n, n))


def two_blocks(n_lower=4, n_upper=3):
    """The arrays of a two-body file (see the module docstring)."""
    lower, lower_cells = _grid(0, 0, 1, 0.5, n_lower, 2, 0)
    upper, upper_cells = _grid(0, 0.5, 1, 0.5, n_upper, 2, len(lower))
    nodes = np.concatenate([lower, upper])
    cells = np.concatenate([lower_cells, upper_cells])
    body = np.repeat([0, 1], [len(lower), len(upper)])
    K_full = sp.block_diag(
        [_stiffness(lower, lower_cells, E0, NU0),
         _stiffness(upper, upper_cells - len(lower), E1, NU1)]).tocsr()
    clamped = np.flatnonzero((nodes[:, 1] == 0) | (nodes[:, 1] == 1))
    fixed = np.zeros((len(nodes), 2), bool)
    fixed[clamped] = True
    free = np.flatnonzero(~fixed.ravel())
    slave = np.flatnonzero((body == 1) & (nodes[:, 1] == 0.5))
    slave = slave[np.argsort(nodes[slave, 0])]  # left to right
    master = np.flatnonzero((body == 0) & (nodes[:, 1] == 0.5))
    master = master[np.argsort(-nodes[master, 0])]  # right to left
    h = np.diff(nodes[slave, 0])
    m = len(slave)
    M = sp.diags([np.r_[h, 0] / 3 + np.r_[0, h] / 3, h / 6, h / 6],
                 [0, 1, -1], shape=(m, m)).tocsr()
    K = K_full[free][:, free]
    lookup = np.full(2 * len(nodes), -1)
    lookup[free] = np.arange(len(free))
    u_prescribed = np.zeros((len(nodes), 2))
    u_prescribed[nodes[:, 1] == 1, 1] = -0.01
    return {
        "format_version": np.array(FORMAT_VERSION), "kind": np.array("mesh"),
        "meta": np.array(json.dumps({
            "E": E1, "nu": NU1, "plane": "strain", "load": "top u_y",
            "mesh": "two blocks", "slave_body": 1, "master_body": 0,
            "bodies": [{"name": "lower", "E": E0, "nu": NU0},
                       {"name": "upper", "E": E1, "nu": NU1}]})),
        "K_data": K.data, "K_indices": K.indices, "K_indptr": K.indptr,
        "K_shape": np.array(K.shape),
        "f": -(K_full @ u_prescribed.ravel())[free],
        "M_data": M.data, "M_indices": M.indices, "M_indptr": M.indptr,
        "M_shape": np.array(M.shape),
        "contact_dofs": lookup[2 * slave[:, None] + np.arange(2)],
        "nodes": nodes, "cells": cells,
        "dof_map": np.stack([free // 2, free % 2], axis=1),
        "u_prescribed": u_prescribed, "contact_nodes": slave,
        "body": body,
        "mortar_slave": np.stack([slave[:-1], slave[1:]], axis=1),
        "mortar_master": np.stack([master[:-1], master[1:]], axis=1),
    }


@pytest.fixture()
def arrays():
    return two_blocks()


def test_the_built_problem(arrays):
    """Sanity of the builder: K is the block-diagonal, positive definite
    plane-strain stiffness (rigid motions of a free block are its null
    space: checked on the unconstrained lower block)."""
    problem = validate_arrays(arrays).check_stiffness()
    assert problem.is_mortar and problem.n_bodies == 2
    lower, cells = _grid(0, 0, 1, 0.5, 4, 2, 0)
    K0 = _stiffness(lower, cells, E0, NU0)
    for mode in ([1, 0], [0, 1]):
        assert abs(K0 @ np.tile(mode, len(lower))).max() < 1e-9 * E0
    rotation = np.stack([-lower[:, 1], lower[:, 0]], axis=1).ravel()
    assert abs(K0 @ rotation).max() < 1e-9 * E0
    assert problem.M.sum() == pytest.approx(1.0, rel=1e-14)  # |Γc| = 1


def test_round_trip(arrays, tmp_path):
    problem = validate_arrays(arrays)
    again = load_problem(save_problem(tmp_path / "two.npz", problem))
    assert again.is_mortar and again.n_bodies == 2 and again.obstacle is None
    for name in ("body", "mortar_slave", "mortar_master", "contact_nodes",
                 "contact_dofs", "f", "nodes", "cells", "dof_map"):
        np.testing.assert_array_equal(getattr(again, name), arrays[name],
                                      err_msg=name)
    # absent pair keys read as one pair
    np.testing.assert_array_equal(again.mortar_slave_pair, np.zeros(3, int))
    np.testing.assert_array_equal(again.mortar_master_pair, np.zeros(4, int))
    assert (again.K != problem.K).nnz == 0
    assert again.meta["bodies"][1] == {"name": "upper", "E": E1, "nu": NU1}
    with np.load(tmp_path / "two.npz", allow_pickle=False) as archive:
        assert int(archive["format_version"]) == FORMAT_VERSION == 4
        assert set(TWO_BODY) <= set(archive.files)
        assert not any(k.startswith("obstacle") for k in archive.files)
    text = repr(again)
    assert "bodies=2, slave_segments=3, master_segments=4" in text
    info = again.summary()
    assert info["bodies"] == 2 and info["pairs"] == 1
    with pytest.raises(ProblemError, match="^search interval: a two-body"):
        again.set_search_interval(0, 1)


def test_two_pairs_round_trip(tmp_path):
    """Two interfaces in one file: pair indices per segment; contact_nodes
    pair by pair."""
    a = two_blocks()
    slave, master = a["mortar_slave"], a["mortar_master"]
    # pair 0: the left slave segment on the two right master segments...
    a.update(mortar_slave_pair=np.array([0, 1, 1]),
             mortar_master_pair=np.array([0, 0, 1, 1]),
             contact_nodes=np.r_[slave[0], slave[1:, 1]])
    # ... slave nodes 0-1 in pair 0 and 1-2-3 in pair 1 share node 1:
    with pytest.raises(ProblemError, match="^mortar_slave_pair: node .* is "
                                           "on the slave side of pairs 0 "
                                           "and 1"):
        validate_arrays(a)
    # drop the middle slave segment: pairs {s0} and {s2}
    keep = slave[[0, 2]]
    nodes = np.r_[keep[0], keep[1]]
    h = a["nodes"][keep[:, 1], 0] - a["nodes"][keep[:, 0], 0]
    M = sp.block_diag([h[0] / 6 * np.array([[2, 1], [1, 2]]),
                       h[1] / 6 * np.array([[2, 1], [1, 2]])]).tocsr()
    lookup = np.full(2 * len(a["nodes"]), -1)
    lookup[2 * a["dof_map"][:, 0] + a["dof_map"][:, 1]] = \
        np.arange(len(a["dof_map"]))
    a.update(mortar_slave=keep, mortar_slave_pair=np.array([0, 1]),
             contact_nodes=nodes,
             contact_dofs=lookup[2 * nodes[:, None] + np.arange(2)],
             M_data=M.data, M_indices=M.indices, M_indptr=M.indptr,
             M_shape=np.array(M.shape))
    problem = validate_arrays(a)
    again = load_problem(save_problem(tmp_path / "pairs.npz", problem))
    np.testing.assert_array_equal(again.mortar_slave_pair, [0, 1])
    np.testing.assert_array_equal(again.mortar_master_pair, [0, 0, 1, 1])
    assert again.summary()["pairs"] == 2
    # the pairs out of order in contact_nodes
    with pytest.raises(ProblemError, match="^contact_nodes: not ordered pair "
                                           "by pair"):
        validate_arrays(dict(a, contact_nodes=np.r_[keep[1], keep[0]],
                             contact_dofs=lookup[2 * np.r_[keep[1], keep[0]]
                                                 [:, None] + np.arange(2)]))


def _meta(a, **change):
    meta = json.loads(str(a["meta"]))
    meta.update(change)
    return np.array(json.dumps(meta))


def _reverse(segments):
    return segments[::-1, ::-1].copy()


def _refusals():
    """(name, change of the arrays, expected start of the message)."""
    a = two_blocks()
    slave, master, body = a["mortar_slave"], a["mortar_master"], a["body"]
    bodies = json.loads(str(a["meta"]))["bodies"]
    lower_bottom = np.array([[0, 1]])  # a boundary edge of body 0, body
    # above: on the left of 0 -> 1
    interior = np.array([[0, 6]])  # the diagonal of the first square
    yield ("body id out of range", dict(body=np.where(body == 1, 99, 0)),
           r"body: index 99 out of range \[0, 27\)")
    yield ("body id unused", dict(body=2 * body),
           r"body: no node of body 1 \(the ids must run 0 … B−1, B = 3\)")
    yield ("body negative", dict(body=body - 1), "body: index -1 out of range")
    yield ("body wrong length", dict(body=body[:-1]),
           r"body: expected shape \(27\), got \(26,\)")
    yield ("a triangle in two bodies",
           dict(body=np.where(np.arange(len(body)) == 0, 1, body)),
           r"cells: triangle 0 joins nodes of bodies \[0, 1\]")
    yield ("no body key", dict(body=None),
           "mortar_slave: a two-body file needs the key body")
    yield ("segment node out of range",
           dict(mortar_master=np.array([[0, 99]])),
           r"mortar_master: index 99 out of range \[0, 27\)")
    yield ("segment of zero length", dict(mortar_master=np.array([[3, 3]])),
           r"mortar_master: segment 0 \(3, 3\) has zero length")
    yield ("slave segment reversed",
           dict(mortar_slave=slave[:, ::-1].copy()),
           r"mortar_slave: segment 0 \(.*\) is oriented with its body on the "
           r"right \(3 segments\)")
    yield ("master segment reversed",
           dict(mortar_master=_reverse(master)),
           r"mortar_master: segment 0 .* is oriented with its body on the "
           r"right")
    yield ("not an edge", dict(mortar_master=np.array([[0, 2]])),
           r"mortar_master: segment 0 \(0, 2\) is no edge of a triangle")
    yield ("interior edge", dict(mortar_master=interior),
           r"mortar_master: segment 0 \(0, 6\) is an interior edge")
    yield ("segment twice",
           dict(mortar_master=np.r_[master, master[:1]]),
           r"mortar_master: segment 0 \(.*\) appears twice")
    yield ("master in the slave body",  # the upper top, right to left
           dict(mortar_master=np.array([[24, 23]])),
           "mortar_master: pair 0: the master segments lie in the slave "
           "body 1")
    yield ("master segments in two bodies",
           dict(mortar_master=np.r_[master, [[24, 23]]]),
           "mortar_master: the segments of pair 0 lie in bodies 0 and 1")
    yield ("slave segments in two bodies",
           dict(mortar_slave=np.r_[slave, lower_bottom]),
           "mortar_slave: the segments of pair 0 lie in bodies 1 and 0")
    yield ("master without slave", dict(mortar_slave=None),
           "mortar_master: given without mortar_slave")
    yield ("slave without master", dict(mortar_master=None),
           r"mortar_master: missing \(mortar_slave needs it\)")
    yield ("pair key without segments",
           dict(mortar_slave=None, mortar_master=None,
                mortar_slave_pair=np.zeros(3, int)),
           "mortar_slave_pair: given without mortar_slave")
    yield ("pair index negative",
           dict(mortar_slave_pair=np.array([0, -1, 0])),
           r"mortar_slave_pair: index -1 out of range \[0, 3\)")
    yield ("pair without master",
           dict(mortar_slave_pair=np.array([0, 1, 1])),
           r"mortar_master_pair: pair 1 has no master segment")
    yield ("pair key wrong length",
           dict(mortar_master_pair=np.zeros(3, int)),
           r"mortar_master_pair: expected shape \(4\), got \(3,\)")
    yield ("contact_nodes not the slave nodes",
           dict(contact_nodes=a["contact_nodes"][::-1].copy(),
                contact_dofs=a["contact_dofs"][::-1].copy()),
           r"contact_nodes: nodes .* are consecutive but no slave segment "
           "runs from the first to the second")
    yield ("contact node not a slave node",
           dict(mortar_slave=slave[:2]),
           r"contact_nodes: node .* is not a node of a mortar_slave segment")
    yield ("with an obstacle",
           dict(obstacle_x=np.array("t"), obstacle_y=np.array("0")),
           "obstacle_x: not allowed in a two-body file")
    yield ("with a polyline obstacle",
           dict(obstacle_points=np.array([[0.0, 0.0], [1.0, 0.0]])),
           "obstacle_points: not allowed in a two-body file")
    yield ("version 3", dict(format_version=np.array(3)),
           r"format_version: a two-body problem \(body\) needs version 4, "
           "the file has 3$")
    yield ("meta without bodies",
           dict(meta=_meta(a, bodies=None)),
           r"meta: bodies must be a list of 2 objects")
    yield ("meta with one body", dict(meta=_meta(a, bodies=bodies[:1])),
           r"meta: bodies must be a list of 2 objects")
    yield ("meta body without nu",
           dict(meta=_meta(a, bodies=[bodies[0], {"name": "u", "E": 1.0}])),
           r"meta: bodies\[1\] must be an object with name, E and nu")
    yield ("meta body with a bad E",
           dict(meta=_meta(a, bodies=[bodies[0], dict(bodies[1], E=-1)])),
           r"meta: bodies\[1\]: E must be a positive finite number")
    yield ("meta slave_body wrong", dict(meta=_meta(a, slave_body=0)),
           "meta: slave_body is 0 for pair 0, but its segments lie in body 1")
    yield ("meta master_body not an id",
           dict(meta=_meta(a, master_body="lower")),
           "meta: master_body must be a body id 0 … 1")
    yield ("meta E not the slave body's", dict(meta=_meta(a, E=E0)),
           r"meta: E, nu \(200000.0, 0.25\) must be those of the slave body 1")


REFUSALS = list(_refusals())


@pytest.mark.parametrize("name, change, message", REFUSALS,
                         ids=[r[0] for r in REFUSALS])
def test_refusals(name, change, message):
    """Every refusal is one line that starts with the key."""
    a = two_blocks()
    a.update(change)
    a = {k: v for k, v in a.items() if v is not None}
    with pytest.raises(ProblemError, match="^" + message) as info:
        validate_arrays(a)
    assert "\n" not in str(info.value)


def test_meta_fields_that_are_none_are_missing():
    a = two_blocks()
    meta = json.loads(str(a["meta"]))
    del meta["slave_body"]
    with pytest.raises(ProblemError, match="^meta: field 'slave_body' "
                                           "missing"):
        validate_arrays(dict(a, meta=np.array(json.dumps(meta))))


def test_master_segments_need_not_form_a_chain():
    """Master segments: any boundary edges of one body (here the top of the
    lower block and its bottom), unlike the slave chain."""
    a = two_blocks()
    a["mortar_master"] = np.r_[a["mortar_master"], [[0, 1]]]
    assert len(validate_arrays(a).mortar_master) == 5


def test_block_coupling_refused():
    """A K entry between the two bodies is refused (they share no node)."""
    a = two_blocks()
    K = sp.csr_matrix((a["K_data"], a["K_indices"], a["K_indptr"]),
                      shape=tuple(a["K_shape"])).tolil()
    i = int(np.flatnonzero(a["dof_map"][:, 0] == 5)[0])
    j = int(np.flatnonzero(a["dof_map"][:, 0] == 20)[0])
    K[i, j] = K[j, i] = 1.0
    K = K.tocsr()
    a.update(K_data=K.data, K_indices=K.indices, K_indptr=K.indptr)
    with pytest.raises(ProblemError, match=rf"^K_data: K couples body 0 "
                                           rf"\(DOF {i}\) and body 1"):
        validate_arrays(a)


@pytest.mark.parametrize("key", TWO_BODY)
def test_two_body_keys_refused_in_discrete_files(key, bar_problem):
    bar = dict(bar_problem.to_arrays(), **{key: np.zeros((1, 2), int)})
    with pytest.raises(ProblemError, match=f"^{key}: unexpected key in a "
                                           "'discrete' problem file"):
        validate_arrays(bar)
    assert KEYS[key][0] == "two-body"


def test_one_body_problem_has_no_two_body_fields(bar_problem):
    assert bar_problem.n_bodies == 1 and not bar_problem.is_mortar
    assert not set(TWO_BODY) & set(bar_problem.to_arrays())


def test_body_key_in_a_rigid_obstacle_file(arrays):
    """``body`` may also describe bodies against a rigid obstacle (each
    supported); one body with all ids 0 needs no meta bodies."""
    a = {k: v for k, v in arrays.items() if not k.startswith("mortar")}
    a.update(obstacle_x=np.array("t"), obstacle_y=np.array("-1"))
    problem = validate_arrays(a)
    assert problem.n_bodies == 2 and not problem.is_mortar
    one = validate_arrays(dict(a, body=np.zeros(len(a["body"]), int)))
    assert one.n_bodies == 1
    with pytest.raises(ProblemError, match="^meta: bodies must be a list"):
        validate_arrays(dict(a, meta=_meta(a, bodies=None)))


@pytest.fixture(scope="module")
def block_arrays(tmp_path_factory):
    """The thesis block (118 triangles) exported by SfePy, one body."""
    from conftest import MESHES, solve_block

    path = tmp_path_factory.mktemp("v4") / "block_118.npz"
    solve_block(MESHES / "block_118.mesh", path)
    with np.load(path, allow_pickle=False) as archive:
        return {k: archive[k] for k in archive.files}


@pytest.mark.parametrize("version", [1, 2, 3, 4])
def test_one_body_files_of_every_version_load_unchanged(block_arrays,
                                                        version):
    """A one-body 2D file written now has exactly the keys of version 1–3
    and loads the same with any version number."""
    assert int(block_arrays["format_version"]) == 4
    assert not set(TWO_BODY) & set(block_arrays)
    problem = validate_arrays(dict(block_arrays,
                                   format_version=np.array(version)))
    assert problem.n_bodies == 1 and not problem.is_mortar
    assert all(getattr(problem, k) is None for k in TWO_BODY)
    reference = validate_arrays(block_arrays)
    np.testing.assert_array_equal(problem.contact_nodes,
                                  reference.contact_nodes)
    assert problem.obstacle.x_text == "5.05 + 0.005*t**2"


def test_info_of_a_two_body_file(arrays, tmp_path, capsys):
    """``python -m solver FILE --info`` shows the bodies and the interface
    (it has no obstacle to show)."""
    from conftest import run_cli

    path = save_problem(tmp_path / "two.npz", validate_arrays(arrays))
    code, out, err = run_cli([path, "--info"], capsys)
    assert code == 0 and err == ""
    assert "27 nodes, 2 bodies" in out
    assert "body 1            upper: E = 70000, nu = 0.25" in out
    assert ("interface         1 pair(s), 3 slave segments (body 1), 4 "
            "master segments (body 0)") in out
