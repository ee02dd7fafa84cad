"""Bad inputs through the command line, and how failures are reported.

The corpus: every case is a problem file or an option that
``python -m solver`` must refuse with exit code 2 and exactly one line on
stderr that starts with ``error:`` (``python -m solver: error:`` for usage
errors from argparse) and names the problem, without a traceback, without
anything on stdout and without creating a file or a folder. Cases the
loader corpus of ``test_problem.py`` already covers key by key are not
repeated; here they go through the whole command line (file checks, the
positive definiteness of K, gaps, options, output folder).

Then non-convergence (exit 3): which status, its message, the residual
history in summary.json and result.npz.
"""

import json
import pickle
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

from conftest import run_cli
from solver.examples import two_dof_bar
from solver.problem import save_problem


@pytest.fixture(scope="module")
def mesh_arrays(exported):
    """The arrays of the 118-triangle block (session export, not copied)."""
    with np.load(exported(118)[0], allow_pickle=False) as archive:
        return {k: archive[k] for k in archive.files}


@pytest.fixture(scope="module")
def bar_arrays():
    return two_dof_bar().to_arrays()


run = run_cli  # main(argv) -> (exit code, stdout, stderr)


def tree(folder):
    """Every file and folder below ``folder`` (relative paths)."""
    return sorted(str(p.relative_to(folder)) for p in Path(folder).rglob("*"))


def assert_refused(code, out, err, phrase):
    lines = err.splitlines()
    assert code == 2, (code, err)
    assert len(lines) == 1 and err.endswith("\n"), err
    assert lines[0].startswith(("error: ", "python -m solver: error: ")), err
    assert "Traceback" not in err
    assert phrase in lines[0], (phrase, err)
    assert out == ""


# ----------------------------------------------------------------------------
# problem files

def csr_keys(name, A):
    A = sp.csr_matrix(A)
    return {f"{name}_data": A.data, f"{name}_indices": A.indices,
            f"{name}_indptr": A.indptr, f"{name}_shape": np.array(A.shape)}


def replace_spectrum(arrays, name, smallest):
    """The symmetric matrix ``name`` with its smallest eigenvalue replaced
    (dense; the 118 block has 138 DOFs): positive diagonal, symmetric, so
    it passes the loader, but it is singular or indefinite."""
    A = sp.csr_matrix((arrays[f"{name}_data"], arrays[f"{name}_indices"],
                       arrays[f"{name}_indptr"]),
                      shape=tuple(arrays[f"{name}_shape"])).toarray()
    w, V = np.linalg.eigh(A)
    w[0] = smallest * w[-1]
    A = (V * w) @ V.T
    A = (A + A.T) / 2
    assert np.diag(A).min() > 0
    return csr_keys(name, A)


def meta_with(arrays, **fields):
    return np.array(json.dumps(dict(json.loads(str(arrays["meta"])),
                                    **fields)))


def without(arrays, key):
    return {k: v for k, v in arrays.items() if k != key}


def swap(a, i, j):
    a = a.copy()
    a[[i, j]] = a[[j, i]]
    return a


def interior_node(a):
    x, y = a["nodes"].T
    return int(np.flatnonzero((np.abs(x) < 4) & (np.abs(y) < 9))[0])


def obstacle(x, y="t"):
    return dict(obstacle_x=np.array(x), obstacle_y=np.array(y))


