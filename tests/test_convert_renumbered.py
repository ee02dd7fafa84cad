"""The converter's default: the nodes renumbered, streamed (issue 33, point
4; solver/mpi/convert.py ``_RenumberedK``): the order comes from the
cells, and K is written in it by an external bucket sort, never held.

Reference: the whole-load renumbering of the same problem
(``solver.problem.renumber.renumbered``: SciPy's fancy indexing of the
whole K, then ``Layout.matrix``, another code path), whose folder must
come out byte for byte the same; ``--no-renumber`` against the whole-load
conversion in the file's order, as before the default changed (a full
disk and signals during the bucket pass: tests/faults/test_fault_convert.py).
No PETSc here (the 2-rank run on the default folder is tests/test_renumber.py's)."""

import json
import os

import numpy as np
import pytest

from solver import load_problem, save_problem
from solver.mpi import convert as conversion
from solver.problem.renumber import cut_cells


def listing(folder):
    """{relative path: bytes} of every file under ``folder`` but
    problem.json (its ``source`` and ``streamed`` differ)."""
    out = {}
    for root, _, names in os.walk(folder):
        for name in names:
            path = os.path.join(root, name)
            rel = os.path.relpath(path, folder)
            if rel != "problem.json":
                with open(path, "rb") as stream:
                    out[rel] = stream.read()
    return out


def meta_of(folder):
    meta = json.loads((folder / "problem.json").read_text())
    for key in ("source", "streamed"):
        meta.pop(key)
    return meta


@pytest.fixture(scope="module")
def files(refined_block, tmp_path_factory):
    """(compressed .npz, the same arrays by np.savez) of the 1878 block
    refined once (7668 DOFs; SfePy's export of a gmsh mesh, whose node
    ranges are spread over the body)."""
    root = tmp_path_factory.mktemp("renumbered")
    compressed = save_problem(root / "r1.npz", refined_block(1))
    plain = root / "plain.npz"
    with np.load(compressed) as data:
        np.savez(plain, **data)
    return compressed, plain


@pytest.fixture(scope="module")
def whole(files, tmp_path_factory):
    """The whole-load renumbered folder (the reference)."""
    folder = tmp_path_factory.mktemp("whole") / "w"
    meta = conversion.convert(load_problem(files[0]), folder)
    assert meta["renumbered"] and not meta["streamed"]
    return folder


@pytest.mark.parametrize("block", [1 << 23, 997])
@pytest.mark.parametrize("kind", ["stored", "compressed"])
def test_streamed_renumbered_folder_equals_the_whole_load(
        files, whole, tmp_path, monkeypatch, capsys, block, kind):
    """Byte for byte the whole-load renumbered folder, from np.savez's
    file (K mapped) and np.savez_compressed's (decompressed in order), in
    one bucket and in buckets of ≈ 997 entries (about 60, rows cut
    anywhere, Dirichlet rows between); no temporary file left."""
    compressed, plain = files
    monkeypatch.setattr(conversion, "BLOCK_NNZ", block)
    out = tmp_path / kind
    meta = conversion.convert(str(plain if kind == "stored" else
                                  compressed), out)
    assert capsys.readouterr().err == ""
    assert meta["streamed"] and meta["renumbered"]
    assert meta["node_order"] == "reverse Cuthill-McKee"
    assert meta_of(out) == meta_of(whole)
    mine, reference = listing(out), listing(whole)
    assert sorted(mine) == sorted(reference)  # no bucket left behind
    for name in reference:
        assert mine[name] == reference[name], name
    n = meta["n_nodes"]
    assert meta["cut_cells"] < conversion.CUT_WARN
    ids = np.load(out / "node_ids.npy")
    assert np.array_equal(np.sort(ids), np.arange(n))


def test_no_renumber_keeps_the_files_order(files, tmp_path, capsys):
    """``--no-renumber``: the folder the converter wrote before the
    default changed (the whole-load conversion in the file's order), no
    node_ids.npy, problem.json saying so, and the command line's note on
    the cells across the halves of the numbering (75 % here)."""
    from solver.cli import main

    compressed, plain = files
    reference = tmp_path / "ref"
    conversion.convert(load_problem(compressed), reference, renumber=False)
    out = tmp_path / "plain"
    assert main(["convert", str(plain), str(out), "--no-renumber"]) == 0
    printed = capsys.readouterr().out
    assert "note:" in printed and "renumbered" not in printed
    meta = json.loads((out / "problem.json").read_text())
    assert not meta["renumbered"] and meta["node_order"] == "file"
    assert meta["streamed"] and meta["cut_cells"] > conversion.CUT_WARN
    assert meta_of(out) == meta_of(reference)
    assert listing(out) == listing(reference)
    assert not (out / "node_ids.npy").exists()
    # the default, into the same folder: renumbered, node_ids.npy back
    assert main(["convert", str(plain), str(out)]) == 0
    printed = capsys.readouterr().out
    assert "renumbered" in printed and "note:" not in printed
    assert (out / "node_ids.npy").exists()
    cells = np.load(out / "cells.npy")
    assert cut_cells(cells, np.array([0, meta["n_nodes"] // 2,
                                      meta["n_nodes"]])) < 0.05


def test_buckets_capped_by_the_open_files(files, whole, tmp_path,
                                         monkeypatch):
    """More buckets than files may be open (16 here, with blocks of 97
    entries: ≈ 1,000 wanted): larger buckets, the same folder."""
    monkeypatch.setattr(conversion, "BLOCK_NNZ", 97)
    monkeypatch.setattr(conversion, "_open_files", lambda: 16)
    conversion.convert(str(files[1]), tmp_path / "c")
    assert listing(tmp_path / "c") == listing(whole)
