"""Figures: each one is rendered to a PNG and checked for what it must show
— the magnification it states, the obstacle magnified with the body, the
non-negative pressure first, the zoom onto the contact zone, the step
halvings, the closed form on top, the nodes that carry friction and no
round-off drawn as data — and that no legend covers data or an axis label,
no two panels' labels and ticks collide and every axis has its unit."""

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
    figures.pyplot().close("all")


def _render(fig, tmp_path, name="figure.png"):
    """Save (which also lays out and draws) and return the file."""
    path = tmp_path / name
    figures.save_png(fig, path)
    assert path.stat().st_size > 10_000
    return path


def _data_points(ax):
    """Display coordinates of every drawn data point of ``ax``'s lines
    (horizontal reference lines excluded; points outside the axes' limits
    are clipped, not drawn)."""
    points = []
    for line in ax.lines:
        xy = np.column_stack([line.get_xdata(), line.get_ydata()])
        xy = xy[np.all(np.isfinite(xy.astype(float)), axis=1)]
        if len(xy) and line.get_transform() is ax.transData:
            points.append(ax.transData.transform(xy.astype(float)))
    if not points:
        return np.empty((0, 2))
    points = np.vstack(points)
    frame = ax.get_window_extent()
    shown = ((points[:, 0] >= frame.x0) & (points[:, 0] <= frame.x1)
             & (points[:, 1] >= frame.y0) & (points[:, 1] <= frame.y1))
    return points[shown]


def _legends(fig):
    """Every legend of ``fig``: of its axes, of the figure and of its
    subfigures."""
    found = [ax.get_legend() for ax in fig.axes] + list(fig.legends)
    for sub in fig.subfigs:
        found += _legends(sub)
    return [legend for legend in found if legend is not None]


def _assert_legends_clear_of_data(fig):
    for ax in fig.axes:
        for legend in _legends(fig):
            box = legend.get_window_extent()
            for other in fig.axes:
                pts = _data_points(other)
                inside = ((pts[:, 0] >= box.x0) & (pts[:, 0] <= box.x1)
                          & (pts[:, 1] >= box.y0) & (pts[:, 1] <= box.y1))
                assert not inside.any(), (
                    f"legend {legend.get_texts()[0].get_text()!r} covers "
                    f"{inside.sum()} data points")


def _assert_legends_clear_of_labels(fig):
    """No legend overlaps an axis label (the x label under a panel)."""
    renderer = fig.canvas.get_renderer()
    for legend in _legends(fig):
        box = legend.get_window_extent(renderer)
        for ax in fig.axes:
            for label in (ax.xaxis.label, ax.yaxis.label):
                if label.get_text():
                    other = label.get_window_extent(renderer)
                    assert not box.overlaps(other), (
                        f"legend covers the label {label.get_text()!r}")


def _assert_no_offset(fig):
    """No axis shows an additive offset (the "1e−29+1.4e−17" of round-off
    drawn as data); a power-of-ten multiplier is fine."""
    fig.canvas.draw()
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            formatter = axis.get_major_formatter()
            assert getattr(formatter, "offset", 0) == 0, \
                (ax.get_title(), formatter.get_offset())


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


def _line(ax, prefix):
    """The line of ``ax`` whose label starts with ``prefix``."""
    return next(line for line in ax.lines
                if line.get_label().startswith(prefix))


