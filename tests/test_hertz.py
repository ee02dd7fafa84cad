"""Hertz line contact: the half-cylinder of sfepy_problems/hertz_cylinder.py.

Independent references: SfePy's own solution of the linear elasticity problem
with non-zero Dirichlet data (K and f must reproduce it), the geometry of the
arc Γc (|Γc| = 2R asin 0.6, the P1 mass matrix of its chords), the balance of
forces (contact force = reaction on the top edge) and Hertz's closed-form
solution for a cylinder on a rigid flat in plane strain,

    a = 2 sqrt(P R / (π E*)),  p0 = 2P / (π a),  p(x) = p0 sqrt(1 - x²/a²),

E* = E / (1 - ν²), P the force per unit length, known only after the
contact solve (it is the sum of the vertical contact forces).

Measured (gmsh 4.15, R = 1, E = 2e5, ν = 0.3, d = 0.016, P ≈ 1740,
a ≈ 0.1004): a and p0 fitted to the lumped pressure (outermost contact node
on each side left out) differ from Hertz by -0.38 % and +0.25 % on the
committed mesh (h_c = 0.004, 51 contact nodes). Refining h_c (0.016 ...
0.001, 13 ... 201 contact nodes) moves the fitted a by at most 0.3 % and p0
by 0.05 %, without a clean rate (the contact edge falls anywhere between two
nodes); the difference to Hertz stays: it is a model error ≈ -0.4 (a/R)² in
a of the finite body (Hertz assumes a half-space, a ≪ R), which shrinks with
the load (-0.13 % at d = 0.008, -0.05 % at d = 0.004 on the same mesh).
"""

import numpy as np
import pytest
import scipy.sparse.linalg as sla
from scipy.optimize import curve_fit

from solver import load_problem, solve_frictionless
from solver.errors import PenetrationWarning

from conftest import MESHES, ROOT, load_script
HERTZ_PROBLEM = ROOT / "sfepy_problems" / "hertz_cylinder.py"
HERTZ_MESH = MESHES / "hertz.mesh"
STIFFNESS = "dw_lin_elastic.i.Omega(solid.D, v, u)"

E, NU, R, D = 2e5, 0.3, 1.0, 0.016
E_STAR = E / (1 - NU ** 2)
ARC_ANGLE = 2 * np.arcsin(0.6)  # Γc: the arc below y = -0.8 R




hertz = load_script("_contact_ssn_meshes_hertz", MESHES / "hertz.py")
export = load_script("_contact_ssn_sfepy_export", ROOT / "sfepy_problems" / "_export.py")


def _conf(mesh, output, **params):
    from sfepy.base.conf import ProblemConf, get_standard_keywords

    required, other = get_standard_keywords()
    return ProblemConf.from_file(
        str(HERTZ_PROBLEM), required, other,
        define_args=dict(mesh=str(mesh), output=str(output), **params))


def solve_hertz(mesh, output, **params):
    """Run the Hertz problem file like ``sfepy-run -d ...`` (in-process).

    Returns SfePy's problem and solution variables; the export hook writes
    the ``.npz``.
    """
    from sfepy.applications import solve_pde

    return solve_pde(_conf(mesh, output, **params), save_results=False)


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    """``meshes(h_c)`` -> path: the committed mesh for 0.004, else gmsh."""
    folder = tmp_path_factory.mktemp("hertz_meshes")
    cache = {hertz.H_CONTACT: HERTZ_MESH}

    def get(h_contact):
        if h_contact not in cache:
            path = folder / f"hertz_{h_contact}.mesh"
            hertz.write_mesh(path, *hertz.hertz_mesh(h_contact))
            cache[h_contact] = path
        return cache[h_contact]

    return get


@pytest.fixture(scope="module")
def exported(tmp_path_factory, meshes):
    """``exported(h_c, d)`` -> (npz path, SfePy problem, SfePy variables)."""
    folder = tmp_path_factory.mktemp("hertz_export")
    cache = {}

    def get(h_contact=hertz.H_CONTACT, d=D):
        key = (h_contact, d)
        if key not in cache:
            path = folder / f"hertz_{h_contact}_{d}.npz"
            pb, variables = solve_hertz(meshes(h_contact), path, d=d)
            cache[key] = (path, pb, variables)
        return cache[key]

    return get


