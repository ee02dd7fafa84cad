"""The .npz problem format: round trip and a corpus of malformed files.

Every malformed file must raise the format's own ProblemError whose message
names the offending key (or the file, when it is not an archive at all).
"""

import io
import json
import os
import pickle
import zipfile

import numpy as np
import pytest
import scipy.sparse as sp

from solver.errors import ProblemError
from solver.problem import (FORMAT_VERSION, KEYS, format_table, load_problem,
                            save_problem, validate_arrays)


@pytest.fixture(scope="module")
def mesh_arrays(tmp_path_factory):
    from conftest import MESHES, solve_block

    path = tmp_path_factory.mktemp("fmt") / "block_118.npz"
    solve_block(MESHES / "block_118.mesh", path)
    with np.load(path, allow_pickle=False) as archive:
        return {k: archive[k] for k in archive.files}


def write(path, arrays):
    np.savez(path, **arrays)
    return path


def test_round_trip_mesh(mesh_arrays, tmp_path):
    problem = validate_arrays(mesh_arrays)
    path = save_problem(tmp_path / "again.npz", problem)
    again = load_problem(path)
    assert again.kind == "mesh"
    assert (again.K != problem.K).nnz == 0
    assert (again.M != problem.M).nnz == 0
    for name in ("f", "contact_dofs", "nodes", "cells", "dof_map",
                 "u_prescribed", "contact_nodes"):
        np.testing.assert_array_equal(getattr(again, name),
                                      getattr(problem, name))
    assert again.obstacle.x_text == problem.obstacle.x_text
    assert again.meta["E"] == problem.meta["E"]
    assert again.meta["versions"]["format"] == FORMAT_VERSION
    assert again.source == os.fspath(path)


def test_round_trip_discrete(bar_problem, tmp_path):
    path = save_problem(tmp_path / "bar.npz", bar_problem)
    again = load_problem(path)
    assert again.kind == "discrete"
    np.testing.assert_array_equal(again.K.toarray(), 9e4 * np.eye(2))
    np.testing.assert_array_equal(again.f, [1000.0, -1000.0])
    np.testing.assert_array_equal(again.gap, [0.005])
    np.testing.assert_array_equal(again.normal, [[0.0, -1.0]])
    assert again.obstacle is None


def test_files_load_without_pickle(mesh_arrays, tmp_path):
    path = save_problem(tmp_path / "p.npz", validate_arrays(mesh_arrays))
    with np.load(path, allow_pickle=False) as archive:
        assert all(archive[k].dtype != object for k in archive.files)
        assert set(archive.files) <= set(KEYS)


def test_obstacle_t_range_round_trip(mesh_arrays, tmp_path):
    arrays = dict(mesh_arrays, obstacle_t_range=np.array([-20.0, 20.0]))
    path = save_problem(tmp_path / "p.npz", validate_arrays(arrays))
    assert load_problem(path).obstacle.t_range == (-20.0, 20.0)


def _csr_keys(name, A):
    A = sp.csr_matrix(A)
    return {f"{name}_data": A.data, f"{name}_indices": A.indices,
            f"{name}_indptr": A.indptr, f"{name}_shape": np.array(A.shape)}


