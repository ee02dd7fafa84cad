"""Independent cross-check: the frictionless solution is the minimiser of
½uᵀKu − fᵀu subject to YRu ≤ s, solved here by Clarabel, an interior-point
conic solver that shares no code with ours (thesis meshes and one other
obstacle). Clarabel is in the ``test`` extra."""

import clarabel
import numpy as np
import pytest
import scipy.sparse as sp

from conftest import MESHES, THESIS_MESHES, solve_block
from solver import solve_frictionless
from solver.contact import contact_geometry
from solver.errors import InitialPenetrationWarning, PenetrationWarning
from solver.problem import load_problem


def clarabel_solution(problem, geometry):
    """Solve the QP with Clarabel to tight tolerances; return u.

    The objective is divided by the mean stiffness k̄ (same minimiser):
    unscaled, with K ~ 1e6 and u ~ 1e-1, Clarabel stops at "AlmostSolved"
    with complementarity violated by ~1e-3."""
    n, m = problem.n_dofs, len(geometry.gap)
    k = problem.K.diagonal().mean()
    rows = np.repeat(np.arange(m), 2)
    C = sp.csc_matrix((geometry.normal.ravel(), (rows, geometry.dofs.ravel())),
                      shape=(m, n))
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = settings.tol_gap_rel = 1e-13
    settings.tol_feas = 1e-13
    settings.max_iter = 400
    solver = clarabel.DefaultSolver(sp.triu(problem.K / k).tocsc(),
                                    -problem.f / k,
                                    C, geometry.gap,
                                    [clarabel.NonnegativeConeT(m)], settings)
    solution = solver.solve()
    assert str(solution.status) == "Solved", solution.status
    return np.asarray(solution.x)


def check(problem, gap):
    geometry = contact_geometry(problem, gap)
    ours = solve_frictionless(problem, method="fb", geometry=geometry,
                              tol=1e-12)
    assert ours.success
    reference = clarabel_solution(problem, geometry)
    err = np.abs(ours.u - reference).max() / np.abs(reference).max()
    assert err <= 1e-8, err
    return ours


@pytest.mark.parametrize("n", THESIS_MESHES)
@pytest.mark.parametrize("gap", ["obstacle", "body"])
def test_thesis_meshes(exported, n, gap):
    check(load_problem(exported(n)[0]), gap)


@pytest.mark.filterwarnings("error::solver.errors.InitialPenetrationWarning")
@pytest.mark.filterwarnings("error::solver.errors.PenetrationWarning")
def test_inclined_line_obstacle(tmp_path):
    """A straight obstacle at an angle, x = 5.1 + 0.02 t, y = t: the block's
    upper part reaches it, and below y = −5 it starts inside the block
    (x < 5 there): four contact nodes penetrate initially, which the
    solver warns about and pushes out, and the clamped corner (5, −10), a
    support, stays inside the obstacle, which it warns about too."""
    path = tmp_path / "line.npz"
    solve_block(MESHES / "block_454.mesh", path, obstacle_x="5.1 + 0.02*t",
                obstacle_y="t")
    with pytest.warns(PenetrationWarning,
                      match=r"1 contact node left out of contact as support"):
        with pytest.warns(InitialPenetrationWarning,
                          match=r"at 4 contact nodes \(13, 14, 15, 16\)"):
            result = check(load_problem(path), "obstacle")
    assert result.n_contact >= 2
