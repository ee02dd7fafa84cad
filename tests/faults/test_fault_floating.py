"""Loads that no contact can hold on a body held by contact only (issue
31): one ``error:`` line naming the rigid-body motion and the load's
component along it, exit code 2, nothing written (no output that looks
like a solution). Reference: Farkas' lemma, statics of the rigid block
(components: the 2 × 1 block's area 2 times the load per unit area, or
the unit corner force; with friction f_c = 0.5 the Coulomb cone: the
tangential load 1.2 beyond f_c times the normal load 2, whose share
along the sliding-and-lifting motion (0.894, 0.447) no cone holds,
1.2·0.894 − 2·0.447 = 0.1789)."""

import numpy as np
import pytest

from fault_tools import assert_one_error_line, run_cli
from solver.problem import save_problem
from tri_elasticity import floor_block

CASES = [
    ("pulled away from the floor", dict(load=(0.0, 1.0)),
     [], "component 2 along the rigid-body motion translation (0, 1)"),
    ("frictionless flat on flat pushed sideways",
     dict(load=(1.0, -1.0), where="corner"), [],
     "component 1 along the rigid-body motion translation (1, 0)"),
    ("no load towards the floor", dict(load=(0.0, 0.0)), [],
     "the load has no resultant along them"),
    ("tangential load beyond f_c times the normal load",
     dict(load=(0.6, -1.0)), ["--friction", "0.5"],
     "component 0.178885 along the rigid-body motion translation "
     "(0.894, 0.447) that contact with friction f_c = 0.5 cannot resist"),
    ("tangential load in the lagged bound's frictionless first step",
     dict(load=(0.1, -1.0), where="corner"), ["--friction", "0.5"],
     "translation (1, 0) that no contact resists (--coulomb lagged bounds "
     "the first load step's friction"),
    ("thesis formulation", dict(), ["--friction", "0.5", "--formulation",
                                    "thesis"],
     "--formulation thesis is not supported"),
    ("pulled away, on the full system", dict(load=(0.0, 1.0)),
     ["--system", "full"],
     "component 2 along the rigid-body motion translation (0, 1)"),
    ("pushed sideways, on the full system",
     dict(load=(1.0, -1.0), where="corner"), ["--system", "full"],
     "component 1 along the rigid-body motion translation (1, 0)"),
    ("tangential load beyond f_c times the normal load, full system",
     dict(load=(0.6, -1.0)), ["--friction", "0.5", "--system", "full"],
     "component 0.178885 along the rigid-body motion translation "
     "(0.894, 0.447) that contact with friction f_c = 0.5 cannot resist"),
    ("thesis formulation on the full system", dict(),
     ["--friction", "0.5", "--formulation", "thesis", "--system", "full"],
     "--formulation thesis is not supported"),
]


@pytest.mark.parametrize("name, block, argv, phrase", CASES,
                         ids=[c[0] for c in CASES])
def test_unheld_load_is_refused(tmp_path, capsys, name, block, argv,
                                phrase):
    path = save_problem(tmp_path / "p.npz", floor_block(**block))
    before = sorted(p.name for p in tmp_path.iterdir())
    code, out, err = run_cli([path, *argv, "-o", tmp_path / "out"], capsys)
    assert_one_error_line(code, out, err, phrase)
    assert out == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == before


def test_info_names_the_same_refusal(tmp_path, capsys):
    """``--info`` says what the solve would refuse, in the same words."""
    path = save_problem(tmp_path / "p.npz", floor_block(load=(0.0, 1.0)))
    code, out, err = run_cli([path, "--info"], capsys)
    assert code == 2 and "translation (0, 1)" in err
    assert "a solve would refuse this problem" in out


def test_a_held_block_solves_from_the_command_line(tmp_path, capsys):
    """The same block under its weight: exit 0, the total contact force
    (the weight, 2 for the 2 × 1 block under a unit load per area) and the
    rigid-body motion in the printout and in summary.json."""
    import json

    path = save_problem(tmp_path / "p.npz", floor_block())
    code, out, err = run_cli([path, "-o", tmp_path / "out"], capsys)
    assert code == 0, err
    assert "contact force     (0, 2) in total, on the body" in out
    assert "3 modes held by contact only" in out
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    np.testing.assert_allclose(summary["total_contact_force"], [0.0, 2.0],
                               rtol=0, atol=1e-12)
    assert summary["rigid_body_motion"]["modes"] == 3


