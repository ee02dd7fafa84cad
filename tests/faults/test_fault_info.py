"""``--info`` says what a solve would refuse (issue 16, class 8).

A problem can load (every key valid) and still be refused when a solve
starts: a floating body (no Dirichlet condition, K singular) or an
obstacle whose gaps cannot be found. ``python -m solver X.npz --info``
used to print its summary and exit 0 for both; now it runs the same
checks (:meth:`ContactProblem.refusals`: K positive definite, the gaps in
the ``--gap`` mode), prints the summary with a ``checks`` line and, when a
solve would refuse, the solve's own ``error:`` line, exit 2; ``--info
--json`` carries them as ``checks`` and ``refusals``. The reference for
each refusal is the solve itself: the same problem solved from the
command line must print the same error line.
"""

import json

import numpy as np
import pytest
import scipy.sparse as sp

from fault_tools import PLANE, run_cli, unit_cube, write
from fault_tools import block  # noqa: F401  (the fixture)
from solver.examples import two_dof_bar
from solver.problem import load_problem, save_problem

FLOATING = "K_data: K is not positive definite"
#: A body held by contact only with no load towards the obstacle (issue 31).
UNLOADED = "f: the body is held by contact only (6 rigid-body modes free)"


def floating_block(block):
    """The block's K with its smallest eigenvalue set to 0 (dense, 138
    DOFs): symmetric, positive diagonal, loads, but singular."""
    K = sp.csr_matrix((block["K_data"], block["K_indices"],
                       block["K_indptr"]),
                      shape=tuple(block["K_shape"])).toarray()
    w, V = np.linalg.eigh(K)
    w[0] = 0.0
    K = sp.csr_matrix((V * w) @ V.T)
    K = (K + K.T) / 2
    return dict(block, K_data=K.data, K_indices=K.indices,
                K_indptr=K.indptr)


def missed(block):
    """A horizontal line the body's normals run along: no gap."""
    return dict(block, obstacle_x=np.array("t"),
                obstacle_y=np.array("50 + 0*t"))


def floating_bar(tmp_path):
    bar = two_dof_bar()
    bar.K = sp.csr_matrix(9e4 * np.array([[1.0, -1.0], [-1.0, 1.0]]))
    return save_problem(tmp_path / "bar.npz", bar)


REFUSED = [
    ("3D floating body (no Dirichlet condition)",
     lambda b, tmp: write(tmp, unit_cube(supported=False)), [], [UNLOADED]),
    ("2D singular K", lambda b, tmp: write(tmp, floating_block(b)), [],
     [FLOATING]),
    ("discrete floating spring", lambda b, tmp: floating_bar(tmp), [],
     [FLOATING]),
    ("obstacle missed, gaps from the obstacle",
     lambda b, tmp: write(tmp, missed(b)), [], ["misses the obstacle"]),
    ("obstacle missed, gaps from the body",
     lambda b, tmp: write(tmp, missed(b)), ["--gap", "body"],
     ["misses the obstacle"]),
    ("3D gaps out of range",
     lambda b, tmp: write(tmp, unit_cube(obstacle={
         "kind": "graph", "z": "-1 + exp(100*x)"})), [],
     ["out of the supported range"]),
    ("singular K and obstacle missed",
     lambda b, tmp: write(tmp, missed(floating_block(b))), [],
     [FLOATING, "misses the obstacle"]),
]


@pytest.mark.parametrize("name, make, argv, phrases", REFUSED,
                         ids=[c[0] for c in REFUSED])
def test_info_says_what_the_solve_refuses(block, tmp_path, capsys, name,
                                          make, argv, phrases):
    path = make(block, tmp_path)
    before = sorted(p.name for p in tmp_path.iterdir())
    code, out, err = run_cli([path, "--info", *argv], capsys)
    assert code == 2, (code, err)
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert "Traceback" not in err and "internal error" not in err
    for phrase in phrases:
        assert phrase in lines[0], (phrase, err)
    assert "a solve would refuse this problem" in out
    assert out.startswith("problem kind")  # the summary is still printed

    code, out, json_err = run_cli([path, "--info", "--json", *argv], capsys)
    assert code == 2 and json_err == err
    info = json.loads(out)
    assert len(info["refusals"]) == len(phrases)
    assert "; ".join(info["refusals"]) == lines[0][len("error: "):]
    assert info["checks"][0].startswith("K positive ")  # or semidefinite

    # the solve refuses with one of them (the first it meets), in the
    # same words
    code, out, solve_err = run_cli([path, *argv, "-o", tmp_path / "out"],
                                   capsys)
    assert code == 2 and out == ""
    assert solve_err.startswith("error: ") and solve_err.endswith("\n")
    assert solve_err[len("error: "):-1] in info["refusals"], solve_err
    assert sorted(p.name for p in tmp_path.iterdir()) == before


@pytest.mark.parametrize("argv", [[], ["--gap", "body"]])
def test_info_of_a_solvable_problem(block, tmp_path, capsys, argv):
    """Exit 0, the checks named and passed, no refusal."""
    for arrays, nodes in ((block, 10), (unit_cube(), 9)):
        path = write(tmp_path, arrays)
        code, out, err = run_cli([path, "--info", *argv], capsys)
        assert code == 0 and err == "", err
        mode = argv[-1] if argv else "obstacle"
        assert out.splitlines()[-1] == (
            f"checks            K positive definite, gaps from the {mode} "
            f"at {nodes} contact nodes: passed")
        code, out, err = run_cli([path, "--info", "--json", *argv], capsys)
        assert code == 0
        info = json.loads(out)
        assert info["refusals"] == [] and len(info["checks"]) == 2


def test_refusals_api(block, tmp_path):
    """The library: refusals() of a good and of a floating problem;
    summary() checks only when asked (the factorisation costs)."""
    good = load_problem(write(tmp_path, block))
    assert good.refusals() == [] and good.refusals("body") == []
    assert "refusals" not in good.summary()
    floating = load_problem(write(tmp_path, unit_cube(supported=False),
                                  "floating.npz"))
    [reason] = floating.refusals()
    assert reason.startswith(UNLOADED) and "\n" not in reason
    info = floating.summary(check=True)
    assert info["refusals"] == [reason]
    assert info["checks"] == [
        "K positive semidefinite, its kernel the rigid-body modes",
        "gaps from the obstacle at 9 contact nodes"]
    assert info["obstacle"] == PLANE


def test_info_json_is_strict_for_huge_stiffness(block, tmp_path, capsys):
    """K × 1e200 (loads: the loader's norm is scaled) with a load inside
    the limit: ‖K‖_F in --info --json is a number, not Infinity (its
    squares overflowed)."""
    arrays = dict(block, K_data=block["K_data"] * 1e200,
                  f=block["f"] * 1e-170)
    code, out, err = run_cli([write(tmp_path, arrays), "--info", "--json"],
                             capsys)
    assert code == 0, err

    def refuse(name):
        raise AssertionError(f"{name} in --info --json")

    info = json.loads(out, parse_constant=refuse)
    K = sp.csr_matrix((block["K_data"], block["K_indices"],
                       block["K_indptr"]), shape=tuple(block["K_shape"]))
    assert info["K_norm_fro"] == pytest.approx(
        1e200 * sp.linalg.norm(K), rel=1e-12)
