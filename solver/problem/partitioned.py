r"""The partitioned problem: a folder that each rank of ``mpiexec`` reads
in part (docs/npz-format.md, "The partitioned problem").

A rigid-obstacle (or two-body mortar) mesh problem is written once, by
``python -m solver convert X.npz DIR`` (:mod:`solver.mpi.convert`), as

* ``K.petsc``, ``f.petsc``: K and f in **PETSc's binary format**
  (``MatView`` / ``VecView`` with a binary viewer; big-endian, 32-bit
  indices), in the *padded* numbering of :class:`solver.mpi.layout.Layout`
  (row ``d·node + component``; a Dirichlet DOF an identity row scaled by
  the mean diagonal of K, its f entry that scale times the prescribed
  value, so that u there is the prescribed value). ``MatLoad`` /
  ``VecLoad`` give each rank only its rows.
* ``nodes.npy``, ``cells.npy``: the coordinates and the cells sorted by
  their smallest node (each rank memory-maps and writes one consecutive
  share of them, whose nodes lie close together).
* ``contact.npz``: what lives on Γc: the contact nodes that take part,
  their padded rows (frame rows and own rows), gaps, normals, tangents.
* ``contact/``: the same arrays, one ``.npy`` each, sorted by node: the
  contact nodes of a rank's node range are one slice of them, which the
  rank finds by a binary search of the memory-mapped ``node.npy`` and
  reads alone (:func:`load_contact_slice`; the full system on Krylov,
  :mod:`solver.mpi.partitioned_full`, where no rank holds all of Γc).
* ``problem.json``: sizes, the Dirichlet scale, ‖f‖, k̄, meta, source
  (``load_path``: whether the ``.npz`` had one).
* ``mass.npz`` (optional: folders converted before friction ran on them
  lack it): Γc's boundary mass matrix M (SciPy's ``save_npz``), for
  friction's lumped D and M⁻¹λ.
* ``mortar/`` (only for two bodies, ``problem.json``'s ``"mortar"``;
  :mod:`solver.mpi.convert_mortar`): E of the mortar's change of
  variables u = (I + E) v by rows, each node's body, D and the covered
  flags; then ``contact/`` and ``mass.npz`` are the nodewise problem's
  (the slave nodes' gaps s_j, normals and diag(D)).
* ``node_ids.npy`` (only in a renumbered folder, the converter's default,
  :mod:`solver.problem.renumber`): the ``.npz``'s number of each of the
  folder's nodes; the outputs' ``node`` fields give these
  (:func:`original_nodes`).

This module defines the layout, writes and checks PETSc's binary headers
with NumPy alone (no petsc4py), and validates a folder before any rank
reads it: each fault is one :class:`~solver.errors.ProblemError` line."""

import json
import os

import numpy as np

from ..errors import ProblemError

__all__ = ["PARTITIONED_VERSION", "FILES", "MASS_FILE", "load_mass",
           "CONTACT_KEYS", "META_KEYS", "MAT_CLASSID", "VEC_CLASSID",
           "write_petsc_matrix", "write_petsc_vector", "petsc_header",
           "read_partitioned_meta", "load_contact", "is_partitioned",
           "PartitionedProblem", "write_contact_by_node",
           "load_contact_slice", "CONTACT_DIR", "NODE_IDS",
           "original_nodes", "MORTAR_DIR", "MORTAR_FILES"]

#: Version of the folder's layout (``problem.json``'s ``"partitioned"``).
PARTITIONED_VERSION = 1

#: PETSc's class ids at the head of a binary Mat and Vec (petscmat.h,
#: petscvec.h: MAT_FILE_CLASSID, VEC_FILE_CLASSID).
MAT_CLASSID, VEC_CLASSID = 1211216, 1211214

#: The folder's files.
FILES = ("problem.json", "K.petsc", "f.petsc", "nodes.npy", "cells.npy",
         "contact.npz")

#: A two-body folder's sub-folder of the coupling, and its files
#: (:mod:`solver.mpi.convert_mortar`).
MORTAR_DIR = "mortar"
MORTAR_FILES = ("E_row.npy", "E_col.npy", "E_val.npy", "body.npy", "D.npy",
                "covered.npy")

#: Γc's boundary mass matrix (optional, friction only).
MASS_FILE = "mass.npz"

#: The ``.npz``'s node numbers of a renumbered folder's nodes (optional).
NODE_IDS = "node_ids.npy"


