"""Everything that makes gaps and frames (thesis §2.1): parametric and
polyline obstacles (:mod:`.obstacle`, :mod:`.polyline`), the parameter
window from the body's extent (:mod:`.window`), the order of Γc's nodes
(:mod:`.mesh`), the body's spline normals (:mod:`.normals`) and the gaps
from the obstacle or along the body's normals (:mod:`.gap`). The contact
systems see only their output: per-node normals and gaps."""

from .gap import GapError, gap_along_normals, gap_from_obstacle
from .normals import boundary_normals
from .obstacle import ParametricCurve, parse_expression
from .polyline import PolylineCurve

__all__ = ["GapError", "gap_along_normals", "gap_from_obstacle",
           "boundary_normals", "ParametricCurve", "parse_expression",
           "PolylineCurve"]
