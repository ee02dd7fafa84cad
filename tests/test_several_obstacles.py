"""Several rigid obstacles in one problem, 3D and 2D (issue 35, point 2).

A box [0, L]³ on rollers (u_y = 0 on y = 0, u_z = 0 on z = 0, u_x = 0 on
the mid-plane x = L/2) squeezed by two rigid planes that enter its faces
x = 0 and x = L by δ each: the closed form is uniaxial compression,
ε_xx = −2δ/L, σ_xx = E ε_xx, the other stresses zero, so every node of
both faces carries the contact pressure p = 2Eδ/L and moves by δ
inwards, while u_y = −ν ε_xx y and u_z = −ν ε_xx z (P1 elements reproduce
the linear field exactly, to round-off). The same with the obstacles given
as bounded rectangles, and with a third obstacle (a rectangle above the
top) that no node reaches, which is listed among the excluded nodes.

2D and every cell kind: ``sfepy_problems/squeezed_block.py`` with
``sides=2`` (SfePy assembles K): the unit block on rollers (u_y = 0 on its
bottom, u_x = 0 at the bottom's midpoint) between two rigid lines entering
its sides by δ (``obstacle_curves``: a parametric line and a polyline) or
two planes (3D). The same closed form, ε_xx = −2δ/L about x = L/2: in
plane strain (the format's default plane of the export) p = 2E'δ/L,
E' = E/(1 − ν²), u_y = 2ν'δy/L, ν' = ν/(1 − ν); in 3D p = 2Eδ/L,
u_y = 2νδy/L, u_z = 2νδz/L. With Coulomb friction the closed form holds
where nothing slides along the obstacles: ν = 0 (any bound), or, with the
default lagged bound, ν = 0.3 too, since the first load step carries the
whole squeeze before any bound exists (with the implicit bound friction
then holds the sides' Poisson sliding, and the pressure is no longer
uniform)."""

import copy
import json
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
from tet_elasticity import box, mesh_problem, stiffness  # noqa: E402

import solver  # noqa: E402
from conftest import MESHES, ROOT, load_script  # noqa: E402
from solver.errors import InitialPenetrationWarning, ProblemError  # noqa: E402
from solver.geometry.curves import SeveralCurves, obstacle_gaps  # noqa: E402
from solver.geometry.surfaces import surface_from_spec  # noqa: E402
from solver.problem import load_problem, validate_arrays  # noqa: E402

E, NU, L, DELTA, N = 100.0, 0.3, 1.0, 1e-3, 4


def side_faces(ids, side):
    """Triangles of the face x = 0 (side 0) or x = L (side −1), oriented
    outward (−x, +x)."""
    g = ids[side]
    a, b = g[:-1, :-1].ravel(), g[1:, :-1].ravel()
    c, d = g[1:, 1:].ravel(), g[:-1, 1:].ravel()
    if side == 0:  # (d − a) × (c − a) = z × (y + z) = −x
        return np.concatenate([np.stack([a, d, c], 1),
                               np.stack([a, c, b], 1)])
    return np.concatenate([np.stack([a, c, d], 1), np.stack([a, b, c], 1)])


def squeezed(obstacles):
    nodes, tets = box((N, N, N), (L, L, L))
    ids = np.arange(len(nodes)).reshape(N + 1, N + 1, N + 1)
    x, y, z = nodes.T
    prescribed = np.full(nodes.shape, np.nan)
    prescribed[np.isclose(y, 0), 1] = 0.0
    prescribed[np.isclose(z, 0), 2] = 0.0
    prescribed[np.isclose(x, L / 2), 0] = 0.0
    faces = np.concatenate([side_faces(ids, 0), side_faces(ids, -1)])
    contact = np.unique(faces)
    problem = mesh_problem(nodes, tets, stiffness(nodes, tets, E, NU),
                           prescribed, contact, faces)
    problem.contact_faces = faces
    problem.obstacle = surface_from_spec({"kind": "several",
                                          "surfaces": obstacles})
    problem.meta = {"E": E, "nu": NU, "load": "two planes, δ each",
                    "mesh": "tests/test_several_obstacles.py"}
    return problem


PLANES = [{"kind": "plane", "point": [DELTA, 0, 0], "normal": [1, 0, 0]},
          {"kind": "plane", "point": [L - DELTA, 0, 0],
           "normal": [-1, 0, 0]}]
