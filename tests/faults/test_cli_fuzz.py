"""Hypothesis fuzzing of the command-line arguments (issue 16).

Any argument list ends with a documented exit code and never a traceback:
0 (solved or --info), 2 (usage or bad input), 3 (not converged). A run that
writes stays inside its own scratch folder; a refused one writes nothing.
"""

import os

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from solver.cli import main

OPTIONS = {
    "--method": st.sampled_from(["min", "fb", "newton", ""]),
    "--gap": st.sampled_from(["obstacle", "body", "x"]),
    "--tol": st.sampled_from(["1e-10", "1e-300", "0", "-1", "nan", "inf",
                              "1e-8", "abc", "0.5", "1e-15"]),
    "--max-iter": st.sampled_from(["1", "3", "0", "-5", "10**30",
                                   "1000000000", "1.5", "100"]),
    "--steps": st.sampled_from(["1", "2", "0", "10**30", "1000000000", "x"]),
    "--friction": st.sampled_from(["0", "0.3", "-1", "inf", "nan", "1e400"]),
    "--system": st.sampled_from(["auto", "condensed", "full", "other"]),
    "--start": st.sampled_from(["nested", "free", "cold"]),
    "--formulation": st.sampled_from(["thesis", "projection", "?"]),
    "--coulomb": st.sampled_from(["lagged", "implicit", ""]),
    "--gap-scale": st.sampled_from(["1", "0", "-1", "1e300", "nan"]),
    "--linear-solver": st.sampled_from(["auto", "superlu", "umfpack"]),
    "--search-interval": st.sampled_from(["-30 30", "1 0", "nan 1",
                                          "-1e300 1e300"]),
}
FLAGS = ["--info", "--json", "--plots", "-v", "--version", "--help"]


@st.composite
def argument_lists(draw):
    argv = []
    for name in draw(st.lists(st.sampled_from(sorted(OPTIONS)),
                              max_size=5, unique=True)):
        argv += [name, *draw(OPTIONS[name]).split(" ")]
    argv += draw(st.lists(st.sampled_from(FLAGS), max_size=2, unique=True))
    return draw(st.permutations(argv))


@pytest.fixture(scope="module")
def block(exported):
    return str(exported(118)[0])


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(argv=argument_lists())
def test_any_arguments_end_with_a_documented_code(block, tmp_path_factory,
                                                  capsys, argv):
    out = tmp_path_factory.mktemp("fuzz") / "out"
    try:
        code = main([block, *argv, "-o", str(out)])
    except SystemExit as exc:  # argparse: --help, --version, usage errors
        code = exc.code
    captured = capsys.readouterr()
    assert code in (0, 2, 3), (argv, code, captured.err)
    assert "Traceback" not in captured.err
    if code == 2:
        assert not os.path.exists(out) or not os.listdir(out), argv
        lines = captured.err.strip().splitlines()
        assert lines and "error" in lines[-1], (argv, captured.err)
