"""Checks of the committed block meshes and of meshes/generate.py.

The triangle counts 118, 454 and 1878 are those of the thesis's three meshes
of the 10 x 20 block (x in [-5, 5], y in [-10, 10]). Reading the committed
files needs only meshio; regenerating them needs the optional gmsh.
"""

import importlib.util
import sys
from pathlib import Path

import meshio
import numpy as np
import pytest

MESH_DIR = Path(__file__).resolve().parent.parent / "meshes"

# Reference: the thesis's meshes have 118, 454 and 1878 triangles.
THESIS_COUNTS = (118, 454, 1878)


def _load_generate():
    spec = importlib.util.spec_from_file_location("meshes_generate", MESH_DIR / "generate.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


generate = _load_generate()


def _read(path):
    mesh = meshio.read(path)
    assert [block.type for block in mesh.cells] == ["triangle"]
    return mesh.points, mesh.cells[0].data


def _areas(points, triangles):
    a, b, c = (points[triangles[:, i]] for i in range(3))
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                  - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


@pytest.mark.parametrize("n_triangles", THESIS_COUNTS)
def test_committed_mesh(n_triangles):
    points, triangles = _read(MESH_DIR / f"block_{n_triangles}.mesh")

    assert points.shape[1] == 2
    assert len(triangles) == n_triangles
    assert points[:, 0].min() == -5.0 and points[:, 0].max() == 5.0
    assert points[:, 1].min() == -10.0 and points[:, 1].max() == 10.0
    areas = _areas(points, triangles)
    assert np.all(areas > 0)
    assert areas.sum() == pytest.approx(200.0, rel=1e-12)
    np.testing.assert_array_equal(np.unique(triangles), np.arange(len(points)))


def test_boundary_nodes_exactly_on_edges():
    points, _ = _read(MESH_DIR / "block_118.mesh")
    x, y = points.T
    off_edge = np.minimum(np.abs(np.abs(x) - 5.0), np.abs(np.abs(y) - 10.0))
    near = off_edge < 1e-6
    assert np.all(off_edge[near] == 0.0)
    # 4 segments on each horizontal edge, 10 on each vertical edge
    assert near.sum() == 2 * 4 + 2 * 10


def test_write_read_roundtrip(tmp_path):
    points, triangles = _read(MESH_DIR / "block_454.mesh")
    path = tmp_path / "copy.mesh"
    generate.write_mesh(path, points, triangles)
    assert path.read_bytes() == (MESH_DIR / "block_454.mesh").read_bytes()
    p2, t2 = generate.read_mesh(path)
    np.testing.assert_array_equal(p2, points)
    np.testing.assert_array_equal(t2, triangles)


def test_refine_uniform():
    points, triangles = _read(MESH_DIR / "block_118.mesh")
    p2, t2 = generate.refine_uniform(points, triangles, levels=2)
    assert len(t2) == 16 * 118
    areas = _areas(p2, t2)
    assert np.all(areas > 0)
    assert areas.sum() == pytest.approx(200.0, rel=1e-12)
    np.testing.assert_array_equal(p2[: len(points)], points)
    assert p2[:, 0].min() == -5.0 and p2[:, 1].max() == 10.0


@pytest.mark.parametrize("argv, message", [
    (["--size", "0", "-o", "x.mesh"], "positive"),
    (["--size", "-0.3", "-o", "x.mesh"], "positive"),
    (["--size", "0.3"], "need -o"),
    (["--size", "0.3", "-o", "x.vtk"], ".mesh"),
    (["--algorithm", "5"], "--algorithm needs --size"),
])
def test_cli_bad_arguments(argv, message, capsys):
    with pytest.raises(SystemExit) as exc:
        generate.main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert message in err
    assert len(err.strip().splitlines()) == 1


def test_cli_without_gmsh(monkeypatch, tmp_path, capsys):
    monkeypatch.setitem(sys.modules, "gmsh", None)  # makes `import gmsh` fail
    assert generate.main(["--size", "1", "-o", str(tmp_path / "x.mesh")]) == 2
    err = capsys.readouterr().err
    assert "pip install gmsh" in err
    assert len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("n_triangles", THESIS_COUNTS)
def test_regenerate_matches_committed(n_triangles, tmp_path):
    # gmsh is in the `test` extra: these tests run in CI, never skip.
    points, triangles = generate.thesis_mesh(n_triangles)
    name = f"block_{n_triangles}.mesh"
    committed_points, committed_triangles = _read(MESH_DIR / name)
    assert len(triangles) == n_triangles
    np.testing.assert_array_equal(points, committed_points)
    np.testing.assert_array_equal(triangles, committed_triangles)

    path = tmp_path / name
    generate.write_mesh(path, points, triangles)
    assert path.read_bytes() == (MESH_DIR / name).read_bytes()


def test_cli_size_gives_finer_mesh(tmp_path, capsys):
    path = tmp_path / "fine.mesh"
    assert generate.main(["--size", "0.3", "-o", str(path)]) == 0
    points, triangles = _read(path)
    assert len(triangles) > 1878
    assert np.all(_areas(points, triangles) > 0)
    assert _areas(points, triangles).sum() == pytest.approx(200.0, rel=1e-12)
    assert f"{len(triangles)} triangles" in capsys.readouterr().out
