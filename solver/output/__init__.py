"""Output of solves: result files (:mod:`.files`) and figures
(:mod:`.figures`, imported lazily because it needs matplotlib)."""

from .files import (atomic_path, summary_of, write_result, write_summary,
                    write_vtk)

__all__ = ["atomic_path", "summary_of", "write_result", "write_summary",
           "write_vtk"]
