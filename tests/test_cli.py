"""``python -m solver``: --info on both thesis examples, errors as one line."""

import json
import subprocess
import sys

import numpy as np
import pytest

from solver.cli import main
from solver.problem import save_problem


def test_info_mesh_problem(exported, capsys):
    path = exported(454)[0]
    assert main([str(path), "--info"]) == 0
    out = capsys.readouterr().out
    assert "reduced DOFs      492" in out  # 2 x (257 nodes - 11 clamped)
    assert "contact nodes Nc  20 (19 free, 1 supported)" in out
    assert "454 triangles, 257 nodes" in out
    assert "x(t) = 5.05 + 0.005*t**2, y(t) = t" in out


def test_info_json(bar_problem, tmp_path, capsys):
    path = save_problem(tmp_path / "bar.npz", bar_problem)
    assert main([str(path), "--info", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["dofs"] == 2 and info["gap"] == [0.005]
    assert info["K_norm_max"] == 9e4  # thesis §6: K = 1e4 diag(9, 9)


@pytest.mark.parametrize("content", [b"garbage", b""])
def test_bad_file_one_line_exit_2(tmp_path, capsys, content):
    path = tmp_path / "bad.npz"
    path.write_bytes(content)
    assert main([str(path), "--info"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.startswith("error: ")
    assert len(captured.err.strip().splitlines()) == 1


def test_malformed_key_named(bar_problem, tmp_path, capsys):
    arrays = bar_problem.to_arrays()
    arrays["gap"] = np.array([np.inf])
    np.savez(tmp_path / "bad.npz", **arrays)
    assert main([str(tmp_path / "bad.npz"), "--info"]) == 2
    assert capsys.readouterr().err.startswith("error: gap: ")


def test_debug_shows_traceback(tmp_path, capsys):
    assert main([str(tmp_path / "missing.npz"), "--info", "--debug"]) == 2
    assert "Traceback" in capsys.readouterr().err


def test_usage_error_exit_2(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--no-such-option"])
    assert exc.value.code == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_module_entry_point(bar_problem, tmp_path):
    path = save_problem(tmp_path / "bar.npz", bar_problem)
    result = subprocess.run([sys.executable, "-m", "solver", str(path),
                             "--info"], capture_output=True, text=True)
    assert result.returncode == 0
    assert "reduced DOFs      2" in result.stdout
    result = subprocess.run([sys.executable, "-m", "solver",
                             str(tmp_path / "nope.npz"), "--info"],
                            capture_output=True, text=True)
    assert result.returncode == 2
    assert result.stderr.strip().count("\n") == 0
    assert "Traceback" not in result.stderr


SUMMARY_KEYS = {"method", "gap", "converged", "iterations", "n_jacobian",
                "n_residual", "residual", "complementarity",
                "n_contact_nodes", "max_contact_pressure", "n_dof",
                "wall_time", "status", "message", "error"}


def test_start_option(exported, tmp_path, capsys):
    """--start nested (default) and free give the same displacements;
    summary.json records the start, the levels (coarsest first, their
    counts adding up to the totals) and the gap scale used (k̄ on the
    condensed system, 1 on the full one); the printed summary names the
    levels."""
    path = exported(454)[0]
    runs, summaries = {}, {}
    for start in ("nested", "free"):
        out = tmp_path / start
        argv = [str(path), "-o", str(out)] + (
            ["--start", start] if start == "free" else [])
        assert main(argv) == 0
        runs[start] = result_displacement(out)
        summaries[start] = json.loads((out / "summary.json").read_text())
    printed = capsys.readouterr().out
    assert "nested start" in printed
    nested, free = summaries["nested"], summaries["free"]
    assert nested["start"] == "nested" and free["start"] == "free"
    assert free["levels"] == []
    sizes = [level["n_nodes"] for level in nested["levels"]]
    assert sizes == sorted(sizes) and len(sizes) > 1
    assert sum(lv["njev"] for lv in nested["levels"]) == nested["n_jacobian"]
    assert nested["gap_scale"] == free["gap_scale"] > 1e3  # k̄, not 1
    assert np.abs(runs["nested"] - runs["free"]).max() <= \
        1e-9 * np.abs(runs["free"]).max()
    out = tmp_path / "full"
    assert main([str(path), "--system", "full", "-o", str(out)]) == 0
    full = json.loads((out / "summary.json").read_text())
    assert full["start"] == "zero" and full["gap_scale"] == 1.0
    capsys.readouterr()


@pytest.mark.parametrize("argv, message", [
    (["--start", "nested", "--system", "full"],
     "--start nested is not supported for 2D, rigid, frictionless, serial "
     "engine: the nested start needs the condensed system"),
    (["--start", "free", "--friction", "0.3"],
     "--start free is not supported for 2D, rigid, friction, serial "
     "engine: it applies to frictionless solves")])
def test_start_option_conflicts(exported, tmp_path, capsys, argv, message):
    """A combination the front refuses: exit 2, one line in the command
    line's words, nothing written."""
    assert main([str(exported(118)[0]), "-o", str(tmp_path / "x")]
                + argv) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not (tmp_path / "x").exists()


@pytest.mark.parametrize("friction", [None, "0.3"])
def test_system_option(exported, tmp_path, capsys, friction):
    """--system full (the thesis's system in all unknowns) and the default
    (condensed onto Γc) write the same displacements; summary.json says
    which ran, and the thesis's friction formulation runs on the full
    system unless told otherwise."""
    path = exported(118)[0]
    extra = [] if friction is None else ["--friction", friction, "--steps",
                                         "5", "--formulation", "projection"]
    runs = {}
    for system in ("auto", "full", "condensed"):
        out = tmp_path / system
        assert main([str(path), "--system", system, "-o", str(out)]
                    + extra) == 0
        runs[system] = result_displacement(out)
        summary = json.loads((out / "summary.json").read_text())
        assert summary["system"] == ("full" if system == "full"
                                     else "condensed")
    scale = np.abs(runs["full"]).max()
    for system in ("auto", "condensed"):
        assert np.abs(runs[system] - runs["full"]).max() <= 1e-9 * scale
    if friction is not None:
        out = tmp_path / "thesis"
        assert main([str(path), "--friction", friction, "--steps", "5",
                     "--formulation", "thesis", "-o", str(out)]) == 0
        assert json.loads((out / "summary.json").read_text())["system"] \
            == "full"
    capsys.readouterr()


@pytest.mark.parametrize("method", ["min", "fb"])
@pytest.mark.parametrize("gap", ["obstacle", "body"])
def test_solve_writes_outputs(exported, tmp_path, capsys, method, gap):
    import meshio

    path = exported(118)[0]
    out = tmp_path / "out"
    code = main([str(path), "--method", method, "--gap", gap, "-o", str(out)]
                + (["--plots"] if method == "fb" and gap == "body" else []))
    assert code == 0
    summary = json.loads((out / "summary.json").read_text())
    assert SUMMARY_KEYS <= set(summary)
    assert summary["converged"] is True
    assert summary["method"] == method and summary["gap"] == gap
    assert summary["n_jacobian"] >= 1 and summary["n_residual"] > \
        summary["n_jacobian"]
    assert summary["n_dof"] == 138
    with np.load(out / "result.npz", allow_pickle=False) as result:
        assert result["displacement"].shape == (74, 2)
        assert len(result["history_residual"]) == summary["iterations"]
        assert result["in_contact"].sum() == summary["n_contact_nodes"]
    vtk = meshio.read(out / "result.vtu")
    np.testing.assert_allclose(vtk.point_data["u"][:, :2],
                               result_displacement(out))
    assert "converged" in capsys.readouterr().out
    pngs = sorted(p.name for p in out.glob("*.png"))
    if method == "fb" and gap == "body":
        assert pngs == ["contact_pressure.png", "convergence.png",
                        "deformed.png", "displacement.png"]
    else:
        assert pngs == []
    assert not list(out.glob(".tmp-*"))  # no temporary files left


def result_displacement(out):
    with np.load(out / "result.npz") as result:
        return result["displacement"]


def test_not_converged_exit_3_with_history(exported, tmp_path, capsys):
    path = exported(118)[0]
    out = tmp_path / "out"
    assert main([str(path), "--method", "fb", "--max-iter", "2",
                 "-o", str(out)]) == 3
    captured = capsys.readouterr()
    assert "NOT CONVERGED" in captured.out
    assert "maximum number of iterations" in captured.err
    assert "residual history" in captured.err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["converged"] is False and summary["iterations"] == 2
    assert (out / "result.npz").exists()


def test_default_outdir_beside_problem(bar_problem, tmp_path, capsys):
    path = save_problem(tmp_path / "bar.npz", bar_problem)
    assert main([str(path)]) == 0
    summary = json.loads((tmp_path / "bar-min-given" / "summary.json")
                         .read_text())
    assert summary["n_contact_nodes"] == 1
    assert summary["max_contact_force"] == pytest.approx(550.0)  # closed form


@pytest.mark.parametrize("argv", [["--tol", "0"], ["--tol", "abc"],
                                  ["--max-iter", "0"], ["--method", "newton"],
                                  ["--gap", "nowhere"], ["--gap-scale", "-1"]])
def test_bad_options_exit_2(bar_problem, tmp_path, capsys, argv):
    path = save_problem(tmp_path / "bar.npz", bar_problem)
    with pytest.raises(SystemExit) as exc:
        main([str(path)] + argv)
    assert exc.value.code == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_unwritable_outdir_exit_2(bar_problem, tmp_path, capsys):
    path = save_problem(tmp_path / "bar.npz", bar_problem)
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    assert main([str(path), "-o", str(blocker / "sub")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: cannot write") and err.count("\n") == 1


def test_friction_run_outputs(exported, tmp_path, capsys):
    path = exported(118)[0]
    out = tmp_path / "fric"
    assert main([str(path), "--friction", "0.3", "--steps", "8", "-o",
                 str(out), "--plots"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["mode"] == "friction" and summary["converged"] is True
    assert summary["method"] == "min"  # the default with the projection
    # formulation (benchmarks/README.md; the thesis's split takes fb)
    assert summary["formulation"] == "projection"  # the default since the
    # thesis's split fails on finer meshes (test_friction_default.py)
    assert summary["coulomb"] == "lagged"
    assert len(summary["per_step"]) == 8 == summary["steps_completed"]
    assert summary["n_jacobian"] == sum(r["njev"] for r in
                                        summary["per_step"])
    assert summary["n_residual"] == sum(r["nfev"] for r in
                                        summary["per_step"])
    with np.load(out / "result.npz") as result:
        assert result["displacement"].shape == (8, 74, 2)
        assert result["friction_traction"].shape == (8, 11)
        np.testing.assert_array_equal(result["step_njev"],
                                      [r["njev"] for r in
                                       summary["per_step"]])
    assert len(list((out / "steps").glob("step_*.vtu"))) == 8
    assert (out / "result.pvd").read_text().count("<DataSet") == 8
    assert sorted(p.name for p in out.glob("*.png")) == [
        "deformed.png", "friction_along_gc.png", "history.png"]
    assert "Table 2" in capsys.readouterr().out


def test_friction_failure_keeps_completed_steps(exported, tmp_path, capsys):
    """A real failure: FB with the implicit bound and f_c = 100 stalls in
    load step 4 of 20 on the 454 mesh in the full system (see
    test_friction); the three completed steps stay on disk."""
    path = exported(454)[0]
    out = tmp_path / "fail"
    assert main([str(path), "--friction", "100", "--coulomb", "implicit",
                 "--formulation", "projection", "--steps", "20",
                 "--system", "full", "--method", "fb", "-o", str(out)]) == 3
    err = capsys.readouterr().err
    assert "load step 4 of 20 did not converge" in err
    assert "residual history" in err and "3 completed steps kept" in err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["converged"] is False and summary["failed_step"] == 4
    assert summary["per_step"][-1]["converged"] is False
    with np.load(out / "result.npz") as result:
        assert len(result["load_factor"]) == 3 == summary["steps_completed"]
        assert not result["converged"]
    assert len(list((out / "steps").glob("*.vtu"))) == 3


@pytest.mark.parametrize("argv", [["--friction", "-0.5"],
                                  ["--friction", "nan"],
                                  ["--friction", "0.3", "--steps", "0"],
                                  ["--friction", "0.3", "--formulation",
                                   "tresca"]])
def test_friction_bad_options_exit_2(bar_problem, tmp_path, capsys, argv):
    path = save_problem(tmp_path / "bar.npz", bar_problem)
    with pytest.raises(SystemExit) as exc:
        main([str(path)] + argv)
    assert exc.value.code == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
