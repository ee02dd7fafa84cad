"""Several rigid obstacles in one 3D problem (issue 35, point 2).

A box [0, L]³ on rollers (u_y = 0 on y = 0, u_z = 0 on z = 0, u_x = 0 on
the mid-plane x = L/2) squeezed by two rigid planes that enter its faces
x = 0 and x = L by δ each: the closed form is uniaxial compression,
ε_xx = −2δ/L, σ_xx = E ε_xx, the other stresses zero, so every node of
both faces carries the contact pressure p = 2Eδ/L and moves by δ
inwards, while u_y = −ν ε_xx y and u_z = −ν ε_xx z (P1 elements reproduce
the linear field exactly, to round-off). The same with the obstacles given
as bounded rectangles, and with a third obstacle (a rectangle above the
top) that no node reaches, which is listed among the excluded nodes."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
from tet_elasticity import box, mesh_problem, stiffness  # noqa: E402

import solver  # noqa: E402
from solver.errors import InitialPenetrationWarning, ProblemError  # noqa: E402
from solver.geometry.surfaces import surface_from_spec  # noqa: E402

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
