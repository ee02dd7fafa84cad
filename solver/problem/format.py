r"""The ``.npz`` problem format: its version, keys and size limits.

A problem file is a plain NumPy ``.npz`` archive of numeric and unicode
arrays (no pickled objects), written by :func:`solver.problem.save_problem`
and read and validated by :func:`solver.problem.load_problem`. Two kinds
share it: ``"mesh"`` (a finite element model and a rigid obstacle, or two
bodies; the solver computes gaps and normals, thesis §2.1) and
``"discrete"`` (given gaps and normals, the thesis's §6 bar). d = 2 or 3
is the number of columns of ``contact_dofs``. Notation (thesis §3.2): Ñ
reduced DOFs, Nc contact nodes, in any order.

Versions (docs/npz-format.md, "Versions"): 1 is the 2D layout, 3 adds 3D,
4 two elastic bodies in contact (2D segments or 3D triangles); 2 was
never written. The table
:data:`KEYS` is the specification; ``docs/npz-format.md`` is generated
from it (:func:`format_table`)."""

__all__ = ["FORMAT_VERSION", "READ_VERSIONS", "DIMS", "KEYS", "KINDS",
           "ONLY_2D", "TWO_BODY", "TWO_BODY_VERSION", "META_REQUIRED",
           "SYMMETRY_RTOL", "MAX_TEXT", "MAX_META_DEPTH", "MAX_INT_DIGITS",
           "MAX_STAGES", "MAX_OBSTACLE_POINTS", "MAX_TOTAL_BYTES",
           "LOAD_LIMIT", "format_table"]

#: Version of the ``.npz`` layout written by ``save_problem``.
FORMAT_VERSION = 4

#: Versions the reader accepts (2 reads like 1; see the module doc).
READ_VERSIONS = (1, 2, 3, 4)

#: First version that may carry the two-body keys :data:`TWO_BODY`.
TWO_BODY_VERSION = 4

#: Space dimensions: 2 from version 1 on, 3 from version 3 on.
DIMS = {2: 1, 3: 3}

#: Relative tolerance of the symmetry check of K and M.
SYMMETRY_RTOL = 1e-10