def _distance_to_polyline(points, polyline):
    """Distance of each point from the polyline (NaN rows break it),
    written out here: the nearest point of each segment, clamped."""
    best = np.full(len(points), np.inf)
    for piece in np.split(polyline, np.flatnonzero(
            np.isnan(polyline[:, 0]))):
        piece = piece[np.isfinite(piece[:, 0])]
        for a, b in zip(piece[:-1], piece[1:]):
            d = b - a
            t = np.clip((points - a) @ d / (d @ d), 0, 1)
            best = np.minimum(best, np.hypot(*(points - a - t[:, None]
                                               * d).T))
    return best


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
    stars = _line(body, "in contact")
    nodes = block.contact_nodes[r.in_contact]
    expected = block.nodes[nodes] + factor * r.displacement[nodes]
    assert np.allclose(np.column_stack(stars.get_data()), expected)
    texts = [t.get_text() for legend in _legends(fig)
             for t in legend.get_texts()]
    assert any("true position" in t for t in texts)
    assert any(f"moved with Γc × {factor - 1:g}" in t for t in texts)
    # beside it, Γc at true scale: contact nodes on the obstacle's side
    zoom = fig.axes[1]
    moved = _line(zoom, "Γc deformed")
    gc = block.contact_nodes
    assert np.allclose(np.column_stack(moved.get_data()),
                       block.nodes[gc] + r.displacement[gc])
    _assert_legends_clear_of_data(fig)
    _assert_legends_clear_of_labels(fig)
    _assert_panels_apart(fig)
    _assert_units(fig)


def test_deformed_figure_magnifies_the_gaps_with_the_body(block,
                                                          full_solves):
    """Drawn with the body at X + s·u, the moved obstacle keeps every gap
    at its true length: the distance of each magnified Γc node from the
    drawn obstacle equals the distance of the deformed node X + u from
    the true obstacle (sampled here from the problem's curve) to 2 %, and
    the nodes in contact lie on it. Left in place, the obstacle would be
    crossed by (s − 1) times each node's displacement towards it."""
    r = full_solves["min"]
    fig = figures.plot_deformed(block, r)
    body = fig.axes[0]
    drawn = np.column_stack(_line(body, "Γo moved").get_data())
    stars = np.column_stack(_line(body, "in contact").get_data())
    factor = float(re.search(r"× ([0-9.e+-]+)", body.get_title()).group(1))
    gc = block.contact_nodes
    magnified = block.nodes[gc] + factor * r.displacement[gc]
    deformed = block.nodes[gc] + r.displacement[gc]
    true = block.obstacle.point(np.linspace(-15, 15, 30001))
    true_gap = _distance_to_polyline(deformed, true)
    drawn_gap = _distance_to_polyline(magnified, drawn)
    size = np.ptp(block.nodes, axis=0).max()
    # equal up to the moved curve's change of shape over a gap's length
    assert np.all(np.abs(drawn_gap - true_gap) <= 0.02 * true_gap
                  + 1e-4 * size)
    assert _distance_to_polyline(stars, drawn).max() <= 1e-4 * size
    # the obstacle at its true position is drawn too, over the body
    true_drawn = np.column_stack(_line(body, "obstacle Γo, true").get_data())
    y = true_drawn[np.isfinite(true_drawn[:, 1]), 1]
    assert y.min() <= block.nodes[:, 1].min() and \
        y.max() >= block.nodes[:, 1].max()


@pytest.fixture(scope="module")
def symmetric_block():
    """The mirror-symmetric plane-strain block [−1, 1] × [0, 1] of
    tests/test_rollers.py, pressed onto the parabola y = −κx²: the
    obstacle is a graph over x, the body is wider than it is high, and
    its node on the symmetry line x = 0 carries the largest contact force
    but, by symmetry, no friction force and no u_x (both round-off)."""
    from test_rollers import block_2d

    return block_2d("whole")


def test_deformed_figure_draws_the_obstacle_over_the_body(symmetric_block,
                                                          tmp_path):
    """The obstacle spans the body's width (before: the parameter window
    was the body's y range, so x = t covered [−0.1, 1.1] of [−1, 1]), and
    no legend covers an axis label of a wide, flat body."""
    problem = symmetric_block
    r = solve_frictionless(problem)
    fig = figures.plot_deformed(problem, r)
    _render(fig, tmp_path)
    for prefix in ("obstacle Γo, true", "Γo moved"):
        x = _line(fig.axes[0], prefix).get_xdata()
        x = x[np.isfinite(x)]
        assert x.min() <= problem.nodes[:, 0].min()
        assert x.max() >= problem.nodes[:, 0].max()
    _assert_legends_clear_of_labels(fig)
    _assert_legends_clear_of_data(fig)
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


