r"""``python -m solver convert X.npz DIR``: a rigid-obstacle problem as the
partitioned folder that ``mpiexec -n N python -m solver DIR --engine
petsc`` reads in part (:mod:`solver.problem.partitioned`; docs/npz-format.md,
"The partitioned problem").

The conversion runs once, serially, on a machine that holds the ``.npz``
(the SfePy export wrote it there): it pads K and f to the node-blocked
numbering of :class:`~solver.mpi.layout.Layout`, writes them in PETSc's
binary format with NumPy, sorts the cells by their smallest node, and
computes the contact geometry (gaps, normals, frames: thesis §2.1) of the
nodes that take part, which is all the distributed solve needs on Γc.

A ``.npz`` is converted without K in memory: the mesh-sized vectors are
read, and K's CSR is checked, padded and written in blocks of rows, so
the conversion's peak memory is O(n) vectors plus one block, not K. In
an uncompressed file (``np.savez``: a zip whose members are stored) K's
members are memory-mapped at their offsets (the zip's local header, then
NumPy's ``.npy`` header; :func:`stored_members`), their pages given back
after each block (``madvise``); in a compressed one (``save_problem``
and SfePy's export write ``np.savez_compressed``) they are decompressed
in order, block by block (:func:`compressed_members`). A K the blocks
cannot copy as they are (column indices not sorted in a row, or, kept
in the file's order, nodes renumbered in ``dof_map``) is converted from
the whole load instead, with one line saying so.

By default the nodes are renumbered first, so that each rank's node
range is a compact piece of the body (:mod:`solver.problem.renumber`):
the order comes from the cells (reverse Cuthill–McKee on the node
graph, O(cells)), and K is written in it without being held, by an
external bucket sort (:class:`_RenumberedK`); ``--no-renumber`` keeps
the file's order."""

import contextlib
import json
import mmap
import os
import shutil
import signal
import struct
import sys
import threading
import zipfile
import zlib

import numpy as np
import scipy.sparse as sp

from ..contact.geometry import contact_geometry, contact_stiffness
from ..errors import STOP_SIGNALS, ProblemError
from ..ncp import stable_norm
from ..problem import load_problem
from ..problem.archive import Archive
from ..problem.core import validate_arrays
from ..problem.format import KEYS
from ..problem.renumber import cut_cells, renumbered
from ..problem.partitioned import (MASS_FILE, MAT_CLASSID, MORTAR_DIR,
                                   NODE_IDS,
                                   PARTITIONED_VERSION,
                                   write_contact_by_node, write_petsc_matrix,
                                   write_petsc_vector)
from .convert_mortar import MortarConversion
from .layout import Layout

__all__ = ["convert", "CELL_KINDS", "stored_members", "compressed_members",
           "BLOCK_NNZ", "temporary_folder"]

@contextlib.contextmanager
def temporary_folder(prefix, where=None):
    """A new folder ``tempfile.mkdtemp(prefix=prefix, dir=where)``,
    removed with its content when the block ends, however it ends. The
    stop signals are held from before the folder exists until its removal
    is armed: a stop raised between the two (the handlers of
    solver/cli raise at the next Python call, mkdtemp's own included)
    would leave the folder behind, and one did, a SIGINT right after
    mkdtemp. A stop that arrives meanwhile is raised once they are
    released, and the folder is removed."""
    import tempfile

    hold = (hasattr(signal, "pthread_sigmask")
            and threading.current_thread() is threading.main_thread())
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS) \
        if hold else None
    try:
        path = tempfile.mkdtemp(prefix=prefix, dir=where)
    except BaseException:
        if hold:
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        raise
    try:
        if hold:
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        yield path
    finally:
        shutil.rmtree(path, ignore_errors=True)

#: K's entries per block of rows of the streamed conversion: ≈ 28 bytes
#: each in flight (read, renumbered, byte-swapped), ≈ 60 MB a block.
BLOCK_NNZ = 1 << 21

#: The share of the cells across the two halves of the node numbering
#: above which :func:`convert` says to renumber (a gmsh block: 75 %; the
#: same in reverse Cuthill–McKee order: 0.4 %).
CUT_WARN = 0.05

