"""Figures: each one is rendered to a PNG and checked for what it must show
— the magnification it states, the non-negative pressure first, the step
halvings, the closed form on top — and that no legend covers data and no
two panels' labels and ticks collide."""

import re
from types import SimpleNamespace

import numpy as np
import pytest

from solver import load_problem, solve_friction, solve_frictionless
from solver.examples import two_dof_bar, two_dof_bar_closed_form
from solver.output import figures, friction_figures


@pytest.fixture(scope="module")
def block(exported):
    return load_problem(exported(454)[0])


@pytest.fixture(scope="module")
def full_solves(block):
    """The thesis's full system with both methods: φ_min's line search fails
    in one iteration, φ_FB halves its steps many times."""
    return {m: solve_frictionless(block, method=m, condense=False)
            for m in ("min", "fb")}


@pytest.fixture(autouse=True)
def close_figures():
    yield
    figures._pyplot().close("all")


def _render(fig, tmp_path, name="figure.png"):
    """Save (which also lays out and draws) and return the file."""
    path = tmp_path / name
    figures._save(fig, path)
    assert path.stat().st_size > 10_000
    return path


def _data_points(ax):
    """Display coordinates of every drawn data point of ``ax``'s lines
    (horizontal reference lines excluded)."""
    points = []
    for line in ax.lines:
        xy = np.column_stack([line.get_xdata(), line.get_ydata()])
        xy = xy[np.all(np.isfinite(xy.astype(float)), axis=1)]
        if len(xy) and line.get_transform() is ax.transData:
            points.append(ax.transData.transform(xy.astype(float)))
    return np.vstack(points) if points else np.empty((0, 2))


def _assert_legends_clear_of_data(fig):
    for ax in fig.axes:
        legends = [ax.get_legend()] + list(fig.legends)
        for legend in filter(None, legends):
            box = legend.get_window_extent()
            for other in fig.axes:
                pts = _data_points(other)
                inside = ((pts[:, 0] >= box.x0) & (pts[:, 0] <= box.x1)
                          & (pts[:, 1] >= box.y0) & (pts[:, 1] <= box.y1))
                assert not inside.any(), (
                    f"legend {legend.get_texts()[0].get_text()!r} covers "
                    f"{inside.sum()} data points")


def _assert_panels_apart(fig):
    """No two axes' tight boxes (frame, ticks, tick labels, axis labels,
    title) overlap."""
    renderer = fig.canvas.get_renderer()
    boxes = [ax.get_tightbbox(renderer) for ax in fig.axes]
    for i in range(len(boxes)):
        for j in range(i + 1, len(boxes)):
            a, b = boxes[i], boxes[j]
            overlap_x = min(a.x1, b.x1) - max(a.x0, b.x0)
            overlap_y = min(a.y1, b.y1) - max(a.y0, b.y0)
            assert min(overlap_x, overlap_y) <= 1.0, (i, j, a, b)


def _assert_units(fig):
    """Axis labels use the one convention (mm, N, MPa), not placeholders."""
    for ax in fig.axes:
        for text in (ax.get_xlabel(), ax.get_ylabel()):
            assert "[length]" not in text and "[force" not in text, text
            unit = re.search(r"\[(.*?)\]", text)
            if unit:
                assert unit.group(1) in ("mm", "N", "MPa"), text


# --- deformed shape --------------------------------------------------------

@pytest.mark.parametrize("largest", [1e-4, 3e-3, 0.37, 0.8, 1.9])
def test_magnification_shows_the_largest_displacement_at_5_to_20_percent(
        largest):
    body = SimpleNamespace(nodes=np.array([[-5.0, -10], [5, -10], [5, 10]]))
    u = np.array([[0.0, 0], [0, 0], [largest * 0.6, largest * 0.8]])
    scale = figures.magnification(body, u)
    mantissa = scale / 10 ** np.floor(np.log10(scale))
    assert round(mantissa, 9) in (1, 2, 5)
    assert 0.05 <= scale * largest / 20 <= 0.2


