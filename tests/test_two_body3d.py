"""Two elastic bodies in 3D by the dual mortar on triangles
(solver.geometry.mortar.triangles, solver.contact.two_body) on two boxes
assembled here without SfePy (tests/tet_two_body.py).

References: the patch test's pressure is the closed form of two layers in
series under uniaxial stress, p = δ / Σ h_b/E_b, and the top reaction of
the full K; at full slip Coulomb's law gives the total friction force
f_c × the normal force (the slip directions agree once the sliding
distance is far beyond the elastic shear)."""

import json

import numpy as np
import pytest

from solver import solve
from solver.problem import load_problem, save_problem
from tet_two_body import stacked_boxes, top_reaction, uniaxial_pressure

MATERIALS = ((1.0, 0.3), (3.0, 0.2))


@pytest.mark.parametrize("slave", ["upper", "lower"])  # coarse / fine slave
@pytest.mark.parametrize("system", ["auto", "full"])
@pytest.mark.parametrize("method", ["min", "fb"])
def test_patch_test_non_matching(slave, system, method):
    """Irregular non-matching interfaces (3 × 3 on 4 × 4 cells, jittered):
    the applied pressure (top reaction / area) is the closed form, and
    λ_j equals it at every slave node to 1e-10, with the traction −λ n,
    and so does its patch recovery p̄_j; at the default tolerance."""
    problem, K, _ = stacked_boxes(materials=MATERIALS, slave=slave)
    result = solve(problem, system=system, method=method)
    assert result.success, result.message
    exact = uniaxial_pressure((0.5, 0.5), MATERIALS, 1e-3)
    applied = -top_reaction(K, problem, result.u)
    assert abs(applied - exact) <= 1e-10 * exact
    p = result.contact_pressure
    assert len(p) == (16 if slave == "upper" else 25)
    assert np.abs(p - applied).max() <= 1e-10 * applied
    recovered = result.contact_pressure_patch  # exact for a uniform λ
    assert np.abs(recovered - applied).max() <= 1e-10 * applied
    up = 1.0 if slave == "upper" else -1.0
    assert np.allclose(result.traction, [[0, 0, up * applied]] * len(p),
                       rtol=0, atol=1e-10 * applied)


@pytest.mark.parametrize("backend", ["superlu", "pardiso", "cholmod"])
def test_patch_test_every_backend(backend):
    """The same answer from every sparse backend of the condensed system."""
    problem, _, _ = stacked_boxes(materials=MATERIALS)
    result = solve(problem, backend=backend)
    assert result.success
    exact = uniaxial_pressure((0.5, 0.5), MATERIALS, 1e-3)
    assert np.abs(result.contact_pressure / exact - 1).max() <= 1e-10


@pytest.mark.parametrize("direction", [(1.0, 0.0), (0.6, 0.8)])
@pytest.mark.parametrize("coulomb", ["lagged", "implicit"])
@pytest.mark.parametrize("system", ["auto", "full"])
def test_full_slip_friction_force(direction, coulomb, system):
    """A box pressed on a box, then its top dragged 0.05 (50 δ) along
    ``direction``: every slave node slips, |g_t,j| equals its bound, and
    the resultant friction force |Σ D_jj g_t,j| = f_c Σ D_jj λ_j (the
    bound of the step: this step's λ, implicit, or the previous one's,
    lagged) to 1e-8, pointing against the drag."""
    fc = 0.3
    shift = 0.05 * np.asarray(direction)
    problem, _, _ = stacked_boxes(materials=MATERIALS, shift=shift)
    result = solve(problem, friction=fc, coulomb=coulomb, system=system)
    assert result.success, result.message
    D = result.mortar_D
    g, bound = result.friction_traction[-1], result.friction_bound[-1]
    assert result.slip[-1].all()
    total = np.linalg.norm((D[:, None] * g).sum(axis=0))
    assert abs(total / (D @ bound) - 1) <= 1e-8
    lam = result.contact_pressure[-1 if coulomb == "implicit" else -2]
    assert abs(D @ bound / (fc * (D @ lam)) - 1) <= 1e-12
    force = (D[:, None] * result.traction[-1]).sum(axis=0)  # on the slave
    along = force[:2] @ direction
    assert along < 0 and abs(abs(along) / np.linalg.norm(force[:2]) - 1) \
        < 1e-6


