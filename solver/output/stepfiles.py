"""Friction steps written to disk as they complete (bounded memory).

:class:`StepWriter` receives each completed load step (a friction run's
``on_step``), writes its VTK file ``steps/step_NNNN.vtu`` at once and its
arrays into one preallocated memory-mapped ``.npy`` scratch file per
field. :meth:`StepWriter.finish`, also after a run that stops early, then
streams ``result.npz`` of the completed steps from the scratch files
(stored, not deflated: deflating gains little and would slow the finish,
which an interrupted run must complete before it is killed; docs/mpi.md,
"Stopping a run") and writes the ParaView index ``result.pvd``."""

import os
import shutil
import tempfile
import zipfile

import numpy as np
from numpy.lib import format as npy

from .folder import atomic_path
from .vtk import step_mesh, write_pvd

__all__ = ["StepWriter"]

#: Rows of a field copied into the archive at a time.
CHUNK_BYTES = 1 << 24


class StepWriter:
    """Stream the completed steps of a friction run into ``folder``."""

    def __init__(self, folder, problem, total_steps, tangents=None):
        self.folder, self.problem = folder, problem
        #: (Nc, d − 1, d) tangent frames over Γc, if known: the step files
        #: of a 3D run then hold the friction traction as a 3-vector
        self.tangents = tangents
        self.total, self.count = int(total_steps), 0
        self.scratch = tempfile.mkdtemp(prefix=".tmp-steps-",
                                        dir=folder.path)
        self.arrays, self.timesteps = {}, []

    def __call__(self, fields):
        """One completed step (called in step order). Interrupted before
        it is counted (Ctrl-C, SIGTERM), it leaves no step file behind: the
        folder then lists exactly the steps of ``result.npz``."""
        k, name = self.count, None
        try:
            for key, value in fields.items():
                value = np.asarray(value)
                if key not in self.arrays:
                    self.arrays[key] = npy.open_memmap(
                        os.path.join(self.scratch, key + ".npy"), mode="w+",
                        dtype=value.dtype, shape=(self.total,) + value.shape)
                self.arrays[key][k] = value
            if self.problem.kind == "mesh":
                name = os.path.join("steps", f"step_{k + 1:04d}.vtu")
                os.makedirs(os.path.join(self.folder.path, "steps"),
                            exist_ok=True)
                import meshio

                with atomic_path(self.folder.file(name)) as tmp:
                    meshio.write(tmp, step_mesh(self.problem, fields,
                                                 self.tangents),
                                 file_format="vtu")
                self.timesteps.append((float(fields["load_factor"]), name))
            self.count = k + 1
        except BaseException:
            if self.count == k and name is not None:
                self._forget(name)
            raise

    def _forget(self, name):
        """Remove the file of a step that was not counted."""
        if self.timesteps and self.timesteps[-1][1] == name:
            self.timesteps.pop()
        if name in self.folder.files:
            self.folder.files.remove(name)
        try:
            os.remove(os.path.join(self.folder.path, name))
        except OSError:
            pass

    def finish(self, extra):
        """Write ``result.npz`` (the completed steps and ``extra`` arrays)
        and ``result.pvd``; remove the scratch files."""
        try:
            with atomic_path(self.folder.file("result.npz")) as tmp:
                with zipfile.ZipFile(tmp, "w", zipfile.ZIP_STORED,
                                     allowZip64=True) as archive:
                    for key, array in self.arrays.items():
                        _write_member(archive, key, array[:self.count])
                    for key, value in extra.items():
                        _write_member(archive, key, np.asarray(value))
            if self.timesteps:
                with atomic_path(self.folder.file("result.pvd")) as tmp:
                    write_pvd(tmp, self.timesteps)
        finally:
            self.close()

    def close(self):
        """Drop the scratch files (also when the run failed)."""
        self.arrays = {}
        shutil.rmtree(self.scratch, ignore_errors=True)


def _write_member(archive, key, array):
    """``key.npy`` in the archive, copied in chunks (as ``np.savez``)."""
    header = {"descr": npy.dtype_to_descr(array.dtype),
              "fortran_order": False, "shape": array.shape}
    with archive.open(key + ".npy", "w", force_zip64=True) as stream:
        npy.write_array_header_2_0(stream, header)
        if array.ndim == 0 or array.size == 0:
            stream.write(np.ascontiguousarray(array).tobytes())
            return
        row = max(1, array[0].nbytes)
        step = max(1, CHUNK_BYTES // row)
        for first in range(0, len(array), step):
            stream.write(np.ascontiguousarray(
                array[first:first + step]).tobytes())