def test_magnification_never_shrinks_large_displacements():
    body = SimpleNamespace(nodes=np.array([[0.0, 0], [1, 1]]))
    assert figures.magnification(body, np.array([[0.0, 0], [0.5, 0]])) == 1
    assert figures.magnification(body, np.zeros((2, 2))) == 1


def test_deformed_figure_states_and_applies_its_factor(block, full_solves,
                                                       tmp_path):
    r = full_solves["min"]
    fig = figures.plot_deformed(block, r)
    _render(fig, tmp_path)
    body = fig.axes[0]
    factor = float(re.search(r"displacements × ([0-9.e+-]+)",
                             body.get_title()).group(1))
    size = np.ptp(block.nodes, axis=0).max()
    largest = np.hypot(*r.displacement.T).max()
    assert factor > 1
    assert 0.05 <= factor * largest / size <= 0.2
    # the starred contact nodes are drawn magnified by that factor
    stars = next(line for line in body.lines
                 if line.get_label().startswith("in contact"))
    nodes = block.contact_nodes[r.in_contact]
    expected = block.nodes[nodes] + factor * r.displacement[nodes]
    assert np.allclose(np.column_stack(stars.get_data()), expected)
    assert any("not magnified" in t.get_text()
               for t in body.get_legend().get_texts())
    # beside it, Γc at true scale: contact nodes on the obstacle's side
    zoom = fig.axes[1]
    moved = next(line for line in zoom.lines
                 if line.get_label().startswith("Γc deformed"))
    gc = block.contact_nodes
    assert np.allclose(np.column_stack(moved.get_data()),
                       block.nodes[gc] + r.displacement[gc])
    _assert_legends_clear_of_data(fig)
    _assert_panels_apart(fig)
    _assert_units(fig)


def test_displacement_arrows_figure(block, full_solves, tmp_path):
    fig = figures.plot_displacement_arrows(block, full_solves["fb"])
    _render(fig, tmp_path)
    _assert_panels_apart(fig)  # the colour bar beside the body
    _assert_units(fig)


# --- contact pressure ------------------------------------------------------

@pytest.mark.parametrize("method", ["min", "fb"])
def test_pressure_figure_leads_with_the_non_negative_nodal_pressure(
        block, full_solves, method, tmp_path):
    r = full_solves[method]
    fig = figures.plot_contact_pressure(block, r)
    _render(fig, tmp_path)
    ax = fig.axes[0]
    first = ax.lines[0]
    assert np.array_equal(first.get_ydata(), r.contact_pressure)
    p = first.get_ydata()
    assert (p >= -1e-12 * p.max()).all()  # ≥ 0 up to round-off
    assert "λ_i" in first.get_label()
    consistent = next(line for line in ax.lines
                      if line.get_label().startswith("M⁻¹λ"))
    assert np.array_equal(consistent.get_ydata(),
                          r.contact_pressure_consistent)
    assert consistent.get_ydata().min() < 0  # the wiggle it explains
    assert consistent.get_linewidth() < first.get_linewidth()
    assert "[MPa]" in ax.get_ylabel()
    assert ax.get_xlabel().startswith("arc length along Γc")
    _assert_legends_clear_of_data(fig)
    _assert_units(fig)


def test_pressure_figure_of_the_bar_says_what_its_values_are(bar_problem,
                                                           tmp_path):
    """A discrete problem has no lengths: no MPa claimed, and its consistent
    curve (M = I) is not said to dip below zero."""
    r = solve_frictionless(bar_problem)
    fig = figures.plot_contact_pressure(bar_problem, r)
    _render(fig, tmp_path)
    ax = fig.axes[0]
    assert ax.get_ylabel() == "λ_i / Σ_j M_ij"
    assert not any("below 0" in t.get_text()
                   for t in ax.get_legend().get_texts())


# --- convergence -----------------------------------------------------------

