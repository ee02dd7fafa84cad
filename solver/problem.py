r"""The ``.npz`` problem format: the one place that defines, writes and checks it.

A problem file carries everything the contact solver needs and nothing it
must guess. SfePy problem files (``sfepy_problems/``) write it through
:func:`save_problem`; ``python -m solver`` reads it through
:func:`load_problem`, which validates every key and raises
:class:`~solver.errors.ProblemError` naming the offending key.

Files are plain NumPy ``.npz`` archives of numeric and unicode arrays, so
they load with ``allow_pickle=False`` (pickled objects are refused).

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

import json
import os
import tempfile
import dataclasses
from dataclasses import dataclass, field

import numpy as np
import scipy
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from .errors import ProblemError
from .mesh import is_boundary_chain
from .obstacle import ParametricCurve
from .polyline import PolylineCurve

__all__ = ["FORMAT_VERSION", "KEYS", "ContactProblem", "load_problem",
           "save_problem", "validate_arrays", "format_table",
           "check_positive_definite"]

#: Version of the ``.npz`` layout written by :func:`save_problem`.
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
_META_REQUIRED = {"mesh": ("E", "nu", "plane", "load", "mesh"),
                  "discrete": ("description",)}


@dataclass(eq=False)
class ContactProblem:
    r"""A contact problem as the solver sees it (one ``.npz`` file).

    Array meanings and shapes are those of :data:`KEYS`; K and M are
    :class:`scipy.sparse.csr_matrix`. Construct it directly (the arrays are
    validated by :meth:`validate`) or with :func:`load_problem`.
    """

    K: sp.csr_matrix
    f: np.ndarray
    M: sp.csr_matrix
    contact_dofs: np.ndarray
    meta: dict
    nodes: np.ndarray = None
    cells: np.ndarray = None
    dof_map: np.ndarray = None
    u_prescribed: np.ndarray = None
    contact_nodes: np.ndarray = None
    obstacle: ParametricCurve = None
    gap: np.ndarray = None
    normal: np.ndarray = None
    load_path: np.ndarray = None
    load_path_steps: np.ndarray = None
    load_path_friction: np.ndarray = None
    load_path_prescribed: np.ndarray = None
    source: str = field(default=None, compare=False)
    _checked: object = field(default=None, init=False, repr=False,
                             compare=False)

    @property
    def kind(self):
        """``"mesh"`` if the problem carries a mesh, else ``"discrete"``."""
        return "mesh" if self.nodes is not None else "discrete"

    @property
    def n_dofs(self):
        """Ñ, the number of reduced DOFs."""
        return self.K.shape[0]

    @property
    def n_contact(self):
        """Nc, the number of nodes on Γc."""
        return self.contact_dofs.shape[0]

    def to_arrays(self):
        """The ``.npz`` arrays of this problem, keyed as in :data:`KEYS`."""
        K, M = sp.csr_matrix(self.K), sp.csr_matrix(self.M)
        arrays = {
            "format_version": np.array(FORMAT_VERSION, dtype=np.int64),
            "kind": np.array(self.kind),
            "meta": np.array(json.dumps(self.meta, sort_keys=True)),
            "K_data": K.data, "K_indices": K.indices, "K_indptr": K.indptr,
            "K_shape": np.array(K.shape, dtype=np.int64),
            "f": self.f,
            "M_data": M.data, "M_indices": M.indices, "M_indptr": M.indptr,
            "M_shape": np.array(M.shape, dtype=np.int64),
            "contact_dofs": self.contact_dofs,
        }
        if self.kind == "mesh":
            arrays.update(nodes=self.nodes, cells=self.cells,
                          dof_map=self.dof_map,
                          u_prescribed=self.u_prescribed,
                          contact_nodes=self.contact_nodes)
            if isinstance(self.obstacle, PolylineCurve):
                arrays["obstacle_points"] = self.obstacle.points
            elif self.obstacle is not None:
                arrays["obstacle_x"] = np.array(self.obstacle.x_text)
                arrays["obstacle_y"] = np.array(self.obstacle.y_text)
                if self.obstacle.t_range is not None:
                    arrays["obstacle_t_range"] = np.array(
                        self.obstacle.t_range, dtype=float)
        for name in ("gap", "normal", "load_path", "load_path_steps",
                     "load_path_friction", "load_path_prescribed"):
            if getattr(self, name) is not None:
                arrays[name] = getattr(self, name)
        return arrays

    def validate(self):
        """Check every array; raise :class:`ProblemError` naming the key."""
        validate_arrays(self.to_arrays())
        return self

    def check_stiffness(self):
        """Check that K is positive definite (see
        :func:`check_positive_definite`).

        Costs one sparse factorisation of K in a fill-reducing order
        (:func:`solver.linalg.dof_ordering`); the solvers call it before
        iterating (the condensed ones get it from the factorisation they
        need anyway). The result is remembered for the K object checked
        (replace ``problem.K``, do not modify it in place).

        Raises
        ------
        ProblemError
            ``"K_data: K is not positive definite (...)"``.
        """
        if self._checked is not self.K:
            from .linalg import dof_ordering
            check_positive_definite(self.K, "K", dof_ordering(self))
            self._checked = self.K
        return self

    def n_load_steps(self, steps=None):
        """Number of load steps: of the ``load_path``, else ``steps``
        (default 100)."""
        if self.load_path is not None:
            return int(self.load_path_steps.sum())
        return 100 if steps is None else int(steps)

    def load_steps(self, steps=None):
        """The load path, one entry per load step (a generator: a vector per
        step is made only when the step is reached).

        Yields (load vector f_κ, friction multiplier, Dirichlet values or
        None, stage index). Without a ``load_path`` the path has one stage
        of ``steps`` steps (default 100) with f_κ = κ/κc·f and the
        Dirichlet values scaled alike.
        """
        if self.load_path is None:
            steps = self.n_load_steps(steps)
            for k in range(1, steps + 1):
                yield (k / steps * self.f, 1.0,
                       None if self.u_prescribed is None
                       else k / steps * self.u_prescribed, 0)
            return
        start = np.zeros_like(self.f)
        prescribed_start = None if self.u_prescribed is None \
            else np.zeros_like(self.u_prescribed)
        for stage, (end, n, factor) in enumerate(zip(
                self.load_path, self.load_path_steps,
                self.load_path_friction)):
            if self.load_path_prescribed is not None:
                prescribed_end = self.load_path_prescribed[stage]
            elif self.u_prescribed is not None:
                prescribed_end = self.u_prescribed * (
                    np.linalg.norm(end) / max(np.linalg.norm(self.f), 1e-300))
            else:
                prescribed_end = None
            for k in range(1, int(n) + 1):
                w = k / n
                value = None if prescribed_end is None else \
                    (1 - w) * prescribed_start + w * prescribed_end
                yield ((1 - w) * start + w * end, float(factor), value,
                       stage)
            start, prescribed_start = end, prescribed_end

    def full_displacement(self, u, prescribed=None):
        """Nodal displacements (n_nodes, 2) from a reduced vector ``u``.

        Free DOFs take ``u``, Dirichlet DOFs take ``prescribed`` (default
        ``u_prescribed``, the values of the full load).
        """
        if self.kind != "mesh":
            raise ProblemError("full_displacement: a discrete problem has "
                               "no mesh")
        full = (self.u_prescribed if prescribed is None
                else np.asarray(prescribed, float)).copy()
        full[self.dof_map[:, 0], self.dof_map[:, 1]] = u
        return full

    def summary(self):
        """A dict of the problem's main figures (for ``--info``)."""
        from scipy.sparse.linalg import norm as sparse_norm

        active = (self.contact_dofs >= 0).all(axis=1)
        info = {
            "kind": self.kind,
            "dofs": int(self.n_dofs),
            "contact_nodes": int(self.n_contact),
            "contact_nodes_free": int(active.sum()),
            "K_nnz": int(self.K.nnz),
            "K_norm_fro": float(sparse_norm(self.K)),
            "K_norm_max": float(abs(self.K).max()),
            "f_norm": float(np.linalg.norm(self.f)),
            "M_sum": float(self.M.sum()),
        }
        if self.kind == "mesh":
            info.update(nodes=int(len(self.nodes)),
                        triangles=int(len(self.cells)),
                        obstacle=(
                            [self.obstacle.x_text, self.obstacle.y_text]
                            if isinstance(self.obstacle, ParametricCurve)
                            else repr(self.obstacle)),
                        obstacle_t_range=self.obstacle.t_range)
        else:
            info.update(gap=self.gap.tolist(), normal=self.normal.tolist())
        info["meta"] = self.meta
        return info


