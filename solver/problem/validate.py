"""Validation of the ``.npz`` arrays of a problem file (all keys).

:func:`validate_fields` checks every key of
:data:`~solver.problem.format.KEYS` (presence for the kind, dtype, shape,
finiteness, ranges, the consistency of K, M, the DOF maps and the load
path) and the mesh geometry (:mod:`solver.problem.geometry`), and raises
:class:`~solver.errors.ProblemError` naming the first offending key.
"""

from collections.abc import Mapping

import numpy as np

from .checks import (check_array, check_norm, check_positive_definite,
                     check_range, csr, fail)
from .format import FORMAT_VERSION, KEYS, KINDS, META_REQUIRED
from .geometry import validate_mesh
from .meta import check_material, parse_meta

__all__ = ["validate_fields"]


class _Arrays(Mapping):
    """``arrays`` with each value as an array, converted when first asked
    for (a :class:`~solver.problem.load.Archive` reads it only then)."""

    def __init__(self, arrays):
        self.source, self.cache = arrays, {}

    def __getitem__(self, key):
        if key not in self.cache:
            self.cache[key] = np.asanyarray(self.source[key])
        return self.cache[key]

    def __iter__(self):
        return iter(self.source)

    def __len__(self):
        return len(self.source)

    def __contains__(self, key):
        return key in self.source


def validate_fields(arrays):
    """Validate a dict of ``.npz`` arrays (keys of
    :data:`~solver.problem.format.KEYS`).

    Returns
    -------
    dict
        The fields of a :class:`~solver.problem.ContactProblem` (K and M as
        CSR matrices, the obstacle as a curve object).

    Raises
    ------
    ProblemError
        Naming the first key found missing, unexpected or malformed.
    """
    # Overflows in the checks of absurd values (1e308 entries) are found by
    # the checks themselves; NumPy's RuntimeWarnings would only add lines to
    # the one-line error message on stderr.
    with np.errstate(all="ignore"):
        return _validate(arrays)


def _validate(arrays):
    arrays = _Arrays(arrays)
    for key in ("format_version", "kind"):
        if key not in arrays:
            fail(key, "missing (is this a problem file of this solver?)")
    version = check_array(arrays, "format_version", "int", 0)
    if int(version) != FORMAT_VERSION:
        fail("format_version", f"file has version {int(version)}, this "
                               f"solver reads version {FORMAT_VERSION}")
    kind = check_array(arrays, "kind", "str", 0)
    if kind not in KINDS:
        fail("kind", f"must be one of {KINDS}, got {kind!r}")
    allowed = {k for k, (need, *_rest) in KEYS.items()
               if need in ("all", kind, "optional")}
    if kind == "discrete":
        for key in ("obstacle_t_range", "obstacle_search_interval",
                    "obstacle_x", "obstacle_y", "obstacle_points",
                    "load_path_prescribed"):
            allowed.discard(key)
    for key in sorted(arrays):
        if key not in allowed:
            fail(key, f"unexpected key in a {kind!r} problem file")
    for key, (need, *_rest) in KEYS.items():
        if need in ("all", kind) and key not in arrays:
            fail(key, f"missing (required in a {kind!r} problem file)")

    meta = parse_meta(check_array(arrays, "meta", "str", 0))
    for name in META_REQUIRED[kind]:
        if name not in meta:
            fail("meta", f"field {name!r} missing")
    if kind == "mesh":
        check_material(meta)

    K = csr(arrays, "K")
    n = K.shape[0]
    f = check_array(arrays, "f", "float", 1, (n,))
    check_norm("f", f)
    contact_dofs = check_array(arrays, "contact_dofs", "int", 2, (None, 2))
    nc = len(contact_dofs)
    if nc < 1:
        fail("contact_dofs", "no contact nodes")
    check_range("contact_dofs", contact_dofs, -1, n)
    used = contact_dofs[contact_dofs >= 0]
    if len(np.unique(used)) != len(used):
        fail("contact_dofs", "a reduced DOF appears twice")
    M = csr(arrays, "M", nc)
    check_positive_definite(M, "M")  # Nc × Nc: cheap; needed for M⁻¹λ

    problem = dict(K=K, f=f, M=M, contact_dofs=contact_dofs, meta=meta)
    if kind == "mesh":
        problem.update(validate_mesh(arrays, n, contact_dofs))
    else:
        if (contact_dofs < 0).any():
            fail("contact_dofs", "a discrete problem has no Dirichlet DOFs "
                                 "(-1 entries are not allowed)")
        gap = check_array(arrays, "gap", "float", 1, (nc,))
        normal = check_array(arrays, "normal", "float", 2, (nc, 2))
        length = np.hypot(normal[:, 0], normal[:, 1])
        if (abs(length - 1) > 1e-9).any():
            i = int(np.argmax(abs(length - 1)))
            fail("normal", f"row {i} has length {length[i]:.12g}, expected "
                           "a unit vector")
        problem.update(gap=gap, normal=normal)
    problem.update(_validate_load_path(arrays, f, problem.get("nodes")))
    return problem


def _validate_load_path(arrays, f, nodes):
    """The optional load path: all of load_path, _steps, _friction or none."""
    keys = ("load_path", "load_path_steps", "load_path_friction")
    present = [k for k in keys if k in arrays]
    if not present:
        if "load_path_prescribed" in arrays:
            fail("load_path_prescribed", "given without load_path")
        return {}
    for key in keys:
        if key not in arrays:
            fail(key, f"missing (load_path needs {', '.join(keys)})")
    path = check_array(arrays, "load_path", "float", 2, (None, len(f)))
    check_norm("load_path", path)
    stages = len(path)
    if stages < 1:
        fail("load_path", "no stages")
    steps = check_array(arrays, "load_path_steps", "int", 1, (stages,))
    if (steps < 1).any():
        fail("load_path_steps", "every stage needs at least one step")
    friction = check_array(arrays, "load_path_friction", "float", 1,
                           (stages,))
    if (friction < 0).any():
        fail("load_path_friction", "multipliers must be >= 0")
    scale = max(np.abs(f).max(initial=0.0), 1e-300)
    if np.abs(path[-1] - f).max() > 1e-12 * scale:
        fail("load_path", "its last row must equal f (the full load)")
    out = dict(load_path=path, load_path_steps=steps,
               load_path_friction=friction)
    if "load_path_prescribed" in arrays:
        out["load_path_prescribed"] = check_array(
            arrays, "load_path_prescribed", "float", 3,
            (stages, len(nodes), 2))
    return out
