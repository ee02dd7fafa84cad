"""Reading problem files (through the bounded, lazy
:class:`~solver.problem.archive.Archive`) and writing them."""

import dataclasses
import os
import tempfile

import numpy as np
import scipy

from ..errors import ProblemError
from .archive import Archive
from .core import validate_arrays
from .format import FORMAT_VERSION

__all__ = ["load_problem", "save_problem"]


def load_problem(path):
    """The :class:`ContactProblem` of the ``.npz`` file at ``path`` (written
    by :func:`save_problem`), read safely (:mod:`.archive`) and validated.

    ProblemError if the file cannot be read, is not an ``.npz`` archive,
    holds pickled objects or members the format does not name, declares
    sizes its dimensions do not allow, or any key is missing, unexpected
    or malformed."""
    path = os.fspath(path)
    if os.path.isdir(path):  # a partitioned problem (python -m solver convert)
        from .partitioned import PartitionedProblem

        return PartitionedProblem(path)
    try:
        with open(path, "rb") as stream:
            magic = stream.read(6)
    except FileNotFoundError:
        raise ProblemError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise ProblemError(f"{path}: is a directory, not a file") from None
    except PermissionError:
        raise ProblemError(f"{path}: permission denied") from None
    except OSError as exc:
        raise ProblemError(f"{path}: cannot be read ({exc})") from None
    if magic.startswith(b"\x93NUMPY"):
        raise ProblemError(f"{path}: a single .npy array, not an .npz "
                           "problem file")
    if not magic.startswith(b"PK"):
        raise ProblemError(f"{path}: not an .npz archive (no zip header)")
    with open(path, "rb") as stream, Archive(stream, path) as archive:
        problem = validate_arrays(archive)
    problem.source = path
    return problem


def save_problem(path, problem):
    """Validate ``problem`` and write it to ``path`` atomically (a
    temporary file renamed over ``path`` when complete), with the library
    versions added to ``meta["versions"]``."""
    path = os.fspath(path)
    versions = dict(problem.meta.get("versions", {}))
    versions.update(format=FORMAT_VERSION, numpy=np.__version__,
                    scipy=scipy.__version__)
    meta = dict(problem.meta, versions=versions)
    arrays = dataclasses.replace(problem, meta=meta).to_arrays()
    validate_arrays(arrays)
    directory = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=".tmp-", suffix=".npz", dir=directory)
    try:
        with os.fdopen(fd, "wb") as stream:
            np.savez_compressed(stream, **arrays)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path