RECTANGLES = [
    {"kind": "rectangle", "center": [DELTA, L / 2, L / 2],
     "normal": [1, 0, 0], "axis": [0, 1, 0], "half_sizes": [L, L]},
    {"kind": "rectangle", "center": [L - DELTA, L / 2, L / 2],
     "normal": [-1, 0, 0], "axis": [0, 0, 1], "half_sizes": [L, L]}]
FAR = {"kind": "rectangle", "center": [L / 2, L / 2, 2 * L],
       "normal": [0, 0, -1], "axis": [1, 0, 0], "half_sizes": [0.1, 0.1]}


@pytest.mark.parametrize("obstacles", [PLANES, RECTANGLES,
                                       RECTANGLES + [FAR]])
@pytest.mark.parametrize("options", [{}, dict(system="full"),
                                     dict(gap="body"),
                                     dict(friction=0.2, steps=2)])
def test_squeezed_between_two_planes_is_uniaxial(obstacles, options):
    problem = squeezed(obstacles)
    with pytest.warns(InitialPenetrationWarning):  # both planes enter
        result = solver.solve(problem, **options)
    assert result.success, result.message
    p = 2 * E * DELTA / L
    pressure = np.atleast_2d(result.contact_pressure)[-1]
    free = ~np.isnan(np.atleast_2d(result.gap)[-1]) \
        if np.ndim(result.gap) else slice(None)
    np.testing.assert_allclose(pressure[free], p, rtol=1e-10)
    u = problem.full_displacement(np.atleast_2d(result.u)[-1]) \
        if np.ndim(result.u) == 2 else problem.full_displacement(result.u)
    x, y, z = problem.nodes.T
    eps = -2 * DELTA / L
    exact = np.column_stack([eps * (x - L / 2), -NU * eps * y,
                             -NU * eps * z])
    np.testing.assert_allclose(u, exact, rtol=0, atol=1e-10 * DELTA)
    assert result.verification["excluded"]["nodes"] == 0  # FAR reaches none


def test_each_node_takes_the_nearer_obstacle():
    surface = surface_from_spec({"kind": "several", "surfaces": PLANES})
    points = np.array([[0, 0.5, 0.5], [L, 0.5, 0.5], [0.4, 0.5, 0.5]])
    gap, nu, foot = surface.gap_along_obstacle_normal(points)
    np.testing.assert_allclose(gap, [-DELTA, -DELTA, 0.4 - DELTA])
    np.testing.assert_allclose(nu, [[-1, 0, 0], [1, 0, 0], [-1, 0, 0]])
    assert surface.which(points).tolist() == [0, 1, 0]
    # along rays only the plane a node faces counts, not the one behind it
    tau, _ = surface.gap_along_rays(points[:2], [[-1, 0, 0], [1, 0, 0]])
    np.testing.assert_allclose(tau, [-DELTA, -DELTA])


def test_a_node_no_obstacle_reaches_is_excluded():
    """A 0.6 × 0.6 rectangle at the left face reaches the 3 × 3 nodes of
    each face x = 0, x = L that lie over it (|y − ½|, |z − ½| ≤ 0.3); the
    other 2·16 have no obstacle in reach."""
    patch = dict(RECTANGLES[0], half_sizes=[0.3, 0.3])
    problem = squeezed([patch, FAR])
    with pytest.warns(InitialPenetrationWarning):
        geometry = solver.contact_geometry(problem, rollers=True)
    reasons = geometry.excluded["reason"]
    assert reasons.count("no obstacle in reach (a bounded one ends "
                         "before it)") == 2 * ((N + 1) ** 2 - 9)
    assert len(geometry.index) == 2 * 9


#: SfePy's bounded plane of elastic_contact_planes.py (its plane cp0:
#: anchor (0, 0, 0.3), normal (0.3, 0, 1) into the obstacle, bounds a
#: triangle at z = 0.3), the normal reversed.
TRIANGLE = {"kind": "polygon", "point": [0, 0, 0.3], "normal": [-0.3, 0, -1],
            "vertices": [[0, 0, 0.3], [-0.25, -0.25, 0.3],
                         [-0.25, 0.25, 0.3]]}


