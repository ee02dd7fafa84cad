"""``python -m solver two_body.npz``: the two-body job of the command line
(solver.cli.jobs.two_body) on files written here (tests/tri_elasticity.py)."""

import json

import numpy as np
import pytest

from solver.cli import main
from solver.problem import save_problem
from tri_elasticity import stacked_blocks, uniform_pressure

MATERIALS = ((1.0, 0.3), (3.0, 0.2))


@pytest.fixture
def patch_file(tmp_path):
    problem, _, _ = stacked_blocks(n_upper=(4, 2), n_lower=(9, 3),
                                   materials=MATERIALS)
    path = tmp_path / "patch.npz"
    save_problem(path, problem)
    return path


def test_frictionless_outputs(patch_file, tmp_path, capsys):
    out = tmp_path / "out"
    assert main([str(patch_file), "-o", str(out), "--plots"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "converged"
    assert summary["coupling"] == "mortar" and summary["gap"] == "mortar"
    assert summary["slave_nodes"] == summary["slave_nodes_covered"] == 5
    assert {"result.npz", "result.vtu", "interface.png",
            "bodies.png"} <= set(summary["files"])
    with np.load(out / "result.npz") as data:
        p = data["contact_pressure"]
        assert data["displacement"].shape == (15 + 40, 2)  # 5×3 + 10×4
        assert data["traction"].shape == (5, 2)
    exact = uniform_pressure((1.0, 1.0), MATERIALS, 1e-3)
    assert np.abs(p / exact - 1).max() < 1e-10
    import meshio

    mesh = meshio.read(out / "result.vtu")
    assert sorted(np.unique(mesh.cell_data["body"][0])) == [0, 1]
    assert "gap from mortar" in capsys.readouterr().out


@pytest.mark.parametrize("system", ["full", "condensed"])
def test_friction_run(tmp_path, system):
    problem, _, _ = stacked_blocks(n_upper=(5, 2), n_lower=(7, 2),
                                   materials=MATERIALS, shift=5e-3)
    path = tmp_path / "slide.npz"
    save_problem(path, problem)
    out = tmp_path / "out"
    assert main([str(path), "--friction", "0.3", "--formulation",
                 "projection", "--system", system, "-o", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["steps_completed"] == 12 and summary["final_n_slip"] > 0
    with np.load(out / "result.npz") as data:
        assert data["friction_traction"].shape == (12, 6)


@pytest.mark.parametrize("option", [["--gap", "body"],
                                    ["--search-interval", "0", "1"]])
def test_rigid_only_options_refused(patch_file, tmp_path, capsys, option):
    """One line on stderr, exit 2 (bad input), nothing written."""
    out = tmp_path / "out"
    assert main([str(patch_file), "-o", str(out)] + option) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "obstacle" in err
    assert not out.exists()


def test_variant_node_to_segment_fails_the_patch_test(patch_file, tmp_path,
                                                      capsys):
    """``--variant``: the mortar coupling passes the patch test, the
    node-to-segment one does not on these non-matching meshes (exact
    reference: the uniform pressure of the stacked blocks)."""
    exact = uniform_pressure((1.0, 1.0), MATERIALS, 1e-3)
    errors = {}
    for variant in ("mortar", "node-to-segment"):
        out = tmp_path / variant
        assert main([str(patch_file), "--variant", variant, "-o",
                     str(out)]) == 0
        summary = json.loads((out / "summary.json").read_text())
        assert summary["coupling"] == variant
        with np.load(out / "result.npz") as data:
            errors[variant] = np.abs(data["contact_pressure"] / exact
                                     - 1).max()
    assert errors["mortar"] < 1e-10 and errors["node-to-segment"] > 1e-3


def test_variant_refused_on_one_body(tmp_path, capsys):
    from solver.examples import two_dof_bar

    path = tmp_path / "bar.npz"
    save_problem(path, two_dof_bar())
    assert main([str(path), "--variant", "mortar"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: --variant mortar is not supported") \
        and "\n" not in err
