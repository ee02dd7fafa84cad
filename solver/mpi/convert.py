r"""``python -m solver convert X.npz DIR``: a rigid-obstacle problem as the
partitioned folder that ``mpiexec -n N python -m solver DIR --engine
petsc`` reads in part (:mod:`solver.problem.partitioned`; docs/npz-format.md,
"The partitioned problem").

The conversion runs once, serially, on a machine that holds the ``.npz``
(the SfePy export wrote it there): it pads K and f to the node-blocked
numbering of :class:`~solver.mpi.layout.Layout`, writes them in PETSc's
binary format with NumPy, sorts the cells by their smallest node, and
computes the contact geometry (gaps, normals, frames: thesis §2.1) of the
nodes that take part, which is all the distributed solve needs on Γc."""

import json
import os

import numpy as np
import scipy.sparse as sp

from ..contact.geometry import contact_geometry, contact_stiffness
from ..errors import ProblemError
from ..ncp import stable_norm
from ..problem import load_problem
from ..problem.partitioned import (MASS_FILE, PARTITIONED_VERSION,
                                   write_petsc_matrix, write_petsc_vector)
from .layout import Layout

__all__ = ["convert", "CELL_KINDS"]

#: (dimension, nodes per cell) -> VTK cell name (meshio's).
CELL_KINDS = {(2, 3): "triangle", (2, 4): "quad", (3, 4): "tetra",
              (3, 8): "hexahedron"}


def _padded_rows(rows, red_to_pad):
    """Reduced DOFs (−1 kept) in the padded numbering."""
    rows = np.asarray(rows, np.int64)
    return np.where(rows >= 0, red_to_pad[np.maximum(rows, 0)], -1)


def convert(source, folder, gap="obstacle"):
    """Write the partitioned folder ``folder`` from the problem file
    ``source`` (a path or a loaded problem); returns ``problem.json``'s
    contents. One rigid body against a rigid obstacle only (ProblemError
    otherwise); the nodes with a Dirichlet DOF take part as rollers, as
    :func:`solver.solve`'s default."""
    problem = load_problem(source) if isinstance(source, (str, os.PathLike)) \
        else source
    if problem.kind != "mesh" or problem.n_bodies != 1 or problem.is_mortar:
        raise ProblemError("convert: the partitioned problem holds one "
                           "elastic body against a rigid obstacle (a mesh "
                           "problem without mortar interfaces)")
    geometry = contact_geometry(problem, gap, rollers=True)
    layout = Layout(problem, 1)
    os.makedirs(folder, exist_ok=True)
    K = problem.K
    scale = float(np.mean(K.diagonal())) if K.shape[0] else 1.0
    K_pad = layout.matrix(K)
    nnz = int(K_pad.nnz)
    write_petsc_matrix(os.path.join(folder, "K.petsc"), K_pad)
    del K_pad
    f_pad = layout.pad(problem.f)  # Dirichlet rows: scale · ū (module doc)
    f_pad[layout.dirichlet] = scale * np.asarray(
        problem.u_prescribed, float).ravel()[layout.dirichlet]
    write_petsc_vector(os.path.join(folder, "f.petsc"), f_pad)
    cells = np.asarray(problem.cells, np.int64)
    first = cells.min(axis=1)
    order = np.argsort(first, kind="stable")
    np.save(os.path.join(folder, "nodes.npy"), np.asarray(problem.nodes,
                                                          float))
    np.save(os.path.join(folder, "cells.npy"), cells[order])
    pad = layout.red_to_pad
    np.savez(os.path.join(folder, "contact.npz"),
             node=np.asarray(problem.contact_nodes, np.int64)[geometry.index],
             index=np.asarray(geometry.index, np.int64),
             dofs=_padded_rows(geometry.dofs, pad),
             node_dofs=_padded_rows(geometry.node_dofs, pad),
             gap=np.asarray(geometry.gap, float),
             normal=np.asarray(geometry.normal, float),
             tangents=np.asarray(geometry.tangents, float),
             oblique=np.asarray(geometry.oblique, bool))
    # Γc's boundary mass matrix (n_contact², sparse): friction's lumped D
    # and M⁻¹λ (solver.mpi.partitioned_friction)
    sp.save_npz(os.path.join(folder, MASS_FILE), sp.csr_matrix(problem.M))
    meta = dict(
        partitioned=PARTITIONED_VERSION, dim=int(problem.dim),
        n_nodes=int(len(problem.nodes)), n=int(layout.n),
        n_free=int(problem.n_dofs), nnz=nnz,
        cell_kind=CELL_KINDS[problem.dim, cells.shape[1]],
        dirichlet_scale=scale, load_norm=float(stable_norm(problem.f)),
        stiffness=float(contact_stiffness(K, geometry)), gap_mode=gap,
        n_contact=int(problem.n_contact),
        excluded=int(len(geometry.excluded["index"])),
        load_path=problem.load_path is not None,
        meta=problem.meta, source=str(problem.source))
    with open(os.path.join(folder, "problem.json"), "w") as stream:
        json.dump(meta, stream, indent=1, sort_keys=True)
    return meta