def _mutations(arrays):
    """(description, arrays, key the error must name)."""
    a = arrays
    nc = len(a["contact_nodes"])
    nonsym = sp.csr_matrix((a["K_data"], a["K_indices"], a["K_indptr"]),
                           shape=tuple(a["K_shape"])).tolil()
    nonsym[0, 1] += 1.0
    negative = sp.csr_matrix((a["K_data"], a["K_indices"], a["K_indptr"]),
                             shape=tuple(a["K_shape"])).tolil()
    negative[3, 3] = -1.0
    reversed_dofs = a["contact_dofs"][::-1].copy()
    shuffled = a["contact_nodes"].copy()
    shuffled[[2, 5]] = shuffled[[5, 2]]
    interior = a["contact_nodes"].copy()
    interior[3] = int(np.flatnonzero(
        (np.abs(a["nodes"][:, 0]) < 4) & (np.abs(a["nodes"][:, 1]) < 9))[0])
    cases = [
        ("missing K_data", {k: v for k, v in a.items() if k != "K_data"},
         "K_data"),
        ("missing f", {k: v for k, v in a.items() if k != "f"}, "f"),
        ("missing obstacle", {k: v for k, v in a.items()
                              if k != "obstacle_y"}, "obstacle_y"),
        ("extra key", dict(a, extra=np.zeros(3)), "extra"),
        ("discrete key in mesh file", dict(a, gap=np.zeros(nc)), "gap"),
        ("no version", {k: v for k, v in a.items() if k != "format_version"},
         "format_version"),
        ("future version", dict(a, format_version=np.array(99)),
         "format_version"),
        ("bad kind", dict(a, kind=np.array("solid")), "kind"),
        ("f wrong shape", dict(a, f=a["f"][:-1]), "f"),
        ("f 2-D", dict(a, f=a["f"][:, None]), "f"),
        ("f NaN", dict(a, f=np.where(np.arange(len(a["f"])) == 7, np.nan,
                                      a["f"])), "f"),
        ("f Inf", dict(a, f=a["f"] + np.inf), "f"),
        ("f text", dict(a, f=np.array(["1"] * len(a["f"]))), "f"),
        ("K data NaN", dict(a, K_data=a["K_data"] * np.nan), "K_data"),
        ("K index out of range",
         dict(a, K_indices=np.where(np.arange(len(a["K_indices"])) == 0,
                                    10 ** 6, a["K_indices"])), "K_indices"),
        ("K indptr broken", dict(a, K_indptr=a["K_indptr"][::-1].copy()),
         "K_indptr"),
        ("K not square", dict(a, K_shape=np.array([a["K_shape"][0], 5])),
         "K_shape"),
        ("K float indices", dict(a, K_indices=a["K_indices"] + 0.5),
         "K_indices"),
        ("K not symmetric", dict(a, **_csr_keys("K", nonsym)), "K_data"),
        ("K negative diagonal", dict(a, **_csr_keys("K", negative)),
         "K_data"),
        ("M wrong size", dict(a, **_csr_keys("M", sp.eye(nc + 1))),
         "M_shape"),
        ("M NaN", dict(a, M_data=a["M_data"] * np.nan), "M_data"),
        ("contact_dofs out of range",
         dict(a, contact_dofs=a["contact_dofs"] + 10 ** 6), "contact_dofs"),
        ("contact_dofs inconsistent", dict(a, contact_dofs=reversed_dofs),
         "contact_dofs"),
        ("contact_nodes not ordered", dict(a, contact_nodes=shuffled),
         "contact_nodes"),
        ("contact node not on boundary", dict(a, contact_nodes=interior),
         "contact_nodes"),
        ("contact node index negative",
         dict(a, contact_nodes=a["contact_nodes"] - 10 ** 6),
         "contact_nodes"),
        ("cells bad index", dict(a, cells=a["cells"] + 10 ** 6), "cells"),
        ("nodes 3-D", dict(a, nodes=np.zeros((len(a["nodes"]), 3))),
         "nodes"),
        ("dof_map component 2", dict(a, dof_map=a["dof_map"] * [1, 2]),
         "dof_map"),
        ("meta not JSON", dict(a, meta=np.array("{E: 1")), "meta"),
        ("meta missing E", dict(a, meta=np.array(json.dumps({
            k: v for k, v in json.loads(str(a["meta"])).items()
            if k != "E"}))), "meta"),
        ("meta negative E", dict(a, meta=np.array(json.dumps(dict(
            json.loads(str(a["meta"])), E=-1.0)))), "meta"),
        ("meta as number array", dict(a, meta=np.array(3.0)), "meta"),
        ("unsafe obstacle", dict(a, obstacle_x=np.array(
            "__import__('os').system('true')")), "obstacle"),
        ("obstacle attribute access", dict(a, obstacle_y=np.array(
            "t.__class__")), "obstacle"),
        ("obstacle unknown name", dict(a, obstacle_y=np.array("s + 1")),
         "obstacle"),
        ("obstacle syntax", dict(a, obstacle_x=np.array("5 +")),
         "obstacle"),
        ("obstacle range reversed", dict(a, obstacle_t_range=np.array(
            [1.0, -1.0])), "obstacle"),
    ]
    return cases


@pytest.mark.parametrize("index", range(39))
def test_malformed_file_names_the_key(mesh_arrays, tmp_path, index):
    description, arrays, key = _mutations(mesh_arrays)[index]
    path = write(tmp_path / "bad.npz", arrays)
    with pytest.raises(ProblemError) as exc:
        load_problem(path)
    message = str(exc.value)
    assert message.startswith(key), (description, message)
    assert "\n" not in message


def test_mutation_count_matches_parametrization(mesh_arrays):
    # every case is run above, and the corpus has the >= 30 cases asked for
    assert len(_mutations(mesh_arrays)) == 39


