r"""Counterparts of the thesis's Fig. 1-27, for the notebooks
(``notebooks/README.md`` lists which figure each stands for). Each
function draws one figure in the thesis's layout, returns the Figure and,
given ``path``, saves it as a PNG (100 dpi); units as
:data:`solver.output.figures.UNITS`. The sketches (Fig. 1, 2, 3, 16, 17)
are drawn from the problem data where there is data (Fig. 3 from the
exported mesh, Fig. 16 from the bar's computed load path)."""

from .common import DPI, FORCE, LENGTH, PRESSURE, UNITS, panel_position, save_png  # noqa: F401
from .sketches import ncp_functions, boundary_conditions_sketch  # noqa: F401
from .model import outline, obstacle_for_display, contact_offset, model_problem  # noqa: F401
from .frictionless import nice_scale, deformed_and_directions, convergence, pressure_along_contact, mesh_comparison  # noqa: F401
from .bar import load_increment, bar_sketch, BAR_QUANTITIES, bar_values, bar_history  # noqa: F401
from .friction import tractions_along_contact, fit_y, tangential_displacement  # noqa: F401

__all__ = ["LENGTH", "FORCE", "PRESSURE", "UNITS",
           "ncp_functions", "boundary_conditions_sketch", "model_problem",
           "deformed_and_directions", "obstacle_for_display",
           "convergence", "pressure_along_contact", "mesh_comparison",
           "load_increment", "bar_sketch", "bar_history",
           "tractions_along_contact", "tangential_displacement"]
