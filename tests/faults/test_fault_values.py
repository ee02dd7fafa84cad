"""Extreme values (issue 16, class 7): loads that overflow double
precision are bad input; legal values whose solve overflows still give
strict JSON and a printed summary.

A load is refused when ‖f‖₂·max(k, 1/k) exceeds
:data:`solver.problem.format.LOAD_LIMIT` (k = max|K_ij|), for ``f`` and for
every stage of ``load_path``: exit 2, one line naming the key, the norm,
the largest entry and the limit, nothing written. A load just inside the
limit is accepted, and the same problem in other force units (K and f
scaled together) loads as long as the product stays inside. A legal
problem whose solve overflows (a load near the limit with a gap scale of
1e300) ends with exit 3, not as an internal error: ``summary.json`` is
strict JSON with the non-finite numbers written as ``"inf"``/``"nan"``,
and the printed summary and failure line show them.
"""

import json

import numpy as np
import pytest
import scipy.sparse as sp

from fault_tools import run_cli
from solver.errors import ProblemError
from solver.output.files import json_ready, write_summary
from solver.output.report import (format_friction_result, format_result,
                                  format_summary)
from solver.problem import load_problem
from solver.problem.checks import load_limit
from solver.problem.format import LOAD_LIMIT


@pytest.fixture(scope="module")
def block(exported):
    """The arrays of the 118-triangle thesis block (‖f‖ = 4000)."""
    with np.load(exported(118)[0], allow_pickle=False) as archive:
        return {k: archive[k] for k in archive.files}


def stiffness(arrays):
    return sp.csr_matrix((arrays["K_data"], arrays["K_indices"],
                          arrays["K_indptr"]),
                         shape=tuple(arrays["K_shape"]))


def write(tmp_path, arrays, name="p.npz"):
    path = tmp_path / name
    np.savez(path, **arrays)
    return path


def with_load_path(block, first_stage):
    """A two-stage load path ending in f (frictionless first stage)."""
    return dict(block, load_path=np.array([first_stage, block["f"]]),
                load_path_steps=np.array([1, 1]),
                load_path_friction=np.array([0.0, 1.0]))


def strict_json(path):
    """summary.json parsed by a parser that refuses NaN and Infinity."""
    def refuse(name):
        raise AssertionError(f"{name} in {path}")

    return json.loads(path.read_text(), parse_constant=refuse)


def one_error_line(code, out, err, phrases, tmp_path, before):
    assert code == 2, (code, err)
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert "internal error" not in err and "Traceback" not in err
    for phrase in phrases:
        assert phrase in lines[0], (phrase, err)
    assert out == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == before


# --------------------------------------------------------------------------
# loads that overflow: refused at load, naming the key and the limit

def huge_entry(block):
    f = block["f"].copy()
    f[int(np.argmax(np.abs(f)))] = 1e308
    return f


LOADS = [
    # the issue's cases: a load scaled by 1e152 with friction, one entry
    # of 1e308 (printed summary), a load-path stage of 1e308 (summary.json)
    ("f scaled by 1e152", lambda b: dict(b, f=b["f"] * 1e152),
     ["--friction", "0.3", "--steps", "2"], "f: ‖f‖₂ = 4e+155"),
    ("f entry 1e308", lambda b: dict(b, f=huge_entry(b)), [],
     "f: ‖f‖₂ = 1e+308 (largest entry 1e+308 at DOF"),
    ("load path stage of 1e308",
     lambda b: with_load_path(b, huge_entry(b)),
     ["--friction", "0.3", "--method", "min"],
     "load_path: stage 0 has ‖f‖₂ = 1e+308 (largest entry 1e+308"),
    ("f below a tiny K", lambda b: dict(b, K_data=b["K_data"] * 1e-200),
     [], "f: ‖f‖₂ = 4e+03"),
]


@pytest.mark.parametrize("name, mutate, argv, phrase", LOADS,
                         ids=[c[0] for c in LOADS])
def test_overflowing_load_is_refused(block, tmp_path, capsys, name, mutate,
                                     argv, phrase):
    arrays = mutate(dict(block))
    path = write(tmp_path, arrays)
    limit, k = load_limit(stiffness(arrays))
    before = sorted(p.name for p in tmp_path.iterdir())
    code, out, err = run_cli([path, *argv, "-o", tmp_path / "out"], capsys)
    one_error_line(code, out, err, [phrase, f"above {limit:.3g}",
                                    f"k = max|K_ij| = {k:.3g}",
                                    f"<= {LOAD_LIMIT:g}"], tmp_path, before)
    code, out, err = run_cli([path, "--info"], capsys)
    one_error_line(code, out, err, [phrase], tmp_path, before)


@pytest.mark.parametrize("factor, accepted", [(0.99, True), (1.01, False)])
def test_load_limit_is_the_documented_one(block, tmp_path, factor,
                                          accepted):
    """‖f‖₂ at 0.99 and 1.01 times LOAD_LIMIT / k (k > 1 here)."""
    k = np.abs(block["K_data"]).max()
    assert k > 1
    f = block["f"] / np.linalg.norm(block["f"]) * factor * LOAD_LIMIT / k
    path = write(tmp_path, dict(block, f=f))
    if accepted:
        assert np.linalg.norm(load_problem(path).f) == pytest.approx(
            factor * LOAD_LIMIT / k)
    else:
        with pytest.raises(ProblemError, match="^f: ‖f‖₂ = "):
            load_problem(path)


