"""The converter without the whole problem in memory (issue 33, point 4;
solver/mpi/convert.py): K is checked, padded and written by blocks of
rows, memory-mapped from an uncompressed ``.npz`` (np.savez) and
decompressed in order from a compressed one (np.savez_compressed, what
save_problem and the SfePy export write); a K whose rows the blocks cannot
copy as they are is converted from the whole load, with one line saying so.

Reference: the whole-load conversion of the same problem (Layout.matrix,
another code path), whose files must come out byte for byte the same;
NumPy's own np.load for the mapped and decompressed members. No PETSc
here."""

import json

import numpy as np
import pytest
import scipy.sparse as sp

from solver import load_problem, save_problem
from solver.errors import ProblemError
from solver.mpi import convert as conversion
from solver.problem.partitioned import CONTACT_KEYS, load_contact_slice

FILES = ("K.petsc", "f.petsc", "nodes.npy", "cells.npy", "contact.npz")


@pytest.fixture(scope="module")
def files(exported, tmp_path_factory):
    """(compressed .npz, the same arrays by np.savez) of the 454 block."""
    root = tmp_path_factory.mktemp("streamed")
    compressed = root / "b454.npz"
    save_problem(compressed, load_problem(exported(454)[0]))
    plain = root / "plain.npz"
    with np.load(compressed) as data:
        np.savez(plain, **data)
    return compressed, plain


def test_members_mapped_as_numpy_reads_them(files):
    compressed, plain = files
    assert conversion.stored_members(compressed) is None
    arrays, mapped = conversion.stored_members(plain)
    with np.load(plain) as data:
        assert sorted(arrays) == sorted(data.files)
        for key in data.files:
            assert np.array_equal(arrays[key], data[key]), key
    # K's entries stay in the file's mapping; the O(n) members are read
    assert not arrays["K_data"].flags.owndata
    assert not arrays["K_indices"].flags.owndata
    assert arrays["f"].flags.owndata


def test_compressed_members_read_in_order_as_numpy_reads_them(files):
    """K's members of a compressed file come out by slices, forwards and
    after a restart (a slice behind what was read); the others whole."""
    compressed, _ = files
    arrays, mapped = conversion.compressed_members(compressed)
    assert mapped is None
    with np.load(compressed) as data:
        for key in ("f", "K_indptr", "nodes"):
            assert np.array_equal(arrays[key], data[key]), key
        for key in ("K_indices", "K_data"):
            member, whole = arrays[key], data[key]
            assert len(member) == len(whole)
            for a, b in ((0, 5), (5, 900), (1000, len(whole)), (3, 40)):
                assert np.array_equal(member[a:b], whole[a:b]), (key, a, b)
            member.close()


@pytest.mark.parametrize("block", [1 << 23, 97])
def test_streamed_files_equal_the_whole_load(files, tmp_path, monkeypatch,
                                             capsys, block):
    """Byte for byte the files of the whole load, from the uncompressed
    and the compressed file, in one block and in blocks of 97 entries
    (rows cut anywhere, Dirichlet rows between); in the file's order (the
    renumbered default: tests/test_convert_renumbered.py)."""
    compressed, plain = files
    monkeypatch.setattr(conversion, "BLOCK_NNZ", block)
    whole = conversion.convert(load_problem(compressed), tmp_path / "whole",
                               renumber=False)
    assert not whole.pop("streamed")
    whole.pop("source")
    for name, source in (("plain", plain), ("deflated", compressed)):
        streamed = conversion.convert(str(source), tmp_path / name,
                                      renumber=False)
        assert capsys.readouterr().err == ""
        assert streamed.pop("streamed")
        streamed.pop("source")
        assert whole == streamed
        for file in FILES:
            assert (tmp_path / "whole" / file).read_bytes() == \
                (tmp_path / name / file).read_bytes(), (name, file)
        assert json.loads((tmp_path / name / "problem.json").read_text(
        ))["streamed"] is True