def test_pressure_figure_zooms_onto_the_contact_zone(block, full_solves,
                                                   tmp_path):
    """Four nodes in contact on a 20 mm Γc: the main panel shows the
    contact zone and its open neighbours, under half of Γc, and a panel
    below shows all of Γc (before: one panel over all 20 mm)."""
    r = full_solves["min"]
    fig = figures.plot_contact_pressure(block, r)
    _render(fig, tmp_path)
    assert len(fig.axes) == 2
    main, whole = fig.axes
    xy = block.nodes[block.contact_nodes]
    arc = np.r_[0, np.cumsum(np.hypot(*np.diff(xy, axis=0).T))]
    touching = arc[r.in_contact]
    low, high = main.get_xlim()
    assert low < touching.min() and touching.max() < high
    assert high - low < 0.5 * arc[-1]
    assert whole.get_xlim()[0] <= 0 and whole.get_xlim()[1] >= arc[-1]
    _assert_legends_clear_of_data(fig)
    _assert_panels_apart(fig)
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
    # the tractions zoom onto the contact zone, all of Γc below
    main, whole = fig.axes
    xy = block.nodes[block.contact_nodes]
    arc = np.r_[0, np.cumsum(np.hypot(*np.diff(xy, axis=0).T))]
    touching = arc[r.in_contact[-1]]
    low, high = main.get_xlim()
    assert low < touching.min() and touching.max() < high
    assert high - low < 0.5 * arc[-1] <= whole.get_xlim()[1]
    _assert_panels_apart(fig)


@pytest.fixture(scope="module")
def symmetric_friction(symmetric_block):
    r = solve_friction(symmetric_block, 0.3, steps=4)
    assert r.success
    return symmetric_block, r


def _friction_force(problem, r):
    """|D g_t| per step and node, D the row sums of M (written out here)."""
    return np.abs(np.asarray(problem.M.sum(axis=1)).ravel()
                  * r.friction_traction)


def test_history_follows_nodes_that_carry_friction(symmetric_friction,
                                                   tmp_path):
    """On the symmetric block the node of largest contact force is the
    one on the symmetry line, whose friction force is round-off (the
    figure followed it before). The history follows the node of largest
    friction force instead and draws its friction force. The two nodes
    that slip carry no friction force (the lagged bound of their first
    step in contact is 0), so no second node is added for contrast."""
    problem, r = symmetric_friction
    centre = int(np.argmax(r.contact_force[-1]))
    x = problem.nodes[problem.contact_nodes, 0]
    force = _friction_force(problem, r)
    assert x[centre] == 0 and force[:, centre].max() < 1e-12 * force.max()
    assert force[:, r.slip[-1]].max() < 1e-12 * force.max()
    chosen = friction_figures.history_nodes(problem, r)
    assert [n for n, _ in chosen] == [int(np.argmax(force.max(axis=0)))]
    fig = friction_figures.plot_step_history(problem, r)
    _render(fig, tmp_path)
    drawn = [line.get_ydata() for line in fig.axes[1].lines]
    assert max(np.abs(y).max() for y in drawn) == pytest.approx(force.max())
    _assert_no_offset(fig)
    _assert_legends_clear_of_data(fig)
    _assert_panels_apart(fig)
    _assert_units(fig)


def test_history_nodes_contrast_stick_and_slip():
    """The rule on a hand-made run of four nodes (M = I, so the friction
    force is g_t): node 3 has the largest contact force but only
    round-off friction; node 0 has the largest friction force and slips
    at the end; of the nodes that stick, node 2 has the larger friction
    force. The history follows 0, then 2; reversed states, 0 then the
    largest slipping node."""
    import scipy.sparse as sp

    problem = SimpleNamespace(n_contact=4, M=sp.identity(4, format="csr"))
    g = np.array([[0.0, 0.1, 0.2, 1e-15], [-1.0, 0.5, 0.8, -1e-15]])
    run = SimpleNamespace(
        friction_traction=g, contact_force=np.array([[1, 1, 1, 5.0]] * 2),
        slip=np.array([[0, 0, 0, 0], [1, 0, 0, 0]], bool),
        stick=np.array([[0, 0, 0, 0], [0, 1, 1, 1]], bool))
    chosen = friction_figures.history_nodes(problem, run)
    assert [n for n, _ in chosen] == [0, 2]
    assert "slips" in chosen[0][1] and "sticks" in chosen[1][1]
    run.slip, run.stick = (np.array([[0, 0, 0, 0], [0, 1, 1, 0]], bool),
                           np.array([[0, 0, 0, 0], [1, 0, 0, 1]], bool))
    assert [n for n, _ in friction_figures.history_nodes(problem, run)] \
        == [0, 2]
    run.friction_traction = np.zeros((2, 4))
    assert [n for n, _ in friction_figures.history_nodes(problem, run)] \
        == [3]