# ----------------------------------------------------------------------------
# validation

def _fail(key, message):
    raise ProblemError(f"{key}: {message}")


def _check_array(arrays, key, kind, ndim, shape=None):
    """Generic checks of one key: dtype class, ndim, shape, finiteness."""
    a = arrays[key]
    if a.dtype == object:
        _fail(key, "contains Python objects (refused)")
    if kind == "str":
        if a.dtype.kind != "U" or a.ndim != 0:
            _fail(key, f"expected a text scalar, got dtype {a.dtype} with "
                       f"shape {a.shape}")
        order = a.dtype.byteorder if a.dtype.byteorder in "<>" else "="
        codes = np.frombuffer(a.tobytes(),
                              dtype=np.dtype("u4").newbyteorder(order))
        surrogate = (codes >= 0xD800) & (codes <= 0xDFFF)
        if ((codes > 0x10FFFF) | surrogate).any():
            # NumPy would make a Python str that breaks later (SystemError)
            _fail(key, "not valid text: invalid code points (damaged file?)")
        return str(a)
    if kind == "int" and a.dtype.kind not in "iu":
        _fail(key, f"expected integers, got dtype {a.dtype}")
    if kind == "float" and a.dtype.kind not in "fiu":
        _fail(key, f"expected real numbers, got dtype {a.dtype}")
    if a.ndim != ndim:
        _fail(key, f"expected {ndim} dimension(s), got shape {a.shape}")
    if shape is not None:
        for axis, (want, got) in enumerate(zip(shape, a.shape)):
            if want is not None and want != got:
                _fail(key, f"expected shape {_shape_text(shape)}, got "
                           f"{a.shape}")
    if kind == "float":
        a = a.astype(np.float64)
        bad = ~np.isfinite(a)
        if bad.any():
            _fail(key, f"{int(bad.sum())} entries are NaN or infinite "
                       f"(first at index {np.argwhere(bad)[0].tolist()})")
    else:
        a = a.astype(np.int64)
    return a