#: (case id, base ("mesh" or "bar"), mutation of the arrays, phrase that the
#: one-line message must contain)
ARRAY_CASES = [
    # keys
    ("missing key", "mesh", lambda a: without(a, "K_indptr"),
     "K_indptr: missing"),
    ("extra key", "mesh", lambda a: dict(a, notes=np.array("hello")),
     "notes: unexpected key"),
    ("discrete key in a mesh file", "mesh",
     lambda a: dict(a, normal=np.ones((11, 2))), "normal: unexpected key"),
    ("mesh key in a discrete file", "bar",
     lambda a: dict(a, nodes=np.zeros((1, 2))), "nodes: unexpected key"),
    ("kind misspelt", "mesh", lambda a: dict(a, kind=np.array("Mesh")),
     "kind: must be one of"),
    ("old format version", "mesh",
     lambda a: dict(a, format_version=np.array(0)),
     "format_version: file has version 0"),
    # dtypes and shapes
    ("f complex", "mesh", lambda a: dict(a, f=a["f"] + 0j),
     "f: expected real numbers"),
    ("f boolean", "bar", lambda a: dict(a, f=np.array([True, False])),
     "f: expected real numbers"),
    ("contact_dofs float", "mesh",
     lambda a: dict(a, contact_dofs=a["contact_dofs"].astype(float)),
     "contact_dofs: expected integers"),
    ("nodes as text", "mesh",
     lambda a: dict(a, nodes=a["nodes"].astype(str)),
     "nodes: expected real numbers"),
    ("K_shape of three entries", "mesh",
     lambda a: dict(a, K_shape=np.array([138, 138, 1])),
     "K_shape: expected shape (2)"),
    ("flat quadrilateral cells", "mesh",
     lambda a: dict(a, cells=np.c_[a["cells"], a["cells"][:, :1]]),
     "cells: quadrilateral 0 (nodes"),
    ("pentagon cells", "mesh",
     lambda a: dict(a, cells=np.c_[a["cells"], a["cells"][:, :2]]),
     "cells: expected shape (?, 3) or (?, 4)"),
    ("dof_map too short", "mesh",
     lambda a: dict(a, dof_map=a["dof_map"][:-2]), "dof_map: expected shape"),
    ("meta as bytes", "mesh",
     lambda a: dict(a, meta=np.array(str(a["meta"]).encode())),
     "meta: expected a text scalar"),
    ("obstacle as two strings", "mesh",
     lambda a: dict(a, obstacle_x=np.array(["5", "t"])),
     "obstacle_x: expected a text scalar"),
    # values
    ("nodes NaN", "mesh",
     lambda a: dict(a, nodes=np.where(a["nodes"] == a["nodes"].max(),
                                      np.nan, a["nodes"])),
     "nodes: "),
    ("u_prescribed infinite", "mesh",
     lambda a: dict(a, u_prescribed=a["u_prescribed"] - np.inf),
     "u_prescribed: "),
    ("M_data infinite", "mesh",
     lambda a: dict(a, M_data=np.r_[np.inf, a["M_data"][1:]]),
     "M_data: 1 entries are NaN or infinite"),
    ("t_range NaN", "mesh",
     lambda a: dict(a, obstacle_t_range=np.array([np.nan, 1.0])),
     "obstacle_t_range: "),
    ("meta nu = 0.5", "mesh", lambda a: dict(a, meta=meta_with(a, nu=0.5)),
     "meta: nu must be"),
    ("meta E infinite", "mesh",
     lambda a: dict(a, meta=meta_with(a, E=float("inf"))),
     "meta: Infinity is not a number in JSON"),
    ("meta E boolean", "mesh", lambda a: dict(a, meta=meta_with(a, E=True)),
     "meta: E must be"),
    # K and M
    ("K not symmetric", "mesh",
     lambda a: dict(a, K_data=np.where(np.arange(len(a["K_data"])) == 1,
                                       2 * a["K_data"], a["K_data"])),
     "K_data: the matrix is not symmetric"),
    ("K indefinite", "mesh", lambda a: dict(a, **replace_spectrum(a, "K",
                                                                  -0.1)),
     "K_data: K is not positive definite: it has 1 negative eigenvalue"),
    ("K singular", "mesh", lambda a: dict(a, **replace_spectrum(a, "K", 0.0)),
     "K is not positive definite (singular stiffness: is the body "
     "supported?)"),
    ("K of a floating spring", "bar",
     lambda a: dict(a, **csr_keys("K", 9e4 * np.array([[1.0, -1.0],
                                                       [-1.0, 1.0]]))),
     "singular stiffness: is the body supported?"),
    ("K indefinite 2x2", "bar",
     lambda a: dict(a, **csr_keys("K", [[1.0, 2.0], [2.0, 1.0]])),
     "K is not positive definite"),
    ("M singular", "mesh", lambda a: dict(a, **replace_spectrum(a, "M", 0.0)),
     "M_data: M is not positive definite"),
    ("M of the wrong size", "mesh",
     lambda a: dict(a, **csr_keys("M", sp.eye(10))),
     "M_shape: expected (11, 11)"),
    # the contact boundary
    ("contact node inside the body", "mesh",
     lambda a: dict(a, contact_nodes=np.r_[a["contact_nodes"][:-1],
                                           interior_node(a)]),
     "contact_nodes: not ordered along the boundary"),
    ("contact nodes out of order", "mesh",
     lambda a: dict(a, contact_nodes=swap(a["contact_nodes"], 0, -1)),
     "contact_nodes: not ordered along the boundary"),
    ("contact node twice", "mesh",
     lambda a: dict(a, contact_nodes=np.r_[a["contact_nodes"][:-1],
                                           a["contact_nodes"][0]]),
     "contact_nodes: a node appears twice"),
    ("contact_dofs shifted", "mesh",
     lambda a: dict(a, contact_dofs=np.roll(a["contact_dofs"], 1, axis=0)),
     "contact_dofs: does not match dof_map"),
    ("discrete normal not unit", "bar",
     lambda a: dict(a, normal=np.array([[0.0, -0.5]])), "normal: row 0"),
    # obstacle expressions
    ("obstacle syntax", "mesh", lambda a: dict(a, **obstacle("5 + 0.1*t**")),
     "syntax error"),
    ("obstacle caret", "mesh", lambda a: dict(a, **obstacle("5 + t^2")),
     "use ** for powers"),
    ("obstacle unknown name", "mesh", lambda a: dict(a, **obstacle("y + 5")),
     "unknown name 'y'"),
    ("obstacle unknown function", "mesh",
     lambda a: dict(a, **obstacle("5 + floor(t)")),
     "call of 'floor' is not allowed"),
    ("obstacle code execution", "mesh",
     lambda a: dict(a, **obstacle("__import__('os').system('touch PWNED')")),
     "is not allowed"),
    ("obstacle attribute access", "mesh",
     lambda a: dict(a, **obstacle("5", "t.__class__.__mro__")),
     "Attribute is not allowed"),
    ("obstacle lambda", "mesh",
     lambda a: dict(a, **obstacle("(lambda: 5)() + 0*t")), "is not allowed"),
    ("obstacle comprehension", "mesh",
     lambda a: dict(a, **obstacle("[t for t in ()]")),
     "ListComp is not allowed"),
    ("obstacle overflowing constant", "mesh",
     lambda a: dict(a, **obstacle("exp(1000) + t")),
     "constant exp(1000) is not a finite real number in double precision"),
    ("obstacle complex constant", "mesh",
     lambda a: dict(a, **obstacle("5 + asin(2)*t")),
     "constant asin(2) is not a finite real number"),
    ("obstacle a point", "mesh", lambda a: dict(a, **obstacle("5", "0")),
     "does not depend on t"),
    ("obstacle overflowing coefficient", "mesh",
     lambda a: dict(a, **obstacle("5 + 1e308*10*t**2")),
     "is not a finite real number"),
    # expressions that used to keep SymPy busy for minutes or longer
    ("obstacle deeply nested calls", "mesh",
     lambda a: dict(a, **obstacle("5", "sin(" * 80 + "t" + ")" * 80)),
     "too many nested function calls (80 > 8)"),
    ("obstacle deeply nested powers", "mesh",
     lambda a: dict(a, **obstacle("5 + " + "(" * 20 + "t" + "**2+t)" * 20)),
     "nests too deeply"),
    ("obstacle huge derivative", "mesh",
     lambda a: dict(a, **obstacle("5 + " + "*".join(f"sin({i}*t)" for i in
                                                    range(1, 60)))),
     "too complex"),
    # normal lines that miss the body (GapError, found before solving)
    ("obstacle parallel to the normals", "mesh",
     lambda a: dict(a, **obstacle("t", "50 + 0*t")),
     "misses the obstacle"),
    ("obstacle ends below the body", "mesh",
     lambda a: dict(a, **obstacle("5.05 + 0*t"),
                    obstacle_t_range=np.array([20.0, 30.0])),
     "misses the obstacle"),
]