def test_contact_slices_by_node(files, tmp_path):
    """``contact/`` sorted by node: the slices of two node ranges are the
    rows of contact.npz in those ranges."""
    conversion.convert(str(files[1]), tmp_path / "c")
    with np.load(tmp_path / "c" / "contact.npz") as data:
        whole = {k: data[k] for k in data.files}
    n = int(json.loads((tmp_path / "c" / "problem.json").read_text())[
        "n_nodes"])
    cut = int(np.median(whole["node"]))
    for lo, hi in ((0, cut), (cut, n)):
        part = load_contact_slice(tmp_path / "c", 2, lo, hi)
        inside = (whole["node"] >= lo) & (whole["node"] < hi)
        order = np.argsort(whole["node"][inside])
        for key in CONTACT_KEYS:
            assert np.array_equal(part[key], whole[key][inside][order]), key
    with pytest.raises(ProblemError, match="convert the .npz again"):
        load_contact_slice(tmp_path, 2, 0, n)


@pytest.mark.parametrize("save", [np.savez, np.savez_compressed])
def test_unsorted_rows_are_converted_whole(files, tmp_path, capsys, save):
    """A K whose rows' column indices are not sorted (the same matrix):
    the blocks cannot copy its rows as they are, so it is converted from
    the whole load, with one line on stderr, to the sorted file's K."""
    with np.load(files[1]) as data:
        arrays = {k: data[k] for k in data.files}
    K = sp.csr_matrix((arrays["K_data"], arrays["K_indices"],
                       arrays["K_indptr"]), shape=tuple(arrays["K_shape"]))
    a, b = K.indptr[5], K.indptr[6]
    arrays["K_indices"][a:b] = arrays["K_indices"][a:b][::-1].copy()
    arrays["K_data"][a:b] = arrays["K_data"][a:b][::-1].copy()
    save(tmp_path / "bad.npz", **arrays)
    meta = conversion.convert(str(tmp_path / "bad.npz"), tmp_path / "out")
    err = capsys.readouterr().err.strip()
    assert "not sorted" in err and "whole" in err and "\n" not in err
    assert meta["streamed"] is False
    conversion.convert(str(files[1]), tmp_path / "sorted")
    assert (tmp_path / "out" / "K.petsc").read_bytes() == \
        (tmp_path / "sorted" / "K.petsc").read_bytes()


def _flipped(path, target):
    """``path`` with one byte of K_data's compressed bytes inverted (its
    CRC no longer matches: found only once the member is decompressed)."""
    import zipfile

    raw = bytearray(path.read_bytes())
    with zipfile.ZipFile(path) as archive:
        info = archive.getinfo("K_data.npy")
    head = raw[info.header_offset:info.header_offset + 30]
    start = info.header_offset + 30 + int.from_bytes(head[26:28], "little") \
        + int.from_bytes(head[28:30], "little")
    raw[start + info.compress_size // 2] ^= 0xFF
    target.write_bytes(bytes(raw))
    return target


@pytest.mark.parametrize("fault", ["flipped", "float indices"])
def test_damaged_files_refused_in_one_line(files, tmp_path, fault):
    """A damaged compressed member, or column indices that are not
    integers: one ProblemError line, and no folder written (K is read
    through once before anything is written)."""
    if fault == "flipped":
        bad = _flipped(files[0], tmp_path / "bad.npz")
    else:
        with np.load(files[0]) as data:
            arrays = {k: data[k] for k in data.files}
        arrays["K_indices"] = arrays["K_indices"].astype(float)
        bad = tmp_path / "bad.npz"
        np.savez_compressed(bad, **arrays)
    with pytest.raises(ProblemError) as info:
        conversion.convert(str(bad), tmp_path / "out")
    assert "\n" not in str(info.value) and "bad.npz" in str(info.value)
    assert not (tmp_path / "out").exists()