@pytest.fixture(scope="module")
def contact(exported):
    """``contact(h_c, d)`` -> (problem, frictionless result)."""
    cache = {}

    def get(h_contact=hertz.H_CONTACT, d=D):
        key = (h_contact, d)
        if key not in cache:
            problem = load_problem(exported(h_contact, d)[0])
            result = solve_frictionless(problem, method="min", gap="obstacle")
            assert result.success, result.message
            cache[key] = (problem, result)
        return cache[key]

    return get


def semi_ellipse(x, p0, a):
    return p0 * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None))


def hertz_fit(problem, result, drop=1):
    """Total force P, Hertz's (a, p0) for it, and the fitted (a, p0).

    The semi-ellipse is fitted by least squares to the lumped pressure of the
    nodes in contact, without the ``drop`` outermost ones on each side:
    their hat functions reach past the contact edge, so their lumped
    pressure is low and pulls a down (measured: -1.8 % with all nodes vs
    -0.5 % without the outermost ones for h_c = 0.016, 13 contact nodes).
    """
    x = problem.nodes[problem.contact_nodes, 0]
    # Contact force on the body is -λν; ν = (0, -1) points down, λ >= 0.
    P = float(np.sum(result.contact_force * -result.normal[:, 1]))
    a_h = 2 * np.sqrt(P * R / (np.pi * E_STAR))
    p0_h = 2 * P / (np.pi * a_h)
    inside = np.flatnonzero(result.in_contact)
    keep = inside[drop:len(inside) - drop]
    (p0, a), _ = curve_fit(semi_ellipse, x[keep],
                           result.contact_pressure[keep],
                           p0=[p0_h, a_h])
    return P, (a_h, p0_h), (a, p0)


# ----------------------------------------------------------------------------
# the mesh

def test_committed_mesh_regenerates(tmp_path):
    """meshes/hertz.mesh is `python meshes/hertz.py` (gmsh is in the test
    extra; reruns give identical files)."""
    path = tmp_path / "hertz.mesh"
    assert hertz.main(["-o", str(path)]) == 0
    assert path.read_bytes() == HERTZ_MESH.read_bytes()
    assert HERTZ_MESH.stat().st_size < 400_000


def test_mesh_geometry():
    points, triangles = hertz.read_mesh(HERTZ_MESH)
    r = np.hypot(points[:, 0], points[:, 1])
    assert r.max() <= R * (1 + 1e-15) and points[:, 1].max() == 0.0
    assert (hertz.generate.signed_areas(points, triangles) > 0).all()
    assert len(np.unique(triangles)) == len(points)
    # Symmetric about x = 0, node by node.
    key = lambda p: set(map(tuple, np.round(p, 14)))  # noqa: E731
    assert key(points) == key(points * [-1, 1])
    for corner in ((0, 0), (0.6, -0.8), (-0.6, -0.8), (0, -1)):
        assert ((points[:, 0] == corner[0]) & (points[:, 1] == corner[1])).sum() == 1
    # (c) the contact zone |x| < a ≈ 0.1 is resolved by >= 40 arc nodes.
    arc = hertz.arc_nodes(points)
    assert np.abs(r[arc] - R).max() < 1e-15
    assert (np.abs(points[arc, 0]) < 0.1).sum() >= 40


def test_mesh_cli_errors(tmp_path, capsys):
    assert hertz.main(["--h-contact", "0.2", "-o", str(tmp_path / "x.mesh")]) == 1
    assert "must not exceed h_far" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        hertz.main(["-o", str(tmp_path / "x.msh")])


# ----------------------------------------------------------------------------
# the export

