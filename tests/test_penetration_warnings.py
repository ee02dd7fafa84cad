"""An obstacle that penetrates the undeformed body is reported in 3D as in
2D (issue 34, point 3), and so are overlapping bodies: one
``InitialPenetrationWarning`` naming the nodes and the deepest one, and
the solve goes on (the contact conditions push the nodes out). The
reference is the geometry itself: a sphere lifted into the body by a
known depth."""

import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
from test_combinations import quarter_block_3d  # noqa: E402
from tri_elasticity import stacked_blocks  # noqa: E402

import solver  # noqa: E402
from solver.errors import InitialPenetrationWarning  # noqa: E402
from solver.geometry.surfaces import surface_from_spec  # noqa: E402


def test_3d_obstacle_inside_the_body_warns():
    problem = quarter_block_3d(n=4, nz=2)
    depth = 0.01  # the sphere's top 0.01 above the body's bottom z = 0
    problem.obstacle = surface_from_spec({"kind": "sphere",
                                          "center": [0, 0, -2.0 + depth],
                                          "radius": 2.0})
    with pytest.warns(InitialPenetrationWarning) as caught:
        result = solver.solve(problem)
    message = str(caught[0].message)
    assert message.startswith("the obstacle penetrates the undeformed body")
    assert f"deepest {depth:.3g} at node" in message
    assert result.success
    # the nodes pushed out: none is left inside the sphere
    moved = problem.nodes[problem.contact_nodes] + \
        result.displacement[problem.contact_nodes]
    distance = np.linalg.norm(moved - [0, 0, -2.0 + depth], axis=1)
    assert distance.min() >= 2.0 - 1e-9


def test_3d_obstacle_clear_of_the_body_is_silent():
    problem = quarter_block_3d(n=4, nz=2)
    with warnings_as_errors():
        solver.contact_geometry(problem, "obstacle", rollers=True)


def test_overlapping_bodies_warn():
    """The upper block's bottom curved down 0.02 into the lower block at
    its middle (stacked_blocks' curvature with a negative sign)."""
    problem, _, _ = stacked_blocks(n_upper=(8, 2), n_lower=(5, 2),
                                   curvature=-0.08)
    with pytest.warns(InitialPenetrationWarning,
                      match="the undeformed bodies overlap"):
        solver.solve(problem)


class warnings_as_errors:
    def __enter__(self):
        import warnings

        self.context = warnings.catch_warnings()
        self.context.__enter__()
        warnings.simplefilter("error", InitialPenetrationWarning)

    def __exit__(self, *exc):
        return self.context.__exit__(*exc)


@pytest.mark.parametrize("depth, warns", [(1e-5, False), (2e-3, True)])
def test_overlap_relative_to_the_element_size(depth, warns):
    """The upper box lowered by ``depth`` into the lower one (a uniform
    overlap, the weighted gaps −depth exactly on a flat interface): below
    a thousandth of the slave edges (about 1/3 here) it is the
    discretisation's (two curved bodies touching at a point give −4e-5 h
    at the apex), silent; above, reported with its depth."""
    from tet_two_body import stacked_boxes

    problem, _, _ = stacked_boxes()
    problem.nodes[problem.body == 0, 2] -= depth
    mapping = solver.contact.TwoBodyMap(problem)
    geometry = solver.contact_geometry(mapping.equivalent, "obstacle",
                                       rollers=True)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mapping.mark_uncovered(geometry)
    found = [w for w in caught
             if issubclass(w.category, InitialPenetrationWarning)]
    assert bool(found) == warns
    if warns:
        assert f"deepest {depth:.3g}" in str(found[0].message)
