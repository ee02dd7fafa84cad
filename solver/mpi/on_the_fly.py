r"""Friction on the full system of a ``.npz`` under ``mpiexec``, by
conversion on the fly: ``mpiexec -n N python -m solver X.npz --engine
petsc --system full --ksp gamg --friction F`` converts ``X.npz`` to a
partitioned folder (:func:`solver.mpi.convert.convert`) in a temporary
folder, then runs that folder's Krylov friction
(:mod:`solver.mpi.krylov_friction`) unchanged, and removes the folder.

Why a conversion and not rank 0's rows scattered to the ranks: the
folder's set-up (:mod:`.partitioned_full`) reads each rank's rows of K
and f, its contact nodes, frames and mass rows from the files; feeding it
from rank 0 instead would need a second set-up for the same solve.
The conversion streams K in blocks of rows (O(n) vectors and one block
in memory on rank 0), while the other ranks wait idle in the service
(:meth:`~solver.mpi.service.Service.serve`), so the first command the
folder's solve sends them is the barrier after it. The answer is the
folder run's by construction, and the folder run's is the serial run's
(tests/test_mpi_krylov_friction*.py, tests/test_mpi_npz_friction.py).

The temporary folder (``.NAME-converted-XXXXXX`` beside the outputs, or
in ``$TMPDIR``) is removed when the run ends: on success, on an error,
on a full disk (the conversion's ``OSError`` reaches the command line's
disk-full line, exit 4) and on a stop signal (the command line's
signals are exceptions, so the removal runs before the exit; Open MPI's
``mpiexec`` kills the ranks two seconds after forwarding SIGTERM). Only
a SIGKILL leaves it: its name says what it is."""

import contextlib
import errno
import os
import time

__all__ = ["converted_folder", "PREFIX"]

#: The temporary folder's name: ``.{PREFIX}XXXXXX``-like, hidden, beside
#: the outputs (``tempfile.mkdtemp``'s random suffix).
PREFIX = "converted-"


@contextlib.contextmanager
def converted_folder(source, gap="obstacle", workdir=None, name="problem"):
    """Convert ``source`` (a ``.npz`` path, streamed, or a loaded problem)
    to a partitioned folder in a new temporary folder under ``workdir``
    (``$TMPDIR`` when None) with gaps by ``gap``; yield ``(folder, info)``,
    ``info`` saying what was converted (``summary.json``'s
    ``"converted"``); remove the folder on leaving, however the block
    ends (an exception or a stop signal included)."""
    from .convert import convert, temporary_folder

    with temporary_folder(f".{name}-{PREFIX}", workdir) as root:
        folder = os.path.join(root, "folder")
        clock, cpu = time.perf_counter(), time.process_time()
        try:
            meta = convert(source, folder, gap)
        except OSError as exc:
            raise _with_errno(exc, root) from exc
        info = dict(
            source=os.fspath(source) if isinstance(
                source, (str, os.PathLike)) else getattr(source, "source",
                                                         None),
            folder=folder, gap=gap, rollers=True,
            streamed=bool(meta.get("streamed", False)),
            renumbered=bool(meta.get("renumbered", False)),
            rows=int(meta["n"]), nnz=int(meta["nnz"]),
            seconds=round(time.perf_counter() - clock, 3),
            cpu_seconds=round(time.process_time() - cpu, 3),
            removed=True)
        yield folder, info


#: Free bytes below which a short write is taken for a full disk.
FULL = 1 << 20


def _with_errno(exc, root):
    """The conversion's ``OSError`` with an errno and a file name (the
    temporary folder's where it has none), for the command line's one
    line: NumPy's ``tofile`` reports a short write
    (a full disk) as "N requested and M written", without either; it is
    ENOSPC when the disk under ``root`` has (almost) no room left, else
    EIO."""
    if exc.errno is not None:  # a write into an open file names none
        return exc if exc.filename else OSError(
            exc.errno, exc.strerror or os.strerror(exc.errno), root)
    try:
        disk = os.statvfs(root)
        full = disk.f_bavail * disk.f_frsize < FULL
    except OSError:
        full = False
    code = errno.ENOSPC if full else errno.EIO
    return OSError(code, f"{os.strerror(code)} ({exc})"
                   if not full else os.strerror(code), root)