def _shape_text(shape):
    return "(" + ", ".join("?" if s is None else str(s) for s in shape) + ")"


def _check_range(key, a, low, high):
    if a.size and (a.min() < low or a.max() >= high):
        bad = a[(a < low) | (a >= high)][0]
        _fail(key, f"index {int(bad)} out of range [{low}, {high})")


def _csr(arrays, name, n=None):
    """Validate and build the CSR matrix stored under ``name_*``."""
    shape = _check_array(arrays, f"{name}_shape", "int", 1, (2,))
    rows, cols = (int(v) for v in shape)
    if rows != cols or rows < 1:
        _fail(f"{name}_shape", f"expected a square non-empty matrix, got "
                               f"{(rows, cols)}")
    if n is not None and rows != n:
        _fail(f"{name}_shape", f"expected ({n}, {n}), got {(rows, cols)}")
    data = _check_array(arrays, f"{name}_data", "float", 1)
    indices = _check_array(arrays, f"{name}_indices", "int", 1,
                           (len(data),))
    indptr = _check_array(arrays, f"{name}_indptr", "int", 1, (rows + 1,))
    if indptr[0] != 0 or indptr[-1] != len(data) or (np.diff(indptr) < 0).any():
        _fail(f"{name}_indptr", f"not a valid CSR row pointer (must rise "
                                f"from 0 to nnz = {len(data)})")
    _check_range(f"{name}_indices", indices, 0, cols)
    A = sp.csr_matrix((data, indices, indptr), shape=(rows, cols))
    A.sum_duplicates()
    scale = abs(A).max() if A.nnz else 0.0
    if scale == 0.0:
        _fail(f"{name}_data", "the matrix is zero")
    asym = abs(A - A.T).max()
    if asym > SYMMETRY_RTOL * scale:
        _fail(f"{name}_data", f"the matrix is not symmetric (max |A - Aᵀ| = "
                              f"{asym:.3g}, max |A| = {scale:.3g})")
    diagonal = A.diagonal()
    if (diagonal <= 0).any():
        i = int(np.argmax(diagonal <= 0))
        _fail(f"{name}_data", f"diagonal entry {i} is {diagonal[i]:.3g}: the "
                              "matrix is not positive definite")
    return A


