"""solver.output.thesis_figures: the figures say what they show.

References: the contact condition u_n = s at nodes in contact (the solver's
complementarity, checked independently in test_frictionless) for the drawn
obstacle; the bar's closed form (``two_dof_bar_closed_form``, derived by
hand) for which curves coincide; the units convention of the module
docstring for the axis labels.
"""

import re

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from solver import load_problem, solve_friction, solve_frictionless  # noqa: E402
from solver.examples import two_dof_bar_closed_form  # noqa: E402
from solver.output import thesis_figures as tf  # noqa: E402

#: Units the convention allows in a label "[...]".
UNITS = {"mm", "N", "MPa", "N/mm"}


def units_of(fig):
    labels = [label for ax in fig.axes
              for label in (ax.get_xlabel(), ax.get_ylabel())]
    return {u for label in labels for u in re.findall(r"\[([^\]]+)\]", label)}


@pytest.fixture(scope="module")
def block(exported):
    problem = load_problem(exported(118)[0])
    return problem, solve_frictionless(problem, condense=False)


@pytest.fixture(scope="module")
def bar_runs():
    from solver.examples import two_dof_bar

    bar = two_dof_bar()
    return bar, {fc: solve_friction(bar, fc, steps=100) for fc in (10.0, 0.5)}


def test_contact_nodes_lie_on_the_drawn_obstacle(block):
    """Displacements and gaps magnified alike: at true scale a node with
    u_n = s is drawn on the obstacle; at the default magnification it is
    off by a small part of the magnified gap (the magnified tangential
    displacement moves it along the curved obstacle), and the figure says
    by how much."""
    problem, r = block
    true_scale = tf.contact_offset(problem, r.displacement, r.in_contact, 1.0)
    assert true_scale < 1e-3 * np.nanmax(r.gap[r.in_contact])
    fig = tf.deformed_and_directions(problem, r.displacement, r.in_contact)
    magnified_gap = fig.scale * np.nanmax(r.gap[r.in_contact])
    assert fig.scale > 1
    assert 0 < fig.contact_offset < 0.15 * magnified_gap
    assert fig.contact_offset == tf.contact_offset(
        problem, r.displacement, r.in_contact, fig.scale)
    # nodes out of contact are drawn on the body's side of the obstacle
    assert tf.contact_offset(problem, r.displacement, ~r.in_contact
                             & np.isfinite(r.gap), 1.0) > true_scale


def test_identical_bar_curves_are_detected(bar_runs):
    """λ and u_y of the bar do not depend on f_c (closed form), the
    friction force and u_x do."""
    bar, runs = bar_runs
    exact = {fc: np.array([two_dof_bar_closed_form(k, fc)
                           for k in range(1, 101)]) for fc in runs}
    assert np.array_equal(exact[10.0][:, 2], exact[0.5][:, 2])
    assert not np.allclose(exact[10.0][:, 0], exact[0.5][:, 0])
    same = {q: tf.bar_history(bar, runs, q, exact).max_difference
            for q in tf.BAR_QUANTITIES}
    assert same["contact_force"] is not None and same["u_y"] is not None
    assert same["friction_force"] is None and same["u_x"] is None


def test_every_figure_is_written_with_the_units_convention(block, bar_runs,
                                                           tmp_path):
    problem, r = block
    bar, runs = bar_runs
    friction = solve_friction(problem, 0.3, steps=10)
    figures = {
        "ncp": tf.ncp_functions(path=tmp_path / "ncp.png"),
        "bc": tf.boundary_conditions_sketch(path=tmp_path / "bc.png"),
        "model": tf.model_problem(problem, path=tmp_path / "model.png"),
        "deformed": tf.deformed_and_directions(
            problem, r.displacement, r.in_contact, path=tmp_path / "d.png"),
        "convergence": tf.convergence({"min": r}, path=tmp_path / "c.png"),
        "pressure": tf.pressure_along_contact(problem, {"min": r},
                                              path=tmp_path / "p.png"),
        "meshes": tf.mesh_comparison({118: problem}, {118: r},
                                     path=tmp_path / "m.png"),
        "increment": tf.load_increment(runs[0.5], 45,
                                       path=tmp_path / "i.png"),
        "bar": tf.bar_sketch(bar, path=tmp_path / "bar.png"),
        "tractions": tf.tractions_along_contact(problem, friction,
                                                path=tmp_path / "t.png"),
        "ut": tf.tangential_displacement(
            problem, {"f_c = 0.3": (friction.tangential_displacement[-1],
                                    {})}, path=tmp_path / "ut.png"),
    }
    for name, fig in figures.items():
        assert units_of(fig) <= UNITS, (name, units_of(fig))
    pngs = sorted(tmp_path.glob("*.png"))
    assert len(pngs) == len(figures)
    for png in pngs:
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert png.stat().st_size < 400_000, png.name
    assert units_of(figures["pressure"]) == {"mm", "MPa"}
    assert units_of(figures["tractions"]) == {"mm", "MPa"}
