"""The thesis's §6 two-DOF bar system (reference: the thesis's numbers)."""

import subprocess
import sys

import numpy as np

from conftest import ROOT
from solver.problem import load_problem


def test_bar_matches_thesis(bar_problem):
    # Thesis §6: K = 1e4 diag(9, 9), f = [1000, -1000], s = 0.005.
    np.testing.assert_array_equal(bar_problem.K.toarray(),
                                  1e4 * np.diag([9.0, 9.0]))
    np.testing.assert_array_equal(bar_problem.f, [1000.0, -1000.0])
    np.testing.assert_array_equal(bar_problem.gap, [0.005])
    # With the reconstructed normal (0, -1) the free motion closes the gap at
    # load step 45 of 100: u_n(κ) = κ/100 · 1000/9e4 = s  ⇒  κ = 45.
    u_free = np.linalg.solve(bar_problem.K.toarray(), bar_problem.f)
    kappa = 100 * bar_problem.gap[0] / (bar_problem.normal[0] @ u_free)
    np.testing.assert_allclose(kappa, 45.0, rtol=1e-12)


def test_bar_writer_script(tmp_path):
    out = tmp_path / "new" / "two_dof_bar.npz"
    result = subprocess.run([sys.executable, str(ROOT / "sfepy_problems" /
                                                  "two_dof_bar.py"), str(out)],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    problem = load_problem(out)
    assert problem.kind == "discrete" and problem.n_contact == 1
    result = subprocess.run([sys.executable, str(ROOT / "sfepy_problems" /
                                                  "two_dof_bar.py")],
                            capture_output=True, text=True)
    assert result.returncode == 2 and "usage" in result.stderr