def check_positive_definite(A, name="K", order=None):
    r"""Raise :class:`ProblemError` unless the symmetric matrix A is
    positive definite (numerically: no LDLᵀ pivot below
    :data:`~solver.linalg.PIVOT_RTOL` of the largest).

    One sparse LDLᵀ factorisation, :class:`solver.linalg.Factorization`
    (its docstring explains the test), with the elimination ``order`` if
    given (e.g. :func:`solver.linalg.dof_ordering`), else SuperLU's minimum
    degree ordering.

    Parameters
    ----------
    A : sparse matrix
        Symmetric (the loader checks it).
    name : str
        The matrix's key prefix for the message (``"K"`` or ``"M"``).
    order : (n,) int array, optional
        Elimination order.
    """
    from .linalg import Factorization
    Factorization(A, order, name)


def validate_arrays(arrays):
    """Validate a dict of ``.npz`` arrays and build a :class:`ContactProblem`.

    Raises
    ------
    ProblemError
        Naming the first key found missing, unexpected or malformed.
    """
    # Overflows in the checks of absurd values (1e308 entries) are found by
    # the checks themselves; NumPy's RuntimeWarnings would only add lines to
    # the one-line error message on stderr.
    with np.errstate(all="ignore"):
        return _validate_arrays(arrays)


def _validate_arrays(arrays):
    arrays = {k: np.asanyarray(v) for k, v in arrays.items()}
    for key in ("format_version", "kind"):
        if key not in arrays:
            _fail(key, "missing (is this a problem file of this solver?)")
    version = _check_array(arrays, "format_version", "int", 0)
    if int(version) != FORMAT_VERSION:
        _fail("format_version", f"file has version {int(version)}, this "
                                f"solver reads version {FORMAT_VERSION}")
    kind = _check_array(arrays, "kind", "str", 0)
    if kind not in KINDS:
        _fail("kind", f"must be one of {KINDS}, got {kind!r}")
    allowed = {k for k, (need, *_rest) in KEYS.items()
               if need in ("all", kind, "optional")}
    if kind == "discrete":
        for key in ("obstacle_t_range", "obstacle_x", "obstacle_y",
                    "obstacle_points", "load_path_prescribed"):
            allowed.discard(key)
    for key in sorted(arrays):
        if key not in allowed:
            _fail(key, f"unexpected key in a {kind!r} problem file")
    for key, (need, *_rest) in KEYS.items():
        if need in ("all", kind) and key not in arrays:
            _fail(key, f"missing (required in a {kind!r} problem file)")

    meta_text = _check_array(arrays, "meta", "str", 0)
    try:
        meta = json.loads(meta_text)
    except json.JSONDecodeError as exc:
        _fail("meta", f"not valid JSON ({exc.msg})")
    if not isinstance(meta, dict):
        _fail("meta", "must be a JSON object")
    for name in _META_REQUIRED[kind]:
        if name not in meta:
            _fail("meta", f"field {name!r} missing")
    if kind == "mesh":
        _check_material(meta)

    K = _csr(arrays, "K")
    n = K.shape[0]
    f = _check_array(arrays, "f", "float", 1, (n,))
    contact_dofs = _check_array(arrays, "contact_dofs", "int", 2, (None, 2))
    nc = len(contact_dofs)
    if nc < 1:
        _fail("contact_dofs", "no contact nodes")
    _check_range("contact_dofs", contact_dofs, -1, n)
    used = contact_dofs[contact_dofs >= 0]
    if len(np.unique(used)) != len(used):
        _fail("contact_dofs", "a reduced DOF appears twice")
    M = _csr(arrays, "M", nc)
    check_positive_definite(M, "M")  # Nc × Nc: cheap; needed for M⁻¹λ

    problem = dict(K=K, f=f, M=M, contact_dofs=contact_dofs, meta=meta)
    if kind == "mesh":
        problem.update(_validate_mesh(arrays, n, contact_dofs))
    else:
        if (contact_dofs < 0).any():
            _fail("contact_dofs", "a discrete problem has no Dirichlet DOFs "
                                  "(-1 entries are not allowed)")
        gap = _check_array(arrays, "gap", "float", 1, (nc,))
        normal = _check_array(arrays, "normal", "float", 2, (nc, 2))
        length = np.hypot(normal[:, 0], normal[:, 1])
        if (abs(length - 1) > 1e-9).any():
            i = int(np.argmax(abs(length - 1)))
            _fail("normal", f"row {i} has length {length[i]:.12g}, expected "
                            "a unit vector")
        problem.update(gap=gap, normal=normal)
    problem.update(_validate_load_path(arrays, f, problem.get("nodes")))
    return ContactProblem(**problem)