#: (dimension, nodes per cell) -> VTK cell name (meshio's).
CELL_KINDS = {(2, 3): "triangle", (2, 4): "quad", (3, 4): "tetra",
              (3, 8): "hexahedron"}


def _padded_rows(rows, red_to_pad):
    """Reduced DOFs (−1 kept) in the padded numbering."""
    rows = np.asarray(rows, np.int64)
    return np.where(rows >= 0, red_to_pad[np.maximum(rows, 0)], -1)


def convert(source, folder, gap="obstacle", renumber=True):
    """Write the partitioned folder ``folder`` from the problem file
    ``source`` (a path or a loaded problem); returns ``problem.json``'s
    contents. One rigid body against a rigid obstacle only (ProblemError
    otherwise); the nodes with a Dirichlet DOF take part as rollers, as
    :func:`solver.solve`'s default. A path to a ``.npz`` is streamed
    (module docstring; ``meta``'s ``"streamed"`` says whether it was).
    ``renumber`` (the default): the nodes in reverse Cuthill–McKee order
    (:mod:`solver.problem.renumber`), their ``.npz`` numbers kept in
    ``node_ids.npy``; from a path, streamed too (:class:`_RenumberedK`);
    ``renumber=False`` keeps the file's order. ``meta``'s
    ``"cut_cells"``: the share of the cells with nodes in both halves of
    the numbering (:func:`~solver.problem.renumber.cut_cells`; the
    command line says to renumber above :data:`CUT_WARN`).

    ``problem.json`` is written last and removed first (when the folder
    is written again), so a conversion cut short (a full disk, a signal)
    leaves no folder that reads as complete; the temporary buckets of the
    renumbered K are removed on every way out but SIGKILL."""
    try:
        return _converted(source, folder, gap, renumber)
    except BaseException:
        try:  # a problem.json cut short by a full disk
            os.unlink(os.path.join(folder, "problem.json"))
        except OSError:
            pass
        raise


def _converted(source, folder, gap, renumber):
    if not isinstance(source, (str, os.PathLike)):
        if renumber and source.kind == "mesh":
            problem, order = renumbered(source)
            return _convert(problem, folder, gap, None, order)
        return _convert(source, folder, gap, None)
    try:
        stream = _StreamedK.open(source)
        try:
            if renumber and stream.problem.kind == "mesh":
                problem, order = renumbered(stream.problem)
                return _convert(problem, folder, gap,
                                _RenumberedK(stream, order), order)
            return _convert(stream.problem, folder, gap, stream)
        finally:
            stream.close()
    except _WholeLoad as exc:
        print(f"{os.fspath(source)}: {exc}: converting it from the whole "
              f"problem in memory", file=sys.stderr)
    problem = load_problem(source)
    if renumber and problem.kind == "mesh":
        problem, order = renumbered(problem)
        return _convert(problem, folder, gap, None, order)
    return _convert(problem, folder, gap, None)