def test_K_reproduces_sfepy_solution(exported):
    """(a) With u_y = -d on the top edge SfePy's solution (no contact) is the
    rigid translation (0, -d); K, f = -(K_full u_D)_F must give it."""
    path, pb, variables = exported()
    problem = load_problem(path)
    reference = variables["u"]().reshape(-1, 2)
    np.testing.assert_allclose(reference, np.tile([0.0, -D], (len(reference), 1)),
                               atol=1e-12)
    full = problem.full_displacement(sla.spsolve(problem.K.tocsc(), problem.f))
    assert np.abs(full - reference).max() <= 1e-10 * D
    # Dirichlet DOFs: u_y on the top edge, u_x at the top centre only.
    top = problem.nodes[:, 1] == 0.0
    centre = top & (problem.nodes[:, 0] == 0.0)
    fixed = np.ones((len(problem.nodes), 2), bool)
    fixed[problem.dof_map[:, 0], problem.dof_map[:, 1]] = False
    np.testing.assert_array_equal(fixed, np.stack([centre, top], axis=1))
    expected = np.zeros_like(problem.u_prescribed)
    expected[top, 1] = -D
    np.testing.assert_array_equal(problem.u_prescribed, expected)
    # K is the free-free block of the unconstrained matrix, f its lifting.
    K_full = export.full_stiffness(pb, STIFFNESS)
    free = 2 * problem.dof_map[:, 0] + problem.dof_map[:, 1]
    assert abs(K_full[free][:, free] - problem.K).max() == 0.0
    np.testing.assert_array_equal(
        problem.f, -(K_full @ problem.u_prescribed.ravel())[free])
    # The contact nodes are free: Γc does not reach the top edge.
    assert (problem.contact_dofs >= 0).all()


def test_nonuniform_dirichlet_values(meshes, tmp_path):
    """(a) A deformation that is not rigid: the top edge stretched,
    u = (0.01 x, -d), and the arc Γc held at u_y = 0. K and the lifted f
    reproduce SfePy's solution."""
    from sfepy.applications import solve_pde
    from sfepy.base.conf import ProblemConf, get_standard_keywords

    module = load_script("_contact_ssn_hertz_cylinder", HERTZ_PROBLEM)
    path = tmp_path / "stretched.npz"
    define = module.define(mesh=str(meshes(0.016)), output=str(path))

    def stretch(ts, coors, **kwargs):
        return 0.01 * coors[:, 0]

    define["functions"] = {"stretch": (stretch,)}
    define["ebcs"] = {"pressed": ("Top", {"u.0": "stretch", "u.1": -D}),
                      "held": ("Gamma_c", {"u.1": 0.0})}
    required, other = get_standard_keywords()
    conf = ProblemConf.from_dict(define, module, required, other)
    pb, variables = solve_pde(conf, save_results=False)
    problem = load_problem(path)
    reference = variables["u"]().reshape(-1, 2)
    assert np.ptp(reference[:, 1]) > 0.9 * D  # far from a rigid motion
    full = problem.full_displacement(sla.spsolve(problem.K.tocsc(), problem.f))
    assert np.abs(full - reference).max() <= 1e-10 * np.abs(reference).max()
    top = problem.nodes[:, 1] == 0.0
    np.testing.assert_allclose(problem.u_prescribed[top, 0],
                               0.01 * problem.nodes[top, 0], rtol=1e-15)
    # Γc is held: every contact node is a support (its y DOF is fixed).
    assert (problem.contact_dofs[:, 1] == -1).all()


