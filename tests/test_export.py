"""The SfePy problem file exports K, f, M as the thesis's workflow did.

Independent references: SfePy's own solution of the same linear elasticity
problem (K must reproduce it), the analytic P1 boundary mass matrix of a
straight edge (M), and the geometry of the block (|Γc| = 20).
"""

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from conftest import (BLOCK_PROBLEM, MESHES, ROOT, THESIS_MESHES, load_script,
                      solve_block)
from solver.problem import load_problem


def sfepy_run():
    """The sfepy-run script of the running interpreter's environment."""
    script = Path(sys.executable).parent / "sfepy-run"
    return str(script) if script.exists() else "sfepy-run"


@pytest.mark.parametrize("n", THESIS_MESHES)
def test_K_reproduces_sfepy_solution(exported, n):
    path, pb, variables = exported(n)
    problem = load_problem(path)
    u = sla.spsolve(problem.K.tocsc(), problem.f)
    full = problem.full_displacement(u)  # the reduced-DOF map rebuilds it
    reference = variables["u"]().reshape(-1, 2)  # SfePy's own solution
    err = np.abs(full - reference).max() / np.abs(reference).max()
    assert err <= 1e-10
    # Dirichlet DOFs are exactly the clamped bottom edge, value 0.
    clamped = problem.nodes[:, 1] == -10.0
    fixed = np.ones((len(problem.nodes), 2), bool)
    fixed[problem.dof_map[:, 0], problem.dof_map[:, 1]] = False
    np.testing.assert_array_equal(fixed, np.repeat(clamped[:, None], 2, 1))
    assert problem.n_dofs == 2 * (len(problem.nodes) - clamped.sum())


@pytest.mark.parametrize("n", THESIS_MESHES)
def test_K_symmetric_positive_definite(exported, n):
    problem = load_problem(exported(n)[0])
    K = problem.K
    assert abs(K - K.T).max() <= 1e-12 * abs(K).max()
    # Smallest eigenvalue by shift-invert around 0: positive.
    smallest = sla.eigsh(K.tocsc(), k=1, sigma=0, which="LM",
                         return_eigenvectors=False)[0]
    assert smallest > 0


def p1_edge_mass(y):
    """Analytic ∫ φi φj on a polyline with nodes at heights y (straight edge):
    each segment of length h adds h/6 [[2, 1], [1, 2]]."""
    h = np.diff(y)
    n = len(y)
    main = np.zeros(n)
    main[:-1] += h / 3
    main[1:] += h / 3
    return sp.diags([h / 6, main, h / 6], [-1, 0, 1]).toarray()


@pytest.mark.parametrize("n", THESIS_MESHES)
def test_M_is_the_boundary_mass_matrix(exported, n):
    problem = load_problem(exported(n)[0])
    xy = problem.nodes[problem.contact_nodes]
    # Γc is the right edge x = 5, ordered bottom to top.
    assert np.all(xy[:, 0] == 5.0)
    assert np.all(np.diff(xy[:, 1]) > 0)
    assert xy[0, 1] == -10.0 and xy[-1, 1] == 10.0
    assert problem.M.sum() == pytest.approx(20.0, rel=1e-13)  # |Γc| = 20
    np.testing.assert_allclose(problem.M.toarray(), p1_edge_mass(xy[:, 1]),
                               rtol=1e-12, atol=1e-14)
    # The clamped corner (5, -10) is a support: no free DOFs.
    assert np.all(problem.contact_dofs[0] == -1)
    assert np.all(problem.contact_dofs[1:] >= 0)


def test_f_is_the_point_force(exported):
    problem = load_problem(exported(454)[0])
    corner = np.flatnonzero((problem.nodes[:, 0] == -5.0)
                            & (problem.nodes[:, 1] == 10.0))
    assert len(corner) == 1
    dofs = [np.flatnonzero((problem.dof_map[:, 0] == corner[0])
                           & (problem.dof_map[:, 1] == c))[0] for c in (0, 1)]
    np.testing.assert_array_equal(problem.f[dofs], [4000.0, 0.0])
    assert np.count_nonzero(problem.f) == 1
    assert problem.meta["E"] == 2e5 and problem.meta["nu"] == 0.3
    assert problem.meta["plane"] == "strain"
    assert problem.obstacle.x_text == "5.05 + 0.005*t**2"


def test_reconstructed_supports_give_partial_contact(exported):
    """The docstring's claim about the lost Fig. 3: the unconstrained solution
    crosses the obstacle x = 5.05 + 0.005 y² only for y ≳ -3.7."""
    path, _, _ = exported(1878)
    problem = load_problem(path)
    u = problem.full_displacement(sla.spsolve(problem.K.tocsc(), problem.f))
    moved = problem.nodes[problem.contact_nodes] + u[problem.contact_nodes]
    overlap = moved[:, 0] - (5.05 + 0.005 * moved[:, 1] ** 2)
    crossing = moved[np.argmax(overlap > 0), 1]
    assert np.all(overlap[moved[:, 1] > crossing] > 0)
    assert -4.2 < crossing < -3.2


def test_parameters_from_define(tmp_path):
    """E, nu, plane, F and the obstacle reach the export through -d."""
    path = tmp_path / "stress.npz"
    solve_block(MESHES / "block_118.mesh", path, E=1e5, nu=0.25,
                plane="stress", F=(0.0, -100.0), obstacle_x="5.1 + 0*t",
                obstacle_y="t")
    problem = load_problem(path)
    assert problem.meta["plane"] == "stress" and problem.meta["E"] == 1e5
    assert problem.f.sum() == -100.0
    assert problem.obstacle.x_text == "5.1 + 0*t"
    base = tmp_path / "strain.npz"
    solve_block(MESHES / "block_118.mesh", base, E=1e5, nu=0.25)
    # Plane stress is softer than plane strain for the same E, nu.
    assert problem.K.diagonal().sum() < load_problem(base).K.diagonal().sum()