@pytest.mark.parametrize("name, base, mutate, phrase", ARRAY_CASES,
                         ids=[c[0] for c in ARRAY_CASES])
@pytest.mark.parametrize("mode", ["solve", "friction"])
def test_bad_problem_file(mesh_arrays, bar_arrays, tmp_path, capsys, name,
                          base, mutate, phrase, mode):
    """The frictionless solve (default output folder beside the problem) and
    the friction run (-o) refuse the file the same way and create nothing."""
    arrays = mutate(dict(mesh_arrays if base == "mesh" else bar_arrays))
    path = tmp_path / "problem.npz"
    np.savez(path, **arrays)
    before = tree(tmp_path)
    argv = [path] if mode == "solve" else [
        path, "--friction", "0.3", "--steps", "2", "-o", tmp_path / "out"]
    assert_refused(*run(argv, capsys), phrase)
    assert tree(tmp_path) == before
    assert not Path("PWNED").exists()


def test_corpus_size():
    assert len(ARRAY_CASES) + len(FILE_CASES) + len(OPTION_CASES) >= 30


def truncated(tmp_path, bar):
    data = Path(save_problem(tmp_path / "full.npz", bar)).read_bytes()
    path = tmp_path / "problem.npz"
    path.write_bytes(data[:len(data) // 2])
    (tmp_path / "full.npz").unlink()
    return path


def zip_of_text(tmp_path, bar):
    path = tmp_path / "problem.npz"
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("readme.txt", "not an array")
    return path


def pickled_member(tmp_path, bar):
    arrays = bar.to_arrays()
    arrays["f"] = np.array([{"evil": 1}, 2], dtype=object)
    path = tmp_path / "problem.npz"
    np.savez(path, **arrays)
    return path


def pickle_file(tmp_path, bar):
    path = tmp_path / "problem.npz"
    path.write_bytes(pickle.dumps(bar.to_arrays()))
    return path


def npy_file(tmp_path, bar):
    path = tmp_path / "problem.npz"
    with open(path, "wb") as stream:
        np.save(stream, bar.K.toarray())
    return path


def directory(tmp_path, bar):
    path = tmp_path / "problem.npz"
    path.mkdir()
    return path


def missing(tmp_path, bar):
    return tmp_path / "problem.npz"


FILE_CASES = [
    ("truncated file", truncated, "not a readable .npz file"),
    ("zip of text", zip_of_text,
     "format_version: missing (is this a problem file of this solver?)"),
    ("pickled member", pickled_member, "f: contains pickled Python objects"),
    ("pickle file", pickle_file, "not an .npz archive"),
    (".npy file", npy_file, "a single .npy array"),
    ("directory", directory, "is a directory"),
    ("missing file", missing, "no such file"),
]


@pytest.mark.parametrize("name, make, phrase", FILE_CASES,
                         ids=[c[0] for c in FILE_CASES])
def test_bad_file(tmp_path, capsys, name, make, phrase):
    path = make(tmp_path, two_dof_bar())
    before = tree(tmp_path)
    assert_refused(*run([path], capsys), phrase)
    assert tree(tmp_path) == before


OPTION_CASES = [
    ("negative friction", ["--friction", "-0.1"], "must be >= 0"),
    ("infinite friction", ["--friction", "inf"], "must be >= 0 and finite"),
    ("zero steps", ["--friction", "0.3", "--steps", "0"],
     "between 1 and"),
    ("negative steps", ["--friction", "0.3", "--steps", "-2"],
     "between 1 and"),
    ("fractional steps", ["--friction", "0.3", "--steps", "1.5"],
     "not an integer"),
    ("NaN tolerance", ["--tol", "nan"], "must be positive and finite"),
    ("infinite gap scale", ["--gap-scale", "inf"],
     "must be positive and finite"),
    ("negative max-iter", ["--max-iter", "-1"], "between 1 and"),
    ("huge steps", ["--steps", "1000000000"], "between 1 and 100000"),
    ("steps 10**30", ["--steps", "10**30"], "not an integer"),
    ("huge max-iter", ["--max-iter", str(10**30)], "not an integer"),
    ("tol below round-off", ["--tol", "1e-300"], "between 1e-15 and 0.1"),
    ("tol not relative", ["--tol", "2"], "between 1e-15 and 0.1"),
    ("unknown coulomb", ["--friction", "0.3", "--coulomb", "exact"],
     "invalid choice"),
    ("unknown option", ["--frcition", "0.3"], "unrecognized arguments"),
]


@pytest.mark.parametrize("name, argv, phrase", OPTION_CASES,
                         ids=[c[0] for c in OPTION_CASES])
def test_bad_option(tmp_path, capsys, name, argv, phrase):
    path = save_problem(tmp_path / "bar.npz", two_dof_bar())
    before = tree(tmp_path)
    assert_refused(*run([path] + argv, capsys), phrase)
    assert tree(tmp_path) == before


def test_no_problem_argument(capsys):
    assert_refused(*run([], capsys), "the following arguments are required")


@pytest.mark.parametrize("friction", [[], ["--friction", "0.3"]])
def test_output_folder_is_a_file(tmp_path, capsys, friction):
    path = save_problem(tmp_path / "bar.npz", two_dof_bar())
    before = tree(tmp_path)
    assert_refused(*run([path, "-o", path] + friction, capsys),
                   f"cannot write {path}: File exists")
    assert tree(tmp_path) == before


def test_output_folder_not_writable(tmp_path, capsys, monkeypatch):
    """An existing folder in which no file can be created (simulated: the
    tests may run as root, for whom permission bits do not count)."""
    import tempfile

    path = save_problem(tmp_path / "bar.npz", two_dof_bar())
    out = tmp_path / "out"
    out.mkdir()

    def refuse(*args, **kwargs):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    assert_refused(*run([path, "-o", out], capsys),
                   f"cannot write {out}: Permission denied")
    assert tree(tmp_path) == ["bar.npz", "out"]


def test_nested_output_folder_not_left_behind(mesh_arrays, tmp_path,
                                              capsys):
    """-o a/b/c for a problem whose gaps fail: no folder a is created (the
    geometry is computed before the output folder)."""
    path = tmp_path / "problem.npz"
    np.savez(path, **dict(mesh_arrays, **obstacle("t", "50 + 0*t")))
    assert_refused(*run([path, "-o", tmp_path / "a" / "b" / "c"], capsys),
                   "misses the obstacle")
    assert tree(tmp_path) == ["problem.npz"]


def test_debug_shows_the_traceback(mesh_arrays, tmp_path, capsys):
    path = tmp_path / "problem.npz"
    np.savez(path, **dict(mesh_arrays, **obstacle("t", "50 + 0*t")))
    code, out, err = run([path, "--debug"], capsys)
    assert code == 2
    assert "Traceback" in err and "GapError" in err
    assert err.splitlines()[-1].startswith("error: the normal line")
    assert tree(tmp_path) == ["problem.npz"]


@pytest.mark.parametrize("arrays, phrase", [
    (lambda a: dict(a, **obstacle("t", "50 + 0*t")), "misses the obstacle"),
    (lambda a: dict(a, **replace_spectrum(a, "K", 0.0)),
     "is the body supported?"),
])
def test_subprocess(mesh_arrays, tmp_path, arrays, phrase):
    """``python -m solver`` as a process: exit 2, one line, nothing left."""
    path = tmp_path / "problem.npz"
    np.savez(path, **arrays(dict(mesh_arrays)))
    result = subprocess.run([sys.executable, "-m", "solver", str(path)],
                            capture_output=True, text=True, cwd=tmp_path)
    assert_refused(result.returncode, result.stdout, result.stderr, phrase)
    assert tree(tmp_path) == ["problem.npz"]


@pytest.mark.parametrize("name, base, mutate, phrase", ARRAY_CASES,
                         ids=[c[0] for c in ARRAY_CASES])
def test_bad_problem_api(mesh_arrays, bar_arrays, name, base, mutate,
                         phrase):
    """The Python API raises the ProblemError the command line prints: at
    validation, or (K not positive definite, gaps) when solving."""
    from solver import ProblemError, solve_friction, solve_frictionless
    from solver.problem import validate_arrays

    arrays = mutate(dict(mesh_arrays if base == "mesh" else bar_arrays))
    for solve in (solve_frictionless,
                  lambda p: solve_friction(p, 0.3, steps=2)):
        with pytest.raises(ProblemError) as exc:
            solve(validate_arrays(arrays))
        assert phrase in str(exc.value) and "\n" not in str(exc.value)


# ----------------------------------------------------------------------------
# non-convergence: exit 3, which status, the history on disk

def failed_run(argv, capsys, out):
    code, stdout, err = run(list(argv) + ["-o", out], capsys)
    assert code == 3, err
    assert "NOT CONVERGED" in stdout
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ")
    assert "not converged: " in lines[0]
    assert "Traceback" not in err and "residual history ||Phi||: [" in err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["converged"] is False
    return lines[0], summary


def test_max_iterations_status_1(exported, tmp_path, capsys):
    out = tmp_path / "out"
    err, summary = failed_run([exported(118)[0], "--method", "min",
                               "--max-iter", "1"], capsys, out)
    assert "maximum number of iterations reached after 1 iterations" in err
    assert summary["ncp_status"] == 1 and summary["iterations"] == 1
    # ‖Φ‖ before the one iteration, then of the final iterate (issue 15.13)
    assert len(summary["residual_history"]) == 2
    assert summary["residual_history"][-1] == summary["residual"]
    with np.load(out / "result.npz") as result:
        assert not result["converged"]
        np.testing.assert_array_equal(result["history_residual"],
                                      summary["residual_history"][:-1])
    assert not list(out.glob(".tmp-*"))


def test_line_search_exhausted_status_2(exported, tmp_path, capsys,
                                        monkeypatch):
    """φ_FB's Armijo search (27) with at most one trial step (max_halvings
    = 0 instead of 60, patched: the option is not on the command line) runs
    out in iteration 5 on the 118 block. With the default 60 halvings this
    only happens at round-off level, where the run stops with status 5
    ("no progress") instead."""
    from solver.ncp import DEFAULT_OPTIONS

    monkeypatch.setitem(DEFAULT_OPTIONS["fb"], "max_halvings", 0)
    out = tmp_path / "out"
    err, summary = failed_run([exported(118)[0], "--method", "fb",
                               "--system", "full"], capsys,
                              out)
    assert "line search found no acceptable step" in err
    assert summary["ncp_status"] == 2
    assert len(summary["residual_history"]) - 1 == summary["iterations"] == 5
    with np.load(out / "result.npz") as result:
        assert result["history_alpha"][-1] == 0.0  # the step not taken
        assert len(result["history_residual"]) == 5


def test_no_progress_status_5(exported, tmp_path, capsys):
    out = tmp_path / "out"
    err, summary = failed_run([exported(118)[0], "--method", "fb", "--tol",
                               "1e-15", "--system", "full"], capsys, out)
    assert "no progress" in err and "tol too small?" in err
    assert summary["ncp_status"] == 5


def test_singular_jacobian_status_3_friction(exported, tmp_path, capsys):
    """The thesis's split (110)/(111) with φ_min: J is singular where p = 0
    (see test_friction); on the command line exit 3, no completed step."""
    out = tmp_path / "out"
    err, summary = failed_run([exported(118)[0], "--friction", "0.3",
                               "--formulation", "thesis", "--method", "min",
                               "--steps", "4"], capsys,
                              out)
    assert "load step 1 of 4 did not converge" in err
    assert "singular Jacobian" in err and "0 completed steps kept" in err
    assert summary["steps_completed"] == 0 and summary["failed_step"] == 1
    record = summary["per_step"][-1]
    assert record["converged"] is False and record["residual_history"]
    assert tree(out) == ["summary.json"]  # nothing else to keep


def test_singular_jacobian_status_3_frictionless(tmp_path, capsys,
                                                 monkeypatch):
    """Without friction J is never singular when K is positive definite
    (its rows are rows of RK or unit normal rows: J·Rᵀ = D₁RKRᵀ + D₂ with
    non-negative diagonal D₁, D₂, D₁ + D₂ > 0, nonsingular for RKRᵀ
    positive definite), and a singular K is refused before solving (exit 2,
    above). So status 3 only comes with the check switched off: a spring
    that floats in x, pulled away from the obstacle."""
    from solver.problem import ContactProblem

    bar = two_dof_bar(load=(0.0, 1000.0))
    bar.K = sp.csr_matrix(9e4 * np.array([[1.0, -1.0], [-1.0, 1.0]]))
    path = save_problem(tmp_path / "float.npz", bar)
    code, _, err = run([path, "-o", tmp_path / "out"], capsys)
    assert code == 2 and "is the body supported?" in err
    assert tree(tmp_path) == ["float.npz"]
    monkeypatch.setattr(ContactProblem, "check_stiffness", lambda self: self)
    err, summary = failed_run([path, "--system", "full"], capsys,
                              tmp_path / "out")
    assert "singular Jacobian" in err and summary["ncp_status"] == 3
