"""Validation of the ``.npz`` arrays of a problem file: every key of
:data:`~solver.problem.format.KEYS`, the mesh geometry (:mod:`.geometry`)
and the two-body keys (:mod:`.two_body`)."""

from collections.abc import Mapping

import numpy as np

from .checks import (check_array, check_load, check_positive_definite,
                     check_range, csr, fail)
from .format import (DIMS, KEYS, KINDS, META_REQUIRED, ONLY_2D,
                     READ_VERSIONS, TWO_BODY, TWO_BODY_VERSION)
from .geometry import validate_mesh
from .meta import check_material, parse_meta
from .two_body import validate_two_body

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
    :data:`~solver.problem.format.KEYS`) and return the fields of a
    :class:`~solver.problem.ContactProblem` (K and M as CSR matrices, the
    obstacle as a curve object); ProblemError naming the first key found
    missing, unexpected or malformed."""
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
    version = int(check_array(arrays, "format_version", "int", 0))
    if version not in READ_VERSIONS:
        fail("format_version", f"file has version {version}, this "
                               f"solver reads versions "
                               f"{', '.join(map(str, READ_VERSIONS))}")
    kind = check_array(arrays, "kind", "str", 0)
    if kind not in KINDS:
        fail("kind", f"must be one of {KINDS}, got {kind!r}")
    if "contact_dofs" not in arrays:
        fail("contact_dofs", f"missing (required in a {kind!r} problem "
                             "file)")
    contact_dofs = check_array(arrays, "contact_dofs", "int", 2)
    dim = contact_dofs.shape[1]
    if dim not in DIMS:
        fail("contact_dofs", f"expected 2 or 3 columns (the dimension), got "
                             f"shape {contact_dofs.shape}")
    if version < DIMS[dim]:
        fail("format_version", f"a {dim}D problem needs version "
                               f"{DIMS[dim]}, the file has {version}")
    _check_keys(arrays, kind, dim)
    two_body = [k for k in TWO_BODY if k in arrays]
    if two_body and version < TWO_BODY_VERSION:
        fail("format_version", f"a two-body problem ({two_body[0]}) needs "
                               f"version {TWO_BODY_VERSION}, the file has "
                               f"{version}")

    meta = parse_meta(check_array(arrays, "meta", "str", 0))
    need = "mesh3d" if kind == "mesh" and dim == 3 else kind
    for name in META_REQUIRED[need]:
        if name not in meta:
            fail("meta", f"field {name!r} missing")
    if kind == "mesh":
        check_material(meta, dim)

    K = csr(arrays, "K")
    n = K.shape[0]
    f = check_array(arrays, "f", "float", 1, (n,))
    check_load("f", f, K)
    nc = len(contact_dofs)
    if nc < 1:
        fail("contact_dofs", "no contact nodes")
    check_range("contact_dofs", contact_dofs, -1, n)
    used = contact_dofs[contact_dofs >= 0]
    if len(np.unique(used)) != len(used):
        fail("contact_dofs", "a reduced DOF appears twice")
    M = csr(arrays, "M", nc)
    check_positive_definite(M, "M", backend="superlu")  # Nc × Nc; M⁻¹λ

    problem = dict(K=K, f=f, M=M, contact_dofs=contact_dofs, meta=meta)
    if kind == "mesh":
        problem.update(validate_mesh(arrays, n, contact_dofs))
        problem.update(validate_two_body(arrays, problem, K, meta))
    else:
        if (contact_dofs < 0).any():
            fail("contact_dofs", "a discrete problem has no Dirichlet DOFs "
                                 "(-1 entries are not allowed)")
        gap = check_array(arrays, "gap", "float", 1, (nc,))
        normal = check_array(arrays, "normal", "float", 2, (nc, dim))
        length = np.sqrt((normal ** 2).sum(axis=1))
        if (abs(length - 1) > 1e-9).any():
            i = int(np.argmax(abs(length - 1)))
            fail("normal", f"row {i} has length {length[i]:.12g}, expected "
                           "a unit vector")
        problem.update(gap=gap, normal=normal)
    problem.update(_validate_load_path(arrays, f, K, problem.get("nodes"),
                                       dim))
    return problem


def _check_keys(arrays, kind, dim):
    """Missing and unexpected keys for the kind and the dimension."""
    needs = {"all", kind, "optional"}
    if kind == "mesh" and dim == 3:
        needs.add("mesh3d")
    allowed = {k for k, (need, *_rest) in KEYS.items() if need in needs}
    if kind == "mesh":
        allowed |= set(TWO_BODY)
    if kind == "mesh" and dim == 3 and "mortar_slave" in arrays:
        for key in ("contact_faces", "obstacle_surface"):
            if key in arrays:
                fail(key, "not allowed in a two-body file (mortar_slave): "
                          "the contact is with the master body, whose "
                          "triangles are mortar_master")
        allowed -= {"contact_faces", "obstacle_surface"}
    if kind == "discrete":
        allowed -= set(ONLY_2D) | {"load_path_prescribed"}
    if dim == 3:
        allowed -= set(ONLY_2D)
    for key in sorted(arrays):
        if key not in allowed:
            where = f"{dim}D {kind!r}" if kind == "mesh" else repr(kind)
            fail(key, f"unexpected key in a {where} problem file")
    for key, (need, *_rest) in KEYS.items():
        if need in ("all", kind) and key not in arrays \
                or need == "mesh3d" and key in allowed and key not in arrays:
            where = f"3D {kind!r}" if need == "mesh3d" else repr(kind)
            fail(key, f"missing (required in a {where} problem file)")


def _validate_load_path(arrays, f, K, nodes, dim):
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
    check_load("load_path", path, K)
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
            (stages, len(nodes), dim))
    return out
