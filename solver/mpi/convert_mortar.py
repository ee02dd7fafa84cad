r"""The two-body (dual mortar) branch of ``python -m solver convert``: two
elastic bodies as a partitioned folder whose ranks solve the nodewise
problem in v = T u (:mod:`solver.contact.two_body`, module docstring).

The coupling (D, M, slave normals, weighted gaps) is computed here, once,
on the contact surface only, by the serial
:class:`~solver.contact.two_body.TwoBodyMap`; K and f are written
*unchanged* by the converter (streamed as for one body: the map sees K's
diagonal, which is all it reads of K here, since the slave DOFs' diagonal
of K̃ = T⁻ᵀKT⁻¹ is K's: E has master columns only). Written besides:

* ``mortar/E_row.npy``, ``E_col.npy``, ``E_val.npy``: E of T⁻¹ = I + E
  (free slave DOF rows × free master DOF columns, P = D⁻¹M ⊗ n-blocks) in
  the padded numbering, sorted by row: each rank reads the rows of its
  slave DOFs (:func:`solver.mpi.mortar_folder.read_E`);
* ``mortar/body.npy``: each node's body (the near-null space is each
  body's rigid modes, :func:`solver.contact.two_body.near_null_space`);
* ``mortar/D.npy``, ``mortar/covered.npy``: the dual weight D_jj of each
  slave node (``contact_nodes`` order) and whether it takes part;
* ``contact/``: the nodewise problem's geometry (gap s_j = g̃⁰_j/D_jj plus
  the Dirichlet shift, the slave normal, its frame), and ``mass.npz`` =
  diag(D), friction's lumped weight (the equivalent problem's M).

``problem.json`` says ``"mortar": true`` and carries ‖f̃‖ = ‖T⁻ᵀ f‖, the
stopping scale of the serial run on the same problem."""

import os

import numpy as np
import scipy.sparse as sp

from ..contact.geometry import contact_geometry
from ..contact.two_body import TwoBodyMap
from ..errors import ProblemError
from ..ncp import stable_norm
from ..problem.partitioned import MORTAR_DIR

__all__ = ["MortarConversion"]


class MortarConversion:
    """The coupling of the two-body mesh problem ``problem`` (K may be the
    streamed converter's diagonal stand-in): ``geometry`` (the nodewise
    problem's, in the reduced numbering), ``mass`` (diag D), ``load_norm``
    (‖T⁻ᵀ f‖), ``shift`` (whether prescribed displacements enter the
    gaps: friction then refuses the folder) and ``E`` (reduced, CSR)."""

    def __init__(self, problem):
        if problem.n_bodies != 2:
            raise ProblemError("convert: a mortar problem of two bodies is "
                               f"converted, this one has {problem.n_bodies}")
        if not problem.held_by_supports():
            raise ProblemError(
                "convert: a body held by contact only (its Dirichlet "
                "conditions leave a rigid motion free) is not converted; "
                "run the .npz (serial engine, backend='amg' or the "
                "factorisation)")
        mapping = TwoBodyMap(problem, "mortar")
        equivalent = mapping.equivalent
        self.geometry = mapping.mark_uncovered(
            contact_geometry(equivalent, rollers=True))
        self.mass = sp.csr_matrix(equivalent.M)
        self.load_norm = float(stable_norm(equivalent.f))
        self.E = (mapping.T_inv - sp.identity(problem.n_dofs,
                                              format="csr")).tocsr()
        self.E.eliminate_zeros()
        coupling = mapping.coupling
        self.D, self.covered = np.asarray(coupling.D, float), \
            np.asarray(mapping.covered, bool)
        # the gap of the problem in v minus g̃⁰/D: the Dirichlet shift
        self.shift = bool(np.any(np.abs(
            equivalent.gap - coupling.gap / coupling.D) > 0))
        self.body = np.asarray(problem.body, np.int64)

    def write(self, folder, red_to_pad):
        """Write ``mortar/`` (module docstring); E's rows and columns in
        the padded numbering (``red_to_pad``), its rows sorted."""
        path = os.path.join(os.fspath(folder), MORTAR_DIR)
        os.makedirs(path, exist_ok=True)
        E = self.E.tocoo()
        rows, cols = red_to_pad[E.row], red_to_pad[E.col]
        order = np.lexsort((cols, rows))
        for name, array in (("E_row", rows[order]), ("E_col", cols[order]),
                            ("E_val", E.data[order]), ("body", self.body),
                            ("D", self.D), ("covered", self.covered)):
            np.save(os.path.join(path, f"{name}.npy"), array)

    def meta(self):
        """``problem.json``'s entries of a two-body folder."""
        return dict(mortar=True, n_bodies=2, interface_shift=self.shift,
                    E_nnz=int(self.E.nnz),
                    n_covered=int(np.count_nonzero(self.covered)))