def original_nodes(folder, nodes):
    """The ``.npz``'s numbers of the folder's ``nodes`` (the same numbers
    unless the folder was renumbered, the converter's default: its
    :data:`NODE_IDS`, memory-mapped, only ``nodes`` read)."""
    path = os.path.join(folder, NODE_IDS)
    nodes = np.asarray(nodes, np.int64)
    if not os.path.exists(path):
        return nodes
    return np.asarray(np.load(path, mmap_mode="r")[nodes], np.int64)

#: ``contact.npz``: name -> (dtype kind, meaning).
CONTACT_KEYS = {
    "node": ("i", "global node of each contact node that takes part (Nca,)"),
    "index": ("i", "its position along the npz's contact_nodes (Nca,)"),
    "dofs": ("i", "padded row of each frame row: tangents, then the normal "
                  "(Nca, d); -1 a roller's constrained direction"),
    "node_dofs": ("i", "padded row of each component (Nca, d); -1 where "
                       "Dirichlet"),
    "gap": ("f", "initial gap s along the normal (Nca,)"),
    "normal": ("f", "unit normal from the body towards the obstacle "
                    "(Nca, d)"),
    "tangents": ("f", "the d - 1 unit tangents (Nca, d - 1, d)"),
    "oblique": ("b", "gap and normal projected onto the free components "
                     "(Nca,)"),
}

#: ``problem.json``'s required entries.
META_KEYS = ("partitioned", "dim", "n_nodes", "n", "nnz", "cell_kind",
             "dirichlet_scale", "load_norm", "stiffness", "gap_mode",
             "meta", "source")

_HEADER = np.dtype(">i4")


def is_partitioned(path):
    """Whether ``path`` names a partitioned problem (a folder)."""
    return os.path.isdir(path)


def write_petsc_matrix(path, A):
    """Write the square sparse ``A`` (CSR, float64, sorted indices) as
    PETSc's binary AIJ (MatView): the class id, rows, columns, nonzeros,
    the row lengths, the column indices, the values; all big-endian."""
    import scipy.sparse as sp

    A = sp.csr_matrix(A)
    A.sort_indices()
    m, n = A.shape
    with open(path, "wb") as stream:
        np.array([MAT_CLASSID, m, n, A.nnz], _HEADER).tofile(stream)
        np.diff(A.indptr).astype(_HEADER).tofile(stream)
        A.indices.astype(_HEADER).tofile(stream)
        A.data.astype(">f8").tofile(stream)


def write_petsc_vector(path, v):
    """Write ``v`` as PETSc's binary Vec (VecView)."""
    v = np.asarray(v, float)
    with open(path, "wb") as stream:
        np.array([VEC_CLASSID, len(v)], _HEADER).tofile(stream)
        v.astype(">f8").tofile(stream)


def petsc_header(path):
    """(class id, sizes…, expected file size in bytes) of a PETSc binary
    file, read from its first 16 bytes; ProblemError if not one."""
    name = os.path.basename(path)
    try:
        with open(path, "rb") as stream:
            head = np.frombuffer(stream.read(16), _HEADER)
    except OSError as exc:
        raise ProblemError(f"{path}: {exc.strerror.lower()}") from None
    if len(head) < 2 or head[0] not in (MAT_CLASSID, VEC_CLASSID):
        raise ProblemError(f"{path}: not a PETSc binary matrix or vector "
                           f"(no class id in its header)")
    if head[0] == VEC_CLASSID:
        return int(head[0]), (int(head[1]),), 8 + 8 * int(head[1])
    if len(head) < 4:
        raise ProblemError(f"{path}: truncated PETSc header ({name})")
    m, n, nnz = (int(x) for x in head[1:4])
    return int(head[0]), (m, n, nnz), 16 + 4 * m + 12 * nnz


def _check_binary(folder, name, classid, sizes):
    path = os.path.join(folder, name)
    found, shape, expected = petsc_header(path)
    kind = "matrix" if classid == MAT_CLASSID else "vector"
    if found != classid:
        raise ProblemError(f"{path}: a PETSc binary {kind} was expected")
    if shape != sizes:
        raise ProblemError(f"{path}: sizes {shape} in its header, "
                           f"problem.json says {sizes}")
    actual = os.path.getsize(path)
    if actual != expected:
        raise ProblemError(f"{path}: {actual} bytes, its header needs "
                           f"{expected} (truncated or damaged file)")


