"""Units, saving and small helpers shared by the thesis figures."""

from ..figures import _pyplot  # noqa: F401  (re-exported for the parts)
from ..figures import _save as save_png

#: Units of the axis labels (see the module docstring).
LENGTH, FORCE, PRESSURE = "mm", "N", "MPa"

#: The convention in one sentence, for notebooks to print.
UNITS = ("Units: lengths in mm, E in MPa, plane strain per unit thickness; "
         "nodal forces in N (per mm of thickness), pressures and tractions "
         "in MPa = N/mm².")

DPI = 100


def _save(fig, path):
    return save_png(fig, path, dpi=DPI)


def _position(problem, axis=1):
    """Coordinate ``axis`` of the nodes of Γc (y for the block's edge)."""
    return problem.nodes[problem.contact_nodes, axis]

