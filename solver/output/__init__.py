"""Output of solves: everything a solve writes (:mod:`.write`), the output
folder (:mod:`.folder`), result files (:mod:`.files`), VTK (:mod:`.vtk`), friction steps streamed to disk
(:mod:`.stepfiles`) and figures (:mod:`.figures`, imported lazily because
it needs matplotlib)."""

from .files import (friction_summary_of, summary_of, write_result,
                    write_summary)
from .folder import OutputError, OutputFolder, atomic_path
from .stepfiles import StepWriter
from .vtk import write_pvd, write_vtk
from .write import StepOutputs, write_all

__all__ = ["atomic_path", "OutputFolder", "OutputError", "StepWriter",
           "summary_of", "write_result", "write_summary", "write_vtk",
           "write_pvd", "friction_summary_of", "StepOutputs", "write_all"]
