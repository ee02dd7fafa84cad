"""Everything that makes gaps and frames (thesis §2.1): 2D obstacle
curves, body normals and gap search (:mod:`.curves`), 3D obstacle
surfaces (:mod:`.surfaces`), the order of Γc's nodes (:mod:`.mesh`),
frames (:mod:`.frames`), the safe expression parser (:mod:`.expression`)
and the dual mortar (:mod:`.mortar`). The contact systems see only their
output: per-node frames and gaps."""

from .curves import GapError, gap_along_normals, gap_from_obstacle
from .curves.normals import boundary_normals
from .curves.parametric import ParametricCurve, parse_expression
from .curves.polyline import PolylineCurve

__all__ = ["GapError", "gap_along_normals", "gap_from_obstacle",
           "boundary_normals", "ParametricCurve", "parse_expression",
           "PolylineCurve"]