#: Key specification: name -> (which kinds need it, dtype, shape, meaning).
#: "all" = both kinds; "mesh"/"discrete" = required for that kind only and
#: refused for the other; "mesh3d" = required in a 3D mesh file, refused
#: elsewhere; "optional" = may be absent in either kind (the 2D obstacle
#: keys are refused in 3D, see :data:`ONLY_2D`); "two-body" = optional in a
#: mesh file of version 4, refused elsewhere (:data:`TWO_BODY`; in 3D they
#: replace contact_faces and obstacle_surface).
KEYS = {
    "format_version": ("all", "int", "()",
                       "layout version: 4 (written); 1, 2, 3 and 4 are read"),
    "kind": ("all", "str", "()", '"mesh" or "discrete"'),
    "meta": ("all", "str", "()",
             "JSON object: E, nu, plane (strain|stress; 2D only), load, "
             "mesh, description, versions (required fields: E, nu, plane, "
             "load, mesh for a 2D mesh; E, nu, load, mesh for a 3D mesh; "
             "description for kind discrete); a two-body file also needs "
             "bodies (a list, index = body id, of {name, E, nu}), "
             "slave_body and master_body (body ids; a list with one per "
             "pair if the pairs differ), and E, nu are then those of the "
             "slave body"),
    "K_data": ("all", "float", "(nnz,)",
               "reduced stiffness K (Ñ×Ñ, Dirichlet DOFs eliminated, "
               "symmetric positive definite, or semidefinite with rigid-body "
               "modes only: a body held by contact) in CSR: values"),
    "K_indices": ("all", "int", "(nnz,)", "CSR column indices of K"),
    "K_indptr": ("all", "int", "(Ñ+1,)", "CSR row pointers of K"),
    "K_shape": ("all", "int", "(2,)", "(Ñ, Ñ)"),
    "f": ("all", "float", "(Ñ,)",
          "load vector for the full load (load step κ applies κ/κc·f)"),
    "M_data": ("all", "float", "(nnzM,)",
               "boundary matrix on Γc, M_ij = ∫Γc φi φj (thesis (80)), "
               "Nc×Nc in CSR: values (two bodies: Γc = the slave "
               "boundary; the mortar D, M are computed by the solver)"),
    "M_indices": ("all", "int", "(nnzM,)", "CSR column indices of M"),
    "M_indptr": ("all", "int", "(Nc+1,)", "CSR row pointers of M"),
    "M_shape": ("all", "int", "(2,)", "(Nc, Nc)"),
    "contact_dofs": ("all", "int", "(Nc, d)",
                     "reduced DOF index of the x, y (and z) component of "
                     "each contact node (in the order of contact_nodes); -1 "
                     "where the component is a Dirichlet DOF (such a node "
                     "is a support, not a contact node, and only enters M "
                     "— unless it is a roller: see below); d = 2 or 3 is "
                     "the problem's dimension"),
    "nodes": ("mesh", "float", "(n_nodes, d)", "node coordinates"),
    "cells": ("mesh", "int", "(n_cells, d+1) or (n_cells, 2^d)",
              "first-order cells as node indices, one kind per file: "
              "triangles or quadrilaterals (2D; quadrilaterals counter-"
              "clockwise and convex), tetrahedra or hexahedra (3D, VTK/SfePy "
              "3_8 node order: 0-1-2-3 counter-clockwise seen from 4-5-6-7, "
              "node k + 4 above node k; all of one orientation); no cell "
              "flat at a corner; a 3D two-body file takes tetrahedra "
              "only"),
    "dof_map": ("mesh", "int", "(Ñ, 2)",
                "(node, component) of each reduced DOF; component 0 = x, "
                "1 = y, 2 = z"),
    "u_prescribed": ("mesh", "float", "(n_nodes, d)",
                     "values of the Dirichlet DOFs (entries of free DOFs "
                     "are 0)"),
    "contact_nodes": ("mesh", "int", "(Nc,)",
                      "nodes of Γc; in 2D ordered along Γc (consecutive "
                      "nodes share a boundary edge; a Γc of separate parts "
                      "lists them chain after chain, a new chain starting "
                      "where two consecutive nodes share none, each of at "
                      "least 2 nodes), in 3D the vertices of "
                      "contact_faces in any order; in a two-body file the "
                      "slave nodes, pair by pair, each pair's chain in the "
                      "direction of its mortar_slave segments"),
    "obstacle_x": ("optional", "str", "()",
                   "x(t) of the obstacle Γo(t) (2D mesh kind: either "
                   "obstacle_x and obstacle_y, or obstacle_points)"),
    "obstacle_y": ("optional", "str", "()", "y(t) of the obstacle Γo(t)"),
    "obstacle_points": ("optional", "float", "(n, 2)",
                        "vertices of a polyline obstacle, parametrised by "
                        "arc length (instead of obstacle_x, obstacle_y)"),
    "obstacle_curves": ("optional", "str", "()",
                        "several obstacles (2D mesh kind only, instead of "
                        "the other obstacle keys): a JSON list of 1 to 64 "
                        'curves, each {"x": "x(t)", "y": "y(t)"} (optional '
                        '"t_range", "search_interval") or {"points": '
                        '[[x, y], ...]} (optional "search_interval"); each '
                        "node takes the curve of smallest gap, and a node no "
                        "curve reaches is excluded (docs/npz-format.md, "
                        "\"Several obstacles\")"),
    "obstacle_t_range": ("optional", "float", "(2,)",
                         "admissible parameter interval [t0, t1] (2D mesh "
                         "kind only; absent = unbounded)"),
    "obstacle_search_interval": ("optional", "float", "(2,)",
                                 "parameter interval [t0, t1] searched for "
                                 "the gaps (2D mesh kind only; absent = found "
                                 "from the body's extent; CLI: "
                                 "--search-interval)"),
    "contact_faces": ("mesh3d", "int", "(n_faces, 3) or (n_faces, 4)",
                      "3D mesh kind only (required there): the contact "
                      "surface as triangles (of tetrahedra) or "
                      "quadrilaterals (of hexahedra) of contact_nodes "
                      "(global node ids), each a face of one cell, oriented "
                      "so that the right-hand rule gives the body's outward "
                      "normal; every contact node is a vertex of one"),
    "obstacle_surface": ("mesh3d", "str", "()",
                         "3D mesh kind only (required there): the rigid "
                         "obstacle as a JSON surface spec, kind plane, "
                         "sphere, graph, parametric, rectangle, polygon or "
                         "several "
                         "(docs/npz-format.md, solver.geometry.surfaces)"),
    "body": ("two-body", "int", "(n_nodes,)",
             "body id (0 … B−1, each used) of every node; the bodies share "
             "no node and no cell, so K is block-diagonal. Absent = one "
             "body (all 0)"),
    "mortar_slave": ("two-body", "int", "(n_s, d)",
                     "slave interface facets as global node ids. 2D: "
                     "segments (a, b), boundary edges of the mesh with the "
                     "body on the LEFT of a→b (its outward normal is (t_y, "
                     "−t_x)/|t|, t = x_b − x_a); each pair's segments form "
                     "one open chain, listed in contact_nodes in their "
                     "direction. 3D: triangles, each a face of one "
                     "tetrahedron, oriented so that the right-hand rule gives "
                     "the body's outward normal (as contact_faces); "
                     "contact_nodes are their vertices, pair by pair. "
                     "Replaces the obstacle keys (refused with it; in 3D "
                     "also contact_faces)"),
    "mortar_master": ("two-body", "int", "(n_m, d)",
                      "master interface facets, oriented like "
                      "mortar_slave, in another body than the slave "
                      "facets of their pair; needs mortar_slave"),
    "mortar_slave_pair": ("two-body", "int", "(n_s,)",
                          "contact pair (interface) of each slave facet, "
                          "0 … P−1 (absent = all 0: one pair)"),
    "mortar_master_pair": ("two-body", "int", "(n_m,)",
                           "contact pair of each master facet (absent = "
                           "all 0)"),
    "load_path": ("optional", "float", "(n_stages, Ñ)",
                  "load vectors at the ends of the load stages of a friction "
                  "run; the load goes linearly from the previous end (zero "
                  "at the start); the last row equals f. Absent: one stage, "
                  "step κ applies κ/κc·f"),
    "load_path_steps": ("optional", "int", "(n_stages,)",
                        "load steps of each stage (>= 1); with load_path"),
    "load_path_friction": ("optional", "float", "(n_stages,)",
                           "multiplier of f_c in each stage (>= 0; e.g. 0 "
                           "for a frictionless first stage); with "
                           "load_path"),
    "load_path_prescribed": ("optional", "float", "(n_stages, n_nodes, d)",
                             "Dirichlet values at the stage ends (mesh kind "
                             "only; absent: u_prescribed scaled like the "
                             "load)"),
    "gap": ("discrete", "float", "(Nc,)",
            "initial gap s of each contact node along its normal"),
    "normal": ("discrete", "float", "(Nc, d)",
               "unit normal ν of each contact node, pointing from the body "
               "towards the obstacle"),
}