@pytest.mark.parametrize("method", ["min", "fb"])
def test_convergence_lower_panel_counts_step_halvings(full_solves, method,
                                                      tmp_path):
    r = full_solves[method]
    fig = figures.plot_convergence(r)
    _render(fig, tmp_path)
    top, bottom = fig.axes
    assert top.get_yscale() == "log"
    assert np.array_equal(bottom.lines[0].get_ydata(),
                          -np.log2(r.history["alpha"]))
    assert bottom.get_yscale() == "linear"
    _assert_legends_clear_of_data(fig)
    _assert_panels_apart(fig)


def test_convergence_marks_the_halvings_of_a_failed_line_search(
        full_solves, tmp_path):
    """φ_min records α = 1 for the full step it takes after its line search
    failed; the figure shows the ten halvings down to α_min = 2⁻¹⁰."""
    r = full_solves["min"]
    failed = np.flatnonzero(r.history["line_search_failed"])
    assert len(failed)  # this run has one; the test needs it
    fig = figures.plot_convergence(r)
    _render(fig, tmp_path)
    bottom = fig.axes[1]
    marks = next(line for line in bottom.lines
                 if line.get_label().startswith("line search failed"))
    assert np.array_equal(marks.get_xdata(), failed)
    assert np.array_equal(marks.get_ydata(), np.full(len(failed), 10.0))
    assert bottom.get_ylim()[1] > 10


def test_step_halvings_prefers_a_recorded_count():
    history = dict(alpha=[1.0, 0.25, 1.0, 0.0],
                   line_search_failed=[False, False, True, True],
                   halvings=[0, 2, 7, 60])
    taken, tried = figures.step_halvings(history, "min")
    assert np.array_equal(taken[:3], [0, 2, 0]) and np.isnan(taken[3])
    assert np.array_equal(tried[2:], [7, 60]) and np.isnan(tried[:2]).all()


# --- friction --------------------------------------------------------------

@pytest.mark.parametrize("fc", [10.0, 0.5])
def test_bar_history_draws_the_closed_form_over_hollow_markers(fc, tmp_path):
    bar = two_dof_bar()
    r = solve_friction(bar, fc, steps=100)
    exact = np.array([two_dof_bar_closed_form(k, fc) for k in range(1, 101)])
    fig = friction_figures.plot_step_history(bar, r, reference=exact)
    _render(fig, tmp_path)
    for ax in fig.axes:
        computed = next(line for line in ax.lines
                        if line.get_label() == "computed")
        closed = next(line for line in ax.lines
                      if line.get_label() == "closed form")
        assert closed.get_zorder() > computed.get_zorder()
        assert closed.get_linestyle() == "-"
        assert computed.get_markerfacecolor() == "none"
    assert len(fig.legends) == 1  # one legend for all panels, outside them
    _assert_legends_clear_of_data(fig)
    _assert_panels_apart(fig)
    _assert_units(fig)


def test_friction_figures_of_a_mesh(block, tmp_path):
    r = solve_friction(block, 0.3, steps=10, formulation="projection")
    paths = friction_figures.write_friction_figures(tmp_path, block, r)
    assert sorted(paths) == ["deformed", "friction_along_gc", "history"]
    for path in paths.values():
        assert (tmp_path / f"{path.rsplit('/', 1)[-1]}").stat().st_size > 1e4
    fig = figures.plot_deformed(block, SimpleNamespace(
        displacement=r.displacement[-1], in_contact=r.in_contact[-1]))
    _render(fig, tmp_path)
    factor = float(re.search(r"× ([0-9.e+-]+)",
                             fig.axes[0].get_title()).group(1))
    largest = np.hypot(*r.displacement[-1].T).max()
    assert 0.05 <= factor * largest / 20 <= 0.2
    fig = friction_figures.plot_friction_along_boundary(block, r)
    _render(fig, tmp_path, "along.png")
    _assert_legends_clear_of_data(fig)
    _assert_units(fig)
