"""The 2D block's export without SfePy's own solve (``solve=False``, issue
33): the same K, f, M and mesh as the export after the solve, and no
solution written. The reference is the export with SfePy's direct solve of
the unconstrained problem (the thesis-size default), an independent run of
the same assembly: K, f and M do not depend on the state they are
evaluated at (linear elasticity, point load, boundary mass)."""

import numpy as np

from conftest import BLOCK_PROBLEM, MESHES, load_script, solve_block
from solver.problem import load_problem


def export_module():
    return load_script("_contact_ssn_sfepy_export",
                       BLOCK_PROBLEM.parent / "_export.py")


def test_no_solve_exports_the_same_problem(tmp_path):
    mesh = MESHES / "block_454.mesh"
    solved = tmp_path / "solved" / "block_454.npz"
    solve_block(mesh, solved)
    quiet = tmp_path / "quiet" / "block_454.npz"
    export_module().export_only(BLOCK_PROBLEM, mesh=str(mesh),
                                output=str(quiet), solve=False)
    a, b = load_problem(solved), load_problem(quiet)
    assert a.n_dofs == b.n_dofs == 492
    assert abs(a.K - b.K).max() == 0.0
    np.testing.assert_array_equal(a.f, b.f)
    np.testing.assert_array_equal(a.M.toarray(), b.M.toarray())
    for key in ("nodes", "cells", "dof_map", "contact_nodes",
                "contact_dofs", "u_prescribed"):
        np.testing.assert_array_equal(getattr(a, key), getattr(b, key))
    assert not list(quiet.parent.glob("*.vtk"))  # nothing solved, no .vtk


def test_no_solve_under_sfepy_run_settings(tmp_path):
    """``-d "solve=False"`` gives ``sfepy-run`` the no-solve Newton
    settings (``_export.NO_SOLVE``) and no result file; the default keeps
    SfePy's one Newton step (the thesis-size exports and their .vtk)."""
    define = load_script("block_obstacle_define", BLOCK_PROBLEM).define
    args = dict(mesh=str(MESHES / "block_118.mesh"),
                output=str(tmp_path / "b.npz"))
    quiet, default = define(solve=False, **args), define(**args)
    assert quiet["solvers"]["newton"][1] == export_module().NO_SOLVE
    assert quiet["options"]["save_results"] is False
    assert default["solvers"]["newton"][1]["i_max"] == 1
    assert default["options"]["save_results"] is True


def test_no_solve_keeps_the_dirichlet_lifting(tmp_path):
    """The Hertz cylinder with its top edge moved down by d: f is the
    lifting −(K_full u_D)_F, which the no-solve export takes from the
    prescribed values alone; the same f and K as after SfePy's solve."""
    from sfepy.applications import solve_pde
    from sfepy.base.conf import ProblemConf, get_standard_keywords

    problem_file = BLOCK_PROBLEM.parent / "hertz_cylinder.py"
    mesh = str(MESHES / "hertz.mesh")
    solved, quiet = (tmp_path / name / "hertz.npz"
                     for name in ("solved", "quiet"))
    required, other = get_standard_keywords()
    solve_pde(ProblemConf.from_file(
        str(problem_file), required, other,
        define_args=dict(mesh=mesh, output=str(solved))), save_results=False)
    export_module().export_only(problem_file, mesh=mesh, output=str(quiet),
                                solve=False)
    a, b = load_problem(solved), load_problem(quiet)
    assert np.linalg.norm(a.f) > 0  # the lifting is there
    assert abs(a.K - b.K).max() == 0.0
    np.testing.assert_array_equal(a.f, b.f)
    np.testing.assert_array_equal(a.u_prescribed, b.u_prescribed)
