r"""The Cattaneo–Mindlin sphere (issue 18): an elastic sphere pressed onto
a rigid plane (normal load P), then sheared (tangential load Q along x,
Q/(f_c P) ≈ 0.5): a central stick circle of radius

.. math::  c = a\,(1 - Q/(f_c P))^{1/3}, \qquad a = (3PR/(4E^*))^{1/3}

(Cattaneo 1938, Mindlin 1949; Johnson, *Contact Mechanics*, 1985, §7.1,
(7.38)-(7.41); Hertz's a for the computed P, §4.2), slip in c < r < a.
The issue asks for c within 10 %.

Why only 10 %, and what is measured. CM assumes no coupling of the normal
and tangential problems. An elastic sphere on a *rigid* plane has Dundurs'
β = (1 − 2ν)/(2(1 − ν)) = 0.286 at ν = 0.3, not 0: the shear traction
changes the pressure and the stick zone is neither exactly a circle nor
centred (Munisamy, Hills & Nowell, *Static axisymmetric Hertzian contacts
subject to shearing forces*, J. Appl. Mech. 61 (1994) 278-283, for the
related problem with β ≠ 0: the stick radius within a few per cent of CM's
for |β| ≲ 0.3). The normal stage is frictionless here (as CM assume; the
load path's stage friction 0), which removes the radial tractions β would
cause on loading. Discretisation: a/h ≈ 6 at the contact (a committed half
mesh, ``meshes/hertz_sphere_half_6.mesh``), so a node ring is ~0.16 a.

Stick radius: the stick nodes' status in the final step (strictly inside
the Coulomb disc, the solver's ``stick``), about the stick nodes' centroid
(lumped-Γc weighted; the coupling shifts it along x): c is the radius where
the indicator changes, the midpoint between the outermost stick node and
the innermost slip node, which must be separated (the stick set is a disc
about its centroid). Also the area estimate √(2 Σ_stick D_ii / π) (D the
lumped Γc measure; 2 for the two halves). Measured: Q/(f_c P) = 0.494,
c from the indicator −3.8 %, from the area −2.4 %, the centroid shifted by
2.9 % of a.

The model is the half y ≥ 0 (``sfepy_problems/cattaneo_mindlin_sphere.py``),
its contact nodes on y = 0 rollers that carry friction along x only; the
exact roller checks (half and quarter against the whole model, with
friction) are in ``tests/test_rollers.py``. P and Q are checked against the
clamp's reactions from SfePy's own full stiffness (equilibrium of the
body, independent of the contact solver's residual).
"""

import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT
from solver import load_problem, solve_friction
from solver.contact import contact_geometry
from test_export import export_module

FC = 0.5
PROBLEM = ROOT / "sfepy_problems" / "cattaneo_mindlin_sphere.py"
MESH = ROOT / "meshes" / "hertz_sphere_half_6.mesh"
STIFFNESS = "dw_lin_elastic.i.Omega(solid.D, v, u)"


@pytest.fixture(scope="module")
def sphere(tmp_path_factory):
    """The export (stage 1 in one step: frictionless contact does not
    depend on the path) and the solve, φ_min, lagged Coulomb."""
    path = tmp_path_factory.mktemp("cm_sphere") / "cm_sphere.npz"
    export = export_module()
    _, pb = export.export_only(PROBLEM, mesh=str(MESH), output=str(path),
                               steps_normal=1, steps_shear=5)
    problem = load_problem(path)
    result = solve_friction(problem, FC, formulation="projection",
                            method="min")
    return problem, result, export.full_stiffness(pb, STIFFNESS)


def resultants(problem, result, step=-1):
    """The contact force on the half body, (F_x, F_y, F_z): −λν + Σ t_k τ_k
    summed over Γc, t = D g the nodal friction force."""
    geometry = contact_geometry(problem, rollers=True)
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()[geometry.index]
    lam = result.contact_force[step][geometry.index]
    g = result.friction_traction[step][geometry.index]
    t = lumped[:, None] * np.einsum("ik,ikj->ij", g, geometry.tangents)
    return (-lam[:, None] * geometry.normal + t).sum(axis=0)


def test_load_path_and_rollers(sphere):
    problem, result, _ = sphere
    assert result.success and result.verification["passed"], result.message
    np.testing.assert_array_equal(problem.load_path_steps, [1, 5])
    np.testing.assert_array_equal(problem.load_path_friction, [0.0, 1.0])
    assert problem.meta["a_h"] > 5.5
    # stage 1 is frictionless
    assert np.abs(result.friction_traction[result.stage == 0]).max() == 0.0
    # the rollers on y = 0: in contact, friction along x (their free
    # tangent) only, some stick and some slip (the annulus crosses y = 0)
    geometry = contact_geometry(problem, rollers=True)
    rollers = np.zeros(problem.n_contact, bool)
    rollers[geometry.index[geometry.rollers]] = True
    on_plane = problem.nodes[problem.contact_nodes, 1] == 0.0
    np.testing.assert_array_equal(rollers, on_plane)
    touching = rollers & result.in_contact[-1]
    assert touching.sum() >= 8
    assert result.stick[-1][touching].any() and \
        result.slip[-1][touching].any()
    g = result.friction_traction[-1][touching]
    np.testing.assert_array_equal(g[:, 0], 0.0)  # e_y: support reaction
    assert (np.abs(g[:, 1]) > 0).all()


