"""Reading the members of a problem file safely (docs/npz-format.md,
"Safe reading"): a hostile file (a zip bomb, an ``.npy`` header that claims
10¹⁰ entries, huge index arrays, thousands of members) costs no more memory
than a good one of its declared size. :class:`Archive` is a lazy mapping
that reads a member only when the validation asks for it, checks its
header against the sizes already known *before decompressing* it, then
reads exactly the declared bytes in chunks (row pointers checked to rise
as they come); every failure is a one-line
:class:`~solver.errors.ProblemError` naming the member."""

import os
import struct
import zipfile
from collections.abc import Mapping

import numpy as np
from numpy.lib import format as npy

from ..errors import ProblemError
from .checks import fail
from .format import KEYS, MAX_OBSTACLE_POINTS, MAX_STAGES, MAX_TEXT, \
    MAX_TOTAL_BYTES

__all__ = ["Archive", "DEFLATE_RATIO", "MAX_DIRECTORY"]

#: Deflate cannot compress by more than 1032:1; a member declaring more
#: bytes than this ratio allows is not in the file (or is a bomb).
DEFLATE_RATIO = 1100

#: Largest central directory accepted (a problem file has ~30 members).
MAX_DIRECTORY = 2 ** 20

#: Most nodes a file may declare: the total's worth of 3 coordinates.
MAX_NODES = MAX_TOTAL_BYTES // 24

_CHUNK = 2 ** 24
_SLACK = 64  # entries beyond the expected size (the validation names them)


def _directory_size(stream, size):
    """Size of the zip central directory from the end record, or None."""
    tail = min(size, 65557)
    stream.seek(size - tail)
    data = stream.read(tail)
    at = data.rfind(b"PK\x05\x06")
    if at < 0 or at + 22 > len(data):
        return None
    return struct.unpack("<I", data[at + 12:at + 16])[0]