#: The refusals that the petsc engine meets at other places than the
#: serial one: the frictionless check after MUMPS has factorised K_F
#: (solver/contact/strategies/floating.py), the friction cones in the
#: front, and its own rule for the full system.
PETSC_CASES = [CASES[0], CASES[3],
               ("full system on the petsc engine", dict(),
                ["--system", "full"], "--system full is not supported "
                "for 2D, rigid, held by contact only, frictionless, petsc "
                "engine")]


@pytest.mark.parametrize("name, block, argv, phrase", PETSC_CASES,
                         ids=[c[0] for c in PETSC_CASES])
def test_unheld_load_is_refused_on_the_petsc_engine(tmp_path, name, block,
                                                    argv, phrase):
    """``mpiexec -n 2 python -m solver X --engine petsc``: the serial
    engine's line and exit code 2, from rank 0 only, nothing written."""
    from test_mpi import REASON, mpirun

    if REASON is not None:
        pytest.skip(str(REASON))
    path = save_problem(tmp_path / "p.npz", floor_block(**block))
    before = sorted(p.name for p in tmp_path.iterdir())
    code, out, err = mpirun(2, ["-m", "solver", path, "--engine", "petsc",
                                *argv, "-o", tmp_path / "out"])
    lines = [ln for ln in err.splitlines() if ln.startswith("error")]
    assert code == 2 and len(lines) == 1, err
    assert phrase in lines[0] and "Traceback" not in err, (phrase, err)
    assert out == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == before


def test_info_says_friction_would_hold_it(tmp_path, capsys):
    """A tangential load that frictionless contact cannot hold but
    friction can: ``--info`` says so and names the least f_c, in the
    command line's words: the 2 × 1 block under (0.2, −1) per unit area
    needs f_c ≥ 0.2 (statics: 0.4 sideways on 2 downwards), and, loaded
    in proportion, the implicit bound."""
    path = save_problem(tmp_path / "p.npz", floor_block(load=(0.2, -1.0)))
    code, out, err = run_cli([path, "--info"], capsys)
    assert code == 2 and err.count("\n") == 1
    assert ("component 0.4 along the rigid-body motion translation (1, 0) "
            "that frictionless contact cannot resist; it needs friction: "
            "--friction F with F ≥ 0.2 (") in err
    assert "and --coulomb implicit (" in err
    assert "friction=" not in err and "coulomb='" not in err


def test_lagged_step_message_names_the_flags(tmp_path, capsys):
    """A load step that the lagged bound cannot hold (step 3: 0.8 of
    friction needed, 0.75 allowed by step 2's pressure) ends the run
    (exit 3) with a line naming --coulomb, not solve()'s coulomb=."""
    from solver.cli.codes import EXIT_NOT_CONVERGED
    from tri_elasticity import floor_block_beyond_lagged

    path = save_problem(tmp_path / "p.npz", floor_block_beyond_lagged())
    code, out, err = run_cli([path, "--friction", "0.5", "-o",
                              tmp_path / "out"], capsys)
    assert code == EXIT_NOT_CONVERGED
    line = [x for x in err.splitlines() if x.startswith("error:")]
    assert len(line) == 1, err
    assert "load step 3 of 3 has no answer" in line[0]
    assert "(--coulomb lagged bounds the friction by it)" in line[0]
    assert "or use --coulomb implicit" in line[0]
    assert "coulomb='" not in line[0]


def test_a_held_block_solves_on_the_full_system(tmp_path, capsys):
    """``--system full`` on the same block: exit 0, the weight as the
    total contact force, the system named as such."""
    path = save_problem(tmp_path / "p.npz", floor_block())
    code, out, err = run_cli([path, "--system", "full", "-o",
                              tmp_path / "out"], capsys)
    assert code == 0, err
    assert "contact force     (0, 2) in total, on the body" in out
    assert "full (in all unknowns; the DOFs that hold the rigid-body " \
        "modes replaced by the modes' amplitudes)" in out
