"""Units, saving and small helpers shared by the thesis figures."""

from .. import figures
from ..figures import pyplot  # noqa: F401  (re-exported for the parts)

#: Units of the axis labels (see the module docstring).
LENGTH, FORCE, PRESSURE = "mm", "N", "MPa"

#: The convention in one sentence, for notebooks to print.
UNITS = ("Units: lengths in mm, E in MPa, plane strain per unit thickness; "
         "nodal forces in N (per mm of thickness), pressures and tractions "
         "in MPa = N/mm².")

DPI = 100


def save_png(fig, path):
    """Save ``fig`` to ``path`` at :data:`DPI` (the thesis figures')."""
    return figures.save_png(fig, path, dpi=DPI)


def panel_position(problem, axis=1):
    """Coordinate ``axis`` of the nodes of Γc (y for the block's edge)."""
    return problem.nodes[problem.contact_nodes, axis]

