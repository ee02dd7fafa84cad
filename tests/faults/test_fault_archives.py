"""Hostile archives and metadata (issue 16, class 3).

Every case is a problem file that must be refused with one
:class:`~solver.errors.SolverError` line naming the member, before any
large allocation: zip bombs (in a known and in an unknown member), .npy
headers that claim 10¹⁰ entries, index arrays larger than their matrix,
lying zip directories, hostile JSON in ``meta``. The byte layouts are
those of the PKWARE zip APPNOTE and the NumPy .npy format description
(``numpy.lib.format``); the deflate ratio bound (at most 1032:1) is
zlib's documented maximum ("zlib technical details", zlib.net).
"""

import io
import json
import resource
import time
import zipfile

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from fault_tools import (Member, assert_one_error_line, members_of,
                         meta_fields, npy_bytes, npy_header, raw_zip,
                         run_cli, with_meta, zeros_bomb)
from solver.errors import ProblemError, SolverError
from solver.examples import two_dof_bar
from solver.problem import load_problem, save_problem


@pytest.fixture(scope="module")
def bar():
    return two_dof_bar().to_arrays()


def refused(path, phrase):
    with pytest.raises(ProblemError) as info:
        load_problem(path)
    message = str(info.value)
    assert "\n" not in message and phrase in message, message
    return message


def test_a_valid_hand_written_archive_loads(bar, tmp_path):
    """The raw zip writer itself is right: stored and deflated members of a
    valid problem load (so the refusals below are about the faults)."""
    for method in (0, 8):
        path = raw_zip(tmp_path / f"ok{method}.npz",
                       members_of(bar, method))
        problem = load_problem(path)
        assert problem.n_dofs == 2 and problem.gap[0] == bar["gap"][0]


def test_fortran_order_and_big_endian_members_load(bar, tmp_path):
    arrays = dict(bar, normal=np.asfortranarray(bar["normal"]).astype(">f8"),
                  f=bar["f"].astype(">f8"))
    path = raw_zip(tmp_path / "f.npz", members_of(arrays))
    problem = load_problem(path)
    assert np.array_equal(problem.normal, bar["normal"])
    assert np.array_equal(problem.f, bar["f"])


# --------------------------------------------------------------------------
# declared sizes

def test_header_claiming_1e10_entries(bar, tmp_path):
    members = members_of(bar)
    members[[m.name for m in members].index(b"K_data.npy")] = Member(
        "K_data.npy", npy_header("<f8", (10 ** 10,)) + bytes(64), method=8)
    refused(raw_zip(tmp_path / "p.npz", members), "K_indptr: not a valid "
                                                  "CSR row pointer")


def test_f_claiming_1e10_entries(bar, tmp_path):
    members = [m for m in members_of(bar) if m.name != b"f.npy"]
    members.append(Member("f.npy", npy_header("<f8", (10 ** 10,)),
                          method=8))
    refused(raw_zip(tmp_path / "p.npz", members), "f: declares shape")


def test_indices_far_larger_than_the_matrix(bar, tmp_path):
    arrays = dict(bar, K_indices=np.zeros(10 ** 6, dtype=np.int64))
    path = raw_zip(tmp_path / "p.npz", members_of(arrays))
    refused(path, "K_indices: expected shape (2,), got (1000000,)")


def test_load_path_stages_beyond_the_limit(bar, tmp_path):
    arrays = dict(bar, load_path=bar["f"][None],
                  load_path_steps=np.array([1]),
                  load_path_friction=np.array([1.0]))
    members = [m for m in members_of(arrays)
               if m.name != b"load_path_steps.npy"]
    members.append(Member("load_path_steps.npy",
                          npy_header("<i8", (10 ** 9,)), method=8))
    refused(raw_zip(tmp_path / "p.npz", members), "load_path_steps: declares")


def test_text_longer_than_the_limit(bar, tmp_path):
    members = [m for m in members_of(bar) if m.name != b"meta.npy"]
    members.append(Member("meta.npy", npy_header("<U2000000", ()),
                          method=8))
    refused(raw_zip(tmp_path / "p.npz", members), "meta: text of 2000000")


def test_directory_size_disagrees_with_header(bar, tmp_path):
    members = members_of(bar)
    m = members[[m.name for m in members].index(b"f.npy")]
    m.directory_size += 8  # the directory claims 8 more bytes
    refused(raw_zip(tmp_path / "p.npz", members), "f: damaged: the zip "
                                                  "directory says")


