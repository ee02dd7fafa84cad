"""The output folder of one run: locked, never overwriting the input,
cleared of an earlier run's files, and marked with the run's status.

``summary.json`` is written first with ``"status": "running"`` and last
with the final status and the files the run wrote, so a folder is either
complete or says that it is not, even after ``kill -9``. Every file is
written to a temporary name and renamed when complete, with the
permissions the umask allows (never the 0600 of :func:`tempfile.mkstemp`)."""

import contextlib
import fcntl
import glob
import json
import os
import tempfile

from ..errors import SolverError

__all__ = ["OutputFolder", "atomic_path", "OutputError"]

#: Names a run may write (besides the figures its summary lists).
OUTPUT_NAMES = ("summary.json", "result.npz", "result.vtu", "result.pvd",
                "result.pvtu", "contact.npz")
#: The pieces of a partitioned run's ``result.pvtu``, one per rank.
PIECE_PATTERN = "result-[0-9]*.vtu"
STEP_PATTERN = os.path.join("steps", "step_[0-9][0-9][0-9][0-9]*.vtu")


class OutputError(SolverError):
    """The output folder cannot be used (in use, or it holds the input)."""


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path``; on success give it the
    umask's permissions and rename it over ``path``, else delete it."""
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=".tmp-", suffix=os.path.splitext(
        path)[1], dir=folder)
    os.close(fd)
    try:
        yield tmp
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


class OutputFolder:
    """Create (if needed) and lock ``path`` for one run reading ``inputs``;
    OutputError if another run holds it or an input would be overwritten."""

    def __init__(self, path, inputs=()):
        self.path = os.fspath(path)
        self.created, folder = [], os.path.abspath(self.path)
        while folder and not os.path.exists(folder):
            self.created.append(folder)
            folder = os.path.dirname(folder)
        os.makedirs(self.path, exist_ok=True)
        self.files = []
        self._fd = os.open(self.path, os.O_RDONLY | os.O_DIRECTORY)
        try:
            fcntl.flock(self._fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(self._fd)
            raise OutputError(f"output folder {self.path} is in use by "
                              "another run; wait for it or choose another "
                              "-o") from None
        try:
            self._check_inputs(inputs)
            self._probe()
        except BaseException:
            self.release(remove_created=True)
            raise

    def _ours(self):
        """Files in the folder that a run of ours wrote or may write: those
        an earlier summary lists, the fixed names and the step files."""
        names = set(OUTPUT_NAMES)
        names.update(glob.glob(STEP_PATTERN, root_dir=self.path))
        names.update(glob.glob(PIECE_PATTERN, root_dir=self.path))
        try:
            with open(os.path.join(self.path, "summary.json")) as stream:
                listed = json.load(stream).get("files", [])
            names.update(name for name in listed if isinstance(name, str)
                         and not os.path.isabs(name) and ".." not in name)
        except (OSError, ValueError, AttributeError):
            pass
        return sorted(names)

    def _check_inputs(self, inputs):
        for name in inputs:
            target = os.path.realpath(name)
            for ours in self._ours() + ["steps"]:
                path = os.path.join(self.path, ours)
                if os.path.realpath(path) == target or (
                        os.path.exists(path) and os.path.samefile(path,
                                                                  target)):
                    raise OutputError(
                        f"the input {name} is the output file {path}; it "
                        "would be overwritten: choose another -o")

    def _probe(self):
        try:  # a real test (os.access is always true for root)
            fd, probe = tempfile.mkstemp(prefix=".tmp-", dir=self.path)
        except OSError as exc:
            raise PermissionError(exc.errno, exc.strerror or "cannot write",
                                  self.path) from None
        os.close(fd)
        os.unlink(probe)

    def clear_stale(self):
        """Remove an earlier run's outputs (only names a run of ours writes)
        and the temporary files of a run killed before it could (``kill -9``,
        or ``mpiexec`` after its grace): the lock says no run writes them now.
        """
        self.sweep_temporaries()
        for name in self._ours():
            path = os.path.join(self.path, name)
            if os.path.isfile(path) or os.path.islink(path):
                os.unlink(path)
        with contextlib.suppress(OSError):
            os.rmdir(os.path.join(self.path, "steps"))

    def sweep_temporaries(self):
        """Remove temporary files a cut-short write may have left (a signal
        can land between creating a temporary name and guarding it)."""
        import shutil

        for pattern in (".tmp-*", os.path.join("steps", ".tmp-*")):
            for name in glob.glob(pattern, root_dir=self.path):
                path = os.path.join(self.path, name)
                if os.path.isdir(path):
                    shutil.rmtree(path, ignore_errors=True)
                else:
                    with contextlib.suppress(OSError):
                        os.unlink(path)

    def file(self, name):
        """The path of output ``name``, recorded as written by this run."""
        if name not in self.files:
            self.files.append(name)
        return os.path.join(self.path, name)

    def release(self, remove_created=False):
        """Unlock; with ``remove_created``, remove the folders this run
        created if they are still empty."""
        if self._fd is not None:
            os.close(self._fd)  # closing the last descriptor unlocks
            self._fd = None
        if remove_created:
            for folder in self.created:  # innermost first
                try:
                    os.rmdir(folder)
                except OSError:
                    break
            self.created = []
