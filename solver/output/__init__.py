"""Output of solves: result files (:mod:`.files`) and figures
(:mod:`.figures`, imported lazily because it needs matplotlib)."""

from .files import (atomic_path, friction_summary_of, summary_of,
                    write_friction_result, write_result, write_summary,
                    write_vtk, write_vtk_series)

__all__ = ["atomic_path", "summary_of", "write_result", "write_summary",
           "write_vtk", "friction_summary_of", "write_friction_result",
           "write_vtk_series"]
