"""Builders of hostile problem files for the fault suite (issue 16).

``raw_zip`` writes a zip archive byte by byte (local headers, central
directory, end record; PKWARE APPNOTE 6.3.x, sections 4.3.7, 4.3.12,
4.3.16), so a test can lie in the directory, set flags, use other
compression methods or hold a deflate bomb of gigabytes built from one
compressed chunk repeated (a full flush makes each copy independent).
"""

import io
import json
import struct
import zlib

import numpy as np
import pytest

from conftest import run_cli  # noqa: F401  (re-exported for the tests)


@pytest.fixture(scope="module")
def block(exported):
    """The arrays of the 118-triangle thesis block (Γc: x = 5, bottom to
    top; its first node, the corner (5, -10), is a support)."""
    with np.load(exported(118)[0], allow_pickle=False) as archive:
        return {k: archive[k] for k in archive.files}


def write(tmp_path, arrays, name="p.npz"):
    """``arrays`` saved as the problem file ``tmp_path / name``."""
    path = tmp_path / name
    np.savez(path, **arrays)
    return path


def npy_bytes(array):
    """The .npy serialisation of ``array``."""
    buffer = io.BytesIO()
    np.save(buffer, array, allow_pickle=True)
    return buffer.getvalue()


def npy_header(dtype, shape, fortran=False):
    """A version 1.0 .npy header (magic included) declaring ``shape``."""
    buffer = io.BytesIO()
    np.lib.format.write_array_header_1_0(buffer, {
        "descr": np.lib.format.dtype_to_descr(np.dtype(dtype)),
        "fortran_order": fortran, "shape": tuple(shape)})
    return buffer.getvalue()


class Member:
    """One member: its name and raw bytes (stored), or deflated chunks."""

    def __init__(self, name, data=b"", *, method=0, chunks=None, crc=None,
                 size=None, flags=0, directory_size=None):
        self.name = name.encode()
        self.method, self.flags = method, flags
        if chunks is None:
            if method == 8:
                c = zlib.compressobj(9, zlib.DEFLATED, -15)
                chunks = [c.compress(data) + c.flush()]
            else:
                chunks = [data]
            crc = zlib.crc32(data) if crc is None else crc
            size = len(data) if size is None else size
        self.chunks, self.crc, self.size = chunks, crc, size
        self.compressed = sum(len(c) for c in chunks)
        self.directory_size = size if directory_size is None \
            else directory_size


def zeros_bomb(name, header, n_bytes, chunk=2 ** 24):
    """A deflated member: ``header`` then ``n_bytes`` zero bytes, from one
    compressed chunk repeated (small to write, gigabytes to inflate)."""
    c = zlib.compressobj(9, zlib.DEFLATED, -15)
    head = c.compress(header) + c.flush(zlib.Z_FULL_FLUSH)
    count, rest = divmod(n_bytes, chunk)
    block = c.compress(bytes(chunk)) + c.flush(zlib.Z_FULL_FLUSH)
    last = c.compress(bytes(rest)) + c.flush(zlib.Z_FULL_FLUSH)
    tail = c.flush()
    crc = zlib.crc32(header)
    zero = bytes(chunk)
    for _ in range(count):  # ~1 s per GB
        crc = zlib.crc32(zero, crc)
    crc = zlib.crc32(bytes(rest), crc)
    return Member(name, method=8,
                  chunks=[head] + [block] * count + [last, tail],
                  crc=crc, size=len(header) + n_bytes)


def raw_zip(path, members):
    """Write ``members`` (a list of :class:`Member`) as a zip file."""
    directory, offset = [], 0
    with open(path, "wb") as out:
        for m in members:
            local = struct.pack("<4s5H3L2H", b"PK\x03\x04", 20, m.flags,
                                m.method, 0, 0, m.crc, m.compressed,
                                m.directory_size, len(m.name), 0)
            out.write(local + m.name)
            for c in m.chunks:
                out.write(c)
            directory.append(struct.pack(
                "<4s6H3L5H2L", b"PK\x01\x02", 20, 20, m.flags, m.method, 0,
                0, m.crc, m.compressed, m.directory_size, len(m.name), 0, 0,
                0, 0, 0, offset) + m.name)
            offset += len(local) + len(m.name) + m.compressed
        blob = b"".join(directory)
        out.write(blob)
        out.write(struct.pack("<4s4H2LH", b"PK\x05\x06", 0, 0,
                              len(members), len(members), len(blob), offset,
                              0))
    return path


def members_of(arrays, method=8):
    """Members for a dict of arrays (as np.savez_compressed would write)."""
    return [Member(k + ".npy", npy_bytes(v), method=method)
            for k, v in arrays.items()]


def with_meta(arrays, text):
    """``arrays`` with the meta key replaced by raw JSON ``text``."""
    return dict(arrays, meta=np.array(text))


def meta_fields(arrays, **fields):
    return with_meta(arrays, json.dumps(dict(json.loads(str(
        arrays["meta"])), **fields)))


def assert_one_error_line(code, out, err, phrase=""):
    """Exit 2, exactly one ``error:`` line on stderr, no traceback."""
    lines = err.splitlines()
    assert code == 2, (code, err)
    assert len(lines) == 1, err
    assert lines[0].startswith(("error: ", "python -m solver: error: ")), err
    assert "Traceback" not in err and phrase in lines[0], (phrase, err)


#: The rigid plane z = -0.01 under :func:`unit_cube`.
PLANE = {"kind": "plane", "point": [0.0, 0.0, -0.01],
         "normal": [0.0, 0.0, 1.0]}


def unit_cube(supported=True, obstacle=PLANE):
    """The ``.npz`` arrays of a 3D problem without SfePy: the unit cube
    (2×2×2 boxes of 6 tetrahedra, P1 elasticity of ``tet_elasticity``,
    E = 100, ν = 0.3), its bottom z = 0 the contact surface above
    ``obstacle``; its top face pressed down by 0.02 (``supported``) or no
    Dirichlet condition at all (a floating body, K singular, no load)."""
    from tet_elasticity import box, mesh_problem, stiffness

    n = (2, 2, 2)
    nodes, tets = box(n)
    z = nodes[:, 2]
    prescribed = np.full(nodes.shape, np.nan)
    if supported:
        top = np.isclose(z, 1.0)
        prescribed[top] = 0.0
        prescribed[top, 2] = -0.02
    ids = np.arange(len(nodes)).reshape(tuple(m + 1 for m in n))
    a, b = ids[:-1, :-1, 0].ravel(), ids[1:, :-1, 0].ravel()
    c, d = ids[1:, 1:, 0].ravel(), ids[:-1, 1:, 0].ravel()
    faces = np.concatenate([np.stack([a, c, b], 1), np.stack([a, d, c], 1)])
    problem = mesh_problem(nodes, tets, stiffness(nodes, tets, 100.0, 0.3),
                           prescribed, np.flatnonzero(np.isclose(z, 0.0)),
                           faces)
    problem.meta = {"E": 100.0, "nu": 0.3,
                    "load": "top pressed by 0.02" if supported else "none",
                    "mesh": "unit cube, 48 tetrahedra"}
    problem.obstacle, problem.contact_faces = obstacle, faces
    return problem.to_arrays()
