r"""The ``.npz`` problem format: its version, keys and size limits.

A problem file carries everything the contact solver needs and nothing it
must guess. SfePy problem files (``sfepy_problems/``) write it through
:func:`solver.problem.save_problem`; ``python -m solver`` reads it through
:func:`solver.problem.load_problem`, which validates every key and raises
:class:`~solver.errors.ProblemError` naming the offending key.

Files are plain NumPy ``.npz`` archives (zip files of ``.npy`` members) of
numeric and unicode arrays; pickled objects are refused.

Two kinds of problem share the format:

``kind = "mesh"``
    A 2D finite element model (the thesis's §4 body): the reduced stiffness
    matrix, the mesh, the map from reduced DOFs to nodes, the contact nodes
    ordered along Γc and a rigid parametric obstacle. Gaps and normals are
    computed by the solver (thesis §2.1).
``kind = "discrete"``
    A small discrete system without a mesh (the thesis's 2-DOF bar of §6):
    the stiffness, the load, and for each contact node its two DOFs, its
    gap *s* and the unit normal ν along which *s* is measured.

Notation (thesis §3.2): Ñ reduced DOFs (Dirichlet DOFs eliminated), Nc
contact nodes. The thesis orders contact nodes first; this format does not
need to: ``contact_dofs`` says where each contact node's DOFs are.

Keys (format version 1)
-----------------------
The table :data:`KEYS` below is the specification; ``docs/npz-format.md``
is generated from it (:func:`format_table`).
"""

__all__ = ["FORMAT_VERSION", "KEYS", "KINDS", "META_REQUIRED",
           "SYMMETRY_RTOL", "MAX_TEXT", "MAX_META_DEPTH", "MAX_INT_DIGITS",
           "MAX_STAGES", "MAX_OBSTACLE_POINTS", "MAX_TOTAL_BYTES",
           "format_table"]

#: Version of the ``.npz`` layout written by ``save_problem``.
FORMAT_VERSION = 1

#: Relative tolerance of the symmetry check of K and M.
SYMMETRY_RTOL = 1e-10