def read_partitioned_meta(folder):
    """``problem.json`` of the partitioned problem ``folder``, after
    checking that every file of :data:`FILES` is there with the sizes it
    says (headers and file lengths, not the values): ProblemError, one
    line, at the first fault."""
    folder = os.fspath(folder)
    for name in FILES:
        if not os.path.isfile(os.path.join(folder, name)):
            raise ProblemError(f"{folder}: a directory missing {name}, "
                               f"so not a partitioned problem (give a .npz "
                               f"file, or make the folder by python -m "
                               f"solver convert X.npz {folder})")
    path = os.path.join(folder, "problem.json")
    try:
        with open(path) as stream:
            meta = json.load(stream)
    except (OSError, ValueError) as exc:
        raise ProblemError(f"{path}: unreadable JSON: "
                           f"{' '.join(str(exc).split())}") from None
    missing = [k for k in META_KEYS if not isinstance(meta, dict)
               or k not in meta]
    if missing:
        raise ProblemError(f"{path}: missing {', '.join(missing)}")
    if meta["partitioned"] != PARTITIONED_VERSION:
        raise ProblemError(f"{path}: partitioned layout version "
                           f"{meta['partitioned']!r}, this solver reads "
                           f"{PARTITIONED_VERSION}")
    n, nnz = int(meta["n"]), int(meta["nnz"])
    if n != int(meta["n_nodes"]) * int(meta["dim"]):
        raise ProblemError(f"{path}: n must be n_nodes × dim")
    _check_binary(folder, "K.petsc", MAT_CLASSID, (n, n, nnz))
    _check_binary(folder, "f.petsc", VEC_CLASSID, (n,))
    if meta.get("mortar"):  # two bodies: E and the bodies, by rows
        for name in MORTAR_FILES:
            if not os.path.isfile(os.path.join(folder, MORTAR_DIR, name)):
                raise ProblemError(f"{folder}: a two-body folder missing "
                                   f"mortar/{name}: convert the .npz again")
    for name, shape in (("nodes.npy", (int(meta["n_nodes"]),
                                       int(meta["dim"]))),
                        ("cells.npy", None)):
        try:
            array = np.load(os.path.join(folder, name), mmap_mode="r")
        except (OSError, ValueError) as exc:
            raise ProblemError(f"{os.path.join(folder, name)}: unreadable "
                               f"array: {' '.join(str(exc).split())}") \
                from None
        if shape is not None and array.shape != shape:
            raise ProblemError(f"{os.path.join(folder, name)}: shape "
                               f"{array.shape}, expected {shape}")
    return meta


def load_contact(folder, dim):
    """The arrays of ``contact.npz`` (:data:`CONTACT_KEYS`), checked."""
    path = os.path.join(os.fspath(folder), "contact.npz")
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {k: data[k] for k in data.files}
    except (OSError, ValueError, EOFError) as exc:
        raise ProblemError(f"{path}: unreadable: "
                           f"{' '.join(str(exc).split())}") from None
    missing = [k for k in CONTACT_KEYS if k not in arrays]
    if missing:
        raise ProblemError(f"{path}: missing {', '.join(missing)}")
    m = len(arrays["gap"])
    for key, (kind, _) in CONTACT_KEYS.items():
        if arrays[key].dtype.kind != kind or len(arrays[key]) != m:
            raise ProblemError(f"{path}: {key} must be {m} entries of "
                               f"kind {kind!r}")
    if arrays["normal"].shape != (m, dim) or arrays["dofs"].shape != \
            (m, dim):
        raise ProblemError(f"{path}: normal and dofs must be ({m}, {dim})")
    if not np.isfinite(arrays["gap"]).all():
        raise ProblemError(f"{path}: a gap is not finite")
    return arrays


def load_mass(folder, n_contact):
    """Γc's boundary mass matrix of ``folder`` (CSR, n_contact²);
    ProblemError, one line, if the folder has none (converted before
    friction ran on partitioned problems) or it is not that size."""
    import scipy.sparse as sp

    path = os.path.join(os.fspath(folder), MASS_FILE)
    if not os.path.isfile(path):
        raise ProblemError(f"{folder}: no {MASS_FILE} (Γc's mass matrix, "
                           "which friction needs): convert the .npz again "
                           "with this version")
    try:
        M = sp.load_npz(path).tocsr()
    except (OSError, ValueError, KeyError) as exc:
        raise ProblemError(f"{path}: unreadable: "
                           f"{' '.join(str(exc).split())}") from None
    if M.shape != (n_contact, n_contact):
        raise ProblemError(f"{path}: shape {M.shape}, expected "
                           f"({n_contact}, {n_contact})")
    return M


