"""The pressure-against-radius figure (solver/output/figures3d.py); the
Hertz profile p0·sqrt(1 − r²/a²) (Johnson 1985, §4.2) written out here."""

import numpy as np
import pytest

from solver.output.figures3d import hertz_pressure, pressure_vs_radius


def test_hertz_pressure_closed_form():
    r = np.array([0.0, 0.6, 0.8, 1.0, 1.5])
    np.testing.assert_allclose(hertz_pressure(r, 1.0, 10.0),
                               [10.0, 8.0, 6.0, 0.0, 0.0], atol=1e-14)


def test_figure_saved_with_points_and_curve(tmp_path):
    rng = np.random.default_rng(0)
    r = rng.uniform(0, 2.0, 50)
    p = hertz_pressure(r, 1.5, 3.0)
    path = tmp_path / "pressure.png"
    fig = pressure_vs_radius(path, r, p, a=1.5, p0=3.0)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    points, curve = fig.axes[0].lines[:2]
    np.testing.assert_array_equal(points.get_xdata(), r)
    np.testing.assert_array_equal(points.get_ydata(), p)
    x, y = curve.get_xdata(), curve.get_ydata()
    np.testing.assert_allclose(y, 3.0 * np.sqrt(np.clip(1 - (x / 1.5) ** 2,
                                                        0, None)))
    assert x.max() == pytest.approx(2.4, rel=0.01)


def test_draws_into_given_axes_without_curve():
    from solver.output.figures import _pyplot

    fig, ax = _pyplot().subplots()
    assert pressure_vs_radius(ax, [0.0, 1.0], [2.0, 1.0]) is fig
    assert len(ax.lines) == 1


@pytest.mark.parametrize("args, kwargs", [(([0, 1], [1]), {}),
                                          (([0, 1], [1, 2]), {"a": 1.0})])
def test_bad_arguments(args, kwargs):
    with pytest.raises(ValueError):
        pressure_vs_radius(None, *args, **kwargs)
