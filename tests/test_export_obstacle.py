"""The export helper's obstacle given as a dict (2D): what a problem file
outside the repository writes instead of importing the solver's classes.

The reference is the ``.npz`` format (docs/npz-format.md): a parametric
obstacle is its two expression strings in t (with an optional t range), a
polyline its vertices; the written file is checked by
tests/test_own_problem.py (the ring's circle).
"""

import numpy as np
import pytest

from test_export import export_module


def test_parametric_dict_is_the_curve_the_format_stores():
    curve = export_module().obstacle_curve(
        {"x": "2.001*cos(t)", "y": "2.001*sin(t)", "t_range": [-1, 3]})
    assert (curve.x_text, curve.y_text) == ("2.001*cos(t)", "2.001*sin(t)")
    assert tuple(curve.t_range) == (-1.0, 3.0)
    t = np.pi / 3  # a point of the circle of radius 2.001
    assert np.allclose(curve.point(t), [2.001 * np.cos(t), 2.001 * np.sin(t)])


def test_points_dict_is_a_polyline():
    points = [[5.5, -10.0], [5.1, 0.0], [5.5, 10.0]]
    curve = export_module().obstacle_curve({"points": points})
    assert np.array_equal(curve.points, points)


@pytest.mark.parametrize("spec", [{"x": "t"}, {"points": [[0, 0], [1, 0]],
                                               "x": "t"},
                                  {"kind": "plane"}])
def test_other_dicts_are_refused_naming_their_keys(spec):
    with pytest.raises(ValueError, match=r"^obstacle: a 2D obstacle is .*"
                       r"got the keys \[") as error:
        export_module().obstacle_curve(spec)
    assert "\n" not in str(error.value)
    assert repr(sorted(spec))[1:-1] in str(error.value)