def test_polygon_reaches_the_nodes_sfepy_masks():
    """The polygon's mask is SfePy's ``ContactPlane.mask_points`` (the
    point and the bounds projected orthogonally onto the plane, a point in
    the triangle): checked against SfePy itself at random points above
    the plane (off the edges, where SfePy's test is either way), and the
    gap is the plane's where the polygon reaches."""
    from sfepy.mechanics.contact_bodies import ContactPlane

    surface = surface_from_spec(TRIANGLE)
    plane = ContactPlane(TRIANGLE["point"], [0.3, 0, 1], TRIANGLE["vertices"])
    points = np.random.default_rng(35).uniform([-0.33, -0.33, 0.35],
                                               [0.33, 0.33, 0.5], (1000, 3))
    gap, nu, _ = surface.gap_along_obstacle_normal(points)
    inside = np.isfinite(gap)
    np.testing.assert_array_equal(inside, plane.mask_points(points))
    assert 50 < inside.sum() < len(points) / 4
    np.testing.assert_allclose(gap[inside],
                               -plane.get_distance(points[inside]))
    np.testing.assert_allclose(nu[inside], np.tile(plane.normal,
                                                   (inside.sum(), 1)))
    # the nodes of SfePy's cube top at x = -0.2 fall just outside (the
    # triangle's projection ends at x = -0.229 on the plane, theirs at
    # -0.2385); at x = -0.1 inside; a point on the edge counts as inside
    top = [[-0.2, 0, 0.5], [-0.1, 0, 0.5], [-0.1, -0.1, 0.5]]
    assert np.isfinite(surface.gap_along_obstacle_normal(top)[0]).tolist() \
        == [False, True, True]
    assert surface_from_spec(json.loads(json.dumps(surface.spec()))).spec() \
        == surface.spec()


@pytest.mark.parametrize("spec, phrase", [
    ({"kind": "several", "surfaces": []}, "non-empty list"),
    ({"kind": "several", "surfaces": [{"kind": "several",
                                       "surfaces": PLANES}]}, "not nested"),
    ({"kind": "several", "surfaces": [PLANES[0]] * 65}, "at most 64"),
    (dict(RECTANGLES[0], axis=[1, 0, 0]), "parallel to the normal"),
    (dict(RECTANGLES[0], half_sizes=[1, 0]), "must be > 0"),
    (dict(TRIANGLE, vertices=[[0, 0, 0], [1, 0, 0]]), "3 to 64 points"),
    (dict(TRIANGLE, vertices=[[0, 0, 0], [1, 0, 5], [2, 0, 0]]),
     "no area"),
    (dict(TRIANGLE, vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 1e300]]),
     "supported range")])
def test_bad_specs_are_refused_in_one_line(spec, phrase):
    with pytest.raises(ProblemError, match=phrase):
        surface_from_spec(json.loads(json.dumps(spec)))


# -- 2D, and every cell kind through the SfePy export -----------------------

SQUEEZED = ROOT / "sfepy_problems" / "squeezed_block.py"
KINDS = {"triangles": (2, 4, True), "quadrilaterals": (2, 4, False),
         "tetrahedra": (3, 2, True), "hexahedra": (3, 2, False)}


@pytest.fixture(scope="module")
def two_sided(tmp_path_factory):
    """The block squeezed from both sides, one export per cell kind (ν =
    NU) and one with ν = 0 (keyed (kind, 0.0))."""
    from test_export import export_module

    structured = load_script("_contact_ssn_structured",
                             MESHES / "structured.py")
    folder = tmp_path_factory.mktemp("two_sided")
    problems = {}
    for name, (dim, n, cut) in KINDS.items():
        nodes, cells = structured.box(n, dim)
        mesh = folder / f"{name}.mesh"
        structured.write(mesh, nodes, cells, cut)
        for nu in (NU, 0.0):
            out = folder / f"{name}_{nu}.npz"
            export_module().export_only(SQUEEZED, mesh=str(mesh),
                                        output=str(out), E=E, nu=nu,
                                        delta=DELTA, sides=2)
            problem = load_problem(out)
            problems[name if nu == NU else (name, nu)] = problem
    return problems


