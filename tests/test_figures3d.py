"""The pressure-against-radius figure (solver/output/figures3d.py); the
Hertz profile p0·sqrt(1 − r²/a²) (Johnson 1985, §4.2) written out here."""

from types import SimpleNamespace

import numpy as np
import pytest

from solver.output.figures3d import (HertzReference, contact_radius,
                                     hertz_pressure, plot_pressure_vs_radius,
                                     pressure_vs_radius, write_figures3d)


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
    from solver.output.figures import pyplot

    fig, ax = pyplot().subplots()
    assert pressure_vs_radius(ax, [0.0, 1.0], [2.0, 1.0]) is fig
    assert len(ax.lines) == 1


@pytest.mark.parametrize("args, kwargs", [(([0, 1], [1]), {}),
                                          (([0, 1], [1, 2]), {"a": 1.0})])
def test_bad_arguments(args, kwargs):
    with pytest.raises(ValueError):
        pressure_vs_radius(None, *args, **kwargs)


def _tilted_disc():
    """Contact nodes on a tilted plane around a centre, with known
    distances from the axis through it; a Hertz pressure on them."""
    rng = np.random.default_rng(3)
    axis = np.array([1.0, 2.0, 2.0]) / 3
    e1 = np.array([2.0, -1.0, 0.0]) / np.sqrt(5)
    e2 = np.cross(axis, e1)
    center = np.array([1.0, -2.0, 0.5])
    r = np.r_[0.0, rng.uniform(0.05, 2.0, 199)]
    phi = rng.uniform(0, np.pi / 2, 200)  # a quarter, as a quarter model
    points = center + r[:, None] * (np.cos(phi)[:, None] * e1
                                    + np.sin(phi)[:, None] * e2)
    return points, r, hertz_pressure(r, 1.5, 7.0), center, axis


def test_contact_radius_finds_the_axis_of_a_quarter_contact():
    points, r, p, center, axis = _tilted_disc()
    np.testing.assert_allclose(contact_radius(points, p), r, atol=1e-12)
    np.testing.assert_allclose(contact_radius(points, p, center, -axis), r,
                               atol=1e-12)


def test_write_figures3d(tmp_path):
    """Given a reference (the tilted disc's own centre and axis, a, p0),
    the figure measures r from that axis, draws that curve and puts the
    reference's note in the title."""
    from solver import solve_frictionless
    from solver.examples import two_dof_bar

    points, r, p, center, axis = _tilted_disc()
    problem = SimpleNamespace(nodes=points, contact_nodes=np.arange(200))
    result = solve_frictionless(two_dof_bar())  # for its history
    result = dict(result, contact_pressure=p)
    result = type("R", (dict,), {"__getattr__": dict.__getitem__})(result)
    reference = HertzReference(center=center, axis=axis, a=1.5, p0=7.0,
                               note="given")
    paths = write_figures3d(tmp_path, problem, result, reference=reference)
    assert sorted(paths) == ["convergence", "pressure_radius"]
    for path in paths.values():
        assert open(path, "rb").read(4) == b"\x89PNG"
    fig = plot_pressure_vs_radius(problem, result, reference=reference)
    np.testing.assert_allclose(fig.axes[0].lines[0].get_xdata(), r,
                               atol=1e-12)
    assert fig.axes[0].lines[1].get_label().startswith("Hertz")
    assert "given" in fig.axes[0].get_title()


def test_pressure_figure_zooms_onto_a_small_contact(tmp_path):
    """Hertz pressure on r < a = 0.05 among nodes out to r = 0.7 (the
    quarter sphere's Γc): the main panel spans [0, ≈ a], a second panel
    all radii (before: one panel over 0.73 for a 0.05 contact)."""
    rng = np.random.default_rng(1)
    r = np.r_[rng.uniform(0, 0.05, 40), rng.uniform(0.05, 0.7, 160)]
    p = hertz_pressure(r, 0.05, 7000.0)
    fig = pressure_vs_radius(tmp_path / "p.png", r, p, a=0.05, p0=7000.0,
                             zoom=True)
    main, whole = fig.axes
    assert 0.05 < main.get_xlim()[1] < 0.1
    assert whole.get_xlim()[1] >= 0.7
    assert main.get_ylabel() == "contact pressure p [MPa]"
    assert whole.get_xlabel().endswith("[mm]")