def _validate_load_path(arrays, f, nodes):
    """The optional load path: all of load_path, _steps, _friction or none."""
    keys = ("load_path", "load_path_steps", "load_path_friction")
    present = [k for k in keys if k in arrays]
    if not present:
        if "load_path_prescribed" in arrays:
            _fail("load_path_prescribed", "given without load_path")
        return {}
    for key in keys:
        if key not in arrays:
            _fail(key, f"missing (load_path needs {', '.join(keys)})")
    path = _check_array(arrays, "load_path", "float", 2, (None, len(f)))
    stages = len(path)
    if stages < 1:
        _fail("load_path", "no stages")
    steps = _check_array(arrays, "load_path_steps", "int", 1, (stages,))
    if (steps < 1).any():
        _fail("load_path_steps", "every stage needs at least one step")
    friction = _check_array(arrays, "load_path_friction", "float", 1,
                            (stages,))
    if (friction < 0).any():
        _fail("load_path_friction", "multipliers must be >= 0")
    scale = max(np.abs(f).max(initial=0.0), 1e-300)
    if np.abs(path[-1] - f).max() > 1e-12 * scale:
        _fail("load_path", "its last row must equal f (the full load)")
    out = dict(load_path=path, load_path_steps=steps,
               load_path_friction=friction)
    if "load_path_prescribed" in arrays:
        out["load_path_prescribed"] = _check_array(
            arrays, "load_path_prescribed", "float", 3,
            (stages, len(nodes), 2))
    return out


def _check_material(meta):
    E, nu, plane = meta["E"], meta["nu"], meta["plane"]

    def number(v):  # JSON true/false are not numbers; NaN/Infinity are not
        return isinstance(v, (int, float)) and not isinstance(v, bool) \
            and np.isfinite(v)

    if not number(E) or not E > 0:
        _fail("meta", f"E must be a positive finite number, got {E!r}")
    if not number(nu) or not -1 < nu < 0.5:
        _fail("meta", f"nu must be a number in (-1, 0.5), got {nu!r}")
    if plane not in ("strain", "stress"):
        _fail("meta", f"plane must be 'strain' or 'stress', got {plane!r}")


def _validate_mesh(arrays, n, contact_dofs):
    nodes = _check_array(arrays, "nodes", "float", 2, (None, 2))
    n_nodes = len(nodes)
    cells = _check_array(arrays, "cells", "int", 2, (None, 3))
    if len(cells) < 1:
        _fail("cells", "the mesh has no triangles")
    _check_range("cells", cells, 0, n_nodes)
    dof_map = _check_array(arrays, "dof_map", "int", 2, (n, 2))
    _check_range("dof_map", dof_map[:, 0], 0, n_nodes)
    _check_range("dof_map", dof_map[:, 1], 0, 2)
    flat = dof_map[:, 0] * 2 + dof_map[:, 1]
    if len(np.unique(flat)) != n:
        _fail("dof_map", "two reduced DOFs map to the same (node, component)")
    u_prescribed = _check_array(arrays, "u_prescribed", "float", 2,
                                (n_nodes, 2))
    contact_nodes = _check_array(arrays, "contact_nodes", "int", 1,
                                 (len(contact_dofs),))
    _check_range("contact_nodes", contact_nodes, 0, n_nodes)
    if len(np.unique(contact_nodes)) != len(contact_nodes):
        _fail("contact_nodes", "a node appears twice")
    if not is_boundary_chain(contact_nodes, cells):
        _fail("contact_nodes", "not ordered along the boundary (consecutive "
                               "contact nodes must share a boundary edge)")
    # contact_dofs must agree with dof_map.
    lookup = np.full(2 * n_nodes, -1, dtype=np.int64)
    lookup[flat] = np.arange(n)
    expected = lookup[(2 * contact_nodes[:, None] + np.arange(2)).ravel()]
    if not np.array_equal(expected.reshape(-1, 2), contact_dofs):
        _fail("contact_dofs", "does not match dof_map and contact_nodes")
    if "obstacle_points" in arrays:
        for key in ("obstacle_x", "obstacle_y", "obstacle_t_range"):
            if key in arrays:
                _fail(key, "not allowed with obstacle_points (a polyline "
                           "is parametrised by its arc length)")
        points = _check_array(arrays, "obstacle_points", "float", 2,
                              (None, 2))
        try:
            obstacle = PolylineCurve(points)
        except ProblemError as exc:
            _fail("obstacle_points", str(exc).split(": ", 1)[-1])
    else:
        for key in ("obstacle_x", "obstacle_y"):
            if key not in arrays:
                _fail(key, "missing (a 'mesh' problem file needs obstacle_x "
                           "and obstacle_y, or obstacle_points)")
        t_range = None
        if "obstacle_t_range" in arrays:
            t_range = _check_array(arrays, "obstacle_t_range", "float", 1,
                                   (2,))
        x = _check_array(arrays, "obstacle_x", "str", 0)
        y = _check_array(arrays, "obstacle_y", "str", 0)
        try:
            obstacle = ParametricCurve(x, y, t_range)
        except ProblemError as exc:
            _fail("obstacle", str(exc))
    return dict(nodes=nodes, cells=cells, dof_map=dof_map,
                u_prescribed=u_prescribed, contact_nodes=contact_nodes,
                obstacle=obstacle)


