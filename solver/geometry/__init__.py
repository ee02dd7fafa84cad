"""Everything that makes gaps and frames (thesis §2.1): parametric and
polyline obstacles (:mod:`.curves.parametric`, :mod:`.curves.polyline`), the parameter
window from the body's extent (:mod:`.curves.window`), the order of Γc's nodes
(:mod:`.mesh`), the body's spline normals (:mod:`.curves.normals`) and the gaps
from the obstacle or along the body's normals (:mod:`.curves`). The contact
systems see only their output: per-node normals and gaps."""

from .curves import GapError, gap_along_normals, gap_from_obstacle
from .curves.normals import boundary_normals
from .curves.parametric import ParametricCurve, parse_expression
from .curves.polyline import PolylineCurve

__all__ = ["GapError", "gap_along_normals", "gap_from_obstacle",
           "boundary_normals", "ParametricCurve", "parse_expression",
           "PolylineCurve"]