@pytest.mark.parametrize("slave", ["upper", "lower"])
def test_node_to_segment_fails_the_patch_test(slave):
    """The same patch tests with the node-to-segment coupling (slave node
    projected onto the master, M_jk = D_jj N_k(ξ_j)): the pressure is not
    uniform (Taylor & Papadopoulos 1991), 2 % off somewhere at least."""
    problem, _, _ = stacked_boxes(materials=MATERIALS, slave=slave)
    result = solve(problem, variant="node-to-segment")
    assert result.success, result.message
    exact = uniaxial_pressure((0.5, 0.5), MATERIALS, 1e-3)
    deviation = np.abs(result.contact_pressure / exact - 1).max()
    assert deviation > 0.02, deviation


def test_cli_outputs(tmp_path):
    """``python -m solver`` on a saved 3D two-body file: exit 0, both
    bodies in result.vtu (cell data body, point data traction), the
    interface pressure (λ_j and its patch recovery) in result.npz, the
    interface in summary.json and the figures with --plots."""
    import meshio

    from solver.cli import main

    problem, _, _ = stacked_boxes(materials=MATERIALS)
    path = tmp_path / "patch3d.npz"
    save_problem(path, problem)
    loaded = load_problem(path)
    assert loaded.is_mortar and loaded.dim == 3
    out = tmp_path / "out"
    assert main([str(path), "-o", str(out), "--plots"]) == 0
    mesh = meshio.read(out / "result.vtu")
    assert set(np.unique(mesh.cell_data["body"][0])) == {0, 1}
    assert mesh.point_data["traction"].shape == (len(problem.nodes), 3)
    data = np.load(out / "result.npz")
    exact = uniaxial_pressure((0.5, 0.5), MATERIALS, 1e-3)
    assert np.allclose(data["contact_pressure"], exact, rtol=1e-10)
    assert np.allclose(data["contact_pressure_patch"], exact, rtol=1e-10)
    summary = json.loads((out / "summary.json").read_text())
    assert np.isclose(summary["interface_normal_force"], exact, rtol=1e-10)
    assert np.isclose(summary["max_interface_pressure_patch"], exact,
                      rtol=1e-10)
    for name in ("interface_pressure.png", "interface_map.png"):
        assert (out / name).stat().st_size > 0


def test_cli_friction_outputs(tmp_path):
    """A friction run from the command line: converged, per-step slip flags
    and slip (tangential displacement of v) in result.npz."""
    from solver.cli import main

    problem, _, _ = stacked_boxes(materials=MATERIALS, shift=(0.05, 0.0))
    path = tmp_path / "slide3d.npz"
    save_problem(path, problem)
    out = tmp_path / "out"
    assert main([str(path), "-o", str(out), "--friction", "0.3",
                 "--plots"]) == 0
    data = np.load(out / "result.npz")
    assert data["slip"][-1].all()
    assert data["tangential_displacement"].shape[-2:] == (16, 2)
    assert (out / "interface_map.png").stat().st_size > 0


def test_progress_counts_the_result_round():
    """A box dragged on a box: the friction run on the candidates is redone
    with more of them (9 → 16: the first round's step 1 lets nodes outside
    it penetrate); each progress line then comes from the round whose steps
    make the result, so its count of nodes in contact is the summary's
    (the first round's 9 were printed before)."""
    problem, _, _ = stacked_boxes(materials=MATERIALS, shift=(0.05, 0.0))
    seen = []
    result = solve(problem, friction=0.3, progress=seen.append)
    assert result.success, result.message
    assert result.candidates["enlarged"] == 1
    assert [r["step"] for r in seen] == [r["step"] for r in result.records]
    assert [r["n_contact"] for r in seen] == \
        [r["n_contact"] for r in result.records] == [16] * len(seen)