def test_history_of_round_off_says_so(symmetric_friction, tmp_path):
    """Asked for the symmetry-line node, the friction and u_x panels draw
    exact zeros and say that the values were round-off, and no axis
    carries an offset like "1e−29+1.4e−17"."""
    problem, r = symmetric_friction
    centre = int(np.argmax(r.contact_force[-1]))
    u_x = r.displacement[:, problem.contact_nodes[centre], 0]
    assert 0 < np.abs(u_x).max() < 1e-12 * np.abs(r.displacement).max()
    fig = friction_figures.plot_step_history(problem, r, node=centre)
    _render(fig, tmp_path)
    panels = {ax.get_title(): ax for ax in fig.axes}
    for title in ("Fig. 19: friction force", "Fig. 20: u_x"):
        ax = panels[title]
        assert np.all(ax.lines[0].get_ydata() == 0)
        assert any("round-off" in t.get_text() for t in ax.texts)
    assert not panels["Fig. 18: contact force"].texts
    _assert_no_offset(fig)


def test_history_in_3d_draws_the_friction_magnitude_and_u_z(tmp_path):
    """A 3D run: |t| = D |g_t| (g_t is a vector in the tangent plane) and
    u_x, u_y, u_z of nodes given by three coordinates."""
    from test_rollers import block_3d

    problem = block_3d("quarter", top=(0.02, 0.0, -0.05))
    r = solve_friction(problem, 0.3, steps=4, formulation="projection")
    assert r.success
    fig = friction_figures.plot_step_history(problem, r)
    _render(fig, tmp_path)
    labels = [ax.get_ylabel() for ax in fig.axes]
    assert labels[1].startswith("friction force |t|")
    assert labels[2:] == ["u_x [mm]", "u_y [mm]", "u_z [mm]"]
    chosen = friction_figures.history_nodes(problem, r)
    force = np.linalg.norm(r.friction_traction, axis=2) * np.asarray(
        problem.M.sum(axis=1)).ravel()
    assert np.allclose(fig.axes[1].lines[0].get_ydata(),
                       force[:, chosen[0][0]])
    assert re.search(r"\(([-0-9.e]+, ){2}[-0-9.e]+\) mm",
                     fig.legends[0].get_texts()[0].get_text()
                     if fig.legends else fig._suptitle.get_text())
    _assert_no_offset(fig)
    _assert_panels_apart(fig)
    _assert_units(fig)


# --- two bodies ------------------------------------------------------------

def test_two_body_figures_label_every_axis_with_its_unit(tmp_path):
    """bodies.png and interface.png: x and y labelled on every panel, in
    mm and MPa (before: no units, no labels on bodies.png)."""
    from tri_elasticity import stacked_blocks

    from solver import solve_two_body
    from solver.output import two_body

    problem, _, _ = stacked_blocks(n_upper=(4, 2), n_lower=(9, 3),
                                   materials=((1.0, 0.3), (3.0, 0.2)))
    r = solve_two_body(problem)
    for fig in (two_body.plot_bodies(problem, r),
                two_body.plot_interface(problem, r)):
        _render(fig, tmp_path)
        for ax in fig.axes:
            for text in (ax.get_xlabel(), ax.get_ylabel()):
                assert re.search(r"\[(mm|MPa)\]$", text), text
        _assert_units(fig)
        _assert_legends_clear_of_data(fig)
        _assert_panels_apart(fig)