#: Key specification: name -> (which kinds need it, dtype, shape, meaning).
#: "all" = both kinds; "mesh"/"discrete" = required for that kind only and
#: refused for the other; "optional" = may be absent in either kind.
KEYS = {
    "format_version": ("all", "int", "()", "layout version, = 1"),
    "kind": ("all", "str", "()", '"mesh" or "discrete"'),
    "meta": ("all", "str", "()",
             "JSON object: E, nu, plane (strain|stress), load, mesh, "
             "description, versions (required fields: E, nu, plane, load, "
             "mesh for kind mesh; description for kind discrete)"),
    "K_data": ("all", "float", "(nnz,)",
               "reduced stiffness K (Ñ×Ñ, Dirichlet DOFs eliminated, "
               "symmetric positive definite) in CSR: values"),
    "K_indices": ("all", "int", "(nnz,)", "CSR column indices of K"),
    "K_indptr": ("all", "int", "(Ñ+1,)", "CSR row pointers of K"),
    "K_shape": ("all", "int", "(2,)", "(Ñ, Ñ)"),
    "f": ("all", "float", "(Ñ,)",
          "load vector for the full load (load step κ applies κ/κc·f)"),
    "M_data": ("all", "float", "(nnzM,)",
               "boundary matrix on Γc, M_ij = ∫Γc φi φj (thesis (80)), "
               "Nc×Nc in CSR: values"),
    "M_indices": ("all", "int", "(nnzM,)", "CSR column indices of M"),
    "M_indptr": ("all", "int", "(Nc+1,)", "CSR row pointers of M"),
    "M_shape": ("all", "int", "(2,)", "(Nc, Nc)"),
    "contact_dofs": ("all", "int", "(Nc, 2)",
                     "reduced DOF index of the x and y component of each "
                     "contact node (in Γc order); -1 where the component is "
                     "a Dirichlet DOF (such a node is a support, not a "
                     "contact node, and only enters M)"),
    "nodes": ("mesh", "float", "(n_nodes, 2)", "node coordinates"),
    "cells": ("mesh", "int", "(n_cells, 3)", "triangles (node indices)"),
    "dof_map": ("mesh", "int", "(Ñ, 2)",
                "(node, component) of each reduced DOF; component 0 = x, "
                "1 = y"),
    "u_prescribed": ("mesh", "float", "(n_nodes, 2)",
                     "values of the Dirichlet DOFs (entries of free DOFs "
                     "are 0)"),
    "contact_nodes": ("mesh", "int", "(Nc,)",
                      "nodes of Γc, ordered along Γc (consecutive nodes "
                      "share a boundary edge)"),
    "obstacle_x": ("optional", "str", "()",
                   "x(t) of the obstacle Γo(t) (mesh kind: either "
                   "obstacle_x and obstacle_y, or obstacle_points)"),
    "obstacle_y": ("optional", "str", "()", "y(t) of the obstacle Γo(t)"),
    "obstacle_points": ("optional", "float", "(n, 2)",
                        "vertices of a polyline obstacle, parametrised by "
                        "arc length (instead of obstacle_x, obstacle_y)"),
    "obstacle_t_range": ("optional", "float", "(2,)",
                         "admissible parameter interval [t0, t1] (mesh "
                         "kind only; absent = unbounded)"),
    "obstacle_search_interval": ("optional", "float", "(2,)",
                                 "parameter interval [t0, t1] searched for "
                                 "the gaps (mesh kind only; absent = found "
                                 "from the body's extent; CLI: "
                                 "--search-interval)"),
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
    "load_path_prescribed": ("optional", "float", "(n_stages, n_nodes, 2)",
                             "Dirichlet values at the stage ends (mesh kind "
                             "only; absent: u_prescribed scaled like the "
                             "load)"),
    "gap": ("discrete", "float", "(Nc,)",
            "initial gap s of each contact node along its normal"),
    "normal": ("discrete", "float", "(Nc, 2)",
               "unit normal ν of each contact node, pointing from the body "
               "towards the obstacle"),
}

KINDS = ("mesh", "discrete")

#: Fields of ``meta`` each kind needs.
META_REQUIRED = {"mesh": ("E", "nu", "plane", "load", "mesh"),
                 "discrete": ("description",)}

# Size limits of the reader (``solver.problem.load``). A bad file costs no
# more memory than a good one of the sizes it declares: every array's size
# follows from a few declared dimensions (Ñ from K_shape, Nc from M_shape,
# the number of nodes from ``nodes``), and these are bounded here.

#: Most characters of a text key (the obstacle expressions are limited
#: further, to 1000, by :mod:`solver.geometry.obstacle`).
MAX_TEXT = 1_000_000

#: Deepest nesting of lists and objects in the ``meta`` JSON.
MAX_META_DEPTH = 32

#: Most digits of an integer in the ``meta`` JSON.
MAX_INT_DIGITS = 30

#: Most load stages of a ``load_path``.
MAX_STAGES = 100_000

#: Most vertices of a polyline obstacle.
MAX_OBSTACLE_POINTS = 10_000_000

#: Most bytes the arrays of one file may occupy once read (16 GiB; the
#: largest benchmark, 916 000 DOFs, needs well under 1 GiB).
MAX_TOTAL_BYTES = 16 * 2 ** 30


def format_table():
    """The key specification as a Markdown table (for the docs)."""
    lines = ["| key | needed in | dtype | shape | meaning |",
             "|---|---|---|---|---|"]
    for key, (need, dtype, shape, doc) in KEYS.items():
        need = {"all": "both kinds", "mesh": "mesh only",
                "discrete": "discrete only", "optional": "optional"}[need]
        lines.append(f"| `{key}` | {need} | {dtype} | {shape} | {doc} |")
    return "\n".join(lines)