def test_other_force_units_still_load(block, tmp_path):
    """K and f in units 1e-200 times as large: the same problem, loaded
    (the limit follows K); f alone that small is fine too."""
    arrays = dict(block, K_data=block["K_data"] * 1e-200,
                  f=block["f"] * 1e-200)
    problem = load_problem(write(tmp_path, arrays))
    assert np.linalg.norm(problem.f) == pytest.approx(4000e-200)
    load_problem(write(tmp_path, dict(block, f=block["f"] * 1e-200),
                       "small.npz"))


# --------------------------------------------------------------------------
# legal values, non-finite results: strict JSON, printed, exit 3

@pytest.fixture()
def near_limit(block, tmp_path):
    """f × 1e140 (inside the limit) with --gap-scale 1e300: the gap rows
    k̄-scaled by 1e300 overflow, legally."""
    arrays = dict(block, f=block["f"] * 1e140)
    load_problem(write(tmp_path, arrays))  # legal
    return write(tmp_path, arrays)


@pytest.mark.parametrize("friction", [[], ["--friction", "0.3", "--steps",
                                           "2"]],
                         ids=["frictionless", "friction"])
def test_overflowing_solve_writes_strict_json(near_limit, tmp_path, capsys,
                                              friction):
    out = tmp_path / "out"
    code, stdout, err = run_cli([near_limit, "--gap-scale", "1e300",
                                 "--method", "min", *friction, "-o", out],
                                capsys)
    assert code == 3, err
    assert "internal error" not in err and "Traceback" not in err
    lines = err.splitlines()
    assert len(lines) == 1 and "non-finite residual" in lines[0], err
    assert "NOT CONVERGED" in stdout
    summary = strict_json(out / "summary.json")
    assert summary["status"] == "not_converged"
    if friction:
        assert summary["per_step"][-1]["error"] == "inf"
    else:
        assert summary["residual_history"][-1] == "inf"
        assert summary["residual"] == "inf"
        assert "final ||Phi||     inf" in stdout
        assert "residual history ||Phi||: [inf]" in lines[0]


def test_write_summary_rule(tmp_path):
    """Non-finite floats at any depth become "inf", "-inf", "nan"; NumPy
    scalars and arrays become JSON numbers and lists; the input is left
    as it was."""
    summary = {"a": np.float64(np.inf), "b": [1.0, -np.inf, {"c": np.nan}],
               "per_step": [{"error": float("nan"), "n": np.int64(3),
                             "ok": np.bool_(True)}],
               "array": np.array([1.5, np.nan]), "text": "inf", "none": None}
    write_summary(tmp_path / "summary.json", summary)
    assert strict_json(tmp_path / "summary.json") == {
        "a": "inf", "b": [1.0, "-inf", {"c": "nan"}],
        "per_step": [{"error": "nan", "n": 3, "ok": True}],
        "array": [1.5, "nan"], "text": "inf", "none": None}
    assert summary["a"] == np.inf and np.isnan(summary["per_step"][0]["error"])
    assert json_ready(2.5) == 2.5 and json_ready(True) is True


def frictionless_summary(value):
    return {"method": "min", "gap": "obstacle", "converged": False,
            "message": "not converged", "iterations": 1, "n_jacobian": 1,
            "n_residual": 2, "system": "full",
            "stopping": {"absolute": value, "tol": 1e-10, "scale": value,
                         "relative": value, "test": "t"},
            "residual": value, "verification": {"passed": False,
                                                "failed": []},
            "complementarity": value, "n_contact_nodes": 0,
            "n_contact_candidates": 3, "max_contact_pressure": value,
            "n_dof": 4, "wall_time": 0.5}


@pytest.mark.parametrize("value", [np.inf, np.nan, "inf", "nan"])
def test_printed_summaries_show_non_finite_numbers(value):
    """Floats (a summary just made) or strings (one read back from
    summary.json): printed as they are, never a format error."""
    text = format_result(frictionless_summary(value), "out")
    assert f"max pressure      {value}" in text
    assert f"final ||Phi||     {value}" in text
    friction = {"friction": 0.3, "steps": 2, "formulation": "projection",
                "coulomb": "lagged", "method": "min", "converged": False,
                "steps_completed": 1, "n_jacobian": 1, "n_residual": 1,
                "system": "full", "gradient_steps": 0, "final_n_contact": 0,
                "final_n_stick": 0, "final_n_slip": 0,
                "final_max_contact_pressure": value, "n_dof": 4,
                "wall_time": value, "verification": {"passed": False,
                                                     "failed": []}}
    text = format_friction_result(friction, "out")
    assert f"max pressure {value}" in text
    assert "verification      FAILED\n" in text


def test_info_of_a_polyline_obstacle(block, tmp_path, capsys):
    """--info prints a polyline obstacle (it unpacked it as x(t), y(t))."""
    arrays = {k: v for k, v in block.items()
              if k not in ("obstacle_x", "obstacle_y")}
    arrays["obstacle_points"] = np.array([[5.05, -20.0], [5.2, 0.0],
                                          [5.05, 20.0]])
    code, out, err = run_cli([write(tmp_path, arrays), "--info"], capsys)
    assert code == 0, err
    assert "obstacle          PolylineCurve(3 points" in out
    info = format_summary(load_problem(tmp_path / "p.npz").summary())
    assert "PolylineCurve(3 points" in info