def test_M_is_the_boundary_mass_matrix_of_the_arc(exported):
    """(b) Σ M = |Γc|: the chords of the arc from (-0.6, -0.8) to
    (0.6, -0.8), and the arc length 2R asin 0.6 up to the chord error."""
    problem = load_problem(exported()[0])
    xy = problem.nodes[problem.contact_nodes]
    np.testing.assert_array_equal(xy[[0, -1]], [[-0.6, -0.8], [0.6, -0.8]])
    assert np.all(np.diff(xy[:, 0]) > 0)  # ordered along the arc
    assert (xy[:, 1] <= -0.8).all()
    assert np.abs(np.hypot(*xy.T) - R).max() < 1e-15
    h = np.linalg.norm(np.diff(xy, axis=0), axis=1)
    angles = 2 * np.arcsin(h / (2 * R))
    assert angles.sum() == pytest.approx(ARC_ANGLE, rel=1e-12)
    assert problem.M.sum() == pytest.approx(h.sum(), rel=1e-13)
    # Arc length R·angle minus chord lengths: Σ R (θ - 2 sin(θ/2)) ≈ Σ h³/24R².
    arc = R * ARC_ANGLE
    assert arc - problem.M.sum() == pytest.approx(np.sum(h ** 3) / 24, rel=0.01)
    assert problem.M.sum() == pytest.approx(arc, rel=2e-4)
    # P1 mass matrix of a polyline: each chord adds h/6 [[2, 1], [1, 2]].
    main = np.zeros(len(xy))
    main[:-1] += h / 3
    main[1:] += h / 3
    M = np.diag(main) + np.diag(h / 6, 1) + np.diag(h / 6, -1)
    np.testing.assert_allclose(problem.M.toarray(), M, rtol=1e-12, atol=1e-16)


def test_meta_and_obstacle(exported):
    problem = load_problem(exported()[0])
    meta = problem.meta
    assert (meta["E"], meta["nu"], meta["plane"], meta["R"], meta["d"]) \
        == (E, NU, "strain", R, D)
    assert meta["E_star"] == pytest.approx(E_STAR, rel=1e-15)
    assert "P" not in meta  # known only after the contact solve
    assert (problem.obstacle.x_text, problem.obstacle.y_text) == ("t", "-1")


# ----------------------------------------------------------------------------
# the contact solution against Hertz

def test_flat_obstacle_gaps_and_normals(contact):
    """The gap code with a constant y(t): vertical normals, s = 1 + y."""
    problem, result = contact()
    xy = problem.nodes[problem.contact_nodes]
    np.testing.assert_array_equal(result.normal, np.tile([0.0, -1.0], (len(xy), 1)))
    np.testing.assert_allclose(result.gap, 1 + xy[:, 1], rtol=0, atol=1e-15)


def test_contact_force_is_the_top_reaction(exported, contact):
    """P = Σ λ (-ν_y) balances the reaction of the top edge, and the contact
    solution is symmetric like the mesh."""
    path, pb, _ = exported()
    problem, result = contact()
    P = np.sum(result.contact_force * -result.normal[:, 1])
    K_full = export.full_stiffness(pb, STIFFNESS)
    forces = (K_full @ result.displacement.ravel()).reshape(-1, 2)
    top = problem.nodes[:, 1] == 0.0
    assert forces[top, 1].sum() == pytest.approx(-P, rel=1e-8)
    assert 1700 < P < 1780  # d = 0.016 gives a ≈ 0.1
    x = problem.nodes[problem.contact_nodes, 0]
    np.testing.assert_allclose(x, -x[::-1], atol=1e-15)
    lam = result.contact_force
    np.testing.assert_allclose(lam, lam[::-1], rtol=1e-6, atol=1e-9 * lam.max())


def test_hertz_half_width_and_peak_pressure(contact):
    """(d) The committed mesh: a within 1 %, p0 within 3 % of Hertz; >= 40
    nodes in contact."""
    problem, result = contact()
    P, (a_h, p0_h), (a, p0) = hertz_fit(problem, result)
    assert result.n_contact >= 40
    assert a_h == pytest.approx(0.1, rel=0.01)
    assert abs(a / a_h - 1) < 0.01      # measured -0.38 %
    assert abs(p0 / p0_h - 1) < 0.03    # measured +0.25 %
    # The contact zone ends between the last node in contact and the next.
    x = np.abs(problem.nodes[problem.contact_nodes, 0])
    assert x[result.in_contact].max() < a < x[~result.in_contact].min()