def test_discrete_corpus(bar_problem, tmp_path):
    base = bar_problem.to_arrays()
    cases = [
        (dict(base, normal=np.array([[0.0, -2.0]])), "normal"),
        ({k: v for k, v in base.items() if k != "gap"}, "gap"),
        (dict(base, gap=np.array([np.nan])), "gap"),
        (dict(base, contact_dofs=np.array([[-1, 1]])), "contact_dofs"),
        (dict(base, contact_dofs=np.array([[1, 1]])), "contact_dofs"),
        (dict(base, obstacle_x=np.array("t")), "obstacle_x"),
        (dict(base, meta=np.array("{}")), "meta"),
    ]
    for arrays, key in cases:
        with pytest.raises(ProblemError, match=f"^{key}"):
            load_problem(write(tmp_path / "bad.npz", arrays))


def test_pickled_member_is_refused(bar_problem, tmp_path):
    arrays = bar_problem.to_arrays()
    arrays["f"] = np.array([{"evil": 1}, 2], dtype=object)
    path = tmp_path / "pickle.npz"
    np.savez(path, **arrays)  # stores an object array (pickled)
    with pytest.raises(ProblemError, match="^f: .*pickled"):
        load_problem(path)


@pytest.mark.parametrize("content, message", [
    (b"", "not an .npz archive"),
    (b"hello world", "not an .npz archive"),
    (pickle.dumps({"K": 1}), "not an .npz archive"),
])
def test_not_an_archive(tmp_path, content, message):
    path = tmp_path / "x.npz"
    path.write_bytes(content)
    with pytest.raises(ProblemError, match=message):
        load_problem(path)


def test_npy_and_missing_and_directory(tmp_path):
    np.save(tmp_path / "a.npy", np.zeros(3))
    with pytest.raises(ProblemError, match="single .npy array"):
        load_problem(tmp_path / "a.npy")
    with pytest.raises(ProblemError, match="no such file"):
        load_problem(tmp_path / "missing.npz")
    with pytest.raises(ProblemError, match="directory"):
        load_problem(tmp_path)


def test_truncated_file(bar_problem, tmp_path):
    path = save_problem(tmp_path / "bar.npz", bar_problem)
    data = open(path, "rb").read()
    for cut in (len(data) // 3, len(data) // 2, len(data) - 30):
        (tmp_path / "cut.npz").write_bytes(data[:cut])
        with pytest.raises(ProblemError):
            load_problem(tmp_path / "cut.npz")


def test_damaged_member(bar_problem, tmp_path):
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as archive:
        for key, value in bar_problem.to_arrays().items():
            member = io.BytesIO()
            np.save(member, value)
            raw = member.getvalue()
            if key == "f":
                raw = raw[:len(raw) - 4]  # array data shorter than header says
            archive.writestr(key + ".npy", raw)
    (tmp_path / "d.npz").write_bytes(buffer.getvalue())
    with pytest.raises(ProblemError, match="^f: "):
        load_problem(tmp_path / "d.npz")


def test_save_is_atomic(bar_problem, tmp_path):
    """An invalid problem raises before anything is written."""
    bad = bar_problem
    bad.f = np.array([np.nan, 0.0])
    with pytest.raises(ProblemError, match="^f: "):
        save_problem(tmp_path / "bad.npz", bad)
    assert list(tmp_path.iterdir()) == []


def test_format_table_lists_every_key():
    table = format_table()
    for key in KEYS:
        assert f"`{key}`" in table


def test_docs_table_is_current():
    """docs/npz-format.md carries the generated key table verbatim."""
    from conftest import ROOT

    assert format_table() in (ROOT / "docs" / "npz-format.md").read_text()


def test_repr_is_short_and_never_dumps_arrays(mesh_arrays, tmp_path,
                                              bar_problem):
    path = tmp_path / "p.npz"
    np.savez(path, **mesh_arrays)
    problem = load_problem(path)
    text = repr(problem)
    assert text.startswith("ContactProblem(kind='mesh', dim=2, dofs=138, "
                           "contact_nodes=11, triangles=118")
    assert "x='5.05 + 0.005*t**2'" in text and repr(str(path)) in text
    assert "array" not in text and "\n" not in text and len(text) < 300
    assert repr(bar_problem) == ("ContactProblem(kind='discrete', dim=2, "
                                 "dofs=2, contact_nodes=1, source=None)")
