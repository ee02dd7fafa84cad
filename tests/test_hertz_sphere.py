"""The 3D Hertz sphere against Hertz's closed form (Johnson, *Contact
Mechanics*, 1985, §4.2; issue 18's targets at a/h ≥ 16), end to end: gmsh
mesh (``meshes/hertz_sphere.py``), SfePy export, condensed 3D solve with the
symmetry-plane nodes as rollers, and ``solver.studies3d``'s measurements.
Also: φ_FB reaches φ_min's answer.
"""

import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT
from solver import solve, solve_frictionless
from solver.problem import load_problem
from solver.studies3d import hertz_sphere_row
from test_export3d import SPHERE, export_module


@pytest.fixture(scope="module")
def mesh16(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sphere16")
    mesh = folder / "hertz_sphere_16.mesh"
    subprocess.run([sys.executable, str(ROOT / "meshes" / "hertz_sphere.py"),
                    "--a-over-h", "16", "-o", str(mesh)], check=True,
                   capture_output=True)
    return mesh


@pytest.fixture(scope="module")
def sphere16(mesh16):
    path = mesh16.with_suffix(".npz")
    export_module().export_only(SPHERE, mesh=str(mesh16), output=str(path))
    problem = load_problem(path)
    return problem, solve_frictionless(problem, method="min")


def test_hertz_sphere_under_a_force(mesh16):
    """Issue 31: the quarter sphere under the force P (load='force': no
    support in z, the vertical translation held by the contact only) at
    a/h ≥ 16: a within 1 % (first moment) and the fitted p0 within 1 % of
    Hertz for the given P, whose contact forces balance P to 1e-10.
    Measured: −0.16 %, +0.50 % (the supported run's numbers)."""
    path = mesh16.with_name("force.npz")
    export_module().export_only(SPHERE, mesh=str(mesh16), output=str(path),
                                load="force", P=36.63)
    problem = load_problem(path)
    assert problem.rigid_modes()[0].shape[1] == 1
    result = solve(problem)
    assert result.success, result.message
    assert abs(4 * result.total_contact_force[2] - 36.63) <= 1e-10 * 36.63
    row = hertz_sphere_row(problem, result)
    assert row["a/h"] >= 16 and abs(row["P"] / 36.63 - 1) < 1e-10
    assert abs(row["a moment err %"]) < 1.0
    assert abs(row["p0 fit err %"]) < 1.0


def test_hertz_sphere_a_over_h_16(sphere16):
    """Issue 18: at a/h ≥ 16, a within 1 % (from the first moment of the
    contact forces), p0 from a least-squares fit of the Hertz profile
    (a and p0 both fitted) within 1 %, the largest nodal pressure within
    3 % and the RMS deviation of the nodal pressures from Hertz's profile
    inside r < a below 3 % of p0 (lumped λ_i/D_ii). Measured on the
    Netgen-optimised a = 0.05 R mesh: −0.16 %, +0.51 %, +0.8 %, 2.2 %
    (the RMS was 3.2 % with gmsh's Delaunay tets alone at a = 0.1 R)."""
    problem, result = sphere16
    assert result.success, result.message
    row = hertz_sphere_row(problem, result)
    assert row["a/h"] >= 16
    assert row["in contact"] >= 250
    assert abs(row["a moment err %"]) < 1.0
    assert abs(row["p0 fit err %"]) < 1.0
    assert abs(row["max p err %"]) < 3.0
    assert row["RMS/p0 %"] < 3.0


def test_hertz_sphere_methods_and_systems_agree(sphere16):
    """φ_FB gives φ_min's u and λ to 1e-9 relative (both solved to tol
    1e-12: at the default 1e-10, a force tolerance, u differs by ~1e-8
    relative). The full system against the condensed one is checked on
    smaller 3D problems in test_core3d.py (here it would take a minute)."""
    problem, _ = sphere16
    reference = solve_frictionless(problem, method="min", tol=1e-12)
    for kwargs in ({"method": "fb"},):
        other = solve_frictionless(problem, tol=1e-12, **kwargs)
        assert other.success, (kwargs, other.message)
        np.testing.assert_allclose(other.u, reference.u, rtol=0,
                                   atol=1e-9 * np.abs(reference.u).max())
        lam, ref = (np.nan_to_num(r.contact_force) for r in (other,
                                                             reference))
        np.testing.assert_allclose(lam, ref, rtol=0, atol=1e-9 * ref.max())
