"""What a mortar coupling is, in 2D and 3D: the diagonal D, the sparse M,
the slave nodal normals (and, in 3D, two tangents per node), the weighted
gaps g̃_j = n_j·(Σ_k M_jk x_k − D_jj x_j) and the coverage Σ_k M_jk/D_jj
(1 where the master covers the slave node's whole support: the partition
of unity)."""

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = ["MortarCoupling", "assemble_coupling", "PAIR_CHUNK"]

#: Candidate pairs integrated at once (bounds the memory: a few arrays of
#: this many floats times the Gauss points).
PAIR_CHUNK = 200_000


@dataclass
class MortarCoupling:
    """D, M, normals and gaps of the slave nodes.

    Attributes: ``slave_nodes`` (ns,) global ids (in 2D in chain order);
    ``D`` (ns,) the diagonal; ``M`` (ns, n_nodes) CSR; ``normal`` (ns, d)
    unit n_j; ``gap`` (ns,) weighted gap g̃_j; ``coverage`` (ns,)
    Σ_k M_jk/D_jj; ``variant`` "mortar" or "node-to-segment"."""

    slave_nodes: np.ndarray
    D: np.ndarray
    M: sp.csr_matrix
    normal: np.ndarray
    gap: np.ndarray
    coverage: np.ndarray
    variant: str = "mortar"

    @property
    def P(self):
        """P = D⁻¹M (sparse): v_j = u_j − Σ_k P_jk u_k."""
        return sp.diags(1.0 / self.D) @ self.M


def assemble_coupling(slave_nodes, n_nodes, D, rows, cols, vals, nodes,
                      normal, variant):
    """MortarCoupling from the triplets of M (rows: positions in
    ``slave_nodes``, cols: node ids) and the diagonal D."""
    ns = len(slave_nodes)
    M = sp.csr_matrix((vals, (rows, cols)), shape=(ns, n_nodes))
    M.sum_duplicates()
    gap = np.einsum("ij,ij->i", normal, M @ nodes - D[:, None]
                    * nodes[slave_nodes])
    coverage = np.asarray(M.sum(axis=1)).ravel() / D
    return MortarCoupling(slave_nodes, D, M, normal, gap, coverage, variant)
