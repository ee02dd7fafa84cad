"""The two-body solver on the SfePy exports of sfepy_problems/ (the
thesis workflow: SfePy assembles, the solver never imports it).

References: the patch test's closed form (meta ``p_exact``, two
plane-strain layers in series); Hertz's plane-strain formulas (meta
``R_star``, ``E_star``; Johnson 1985 §4.3) with P the force the upper
body receives through the interface (= its top reaction: the body is in
equilibrium); the rigid solver of the thesis block (``gap="body"``)."""

import numpy as np
import pytest

from solver import solve_frictionless
from solver import solve_two_body
from test_export_two_body import export


@pytest.mark.parametrize("slave", ["upper", "lower"])
def test_patch_export(tmp_path, slave):
    """Uniform pressure = p_exact to 1e-10 in both orders; node-to-segment
    ≥ 2 % off (measured 4 % fine slave, 22 % coarse slave)."""
    problem = export(tmp_path, "two_body_patch.py", "patch",
                     mesh="meshes/two_body_patch.mesh", slave=slave)
    exact = problem.meta["p_exact"]
    result = solve_two_body(problem, tol=1e-12)
    assert result.success
    assert np.abs(result.contact_pressure / exact - 1).max() <= 1e-10
    nts = solve_two_body(problem, variant="node-to-segment", tol=1e-12)
    assert np.abs(nts.contact_pressure / exact - 1).max() > 0.02


@pytest.mark.parametrize("method", ["min", "fb"])
def test_hertz_export(tmp_path, method):
    """a within 1 % (measured −0.53 %), p₀ within 3 % (+0.42 %), 51 ≥ 40
    slave nodes in contact."""
    problem = export(tmp_path, "two_cylinders.py", "cylinders",
                     mesh="meshes/two_body_cylinders.mesh")
    meta = problem.meta
    result = solve_two_body(problem, method=method, tol=1e-10)
    assert result.success and result.n_contact >= 40
    D, lam = result.mortar_D, result.contact_pressure
    P = -np.nansum(D * lam * result.normal[:, 1])
    a_hertz = 2 * np.sqrt(P * meta["R_star"] / (np.pi * meta["E_star"]))
    x = problem.nodes[problem.contact_nodes, 0]
    a = 2 * np.sqrt((D * lam * x ** 2).sum() / (D * lam).sum())
    assert abs(a / a_hertz - 1) <= 0.01
    assert abs(lam.max() / (2 * P / (np.pi * a_hertz)) - 1) <= 0.03


def test_rigid_limit_export(tmp_path, exported):
    """The 454 block on the elastic parabola body, E ×10⁴: 3.4e-3 from the
    rigid solver (the O(h²) weighted-gap difference of
    test_two_body_rigid_limit.py; ≤ 1e-3 needs the 1878 block, there) and
    within 1e-5 of ×10⁶ (the obstacle's compliance)."""
    from solver.problem import load_problem

    rigid = load_problem(exported(454)[0])
    reference = solve_frictionless(rigid, gap="body", tol=1e-12)
    n = len(rigid.nodes)
    u = {}
    for ratio in (1e4, 1e6):
        problem = export(tmp_path, "block_elastic_obstacle.py",
                         f"block_{ratio:g}",
                         mesh="meshes/two_body_block_454.mesh",
                         E_ratio=ratio)
        result = solve_two_body(problem, tol=1e-12)
        assert result.success and result.nit == reference.nit
        u[ratio] = result.displacement[:n]
    scale = np.abs(reference.displacement).max()
    assert np.abs(u[1e4] - reference.displacement).max() / scale < 5e-3
    assert np.abs(u[1e4] - u[1e6]).max() / scale < 1e-5


@pytest.mark.parametrize("coulomb", ["lagged", "implicit"])
def test_sliding_block_export(tmp_path, coulomb):
    """The patch file's load='slide' (squeeze, then drag the upper block
    10 δ sideways): every slave node slips and the total friction force is
    f_c × the normal force (lagged: the previous step's) to 1e-8
    (measured 1e-13 and 0)."""
    problem = export(tmp_path, "two_body_patch.py", "slide",
                     mesh="meshes/two_body_patch.mesh", load="slide")
    fc = 0.3
    result = solve_two_body(problem, friction=fc, formulation="projection",
                            coulomb=coulomb, method="fb", tol=1e-12)
    assert result.success, result.message
    D = result.mortar_D
    normal = D @ result.contact_pressure[-1 if coulomb == "implicit" else -2]
    friction = D @ result.friction_traction[-1]
    assert result.slip[-1].sum() == problem.n_contact
    assert abs(abs(friction) - fc * normal) <= 1e-8 * fc * normal
