"""Silent physics mistakes (issue 16, class 7).

An obstacle that already penetrates the undeformed body is warned about
(:class:`~solver.errors.InitialPenetrationWarning`, naming the nodes and
the depth), with and without friction. The gap search does not depend on
how fast the obstacle is parametrised: the thesis's parabola
x = 5.05 + 0.005 t², y = t (§4) run a hundred times slower, a hundred
times faster or shifted in t gives the same gaps and the same solution
from the command line, without options; the search interval can be set by
the problem file and by ``--search-interval``. Reference gaps are analytic
(along the normal (1, 0) of the edge x = 5 the gap of the parabola at
height y is 5.05 + 0.005 y² - 5).
"""

import warnings

import numpy as np
import pytest

from fault_tools import run_cli
from solver.contact import contact_geometry
from solver.errors import InitialPenetrationWarning
from solver.geometry.curves import GapError
from solver.problem import load_problem, save_problem


@pytest.fixture(scope="module")
def block(exported):
    with np.load(exported(118)[0], allow_pickle=False) as archive:
        return {k: archive[k] for k in archive.files}


def with_obstacle(block, tmp_path, x, y="t", name="p.npz", **extra):
    path = tmp_path / name
    np.savez(path, **dict(block, obstacle_x=np.array(x),
                          obstacle_y=np.array(y), **extra))
    return path


def free_contact_y(problem):
    free = (problem.contact_dofs >= 0).all(axis=1)
    ids = problem.contact_nodes[free]
    return ids, problem.nodes[ids, 1]


def test_initial_penetration_is_warned_naming_nodes_and_depth(block,
                                                              tmp_path):
    """x = 4.9 + 0.005 t²: the nodes with |y| < √20 lie 0.1 - 0.005 y²
    past the obstacle."""
    problem = load_problem(with_obstacle(block, tmp_path,
                                         "4.9 + 0.005*t**2"))
    ids, y = free_contact_y(problem)
    depth = 0.1 - 0.005 * y ** 2
    inside = ids[depth > 0]
    deepest = ids[np.argmax(depth)]
    with pytest.warns(InitialPenetrationWarning) as record:
        geometry = contact_geometry(problem, "body")
    message = str(record[0].message)
    assert "\n" not in message
    assert f"at {len(inside)} contact nodes" in message
    assert f"deepest {depth.max():.3g} at node {deepest}" in message
    assert str(inside[0]) in message
    np.testing.assert_allclose(geometry.gap, -depth, atol=1e-13)


def test_penetration_is_warned_before_a_friction_run(block, tmp_path,
                                                     capsys):
    """The command line shows the warning as one ``warning:`` line."""
    path = with_obstacle(block, tmp_path, "4.95 + 0.005*t**2")
    code, out, err = run_cli([path, "--friction", "0.3", "--steps", "2",
                              "-o", tmp_path / "out"], capsys)
    warned = [line for line in err.splitlines()
              if line.startswith("warning: ")]
    assert len(warned) == 1 and "penetrates" in warned[0], err
    assert "Traceback" not in err and "warnings.warn" not in err


def test_touching_is_not_penetration(block, tmp_path):
    """x = 5 + 0.005 t² touches the node at y = 0 (gap 0, not < 0)."""
    problem = load_problem(with_obstacle(block, tmp_path,
                                         "5 + 0.005*t**2"))
    _, y = free_contact_y(problem)
    assert np.isclose(y, 0).any()
    with warnings.catch_warnings():
        warnings.simplefilter("error", InitialPenetrationWarning)
        for mode in ("obstacle", "body"):
            gap = contact_geometry(problem, mode).gap
            assert gap.min() == pytest.approx(0.0, abs=1e-14)


PARAMETRISATIONS = [
    ("thesis", "5.05 + 0.005*t**2", "t"),
    ("slow t/100", "5.05 + 0.005*(t/100)**2", "t/100"),
    ("fast 100 t", "5.05 + 0.005*(100*t)**2", "100*t"),
    ("shifted t - 1000", "5.05 + 0.005*(t - 1000)**2", "t - 1000"),
    ("slow t/1e6", "5.05 + 0.005*(t/1e6)**2", "t/1e6"),
]


@pytest.mark.parametrize("mode", ["obstacle", "body"])
@pytest.mark.parametrize("name, x, y", PARAMETRISATIONS,
                         ids=[p[0] for p in PARAMETRISATIONS])
def test_gaps_do_not_depend_on_the_parametrisation(block, tmp_path, mode,
                                                   name, x, y):
    problem = load_problem(with_obstacle(block, tmp_path, x, y))
    geometry = contact_geometry(problem, mode)
    _, ys = free_contact_y(problem)
    if mode == "body":  # analytic
        np.testing.assert_allclose(geometry.gap, 0.05 + 0.005 * ys ** 2,
                                   atol=1e-12)
    reference = contact_geometry(load_problem(with_obstacle(
        block, tmp_path, *PARAMETRISATIONS[0][1:], name="ref.npz")), mode)
    np.testing.assert_allclose(geometry.gap, reference.gap, atol=1e-12)
    np.testing.assert_allclose(geometry.normal, reference.normal,
                               atol=1e-10)


def test_slow_parabola_from_the_command_line(block, tmp_path, capsys):
    """The issue's case: t -> t/100 solves from the CLI without options and
    gives the thesis parabola's solution."""
    results = []
    for name, x, y in PARAMETRISATIONS[:2]:
        path = with_obstacle(block, tmp_path, x, y, name=f"{name[:4]}.npz")
        code, out, err = run_cli([path, "-o", tmp_path / name[:4]], capsys)
        assert code == 0, err
        with np.load(tmp_path / name[:4] / "result.npz") as result:
            results.append(result["u"])
    np.testing.assert_allclose(results[1], results[0], rtol=1e-9,
                               atol=1e-9 * np.abs(results[0]).max())


def test_search_interval_from_the_file_and_the_cli(block, tmp_path, capsys):
    """[-5, 5] holds the feet of the nodes with |y| <= 5 only: the file's
    interval is used (and refused clearly); the CLI's overrides it."""
    path = with_obstacle(block, tmp_path, "5.05 + 0.005*t**2",
                         obstacle_search_interval=np.array([-5.0, 5.0]))
    problem = load_problem(path)
    assert problem.obstacle.search_interval == (-5.0, 5.0)
    again = load_problem(save_problem(tmp_path / "again.npz", problem))
    assert again.obstacle.search_interval == (-5.0, 5.0)
    with pytest.raises(GapError, match="larger search interval"):
        contact_geometry(problem)
    code, out, err = run_cli([path, "-o", tmp_path / "a"], capsys)
    assert code == 2 and "larger search interval" in err
    code, out, err = run_cli([path, "-o", tmp_path / "b",
                              "--search-interval", "-50", "50"], capsys)
    assert code == 0, err
