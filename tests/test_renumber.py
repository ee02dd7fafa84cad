"""The nodes renumbered for the partitioned folder (issue 33, point 4;
solver/problem/renumber.py, ``python -m solver convert X.npz DIR
--renumber``): a gmsh numbering spreads every node range over the whole
body, so each rank's rows of K couple to almost all of the others'; the
reverse Cuthill–McKee order makes the ranges compact.

References: the serial engine's ``solver.solve`` on the original problem
(a permutation of the nodes changes nothing of the answer: u of new node
k is u of original node ``order[k]``); the cells' nodes themselves for the
share of the cells across two ranges. PETSc runs only in the mpiexec
subprocess."""

import json

import numpy as np
import pytest

from solver import solve
from solver.cli import main
from solver.mpi.convert import CUT_WARN
from solver.problem.renumber import cut_cells, renumbered
from test_mpi import REASON
from test_mpi_distributed import read_pvtu
from test_mpi_partitioned_full import run_full

RTOL = 1e-8


@pytest.fixture(scope="module")
def block(refined_block):
    """(problem, its serial result): the 1878 block refined once (7668
    DOFs), SfePy's export of a gmsh mesh."""
    problem = refined_block(1)
    result = solve(problem)
    assert result.success
    return problem, result


def halves(n):
    return np.array([0, n // 2, n])


def test_renumbered_problem_same_answer_compact_ranges(block):
    """The same u and contact set at every node (by the permutation), and
    the share of the cells whose nodes lie in both halves of the
    numbering from the gmsh numbering's to below the converter's note."""
    problem, result = block
    other, order = renumbered(problem)
    assert np.array_equal(np.sort(order), np.arange(len(problem.nodes)))
    assert np.array_equal(other.nodes, problem.nodes[order])
    n = len(problem.nodes)
    before = cut_cells(problem.cells, halves(n))
    after = cut_cells(other.cells, halves(n))
    assert before > 0.2 and after < CUT_WARN, (before, after)
    again = solve(other)
    assert again.success
    ref = result.displacement
    assert np.abs(again.displacement - ref[order]).max() <= \
        1e-10 * np.abs(ref).max()
    assert np.array_equal(np.sort(order[other.contact_nodes[
        again.in_contact]]), np.sort(problem.contact_nodes[
            result.in_contact]))


def test_cut_cells_counts_cells_across_ranges():
    """Three triangles on nodes 0..5, ranges [0, 3), [3, 6): one cell in
    the first, one in the second, one across."""
    cells = np.array([[0, 1, 2], [3, 4, 5], [2, 3, 4]])
    assert cut_cells(cells, np.array([0, 3, 6])) == pytest.approx(1 / 3)
    assert cut_cells(cells, np.array([0, 6])) == 0.0


@pytest.mark.skipif(REASON is not None, reason=str(REASON))
def test_renumbered_folder_on_two_ranks(block, tmp_path, capsys):
    """The converter's default (renumbered, streamed), then the folder's
    full system by CG + GAMG on 2 ranks: u at every node and the nodes in
    contact as the serial engine's in the .npz's numbering (node_ids.npy
    maps the outputs back); --no-renumber prints the note, the default
    does not."""
    from solver import save_problem

    problem, result = block
    npz = save_problem(tmp_path / "b.npz", problem)
    assert main(["convert", str(npz), str(tmp_path / "plain"),
                 "--no-renumber"]) == 0
    assert "--no-renumber" in capsys.readouterr().out
    folder = tmp_path / "ren"
    assert main(["convert", str(npz), str(folder)]) == 0
    out = capsys.readouterr().out
    assert "renumbered" in out and "note" not in out
    meta = json.loads((folder / "problem.json").read_text())
    assert meta["renumbered"] and meta["cut_cells"] < CUT_WARN
    assert meta["streamed"]
    summary = run_full(folder, tmp_path / "o", 2)
    n_nodes, dim = problem.nodes.shape
    u, cells = read_pvtu(tmp_path / "o" / "result.pvtu", n_nodes, dim)
    ref = result.displacement
    assert np.abs(u - ref).max() <= RTOL * np.abs(ref).max()
    assert cells == len(problem.cells)
    with np.load(tmp_path / "o" / "contact.npz") as contact:
        touching = np.sort(contact["node"][contact["in_contact"]])
    assert np.array_equal(touching, np.sort(
        problem.contact_nodes[result.in_contact]))
    assert summary["verification"]["passed"]