def _convert(problem, folder, gap, stream, node_ids=None):
    if problem.kind != "mesh" or (problem.n_bodies != 1
                                  and not problem.is_mortar):
        raise ProblemError("convert: the partitioned problem holds one "
                           "elastic body against a rigid obstacle, or two "
                           "bodies coupled by a mortar interface (a mesh "
                           "problem)")
    n_nodes = len(problem.nodes)
    cut = cut_cells(problem.cells, np.array([0, n_nodes // 2, n_nodes]))
    # two bodies: the nodewise problem in v = T u (convert_mortar)
    mortar = MortarConversion(problem) if problem.is_mortar else None
    geometry = mortar.geometry if mortar else contact_geometry(
        problem, gap, rollers=True)
    layout = Layout(problem, 1)
    os.makedirs(folder, exist_ok=True)
    try:  # the folder of an earlier conversion reads as complete no more
        os.unlink(os.path.join(folder, "problem.json"))
    except FileNotFoundError:
        pass
    K = problem.K  # streamed: diag(K), which is all that is read of it here
    scale = float(np.mean(K.diagonal())) if K.shape[0] else 1.0
    if stream is None:
        K_pad = layout.matrix(K)
        nnz = int(K_pad.nnz)
        write_petsc_matrix(os.path.join(folder, "K.petsc"), K_pad)
        del K_pad
    else:
        nnz = stream.write_padded(os.path.join(folder, "K.petsc"), layout,
                                  scale)
    f_pad = layout.pad(problem.f)  # Dirichlet rows: scale · ū (module doc)
    f_pad[layout.dirichlet] = scale * np.asarray(
        problem.u_prescribed, float).ravel()[layout.dirichlet]
    write_petsc_vector(os.path.join(folder, "f.petsc"), f_pad)
    cells = np.asarray(problem.cells, np.int64)
    first = cells.min(axis=1)
    order = np.argsort(first, kind="stable")
    np.save(os.path.join(folder, "nodes.npy"), np.asarray(problem.nodes,
                                                          float))
    np.save(os.path.join(folder, "cells.npy"), cells[order])
    pad = layout.red_to_pad
    contact = dict(
        node=np.asarray(problem.contact_nodes, np.int64)[geometry.index],
        index=np.asarray(geometry.index, np.int64),
        dofs=_padded_rows(geometry.dofs, pad),
        node_dofs=_padded_rows(geometry.node_dofs, pad),
        gap=np.asarray(geometry.gap, float),
        normal=np.asarray(geometry.normal, float),
        tangents=np.asarray(geometry.tangents, float),
        oblique=np.asarray(geometry.oblique, bool))
    np.savez(os.path.join(folder, "contact.npz"), **contact)
    write_contact_by_node(folder, contact)
    # Γc's boundary mass matrix (n_contact², sparse): friction's lumped D
    # and M⁻¹λ (solver.mpi.partitioned_friction)
    sp.save_npz(os.path.join(folder, MASS_FILE), sp.csr_matrix(
        mortar.mass if mortar else problem.M))
    if mortar:
        mortar.write(folder, layout.red_to_pad)
    elif os.path.isdir(os.path.join(folder, MORTAR_DIR)):  # converted again
        shutil.rmtree(os.path.join(folder, MORTAR_DIR))
    ids = os.path.join(folder, NODE_IDS)
    if node_ids is not None:
        np.save(ids, np.asarray(node_ids, np.int64))
    elif os.path.exists(ids):  # a folder converted again without it
        os.unlink(ids)
    meta = dict(
        partitioned=PARTITIONED_VERSION, dim=int(problem.dim),
        n_nodes=int(len(problem.nodes)), n=int(layout.n),
        n_free=int(problem.n_dofs), nnz=nnz,
        cell_kind=CELL_KINDS[problem.dim, cells.shape[1]],
        dirichlet_scale=scale, load_norm=mortar.load_norm if mortar
        else float(stable_norm(problem.f)),
        stiffness=float(contact_stiffness(K, geometry)),
        gap_mode="given" if mortar else gap,
        n_contact=int(problem.n_contact),
        excluded=int(len(geometry.excluded["index"])),
        load_path=problem.load_path is not None,
        meta=problem.meta, source=str(problem.source),
        streamed=stream is not None, renumbered=node_ids is not None,
        node_order="reverse Cuthill-McKee" if node_ids is not None
        else "file",
        cut_cells=round(cut, 4), **(mortar.meta() if mortar else {}))
    with open(os.path.join(folder, "problem.json"), "w") as stream_:
        json.dump(meta, stream_, indent=1, sort_keys=True)
    return meta


def _open_files():
    """How many bucket files :class:`_RenumberedK` keeps open at most:
    half the process's limit of open files (1024 by default: 512 buckets,
    so a block of 2²¹ entries up to ≈ 10⁹ entries of K)."""
    import resource

    soft, _ = resource.getrlimit(resource.RLIMIT_NOFILE)
    return max(16, (soft if soft != resource.RLIM_INFINITY else 4096) // 2)


def _start_matrix(stream, n, lengths):
    """PETSc's binary AIJ header and row lengths of an n×n matrix written
    to ``stream``; returns the offsets of its column indices and values
    (filled by :func:`_write_entries`)."""
    header = np.dtype(">i4")
    nnz = int(lengths.sum())
    np.array([MAT_CLASSID, n, n, nnz], header).tofile(stream)
    lengths.astype(header).tofile(stream)
    base_i = stream.tell()
    return base_i, base_i + 4 * nnz


def _write_entries(stream, bases, offset, cols, vals):
    """Entries ``offset``.. of the matrix started by :func:`_start_matrix`."""
    stream.seek(bases[0] + 4 * offset)
    cols.astype(">i4").tofile(stream)
    stream.seek(bases[1] + 8 * offset)
    vals.astype(">f8").tofile(stream)


#: The members that stay mapped (every other one is read: O(n) vectors).
MAPPED = ("K_indices", "K_data")


class _WholeLoad(ProblemError):
    """K's blocks cannot be copied as they are: :func:`convert` converts
    from the whole load, which puts K's CSR in canonical form."""


def stored_members(path):
    """{name: array} of the ``.npz`` at ``path`` if every member is stored
    uncompressed (``np.savez``), each a read-only view into one ``mmap``
    of the file at its offset (after the zip's local header and the
    ``.npy`` header) for :data:`MAPPED`, the others read.
    Returns (arrays, the mmap), or None if a member is compressed."""
    path = os.fspath(path)
    try:
        with zipfile.ZipFile(path) as archive:
            infos = archive.infolist()
    except (OSError, zipfile.BadZipFile) as exc:
        raise ProblemError(f"{path}: not a readable .npz ({exc})") from None
    if any(info.compress_type != zipfile.ZIP_STORED for info in infos):
        return None
    arrays = {}
    with open(path, "rb") as stream:
        mapped = mmap.mmap(stream.fileno(), 0, access=mmap.ACCESS_READ)
        for info in infos:
            if not info.filename.endswith(".npy"):
                raise ProblemError(f"{path}: member {info.filename!r} is "
                                   "not an .npy array")
            stream.seek(info.header_offset)
            head = stream.read(30)  # the zip's local file header
            names, extra = struct.unpack("<HH", head[26:30])
            stream.seek(info.header_offset + 30 + names + extra)
            version = np.lib.format.read_magic(stream)
            shape, fortran, dtype = (
                np.lib.format.read_array_header_1_0 if version == (1, 0)
                else np.lib.format.read_array_header_2_0)(stream)
            if dtype.hasobject:
                raise ProblemError(f"{path}: member {info.filename!r} "
                                   "holds pickled objects")
            count = int(np.prod(shape))
            array = np.frombuffer(mapped, dtype, count, stream.tell()) \
                .reshape(shape, order="F" if fortran else "C")
            name = info.filename[:-4]
            if name not in MAPPED:
                array = np.array(array)
            arrays[name] = array
    mapped.madvise(mmap.MADV_DONTNEED)  # the pages read for the copies
    return arrays, mapped


def _npy_header(stream):
    """(shape, Fortran order, dtype) of the ``.npy`` at ``stream``."""
    version = np.lib.format.read_magic(stream)
    return (np.lib.format.read_array_header_1_0 if version == (1, 0)
            else np.lib.format.read_array_header_2_0)(stream)


class _MemberStream:
    """One member of a compressed ``.npz`` (a 1-D array) read in order:
    ``self[a:b]`` decompresses entries a to b, restarting the member when
    a lies behind what was read, so K's arrays pass by blocks of rows and
    are never held whole."""

    def __init__(self, path, name):
        self.path, self.name = path, name
        self._open()
        if len(self.shape) != 1 or self.dtype.hasobject:
            self.close()
            raise ProblemError(f"{path}: member {name!r} is not a 1-D "
                               "array of numbers")

    def _open(self):
        self.archive = zipfile.ZipFile(self.path)
        try:
            self.stream = self.archive.open(self.name)
            self.shape, _, self.dtype = _npy_header(self.stream)
        except (OSError, ValueError, EOFError, zipfile.BadZipFile,
                zlib.error) as exc:
            self.archive.close()
            raise ProblemError(f"{self.path}: member {self.name!r} cannot "
                               f"be read ({' '.join(str(exc).split())})") \
                from None
        self.at = 0  # entries read

    def __len__(self):
        return int(self.shape[0])

    def _read(self, count):
        size = count * self.dtype.itemsize
        try:
            data = self.stream.read(size)
        except (OSError, EOFError, zipfile.BadZipFile, zlib.error) as exc:
            raise ProblemError(f"{self.path}: member {self.name!r} cannot "
                               f"be read, the file is damaged "
                               f"({' '.join(str(exc).split())})") from None
        if len(data) != size:
            raise ProblemError(f"{self.path}: member {self.name!r} ends "
                               "before its header's length")
        self.at += count
        return data

    def __getitem__(self, key):
        a, b = key.start or 0, min(key.stop, len(self))
        if a < self.at:
            self.close()
            self._open()
        while self.at < a:  # the entries before a, in pieces of 8 MB
            self._read(min(a - self.at, (8 << 20) // self.dtype.itemsize))
        return np.frombuffer(self._read(max(b - a, 0)), self.dtype)

    def close(self):
        self.stream.close()
        self.archive.close()


def compressed_members(path):
    """(arrays, None) of the compressed ``.npz`` at ``path``:
    :data:`MAPPED` as :class:`_MemberStream` (decompressed in order, by
    blocks), every other member of the format read through the loader's
    bounded reader (:class:`~solver.problem.archive.Archive`: headers
    checked against the declared sizes before decompressing)."""
    path = os.fspath(path)
    arrays = {}
    try:
        with open(path, "rb") as raw, Archive(raw, path) as archive:
            for name in archive:
                if name in MAPPED:
                    arrays[name] = _MemberStream(path, f"{name}.npy")
                elif name in KEYS:
                    arrays[name] = archive[name]
    except ProblemError:
        _close_members(arrays)
        raise
    except (OSError, ValueError, EOFError, zipfile.BadZipFile,
            zlib.error) as exc:
        _close_members(arrays)
        raise ProblemError(f"{path}: not a readable .npz "
                           f"({' '.join(str(exc).split())})") from None
    return arrays, None


def _close_members(arrays):
    for array in arrays.values():
        if isinstance(array, _MemberStream):
            array.close()


class _StreamedK:
    """An uncompressed problem file with K memory-mapped: ``problem`` is
    the validated problem with diag(K) in K's place (every check of the
    file's other arrays runs as on a whole load; max|K| is on the
    diagonal of an SPD K, so the load limit is K's); K itself is checked
    and written by blocks of rows (:meth:`write_padded`)."""

    def __init__(self, path, arrays, mapped):
        self.path, self.mapped = os.fspath(path), mapped
        n = int(np.asarray(arrays.get("K_shape", [0]))[0])
        try:
            self.indptr = np.array(arrays["K_indptr"], np.int64)
            self.indices, self.data = arrays["K_indices"], arrays["K_data"]
        except KeyError as exc:
            raise ProblemError(f"{path}: missing {exc.args[0]}") from None
        if self.indices.dtype.kind not in "iu" or \
                self.data.dtype.kind not in "fiu":
            raise ProblemError(f"{path}: K_indices must be integers and "
                               f"K_data numbers (the .npz format)")
        if len(self.indptr) != n + 1 or self.indptr[0] != 0 or \
                self.indptr[-1] != len(self.data) or \
                len(self.indices) != len(self.data) or \
                (np.diff(self.indptr) < 0).any() or \
                (n and np.diff(self.indptr).max() > n):
            raise ProblemError(f"{path}: K_indptr is not a valid CSR row "
                               f"pointer of K_shape and K_data")
        self.n = n
        diagonal = np.zeros(n)
        for r0, r1, cols, vals in self._blocks(0, n):
            rows = np.repeat(np.arange(r0, r1), np.diff(self.indptr[r0:r1 + 1]))
            on = cols == rows
            diagonal[rows[on]] = vals[on]
        if (diagonal <= 0).any():
            i = int(np.argmax(diagonal <= 0))
            raise ProblemError(f"{path}: K_data: diagonal entry {i} is "
                               f"{diagonal[i]:.3g}: the matrix is not "
                               f"positive definite")
        stand_in = dict(arrays, K_data=diagonal, K_indices=np.arange(
            n, dtype=np.int64), K_indptr=np.arange(n + 1, dtype=np.int64))
        self.problem = validate_arrays(stand_in)
        self.problem.source = self.path

    @classmethod
    def open(cls, path):
        """The streamed file: K's members mapped (uncompressed) or
        decompressed in order (compressed)."""
        arrays, mapped = stored_members(path) or compressed_members(path)
        try:
            return cls(path, arrays, mapped)
        except ProblemError:
            _close_members(arrays)
            if mapped is not None:
                arrays.clear()
                try:
                    mapped.close()
                except BufferError:  # a view still held: freed with it
                    pass
            raise

    def close(self):
        _close_members({0: self.indices, 1: self.data})
        self.indices = self.data = None
        if self.mapped is None:
            return
        try:
            self.mapped.close()
        except BufferError:  # a view still held: freed with it
            pass

    def _blocks(self, r0, r1):
        """(first row, end row, column indices, values) of K's rows r0:r1
        in blocks of about :data:`BLOCK_NNZ` entries, each checked
        (indices in range and increasing in every row, values finite);
        the mapped pages are given back after each block."""
        ptr = self.indptr
        while r0 < r1:
            end = int(np.searchsorted(ptr, ptr[r0] + BLOCK_NNZ, "right")) - 1
            end = min(max(end, r0 + 1), r1)
            a, b = int(ptr[r0]), int(ptr[end])
            cols = np.array(self.indices[a:b], np.int64)
            vals = np.array(self.data[a:b], float)
            if self.mapped is not None:
                self.mapped.madvise(mmap.MADV_DONTNEED)
            if len(cols) and (cols.min() < 0 or cols.max() >= self.n):
                raise ProblemError(f"{self.path}: K_indices: an index "
                                   f"outside 0..{self.n - 1}")
            if not np.isfinite(vals).all():
                raise ProblemError(f"{self.path}: K_data: a value is not "
                                   "finite")
            step = np.diff(cols)
            starts = ptr[r0 + 1:end] - a  # a row's first entry: no order
            step[starts[(starts > 0) & (starts <= len(step))] - 1] = 1
            if (step <= 0).any():
                raise _WholeLoad("K's column indices are not sorted and "
                                 "unique in every row")
            yield r0, end, cols, vals
            r0 = end

    def write_padded(self, path, layout, scale):
        """K in the padded numbering as PETSc's binary AIJ at ``path``,
        block by block (Layout.matrix's rows: K's rows renumbered, an
        identity row scaled by ``scale`` at each Dirichlet DOF); returns
        its number of entries."""
        r = layout.red_to_pad
        if len(r) > 1 and not np.all(r[1:] > r[:-1]):
            raise _WholeLoad("the nodes' order is not kept in dof_map")
        lengths = np.ones(layout.n, np.int64)
        lengths[r] = np.diff(self.indptr)
        nnz = int(lengths.sum())
        with open(path, "wb") as stream:
            bases = _start_matrix(stream, layout.n, lengths)
            row_ptr = np.r_[0, np.cumsum(lengths)]
            done = 0  # padded rows written
            for r0, r1, cols, vals in self._blocks(0, self.n):
                stop = layout.n if r1 == self.n else int(r[r1])
                rows = np.arange(done, stop)
                block = np.ones(len(rows), np.int64)
                mine = r[r0:r1] - done
                block[mine] = np.diff(self.indptr[r0:r1 + 1])
                ptr = np.r_[0, np.cumsum(block)]
                out_i, out_v = np.empty(ptr[-1], np.int64), \
                    np.empty(ptr[-1])
                copied = np.ones(ptr[-1], bool)
                dirichlet = np.ones(len(rows), bool)
                dirichlet[mine] = False
                at = ptr[:-1][dirichlet]
                copied[at] = False
                out_i[copied], out_v[copied] = r[cols], vals
                out_i[at], out_v[at] = rows[dirichlet], scale
                _write_entries(stream, bases, int(row_ptr[done]), out_i,
                               out_v)
                done = stop
        return nnz


class _RenumberedK:
    """K of a streamed file (:class:`_StreamedK`) written in the renumbered
    order (:func:`~solver.problem.renumber.renumbered` of its stand-in,
    ``problem``; ``order``: the nodes' order) without K in memory, by an
    external bucket sort (Knuth, *TAOCP* vol. 3, §5.4, external sorting):
    K's rows are read in the file's order by blocks, their rows and
    columns renumbered, and every entry appended to the bucket file of
    its new block of rows (≈ :data:`BLOCK_NNZ` entries each, more when
    there would be more buckets than :func:`_open_files`; in a temporary
    folder beside K.petsc); then each bucket is read back,
    sorted by (row, column) and written at its place in K.petsc. Peak
    memory: O(n) vectors plus one block; disk: one more K for the
    buckets, each removed once written. The file equals the whole-load
    conversion of the renumbered problem byte for byte."""

    def __init__(self, stream, order):
        from ..problem.renumber import dof_order

        self.stream = stream
        dofs = dof_order(stream.problem.dof_map, order)
        self.dof_new = np.empty(len(dofs), np.int64)
        self.dof_new[dofs] = np.arange(len(dofs))

    def write_padded(self, path, layout, scale):
        """As :meth:`_StreamedK.write_padded`, K's rows and columns in the
        renumbered padded numbering; returns its number of entries."""
        stream = self.stream
        new = layout.red_to_pad[self.dof_new]  # file's DOF -> padded row
        lengths = np.ones(layout.n, np.int64)
        lengths[new] = np.diff(stream.indptr)
        nnz = int(lengths.sum())
        row_ptr = np.r_[0, np.cumsum(lengths)]
        # buckets: consecutive padded rows of ≈ BLOCK_NNZ entries, or
        # more, so that every bucket file stays open (half the limit)
        size = max(BLOCK_NNZ, -(-nnz // _open_files()))
        cuts = np.searchsorted(row_ptr, np.arange(size, nnz, size),
                               "right") - 1
        bounds = np.unique(np.r_[0, cuts, layout.n])
        bucket_of = (np.searchsorted(bounds, np.arange(layout.n), "right")
                     - 1).astype(np.int32)
        index = np.int32 if layout.n < 2 ** 31 else np.int64
        entry = np.dtype([("row", index), ("col", index), ("val", "<f8")])
        with temporary_folder(".K-buckets-",
                              os.path.dirname(os.path.abspath(path))) as temp:
            names = [os.path.join(temp, f"{k}.bin")
                     for k in range(len(bounds) - 1)]
            files = [open(name, "wb") for name in names]
            try:
                for r0, r1, cols, vals in stream._blocks(0, stream.n):
                    rows = np.repeat(new[r0:r1],
                                     np.diff(stream.indptr[r0:r1 + 1]))
                    part = np.empty(len(rows), entry)
                    part["row"], part["col"], part["val"] = \
                        rows, new[cols], vals
                    del rows, cols, vals
                    which = bucket_of[part["row"]]
                    by = np.argsort(which, kind="stable")
                    part, which = part[by], which[by]
                    ends = np.searchsorted(which, np.arange(len(files) + 1))
                    for k in np.flatnonzero(np.diff(ends)):  # (write,
                        # not tofile: a full disk then says so, errno set)
                        files[k].write(part[ends[k]:ends[k + 1]].data)
                    del part, which, by
            finally:
                for file in files:
                    file.close()
            with open(path, "wb") as out:
                bases = _start_matrix(out, layout.n, lengths)
                dirichlet = np.ones(layout.n, bool)
                dirichlet[new] = False
                for k, name in enumerate(names):
                    self._write_bucket(out, np.fromfile(name, entry),
                                       bounds[k], bounds[k + 1], row_ptr,
                                       dirichlet, scale, bases)
                    os.unlink(name)  # the disk back as the file grows
        return nnz

    @staticmethod
    def _write_bucket(out, part, first, end, row_ptr, dirichlet, scale,
                      bases):
        """Rows first:end of K.petsc from their bucket ``part``: sorted by
        (row, column), an identity row (``scale``) at each Dirichlet row."""
        key = part["row"].astype(np.int64) * len(dirichlet) + part["col"]
        part = part[np.argsort(key, kind="stable")]
        del key
        a, b = int(row_ptr[first]), int(row_ptr[end])
        out_i, out_v = np.empty(b - a, np.int64), np.empty(b - a)
        copied = np.ones(b - a, bool)
        rows = np.arange(first, end)[dirichlet[first:end]]
        at = row_ptr[rows] - a
        copied[at] = False
        out_i[copied], out_v[copied] = part["col"], part["val"]
        out_i[at], out_v[at] = rows, scale
        _write_entries(out, bases, a, out_i, out_v)