def test_refinement(contact):
    """h_c = 0.016, 0.008, 0.004: contact nodes double with each halving;
    the fitted a and p0 are mesh-independent to 0.5 % and 0.1 % and within
    the targets on every mesh."""
    fits = {}
    for h in (0.016, 0.008, 0.004):
        problem, result = contact(h)
        P, (a_h, p0_h), (a, p0) = hertz_fit(problem, result)
        assert abs(a / a_h - 1) < 0.01 and abs(p0 / p0_h - 1) < 0.03
        fits[h] = (result.n_contact, a, p0)
    counts, a, p0 = (np.array(v) for v in zip(*fits.values()))
    assert (counts[1:] >= 1.8 * counts[:-1]).all()  # measured 13, 25, 51
    assert np.ptp(a) / a.mean() < 0.005    # measured 0.35 %
    assert np.ptp(p0) / p0.mean() < 0.001  # measured 0.03 %


def test_difference_to_hertz_is_the_finite_body(contact):
    """On one mesh, the deviation of a from Hertz shrinks with a/R like
    (a/R)²: Hertz's half-space assumption, not the discretisation."""
    errors = {}
    for d in (0.004, 0.008, 0.016):
        problem, result = contact(hertz.H_CONTACT, d)
        P, (a_h, _), (a, _) = hertz_fit(problem, result)
        errors[d] = (a_h, a / a_h - 1)
    (a1, e1), (a2, e2), (a3, e3) = errors.values()
    assert e3 < e2 < e1 < 0       # measured -0.05 %, -0.13 %, -0.38 %
    assert -0.6 < e3 / a3 ** 2 < -0.2 and abs(e1) < 0.001



# ----------------------------------------------------------------------------
# the half model: symmetry plane x = 0, the axis node a roller (issue 18)

def _half_mesh(path):
    """The committed mesh cut at x = 0 (its triangulation is mirror-
    symmetric and no triangle crosses x = 0: checked)."""
    points, triangles = hertz.read_mesh(HERTZ_MESH)
    x = points[triangles, 0]
    assert not ((x.min(axis=1) < -1e-12) & (x.max(axis=1) > 1e-12)).any()
    kept = triangles[(x >= -1e-12).all(axis=1)]
    used = np.unique(kept)
    renumber = np.full(len(points), -1)
    renumber[used] = np.arange(len(used))
    hertz.write_mesh(path, points[used], renumber[kept])


@pytest.fixture(scope="module")
def half_problem(tmp_path_factory):
    """The half cylinder x ≥ 0 exported like ``sfepy-run`` with the
    symmetry condition u_x = 0 on x = 0 (instead of the pin at the top
    centre) and Γc without the facets on x = 0: the node (0, −R) on the
    axis has u_x = 0, a roller (ν = (0, −1))."""
    from sfepy.applications import solve_pde
    from sfepy.base.conf import ProblemConf, get_standard_keywords

    folder = tmp_path_factory.mktemp("hertz_half")
    mesh, path = folder / "half.mesh", folder / "half.npz"
    _half_mesh(mesh)
    module = load_script("_contact_ssn_hertz_cylinder", HERTZ_PROBLEM)
    define = module.define(mesh=str(mesh), output=str(path), d=D)
    tol = 1e-8 * R
    define["regions"]["Axis"] = (f"vertices in (x < {tol})", "facet")
    define["regions"]["Gamma_c"] = ("r.Surface *e r.Low -e r.Axis", "facet")
    define["ebcs"] = {"pressed": ("Top", {"u.1": -D}),
                      "symmetry": ("Axis", {"u.0": 0.0})}
    required, other = get_standard_keywords()
    solve_pde(ProblemConf.from_dict(define, module, required, other),
              save_results=False)
    return load_problem(path)


def _fit_mirrored(problem, result):
    """Hertz's (a, p0) for the whole model's force P = 2 P_half, and the
    semi-ellipse fitted (as :func:`hertz_fit`) to the half's lumped
    pressure mirrored to x < 0 (the axis node once; it is in the fit
    whether in contact or a support with p = 0)."""
    x = problem.nodes[problem.contact_nodes, 0]
    P = 2 * float(np.nansum(result.contact_force * -result.normal[:, 1]))
    a_h = 2 * np.sqrt(P * R / (np.pi * E_STAR))
    p0_h = 2 * P / (np.pi * a_h)
    # every node inside the outermost one in contact, which is left out
    keep = np.flatnonzero(x < x[result.in_contact].max())
    xs = np.concatenate([-x[keep][x[keep] > 0], x[keep]])
    ps = np.concatenate([result.contact_pressure[keep][x[keep] > 0],
                         result.contact_pressure[keep]])
    (p0, a), _ = curve_fit(semi_ellipse, xs, ps, p0=[p0_h, a_h])
    return P, (a_h, p0_h), (a, p0)