def two_sided_exact(problem):
    """p and u of the two-sided squeeze (module docstring)."""
    x, nu = problem.nodes, problem.meta["nu"]
    e_mod, nu_side = (E, nu) if problem.dim == 3 else (E / (1 - nu ** 2),
                                                       nu / (1 - nu))
    strain = 2 * DELTA / L
    u = nu_side * strain * x
    u[:, 0] = -strain * (x[:, 0] - L / 2)
    if problem.dim == 3:
        u[:, 2] = nu * strain * x[:, 2]
    return e_mod * strain, u


@pytest.mark.parametrize("kind", list(KINDS))
@pytest.mark.parametrize("options", [
    {}, dict(system="full"), dict(gap="body"), dict(friction=0.2, steps=2),
    dict(friction=0.2, steps=2, gap="body"),
    dict(friction=0.2, steps=2, coulomb="implicit", nu=0.0),
    dict(friction=0.2, steps=2, coulomb="implicit", nu=0.0, gap="body")],
    ids=["default", "full", "body", "friction", "friction-body",
         "friction-implicit-nu0", "friction-implicit-nu0-body"])
def test_block_between_two_obstacles_on_every_cell_kind(two_sided, kind,
                                                         options):
    """Friction: with the default lagged bound the first step, which
    carries the whole squeeze (the gaps enter at once), has no bound yet,
    so ν = 0.3 gives the frictionless answer; with the implicit bound
    friction holds the Poisson sliding of the sides and ν = 0 (no sliding)
    is the case with a closed form."""
    options = dict(options)
    problem = two_sided[kind] if options.pop("nu", NU) == NU \
        else two_sided[kind, 0.0]
    assert problem.cells.shape[1] == {"triangles": 3, "quadrilaterals": 4,
                                      "tetrahedra": 4, "hexahedra": 8}[kind]
    if problem.dim == 2:
        assert isinstance(problem.obstacle, SeveralCurves)
    with pytest.warns(InitialPenetrationWarning):  # both obstacles enter
        result = solver.solve(problem, **options)
    assert result.success, result.message
    p, u_exact = two_sided_exact(problem)
    pressure = np.atleast_2d(result.contact_pressure)[-1]
    free = ~np.isnan(np.atleast_2d(result.gap)[-1])
    assert free.sum() == len(problem.contact_nodes)  # both sides, corners
    np.testing.assert_allclose(pressure[free], p, rtol=1e-10)
    u = problem.full_displacement(np.atleast_2d(result.u)[-1])
    np.testing.assert_allclose(u, u_exact, rtol=0, atol=1e-10 * DELTA)
    assert result.verification["excluded"]["nodes"] == 0


LEFT = {"x": "0.001", "y": "t"}  # unbounded, x = δ
RIGHT = {"points": [[L - DELTA, -1.0], [L - DELTA, 2.0]]}


def test_each_node_takes_the_nearer_curve():
    """2D: a node takes the line of smaller gap; along the body normals the
    line behind a node does not count (its normal line meets it too)."""
    curves = SeveralCurves([LEFT, RIGHT])
    points = np.array([[0, 0.5], [L, 0.5], [0.4, 0.5]])
    body = np.array([[-1.0, 0], [1, 0], [-1, 0]])
    gap, nu, foot = obstacle_gaps(points, curves, body, warn=False)
    np.testing.assert_allclose(gap, [-DELTA, -DELTA, 0.4 - DELTA])
    np.testing.assert_allclose(nu, [[-1, 0], [1, 0], [-1, 0]])
    np.testing.assert_allclose(foot, [[DELTA, 0.5], [L - DELTA, 0.5],
                                      [DELTA, 0.5]])
    gap, nu, _ = obstacle_gaps(points[:2], curves, body[:2], "body",
                               warn=False)
    np.testing.assert_allclose(gap, [-DELTA, -DELTA])
    np.testing.assert_allclose(nu, body[:2])