def export_module():
    """``sfepy_problems/_export.py``, under the name the problem files use."""
    return load_script("_contact_ssn_sfepy_export",
                       ROOT / "sfepy_problems" / "_export.py")


def run_export(argv, out, env=None):
    """Run an export command from the repository root; its combined output."""
    environ = {k: v for k, v in os.environ.items()
               if k != "CONTACT_SSN_VERBOSE"}
    environ.update(env or {})
    result = subprocess.run(argv, cwd=ROOT, env=environ, timeout=300,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            text=True)
    assert result.returncode == 0, result.stdout[-2000:]
    assert load_problem(out).n_contact == 11  # the 118 mesh: 11 on x = 5
    return result.stdout


def block_118_argv(out, *extra):
    return ["-d", f"mesh='{MESHES / 'block_118.mesh'}', output='{out}'"
            + "".join(f", {e}" for e in extra)]


def test_sfepy_run_command(tmp_path):
    """The ``sfepy-run`` command prints only the export line, once SfePy's
    own notice about missing jax (printed at its import, before the problem
    file is read) is taken away."""
    out = tmp_path / "sub" / "block_118.npz"
    printed = run_export([sfepy_run(), str(BLOCK_PROBLEM)]
                         + block_118_argv(out), out)
    if importlib.util.find_spec("jax") is None:
        assert "install jax and jaxlib" in printed  # what is stripped below
    assert export_module().JAX_NOTICE.sub("", printed) == \
        f"exported 138 DOFs, 11 contact nodes -> {out}\n"
    problem = load_problem(out)
    assert len(problem.cells) == 118
    assert (out.parent / "block_118.vtk").exists()  # SfePy's own solution


def test_script_export_prints_one_line(tmp_path):
    """``python sfepy_problems/block_obstacle.py -d ...``: exactly one line,
    no ``sfepy:`` message, no jax notice."""
    out = tmp_path / "block_118.npz"
    printed = run_export([sys.executable, str(BLOCK_PROBLEM)]
                         + block_118_argv(out), out)
    assert printed == f"exported 138 DOFs, 11 contact nodes -> {out}\n"


@pytest.mark.parametrize("how", ["-v", "env", "define"])
def test_verbose_shows_sfepy_messages(tmp_path, how):
    """``-v`` (script), ``CONTACT_SSN_VERBOSE=1`` and ``-d "verbose=True"``
    (``sfepy-run``) bring back SfePy's messages: the left-over keys of
    define(), the set-up and the log of its own solve."""
    out = tmp_path / "block_118.npz"
    if how == "-v":
        argv = [sys.executable, str(BLOCK_PROBLEM), "-v"] + block_118_argv(out)
    else:
        argv = [sfepy_run(), str(BLOCK_PROBLEM)] + block_118_argv(
            out, *(["verbose=True"] if how == "define" else []))
    printed = run_export(argv, out,
                         {"CONTACT_SSN_VERBOSE": "1"} if how == "env" else {})
    lines = printed.splitlines()
    assert any(line.startswith("sfepy: left over:") for line in lines)
    assert "sfepy: reading mesh (" + str(MESHES / "block_118.mesh") + ")..." \
        in lines
    assert any(line.startswith("sfepy: nls: iter: 1, residual:")
               for line in lines)
    assert lines[-1] == f"exported 138 DOFs, 11 contact nodes -> {out}"


def test_jax_notice_pattern_drops_only_that_notice():
    """The runner drops SfePy's jax notice and passes on anything else."""
    notice = ("install jax and jaxlib to use terms_jax.py!\n"
              "sfepy: WARNING: module /x/sfepy/terms/terms_jax.py cannot be "
              "imported!\nsfepy: reason:\n No module named 'jax'\n")
    other = ("sfepy: WARNING: module /x/sfepy/terms/terms_new.py cannot be "
             "imported!\nsfepy: reason:\n No module named 'foo'\n")
    pattern = export_module().JAX_NOTICE
    assert pattern.sub("", "a\n" + notice + other) == "a\n" + other
    # A jax that is installed but broken is reported, not hidden.
    broken = notice.replace("No module named 'jax'", "jaxlib version too old")
    assert pattern.sub("", broken) == broken


def test_set_verbosity(capsys, monkeypatch):
    """Quiet silences SfePy's screen output; verbose brings it back; the
    environment variable decides when neither is asked for."""
    from sfepy.base.base import output

    module = export_module()
    monkeypatch.setattr(module, "_silenced", module._silenced)
    monkeypatch.setattr(output, "output_function", output.output_function)
    monkeypatch.delenv("CONTACT_SSN_VERBOSE", raising=False)
    output.set_output()  # SfePy's default: the screen
    assert module.set_verbosity(False) is False
    output("hidden")
    assert capsys.readouterr().out == ""
    assert module.set_verbosity(True) is True
    output("shown")
    assert capsys.readouterr().out.endswith("shown\n")
    assert module.set_verbosity(None) is False  # unset: quiet
    monkeypatch.setenv("CONTACT_SSN_VERBOSE", "1")
    assert module.set_verbosity(None) is True
    output("shown")
    assert capsys.readouterr().out.endswith("shown\n")
    monkeypatch.setenv("CONTACT_SSN_VERBOSE", "0")
    assert module.set_verbosity(None) is False