def test_half_model_with_roller_is_the_whole_model(half_problem, contact):
    """Mirror symmetry on the real mesh: with the axis node a roller the
    half model's λ equals the whole model's (half of it on the axis) and
    the lumped pressure equals it everywhere, to 1e-10."""
    problem = half_problem
    axis = np.flatnonzero(np.abs(problem.nodes[problem.contact_nodes, 0])
                          < 1e-12)
    assert len(axis) == 1 and problem.contact_dofs[axis[0], 0] == -1
    half = solve_frictionless(problem, method="min", gap="obstacle")
    assert half.success, half.message
    whole_problem, whole = contact()
    key = {tuple(p): i for i, p in enumerate(
        np.round(whole_problem.nodes[whole_problem.contact_nodes], 12))}
    c = np.array([key[tuple(p)] for p in
                  np.round(problem.nodes[problem.contact_nodes], 12)])
    share = np.ones(problem.n_contact)
    share[axis] = 0.5
    scale = whole.contact_force.max()
    assert np.abs(half.contact_force - share * whole.contact_force[c]).max() \
        <= 1e-10 * scale
    assert np.abs(half.contact_pressure - whole.contact_pressure[c]).max() \
        <= 1e-10 * whole.contact_pressure.max()
    assert half.contact_force[axis[0]] > 0.45 * scale


def test_half_model_roller_brings_it_closer_to_hertz(half_problem, contact):
    """Hertz's closed form on the half model. With the axis node a support
    (λ = 0 there, as before rollers) the pressure profile is wrong near
    the axis: p = 0 on the axis, the node beside it takes the axis node's
    load, the nodal peak is +34 % off p0 and the RMS deviation of the
    nodal pressure from Hertz's profile (mirrored, over the contact zone)
    is 21 % of p0. With the axis node a roller the peak is +0.28 % off,
    the RMS deviation 0.32 %, and the fitted (a, p0) are exactly the whole
    model's (-0.38 %, +0.25 %: the finite body, see the module docstring).
    The support model's fit happens to land nearer Hertz (-0.22 %, +0.12 %:
    its wrong axis value pulls the ellipse the other way than the body's
    finite size does), which is no merit: the reference is the whole
    model, which the roller model reproduces."""
    problem = half_problem
    new = solve_frictionless(problem, method="min", gap="obstacle")
    with pytest.warns(PenetrationWarning):  # the axis node, driven in
        old = solve_frictionless(problem, method="min", gap="obstacle",
                                 rollers=False)
    assert new.success and old.success
    x = problem.nodes[problem.contact_nodes, 0]
    errors = {}
    for name, result in (("old", old), ("new", new)):
        P, (a_h, p0_h), (a, p0) = _fit_mirrored(problem, result)
        keep = x < x[result.in_contact].max()
        rms = np.sqrt(np.mean((result.contact_pressure[keep]
                               - semi_ellipse(x[keep], p0_h, a_h)) ** 2))
        errors[name] = dict(a=a / a_h - 1, p0=p0 / p0_h - 1,
                            peak=result.contact_pressure.max() / p0_h - 1,
                            rms=rms / p0_h)
    old, new = errors["old"], errors["new"]
    assert old["peak"] > 0.3 and abs(new["peak"]) < 0.005  # 34 %, 0.28 %
    assert old["rms"] > 0.1 and new["rms"] < 0.01  # 21 %, 0.32 % of p0
    whole = hertz_fit(*contact())
    assert new["a"] == pytest.approx(whole[2][0] / whole[1][0] - 1, abs=1e-6)
    assert new["p0"] == pytest.approx(whole[2][1] / whole[1][1] - 1, abs=1e-6)
    assert abs(new["a"]) < 0.01 and abs(new["p0"]) < 0.03