#: The folder's per-array copy of ``contact.npz``, sorted by node.
CONTACT_DIR = "contact"


def write_contact_by_node(folder, arrays):
    """Write the arrays of ``contact.npz`` (:data:`CONTACT_KEYS`) as
    ``folder/contact/NAME.npy``, their rows sorted by ``node``."""
    order = np.argsort(arrays["node"], kind="stable")
    path = os.path.join(os.fspath(folder), CONTACT_DIR)
    os.makedirs(path, exist_ok=True)
    for key in CONTACT_KEYS:
        np.save(os.path.join(path, f"{key}.npy"),
                np.asarray(arrays[key])[order])


def load_contact_slice(folder, dim, first, last):
    """The arrays of ``contact/`` (:func:`write_contact_by_node`) at the
    contact nodes ``first`` ≤ node < ``last``: each array memory-mapped
    and only that slice read. ProblemError (one line) if the folder has
    no ``contact/`` (converted before it was written: convert again)."""
    path = os.path.join(os.fspath(folder), CONTACT_DIR)
    arrays = {}
    try:
        node = np.load(os.path.join(path, "node.npy"), mmap_mode="r")
        lo, hi = np.searchsorted(node, [first, last])
        for key in CONTACT_KEYS:
            array = np.load(os.path.join(path, f"{key}.npy"), mmap_mode="r")
            if len(array) != len(node):
                raise ValueError(f"{key}.npy has {len(array)} rows, "
                                 f"node.npy {len(node)}")
            arrays[key] = np.array(array[lo:hi])
    except (OSError, ValueError) as exc:
        raise ProblemError(f"{path}: unreadable ({' '.join(str(exc).split())}"
                           f"); the full system on Krylov reads each rank's "
                           f"contact nodes from it: convert the .npz again")\
            from None
    for key, (kind, _) in CONTACT_KEYS.items():
        if arrays[key].dtype.kind != kind:
            raise ProblemError(f"{path}: {key}.npy must be of kind {kind!r}")
    if arrays["normal"].shape[1:] != (dim,) or \
            arrays["dofs"].shape[1:] != (dim,):
        raise ProblemError(f"{path}: normal and dofs must have {dim} "
                           f"columns")
    if not np.isfinite(arrays["gap"]).all():
        raise ProblemError(f"{path}: a gap is not finite")
    return arrays


class PartitionedProblem:
    """A handle on a partitioned problem folder for :func:`solver.solve`
    (``load_problem(DIR)``): its ``problem.json`` validated, nothing of K
    read (the ranks of ``mpiexec`` read their rows when it is solved)."""

    kind = "partitioned"
    is_mortar = False
    floating = False

    def __init__(self, path):
        self.path = os.fspath(path)
        self.meta = read_partitioned_meta(self.path)
        self.dim = int(self.meta["dim"])
        self.source = self.path
        #: the friction steps are κ/κc · f (a load path is refused)
        self.load_path = None

    def check_friction(self):
        """ProblemError (one line) if friction cannot run on this folder:
        no Γc mass matrix (converted by an earlier version), or the
        ``.npz`` had a load path, which the folder does not keep."""
        if self.meta.get("interface_shift"):
            raise ProblemError(f"{self.path}: prescribed displacements at "
                               "the mortar interface enter its gaps at the "
                               "full load, and friction steps scale them; "
                               "not supported with friction (as the .npz)")
        if self.meta.get("load_path"):
            raise ProblemError(f"{self.path}: the problem file has a load "
                               "path, which the partitioned folder does not "
                               "keep; run the .npz for it")
        load_mass(self.path, int(self.meta.get("n_contact", -1)))

    def n_load_steps(self, steps=None):
        """Number of friction load steps: ``steps`` (default 100, as a
        problem file without a load path)."""
        return 100 if steps is None else int(steps)

    def __repr__(self):
        return (f"PartitionedProblem({self.path!r}: {self.dim}D, "
                f"{self.meta['n']} rows)")