def test_more_than_deflate_can_hold(bar, tmp_path):
    """A member whose directory size exceeds 1100x its compressed size
    cannot be real deflate data: refused before inflating."""
    members = [m for m in members_of(bar) if m.name != b"f.npy"]
    header = npy_header("<f8", (2,))
    m = Member("f.npy", header + bytes(16), method=8)
    m.directory_size = m.size = 10 ** 6  # and a header that agrees:
    m.chunks = [zipfile._get_compressor(8).compress(npy_header(
        "<f8", ((10 ** 6 - 128) // 8,)))]
    m.compressed = len(m.chunks[0])
    members.append(m)
    refused(raw_zip(tmp_path / "p.npz", members), "compressed bytes, more "
                                                  "than they can hold")


def test_truncated_member_data(bar, tmp_path):
    members = [m for m in members_of(bar, 0) if m.name != b"f.npy"]
    raw = npy_bytes(bar["f"])
    members.append(Member("f.npy", raw[:-4], method=0,
                          directory_size=len(raw), size=len(raw)))
    with pytest.raises(ProblemError, match="^f: "):
        load_problem(raw_zip(tmp_path / "p.npz", members))


def test_object_dtype_member(bar, tmp_path):
    arrays = dict(bar, gap=np.array([{"x": 1}], dtype=object))
    refused(raw_zip(tmp_path / "p.npz", members_of(arrays)),
            "gap: contains pickled Python objects")


def test_encrypted_member(bar, tmp_path):
    members = members_of(bar)
    members[0].flags = 0x1
    refused(raw_zip(tmp_path / "p.npz", members), "encrypted member")


def test_unsupported_compression(bar, tmp_path):
    members = members_of(bar, 0)
    members[-1].method = 12  # bzip2
    refused(raw_zip(tmp_path / "p.npz", members), "compression method 12")


def test_duplicate_member(bar, tmp_path):
    members = members_of(bar)
    members.append(members_of({"f": np.zeros(2)})[0])
    refused(raw_zip(tmp_path / "p.npz", members), "f: appears twice")


def test_huge_central_directory(bar, tmp_path):
    members = members_of(bar) + [Member(f"x{i:06d}" + "y" * 200)
                                 for i in range(6000)]
    refused(raw_zip(tmp_path / "p.npz", members), "far too many members")


def test_npy_version_3_and_garbage_headers(bar, tmp_path):
    for i, head in enumerate([b"\x93NUMPY\x03\x00" + bytes(8),
                              b"\x93NUMPY\x01\x00\x10\x00{'descr': (((((",
                              b"not an npy member at all"]):
        members = [m for m in members_of(bar) if m.name != b"gap.npy"]
        members.append(Member("gap.npy", head, method=8))
        with pytest.raises(ProblemError, match="^gap: "):
            load_problem(raw_zip(tmp_path / f"p{i}.npz", members))


# --------------------------------------------------------------------------
# zip bombs: refused without inflating, in bounded memory and time

def max_rss_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


@pytest.mark.parametrize("name", ["f", "evil"])
def test_zip_bomb_in_a_known_and_an_unknown_member(bar, tmp_path, name):
    """2 GiB of zeros deflated to ~2 MB, as the key f (declared (2.7e8,)
    where K_shape says 2) or as an extra member: refused in well under a
    second, and the process's peak memory grows by less than 100 MB."""
    members = [m for m in members_of(bar) if m.name != f"{name}.npy".encode()]
    members.append(zeros_bomb(f"{name}.npy",
                              npy_header("<f8", (2 ** 28,)), 2 ** 31))
    path = raw_zip(tmp_path / "bomb.npz", members)
    assert path.stat().st_size < 10 * 2 ** 20
    before = max_rss_mb()
    start = time.perf_counter()
    refused(path, f"{name}: ")
    assert time.perf_counter() - start < 5.0
    assert max_rss_mb() - before < 100


def test_zip_bomb_through_the_cli(bar, tmp_path, capsys):
    members = [m for m in members_of(bar) if m.name != b"f.npy"]
    members.append(zeros_bomb("f.npy", npy_header("<f8", (2 ** 25,)),
                              2 ** 28))
    path = raw_zip(tmp_path / "bomb.npz", members)
    assert_one_error_line(*run_cli([path, "--info"], capsys), "f: declares")


# --------------------------------------------------------------------------
# metadata JSON

META_CASES = [
    ("deeply nested", '{"E": ' + "[" * 100000 + "]" * 100000 + "}",
     "meta: nests 100001 levels deep"),
    ("4301-digit E", '{"E": ' + "7" * 4301 + "}", "an integer of 4301 digits"),
    ("huge E", '{"E": 1e999}', "overflows double precision"),
    ("NaN nu", '{"nu": NaN}', "NaN is not a number in JSON"),
    ("-Infinity", '{"x": -Infinity}', "-Infinity is not a number in JSON"),
    ("lone surrogate", '{"description": "\\ud800"}', "not valid Unicode"),
    ("surrogate key", '{"\\udfff": 1, "description": "x"}',
     "not valid Unicode"),
    ("a list", "[1, 2]", "must be a JSON object"),
    ("truncated", '{"E": 1', "not valid JSON"),
    ("unbalanced brackets", "]]]]" * 1000, "not valid JSON"),
]


@pytest.mark.parametrize("name, text, phrase", META_CASES,
                         ids=[c[0] for c in META_CASES])
def test_hostile_meta(bar, tmp_path, capsys, name, text, phrase):
    path = tmp_path / "p.npz"
    np.savez(path, **with_meta(bar, text))
    refused(path, phrase)
    assert_one_error_line(*run_cli([path, "--info", "--json"], capsys),
                          phrase)


def test_info_json_is_strict_json(bar, tmp_path, capsys):
    """--info --json parses with a parser that refuses NaN/Infinity."""
    path = tmp_path / "p.npz"
    np.savez(path, **meta_fields(bar, big=10 ** 29, small=1e-300,
                                 text="žluťoučký kůň"))
    code, out, err = run_cli([path, "--info", "--json"], capsys)
    assert code == 0, err

    def refuse(name):
        raise AssertionError(f"{name} in --info --json output")

    info = json.loads(out, parse_constant=refuse)
    assert info["meta"]["big"] == 10 ** 29
    assert info["meta"]["text"] == "žluťoučký kůň"


def test_overflowing_matrix_norm_refused(bar, tmp_path):
    """Entries of 1e308 are finite, but sums of them overflow double
    precision (and --info would print Infinity)."""
    arrays = dict(bar, K_data=np.full(2, 1e308))
    path = tmp_path / "p.npz"
    np.savez(path, **arrays)
    refused(path, "K_data: values up to")


# --------------------------------------------------------------------------
# fuzzing the reader

@pytest.fixture(scope="module")
def valid_bytes(tmp_path_factory):
    path = tmp_path_factory.mktemp("fuzz") / "bar.npz"
    save_problem(path, two_dof_bar())
    return path.read_bytes()


def load_bytes(data, folder):
    path = folder / "fuzz.npz"
    path.write_bytes(data)
    try:
        load_problem(path)
    except SolverError as exc:
        assert "\n" not in str(exc)


FUZZ = settings(max_examples=150, deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.function_scoped_fixture])


@FUZZ
@given(flips=st.lists(st.tuples(st.floats(0, 1), st.integers(0, 255)),
                      min_size=1, max_size=8),
       cut=st.none() | st.floats(0, 1))
def test_fuzz_byte_flips_and_truncation(valid_bytes, tmp_path, flips, cut):
    """Random bytes overwritten anywhere (headers, directory, data), the
    file cut anywhere: only SolverError escapes."""
    data = bytearray(valid_bytes)
    for where, byte in flips:
        data[min(int(where * len(data)), len(data) - 1)] = byte
    if cut is not None:
        data = data[:int(cut * len(data))]
    load_bytes(bytes(data), tmp_path)


@FUZZ
@given(key=st.sampled_from(sorted(two_dof_bar().to_arrays())),
       shape=st.lists(st.sampled_from([0, 1, 2, 3, 7, 10 ** 6, 10 ** 12,
                                       2 ** 62]), max_size=3),
       dtype=st.sampled_from(["<f8", ">i4", "<U5", "|b1", "<c16", "|O",
                              "<M8[s]", "|V4", "<f2"]),
       fortran=st.booleans(), data=st.binary(max_size=64))
def test_fuzz_declared_headers(tmp_path, key, shape, dtype, fortran, data):
    """A member with a random declared dtype and shape (up to 2⁶²
    entries) over a few bytes of data: only SolverError escapes, and no
    memory is allocated for the declared size."""
    arrays = two_dof_bar().to_arrays()
    members = [m for m in members_of(arrays) if m.name != f"{key}.npy"
               .encode()]
    members.append(Member(f"{key}.npy", npy_header(dtype, shape, fortran)
                          + data, method=8))
    out = io.BytesIO()
    raw_zip(tmp_path / "h.npz", members)
    load_bytes((tmp_path / "h.npz").read_bytes(), tmp_path)
    del out


def test_row_pointer_bomb_refused_in_its_first_chunk(bar, tmp_path):
    """K_shape declares 2²⁶ DOFs and K_indptr is 512 MiB of zeros (a
    valid row pointer of an SPD matrix rises strictly): refused after the
    first chunk, not after inflating it all."""
    n = 2 ** 26
    members = [m for m in members_of(bar)
               if m.name not in (b"K_indptr.npy", b"K_shape.npy")]
    members += members_of({"K_shape": np.array([n, n])})
    members.append(zeros_bomb("K_indptr.npy",
                              npy_header("<i8", (n + 1,)), 8 * (n + 1)))
    path = raw_zip(tmp_path / "ptr.npz", members)
    before = max_rss_mb()
    refused(path, "K_indptr: row 0 of K holds no entry")
    assert max_rss_mb() - before < 100