KINDS = ("mesh", "discrete")

#: Keys a 3D file may not carry (the 2D obstacle curve).
ONLY_2D = ("obstacle_x", "obstacle_y", "obstacle_points", "obstacle_t_range",
           "obstacle_search_interval", "obstacle_curves")

#: The two-body keys (version 4, mesh kind only; docs/npz-format.md).
TWO_BODY = ("body", "mortar_slave", "mortar_master", "mortar_slave_pair",
            "mortar_master_pair")

#: Fields of ``meta`` each kind needs (a 3D mesh needs no ``plane``).
META_REQUIRED = {"mesh": ("E", "nu", "plane", "load", "mesh"),
                 "mesh3d": ("E", "nu", "load", "mesh"),
                 "discrete": ("description",)}

# Size limits of the reader (``solver.problem.load``). A bad file costs no
# more memory than a good one of the sizes it declares: every array's size
# follows from a few declared dimensions (Ñ from K_shape, Nc from M_shape,
# the number of nodes from ``nodes``), and these are bounded here.

#: Most characters of a text key (the obstacle expressions are limited
#: further, to 1000, by :mod:`solver.geometry.curves.parametric`).
MAX_TEXT = 1_000_000

#: Deepest nesting of lists and objects in the ``meta`` JSON.
MAX_META_DEPTH = 32

#: Most digits of an integer in the ``meta`` JSON.
MAX_INT_DIGITS = 30

#: Most load stages of a ``load_path``.
MAX_STAGES = 100_000

#: Most vertices of a polyline obstacle.
MAX_OBSTACLE_POINTS = 10_000_000

#: Largest accepted load: ‖f‖₂·max(k, 1/k) ≤ LOAD_LIMIT, k = max|K_ij|,
#: for ``f`` and every stage of ``load_path``
#: (:func:`solver.problem.checks.check_load`): the solver squares forces,
#: K times forces and displacements, and squares overflow above
#: √(max double) ≈ 1.3e154 (docs/npz-format.md, "Validation").
LOAD_LIMIT = 1e150

#: Most bytes the arrays of one file may occupy once read (16 GiB; the
#: largest benchmark, 916 000 DOFs, needs well under 1 GiB).
MAX_TOTAL_BYTES = 16 * 2 ** 30


def format_table():
    """The key specification as a Markdown table (for the docs)."""
    lines = ["| key | needed in | dtype | shape | meaning |",
             "|---|---|---|---|---|"]
    for key, (need, dtype, shape, doc) in KEYS.items():
        need = {"all": "both kinds", "mesh": "mesh only",
                "discrete": "discrete only", "mesh3d": "3D mesh only",
                "optional": "optional",
                "two-body": "two-body (optional)"}[need]
        lines.append(f"| `{key}` | {need} | {dtype} | {shape} | {doc} |")
    return "\n".join(lines)
