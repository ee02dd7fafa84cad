"""Dual mortar couplings of two elastic bodies, computed once on the
undeformed interface (small deformation, small sliding): 2D segments
(:mod:`.segments`) and 3D triangles (:mod:`.triangles`), the bounding-box
pair search both use (:mod:`.search`) and what a coupling holds
(:mod:`.coupling`)."""

from .coupling import MortarCoupling, assemble_coupling, patch_pressure
from .search import box_pairs, candidate_pairs, default_reach, facet_reach
from .segments import (chain_order, mortar_coupling, nodal_normals,
                       node_to_segment, segment_normals)
from .triangles import (node_to_triangle, overlap_polygons, triangle_areas,
                        triangle_coupling)

__all__ = ["MortarCoupling", "assemble_coupling", "patch_pressure",
           "box_pairs",
           "candidate_pairs", "default_reach", "facet_reach", "chain_order",
           "mortar_coupling", "nodal_normals", "node_to_segment",
           "segment_normals", "overlap_polygons", "triangle_areas",
           "triangle_coupling", "node_to_triangle"]
