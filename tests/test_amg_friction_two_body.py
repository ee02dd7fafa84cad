"""Coulomb friction between two bodies (dual mortar) on the iterative
path (issue 33 point 1): the friction active set method on the nodewise
problem in v = T u (slave tangential DOFs relative to the master's through
the dual mortar's change of variables), each Newton system by CG (lagged
bound) or GMRES (implicit bound) with smoothed aggregation of
K̃ = T⁻ᵀKT⁻¹ and each body's rigid modes carried through T
(``backend="amg"``, :mod:`solver.contact.friction.active_set`).

Independent references: the factorisation path (condensed onto the slave
nodes, semismooth Newton with a line search, dense Newton systems) on the
same problems, assembled here without SfePy (the Hertz cylinders squeezed
then shifted, the non-matching patch squeezed then shifted); Coulomb's
law at full slip (a block shifted far over a block: Σ D_jj g_t,j =
f_c Σ D_jj λ_j, with λ this step's (implicit) or the last step's
(lagged))."""

import numpy as np
import pytest

from solver import solve
from solver.linalg import amg
from tri_elasticity import stacked_blocks, two_cylinders

pytestmark = pytest.mark.skipif(not amg.available(),
                                reason="pyamg not installed (.[amg])")


def cylinders():
    return two_cylinders((1.0, 1.5), ((1.0, 0.3), (2.0, 0.25)),
                         h0=0.004, squeeze=0.01, shift=0.004)[0]


def patch2d():
    return stacked_blocks(n_upper=(40, 20), n_lower=(90, 30),
                          materials=((1.0, 0.3), (3.0, 0.2)),
                          slave="upper", shift=2e-4)[0]


def same_answer(iterative, direct):
    """Both converged and verified on every node; u of every step within
    1e-8 (relative); the same contact set in every step and the same
    stick and slip sets up to nodes on the cone's edge (|g| = b to 1e-6:
    stick with |g| = b and slip with no slide are the same state). Returns
    the largest relative difference of u."""
    for result in (iterative, direct):
        assert result.success, result.message
        assert result.verification["passed"]
    assert iterative.linear_solver == "amg" != direct.linear_solver
    worst = 0.0
    for a, b in zip(iterative.displacement, direct.displacement):
        worst = max(worst, np.linalg.norm(a - b) / np.linalg.norm(b))
    assert worst < 1e-8
    for a, b in zip(iterative.in_contact, direct.in_contact):
        assert np.array_equal(a, b)
    for step in range(len(direct.displacement)):
        g = np.linalg.norm(np.reshape(direct.friction_traction[step],
                                      (len(direct.stick[step]), -1)), axis=1)
        bound = direct.friction_bound[step]
        edge = g >= (1 - 1e-6) * bound
        for key in ("stick", "slip"):
            a, b = getattr(iterative, key)[step], getattr(direct, key)[step]
            assert np.array_equal(a[~edge], b[~edge]), (key, step)
    return worst


@pytest.mark.parametrize("coulomb", ["lagged", "implicit"])
@pytest.mark.parametrize("make", [cylinders, patch2d],
                         ids=["cylinders", "patch"])
def test_two_bodies_friction_equals_the_factorisation(make, coulomb):
    """Squeeze, then shift, f_c = 0.3: the same u (measured 7e-13 –
    3e-11) and sets in every step as the factorisation path, stick nodes
    present at the end, a hierarchy of at least two levels."""
    problem = make()
    direct = solve(problem, friction=0.3, coulomb=coulomb)
    iterative = solve(problem, friction=0.3, coulomb=coulomb, backend="amg")
    same_answer(iterative, direct)
    assert iterative.stick[-1].any()
    assert iterative.engine["levels"] >= 2
    assert all(r["krylov"] >= r["njev"] for r in iterative.records)


@pytest.mark.parametrize("coulomb", ["lagged", "implicit"])
def test_sliding_block_full_slip_friction_is_fc_times_normal(coulomb):
    """A block squeezed on a block, then its top shifted far: every node
    slips and Σ D_jj g_t,j = f_c Σ D_jj λ_j to 1e-8 (λ of this step if
    implicit, of the last if lagged); the factorisation's u to 1e-8."""
    problem = stacked_blocks(n_upper=(5, 2), n_lower=(7, 2),
                             materials=((1.0, 0.3), (3.0, 0.2)),
                             squeeze=1e-3, shift=5e-3)[0]
    fc = 0.3
    result = solve(problem, friction=fc, coulomb=coulomb, backend="amg",
                   tol=1e-12)
    assert result.success and result.verification["passed"], \
        result.message
    D = result.mortar_D
    normal = D @ result.contact_pressure[-1 if coulomb == "implicit"
                                         else -2]
    friction = D @ result.friction_traction[-1]
    assert normal > 0
    assert result.slip[-1].sum() == result.in_contact[-1].sum() > 0
    assert abs(abs(friction) - fc * normal) <= 1e-8 * fc * normal
    direct = solve(problem, friction=fc, coulomb=coulomb, tol=1e-12)
    assert np.linalg.norm(result.u - direct.u) \
        <= 1e-8 * np.linalg.norm(direct.u)


def test_two_spheres_3d_slip_reversal_converges(tmp_path):
    """The two unequal spheres (``sfepy_problems/two_spheres.py`` on
    ``meshes/two_spheres.py --a-over-h 4``, the smallest mesh that showed
    it), f_c 0.3, the lagged bound, 5 load steps: a 3D slip node whose
    direction turned back (ŵ·ŵ_prev < 0) on every Newton system kept the
    sets unchanged and the error at a constant value, so load step 4 (3 at
    a/h 8) ran into the Newton limit; with the node stuck after two
    reversals in a row (:class:`~solver.contact.friction.active_set.
    SlipRule`, now in 3D too) every step converges to the factorisation
    path's u (measured 1e-11) with the same contact, stick and slip sets,
    in at most 15 Newton systems per step (measured ≤ 8 at a/h 4 and 8)."""
    from test_two_body3d_exports import export, sphere_mesh

    mesh = sphere_mesh(tmp_path, "--a-over-h", "4")
    problem = export(tmp_path, "two_spheres.py", "spheres", mesh=str(mesh))
    options = dict(friction=0.3, coulomb="lagged", steps=5)
    direct = solve(problem, **options)
    iterative = solve(problem, backend="amg", **options)
    same_answer(iterative, direct)
    assert iterative.slip[-1].any() and iterative.stick[-1].any()
    assert max(r["njev"] for r in iterative.records) <= 15