def test_equilibrium_with_the_clamp(sphere):
    """P and Q (the whole sphere's: twice the half's) from the contact
    forces equal the clamp's reactions, (K_full u)_top from SfePy's full
    stiffness (Σ_rows K = 0: the clamp's force and the contact force
    cancel in x and z; the plane's reactions are along y), to 1e-6 of P;
    Q/(f_c P) = 0.5 as the problem file's δ_x was set for."""
    problem, result, K_full = sphere
    F = resultants(problem, result)
    u = result.displacement[-1].ravel()
    reaction = (K_full @ u).reshape(-1, 3)
    top = problem.nodes[:, 2] == problem.meta["R"]
    clamp = reaction[top].sum(axis=0)
    P, Q = 2 * F[2], -2 * F[0]
    assert P > 0 and Q > 0
    assert abs(2 * clamp[2] + P) <= 1e-6 * P  # clamp + contact = 0
    assert abs(2 * clamp[0] - Q) <= 1e-6 * P
    assert abs(Q / (FC * P) - 0.5) < 0.02


def test_coulomb_bound_at_every_node(sphere):
    """|t_i| ≤ f_c λ_i on nodal forces (t = D g, the bound of the step:
    p of the previous step, lagged) at every node and step, to 1e-8 of the
    step's force scale ‖λ‖₂ (the solver's tolerance is 1e-10 of it: the
    projection row is solved to that, not to round-off); slip nodes at
    the bound, stick nodes inside."""
    problem, result, _ = sphere
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()
    size = np.linalg.norm(result.friction_traction, axis=2)
    bound = result.friction_bound
    scale = np.linalg.norm(result.contact_force, axis=1)[:, None]
    assert (lumped * (size - bound) <= 1e-8 * scale).all()
    assert (size[-1] > 0).sum() >= 40
    slip = result.slip[-1]
    np.testing.assert_allclose(size[-1][slip], bound[-1][slip], rtol=1e-6)
    assert (size[-1][result.stick[-1]] < bound[-1][result.stick[-1]]).all()


def test_stick_radius(sphere):
    """c within 10 % of Cattaneo–Mindlin's, by both estimates (module
    docstring); measured −3.8 % (indicator) and −2.4 % (area)."""
    problem, result, _ = sphere
    F = resultants(problem, result)
    P, Q = 2 * F[2], -2 * F[0]
    R, E_star = problem.meta["R"], problem.meta["E_star"]
    a = (3 * P * R / (4 * E_star)) ** (1 / 3)
    c = a * (1 - Q / (FC * P)) ** (1 / 3)
    xy = problem.nodes[problem.contact_nodes, :2]
    lumped = np.asarray(problem.M.sum(axis=1)).ravel()
    stick, slip = result.stick[-1], result.slip[-1]
    centre = (lumped[stick] * xy[stick, 0]).sum() / lumped[stick].sum()
    assert abs(centre) < 0.1 * a  # the coupling's shift: small
    r = np.hypot(xy[:, 0] - centre, xy[:, 1])
    inner, outer = r[stick].max(), r[slip].min()
    assert inner < outer  # the stick set is a disc about its centroid
    c_indicator = 0.5 * (inner + outer)
    c_area = np.sqrt(2 * lumped[stick].sum() / np.pi)
    assert abs(c_indicator / c - 1) < 0.10
    assert abs(c_area / c - 1) < 0.10
    # and the contact radius itself (slip annulus outside c): Hertz's a
    assert abs(np.hypot(*xy[result.in_contact[-1]].T).max() / a - 1) < 0.1


def test_committed_half_mesh_is_reproducible(tmp_path):
    """``meshes/hertz_sphere.py --a-over-h 6 --half`` rebuilds the committed
    mesh byte for byte (as tests/test_export3d.py checks the quarters)."""
    pytest.importorskip("gmsh")
    out = tmp_path / MESH.name
    subprocess.run([sys.executable, str(ROOT / "meshes" / "hertz_sphere.py"),
                    "--a-over-h", "6", "--half", "-o", str(out)], check=True,
                   capture_output=True, timeout=300)
    assert out.read_bytes() == MESH.read_bytes()