class Archive(Mapping):
    """The members of an ``.npz`` file as a lazy, bounded mapping
    key -> array (see the module docstring). Use as a context manager."""

    def __init__(self, stream, path):
        self.path = path
        self.size = os.fstat(stream.fileno()).st_size
        directory = _directory_size(stream, self.size)
        if directory is not None and MAX_DIRECTORY < directory < 2 ** 32 - 1:
            raise ProblemError(f"{path}: the zip directory has {directory} "
                               "bytes: far too many members for a problem "
                               "file")
        stream.seek(0)
        try:
            self.zip = zipfile.ZipFile(stream)
        except Exception as exc:  # BadZipFile, NotImplementedError("zip
            # file version 6.4"), struct.error, ... of a damaged directory
            raise ProblemError(f"{path}: not a readable .npz file "
                               f"({type(exc).__name__}: {exc})") from None
        self.members, self.cache, self.total = {}, {}, 0
        for info in self.zip.infolist():
            name = info.filename
            key = name[:-4] if name.endswith(".npy") else name
            if key in self.members:
                self.close()
                fail(key, "appears twice in the archive")
            self.members[key] = info

    def close(self):
        self.zip.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __iter__(self):
        return iter(self.members)

    def __len__(self):
        return len(self.members)

    def __contains__(self, key):
        return key in self.members

    def __getitem__(self, key):
        if key not in self.cache:
            if key not in self.members or key not in KEYS:
                raise KeyError(key)
            self.cache[key] = self._read(key)
        return self.cache[key]

    # -- the sizes the format allows -------------------------------------

    def _header(self, key):
        """(shape, fortran_order, dtype, header length) of a member."""
        info = self.members[key]
        if info.flag_bits & 0x1:
            fail(key, "encrypted member (refused)")
        if info.compress_type not in (zipfile.ZIP_STORED,
                                      zipfile.ZIP_DEFLATED):
            fail(key, f"compression method {info.compress_type} is not "
                      "supported (stored or deflated only)")
        if info.compress_size > self.size:
            fail(key, "damaged: the member is larger than the file")
        limit = info.compress_size if info.compress_type == \
            zipfile.ZIP_STORED else DEFLATE_RATIO * info.compress_size + 4096
        if info.file_size > limit:
            how = "stored" if info.compress_type == zipfile.ZIP_STORED \
                else "compressed"
            fail(key, f"the zip directory declares {info.file_size} bytes "
                      f"in {info.compress_size} {how} bytes, more than "
                      f"they can hold (damaged, or a zip bomb)")
        with self.zip.open(info) as member:
            version = npy.read_magic(member)
            if version not in ((1, 0), (2, 0)):
                fail(key, f".npy format version {version} is not supported")
            read = npy.read_array_header_1_0 if version == (1, 0) \
                else npy.read_array_header_2_0
            shape, fortran, dtype = read(member, max_header_size=10000)
            return shape, fortran, dtype, member.tell()

    def _dim(self, key, axis=0, default=None):
        """A dimension declared by a member: its value for the small
        integer keys K_shape, M_shape; else the header's shape[axis]."""
        if key not in self.members:
            return default
        try:
            if key in ("K_shape", "M_shape"):
                value = self[key]
                return int(value[0]) if value.shape == (2,) \
                    and value.dtype.kind in "iu" and value[0] >= 0 \
                    else default
            shape = self._header(key)[0]
            return shape[axis] if len(shape) > axis else default
        except ProblemError:
            return default

    def _last(self, key):
        """nnz of a CSR matrix: the last entry of its row pointer ``key``
        (None if unknown). A row pointer that does not rise from 0 is
        refused as the validation would refuse it."""
        ptr = self._try(key)
        if ptr is None or ptr.ndim != 1 or not len(ptr) \
                or ptr.dtype.kind not in "iu":
            return None
        if ptr[0] != 0 or (np.diff(ptr) < 0).any():
            data = self._dim(key.replace("indptr", "data"), default="?")
            fail(key, f"not a valid CSR row pointer (must rise from 0 to "
                      f"nnz = {data})")
        return int(ptr[-1])

    def _try(self, key):
        try:
            return self[key] if key in self.members else None
        except ProblemError:
            return None

    def _limit(self, key):
        """Most entries member ``key`` may declare."""
        if KEYS[key][2] in ("()", "(2,)"):
            return _SLACK
        if key == "obstacle_points":
            return 2 * MAX_OBSTACLE_POINTS
        if key in ("load_path_steps", "load_path_friction"):
            return MAX_STAGES
        n = self._dim("K_shape", default=0)
        nc = self._dim("M_shape", default=0)
        # a meshed body whose every node is prescribed (a rigid master)
        # has nodes but no free DOFs: the nodes are bounded by the total
        # only (MAX_TOTAL_BYTES), not by Ñ
        n_nodes = min(self._dim("nodes", default=0), MAX_NODES)
        stages = min(self._dim("load_path_steps", default=0), MAX_STAGES)
        per_dof = 3 * (n + n_nodes + nc) + _SLACK
        if key in ("K_data", "K_indices"):
            nnz = self._last("K_indptr")
            return per_dof * per_dof if nnz is None else nnz
        if key in ("M_data", "M_indices"):
            nnz = self._last("M_indptr")
            return (3 * nc + _SLACK) ** 2 if nnz is None else nnz
        if key == "nodes":  # at most 3 coordinates per node
            return 3 * MAX_NODES
        if key == "cells":  # a tetrahedral mesh has ~6 tetrahedra per node
            return 4 * (8 * n_nodes + _SLACK)
        if key == "contact_faces":  # ~2 surface triangles per surface node
            return 3 * (4 * nc + _SLACK)
        if key == "load_path":
            return (stages + 1) * (n + _SLACK)
        if key == "load_path_prescribed":
            return (stages + 1) * per_dof
        return per_dof

    # -- reading ---------------------------------------------------------

    def _read(self, key):
        info = self.members[key]
        try:
            shape, fortran, dtype, header = self._header(key)
            return self._data(key, info, shape, fortran, dtype, header)
        except ProblemError:
            raise
        except MemoryError:
            fail(key, "too large to read")
        except Exception as exc:  # zlib/zip/EOF/header errors
            fail(key, f"cannot be read, the file is damaged "
                      f"({type(exc).__name__}: {str(exc)[:200]})")

    def _data(self, key, info, shape, fortran, dtype, header):
        kind = KEYS[key][1]
        if dtype.hasobject:
            fail(key, "contains pickled Python objects (refused: "
                      "allow_pickle=False)")
        if kind == "str" and (dtype.kind != "U" or shape != ()):
            fail(key, f"expected a text scalar, got dtype {dtype} with "
                      f"shape {shape}")
        if kind == "int" and dtype.kind not in "iu":
            fail(key, f"expected integers, got dtype {dtype}")
        if kind == "float" and dtype.kind not in "fiu":
            fail(key, f"expected real numbers, got dtype {dtype}")
        if kind == "str" and dtype.itemsize > 4 * MAX_TEXT:
            fail(key, f"text of {dtype.itemsize // 4} characters (at most "
                      f"{MAX_TEXT})")
        count = int(np.prod(shape, dtype=object))
        limit = self._limit(key)
        if count > limit and key.endswith(("_data", "_indices")):
            name = key.split("_")[0]  # as the validation (checks.csr) says
            if key.endswith("_data"):
                fail(f"{name}_indptr", f"not a valid CSR row pointer (must "
                                       f"rise from 0 to nnz = {count})")
            fail(key, f"expected shape ({limit},), got {shape}")
        if count > limit:
            fail(key, f"declares shape {shape} ({count} entries), more "
                      f"than the {limit} its dimensions allow (Ñ from "
                      "K_shape, Nc from M_shape, nnz from the row pointers)")
        nbytes = count * dtype.itemsize
        if info.file_size != header + nbytes:
            fail(key, f"damaged: the zip directory says {info.file_size} "
                      f"bytes, the .npy header {header + nbytes}")
        self.total += nbytes
        if self.total > MAX_TOTAL_BYTES:
            fail(key, f"the arrays exceed {MAX_TOTAL_BYTES} bytes in total")
        data = np.empty(count, dtype=dtype)
        view = memoryview(data.view(np.uint8)) if nbytes else None
        pointer = key.endswith("_indptr") and dtype.kind in "iu"
        checked = 0
        with self.zip.open(info) as member:
            member.seek(header)
            done = 0
            while done < nbytes:
                got = member.readinto(view[done:done + _CHUNK])
                if not got:
                    fail(key, f"damaged: {done} of {nbytes} bytes of array "
                              "data")
                done += got
                if pointer:  # a zero bomb fails in the first chunk
                    checked = _check_rows(key, data, checked,
                                          done // dtype.itemsize)
            if member.read(1):  # also checks the CRC at the end
                fail(key, "damaged: more data than the header declares")
        return data.reshape(shape, order="F" if fortran else "C")


def _check_rows(key, pointer, start, stop):
    """Rows of K and M (symmetric positive definite: every row holds its
    diagonal) are not empty: the row pointer rises strictly. Checked as
    the pointer is read; returns the position checked up to."""
    lo = max(start - 1, 0)
    part = pointer[lo:stop]
    flat = np.flatnonzero(np.diff(part) <= 0)
    if len(flat):
        i = int(flat[0])
        fail(key, f"row {lo + i} of {key.split('_')[0]} holds no entry "
                  f"(the row pointer goes from {part[i]} to {part[i + 1]}): "
                  "not the CSR row pointer of a positive definite matrix")
    return stop