def test_at_a_corner_the_nearer_curve_wins():
    """Two lines meeting at the corner (1, 1) (a right and a top wall):
    below the bisector y = x the node takes the right wall, above it the
    top, on it the first listed; the normal jumps across the bisector."""
    right = {"points": [[1, -1], [1, 1]]}
    top = {"x": "t", "y": "1", "t_range": [-1, 1]}
    curves = SeveralCurves([right, top])
    points = np.array([[0.9, 0.8], [0.8, 0.9], [0.9, 0.9]])
    body = np.full((3, 2), 0.5 ** 0.5)  # a body corner's bisector
    for gap in ("obstacle", "body"):
        s, nu, foot = obstacle_gaps(points, curves, body, gap, warn=False)
        if gap == "obstacle":
            np.testing.assert_allclose(s, [0.1, 0.1, 0.1])
            np.testing.assert_allclose(nu, [[1, 0], [0, 1], [1, 0]],
                                       atol=1e-15)
            np.testing.assert_allclose(foot, [[1, 0.8], [0.8, 1], [1, 0.9]])
        else:  # along the bisector: the nearer wall's intersection
            np.testing.assert_allclose(s, np.array([0.1, 0.1, 0.1]) * 2
                                       ** 0.5, rtol=1e-12)
            np.testing.assert_allclose(foot, [[1, 0.9], [0.9, 1], [1, 1]],
                                       atol=1e-12)


def test_a_node_no_curve_reaches_is_excluded(two_sided):
    """A segment x = L − δ, 0.3 ≤ y ≤ 0.7 reaches one node of the right
    side (y = 0.5; the others' nearest point is an end of it, not a foot
    point). Along the body normals the left line lies behind the other 4
    right nodes: no obstacle in reach, excluded. Measured from the
    obstacles (as in 3D) the left line reaches them through the body, at
    gap L − δ, so they take part and stay far from contact."""
    problem = copy.copy(two_sided["quadrilaterals"])  # the fixture's kept
    problem.obstacle = SeveralCurves([
        LEFT, {"points": [[L - DELTA, 0.3], [L - DELTA, 0.7]]}])
    with pytest.warns(InitialPenetrationWarning):
        geometry = solver.contact_geometry(problem, gap="body", rollers=True)
    assert geometry.excluded["reason"].count(
        "no obstacle in reach (a bounded one ends before it)") == 4
    assert len(geometry.index) == 5 + 1
    with pytest.warns(InitialPenetrationWarning):
        geometry = solver.contact_geometry(problem, rollers=True)
    assert len(geometry.index) == 10
    x = problem.nodes[problem.contact_nodes[geometry.index], 0]
    far = (x == L) & (np.abs(geometry.foot[:, 1] - 0.5) > 0.1)
    assert far.sum() == 4
    np.testing.assert_allclose(geometry.gap[far], L - DELTA, rtol=1e-12)
    np.testing.assert_allclose(geometry.foot[far, 0], DELTA, rtol=1e-12)


def test_obstacle_curves_round_trip_and_refusals(two_sided, tmp_path,
                                                 capsys):
    problem = two_sided["triangles"]
    from solver.cli import main
    from solver.problem import save_problem

    save_problem(tmp_path / "two.npz", problem)
    assert main([str(tmp_path / "two.npz"), "--info"]) == 0
    out = capsys.readouterr().out
    assert 'obstacle          {"curves": [{"t_range"' in out
    assert "gaps from the obstacle at 10 contact nodes: passed" in out
    arrays = problem.to_arrays()
    assert "obstacle_curves" in arrays and "obstacle_points" not in arrays
    again = validate_arrays(dict(arrays))
    assert again.obstacle.spec() == problem.obstacle.spec()
    for changes, phrase in [
            (dict(obstacle_x=np.array("t")), "obstacle_x: not allowed with "
                                             "obstacle_curves"),
            (dict(obstacle_curves=np.array("{}")), "must be a JSON list"),
            (dict(obstacle_curves=np.array("[]")), "non-empty list"),
            (dict(obstacle_curves=np.array('[{"z": 1}]')),
             "an obstacle curve is"),
            (dict(obstacle_curves=np.array("[" + ", ".join(
                [json.dumps(RIGHT)] * 65) + "]")), "at most 64")]:
        with pytest.raises(ProblemError, match=phrase):
            validate_arrays(dict(arrays, **changes))
    with pytest.raises(ProblemError, match="several obstacle curves"):
        problem.set_search_interval(0, 1)
    arrays3 = two_sided["tetrahedra"].to_arrays()
    with pytest.raises(ProblemError, match="obstacle_curves"):
        validate_arrays(dict(arrays3,
                             obstacle_curves=arrays["obstacle_curves"]))