# ----------------------------------------------------------------------------
# reading and writing

def load_problem(path):
    """Read and validate a problem file.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.npz`` file written by :func:`save_problem`.

    Returns
    -------
    ContactProblem

    Raises
    ------
    ProblemError
        If the file cannot be read, is not an ``.npz`` archive, holds pickled
        objects, or any key is missing, unexpected or malformed.
    """
    path = os.fspath(path)
    try:
        with open(path, "rb") as stream:
            magic = stream.read(6)
    except FileNotFoundError:
        raise ProblemError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise ProblemError(f"{path}: is a directory, not a file") from None
    except PermissionError:
        raise ProblemError(f"{path}: permission denied") from None
    except OSError as exc:
        raise ProblemError(f"{path}: cannot be read ({exc})") from None
    if magic.startswith(b"\x93NUMPY"):
        raise ProblemError(f"{path}: a single .npy array, not an .npz "
                           "problem file")
    if not magic.startswith(b"PK"):
        raise ProblemError(f"{path}: not an .npz archive (no zip header)")
    with open(path, "rb") as stream:  # ours to close, whatever happens
        arrays = _read_members(path, stream)
    problem = validate_arrays(arrays)
    problem.source = path
    return problem


def _read_members(path, stream):
    try:
        archive = np.load(stream, allow_pickle=False)
    except Exception as exc:  # BadZipFile, NotImplementedError("zip file
        # version 6.4"), struct.error, ... of a damaged central directory
        raise ProblemError(f"{path}: not a readable .npz file "
                           f"({type(exc).__name__}: {exc})") from None
    arrays = {}
    with archive:
        for key in archive.files:
            try:
                arrays[key] = archive[key]
            except ValueError as exc:
                if "allow_pickle" in str(exc):
                    _fail(key, "contains pickled Python objects (refused: "
                               "allow_pickle=False)")
                _fail(key, f"cannot be read ({exc})")
            except Exception as exc:  # zlib/zip/EOF errors of damaged members
                _fail(key, f"cannot be read, the file is damaged "
                           f"({type(exc).__name__}: {exc})")
    return arrays


def save_problem(path, problem):
    """Validate ``problem`` and write it to ``path`` atomically.

    The archive is written to a temporary file in the target directory and
    renamed over ``path`` only when complete, so a failure never leaves a
    half-written problem file. Library versions are added to
    ``meta["versions"]``.
    """
    path = os.fspath(path)
    versions = dict(problem.meta.get("versions", {}))
    versions.update(format=FORMAT_VERSION, numpy=np.__version__,
                    scipy=scipy.__version__)
    meta = dict(problem.meta, versions=versions)
    arrays = dataclasses.replace(problem, meta=meta).to_arrays()
    validate_arrays(arrays)
    directory = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=".tmp-", suffix=".npz", dir=directory)
    try:
        with os.fdopen(fd, "wb") as stream:
            np.savez_compressed(stream, **arrays)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def format_table():
    """The key specification as a Markdown table (for the docs)."""
    lines = ["| key | needed in | dtype | shape | meaning |",
             "|---|---|---|---|---|"]
    for key, (need, dtype, shape, doc) in KEYS.items():
        need = {"all": "both kinds", "mesh": "mesh only",
                "discrete": "discrete only", "optional": "optional"}[need]
        lines.append(f"| `{key}` | {need} | {dtype} | {shape} | {doc} |")
    return "\n".join(lines)
