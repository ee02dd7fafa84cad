"""What a mortar coupling is, in 2D and 3D: the diagonal D, the sparse M,
the slave nodal normals (and, in 3D, two tangents per node), the weighted
gaps g̃_j = n_j·(Σ_k M_jk x_k − D_jj x_j) and the coverage Σ_k M_jk/D_jj
(1 where the master covers the slave node's whole support: the partition
of unity); and a nodal pressure recovered over node patches from the dual
multiplier (:func:`patch_pressure`)."""

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = ["MortarCoupling", "assemble_coupling", "patch_pressure",
           "PAIR_CHUNK"]

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


def patch_pressure(facets, slave_nodes, D, pressure, take_part=None):
    r"""The patch-recovered nodal pressure of a dual multiplier:

    .. math::
        \bar p_j = \frac{\sum_{i \in \bar N(j)} D_{ii} \lambda_i}
                         {\sum_{i \in \bar N(j)} D_{ii}}
                  = \frac{\int \lambda_h w_j}{\int w_j}, \qquad
        w_j = \sum_{i \in \bar N(j)} N_i,

    N̄(j) the closed star of j (j and the slave nodes sharing a facet with
    it) among the nodes that take part: the contact force of the node's
    patch over the patch's area. By biorthogonality (∫ψ_i N_k = δ_ik D_kk)
    D_ii λ_i = ∫λ_h N_i, so p̄_j is the mean of the multiplier field λ_h =
    Σ λ_i ψ_i weighted by w_j ≥ 0 (1 on j's facets, falling to 0 over the
    next ring): an averaging recovery in the sense of Zienkiewicz & Zhu
    (IJNME 33, 1992), one ring wide. It is exact wherever λ_h is uniform
    over the patch (the contact patch test: every λ_i = p), is O(h²) off a
    smooth pressure where its gradient vanishes (at the axis of a Hertz
    contact) and O(h |∇p|) off elsewhere on an irregular star, and it
    damps the node-to-node oscillation of λ_j = z_j / D_jj that an
    irregular patch (a node of valence 5 beside nodes of valence 7, a
    small D_jj) produces; λ_j itself is the lumped L² projection of λ_h
    (∫λ_h N_j / ∫N_j), which that oscillation leaves.

    ``facets`` (nf, k) slave facets (segments or triangles) by node id;
    ``slave_nodes`` (ns,) node ids; ``D`` (ns,); ``pressure`` (ns,) or
    (steps, ns) the λ_j; ``take_part`` (ns,) bool, the nodes that take part
    (default all; the others get 0 and enter no patch). Returns p̄ in
    ``pressure``'s shape."""
    slave_nodes = np.asarray(slave_nodes, np.int64)
    ns = len(slave_nodes)
    position = np.full(int(max(np.max(facets, initial=-1),
                               np.max(slave_nodes, initial=-1))) + 1, -1)
    position[slave_nodes] = np.arange(ns)
    local = position[np.asarray(facets, np.int64)]
    local = local[(local >= 0).all(axis=1)]
    k = local.shape[1]
    rows = np.repeat(local, k, axis=1).ravel()
    cols = np.tile(local, (1, k)).ravel()
    star = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(ns, ns))
    star.data[:] = 1.0  # an edge once, however many facets share it
    part = np.ones(ns, bool) if take_part is None \
        else np.asarray(take_part, bool)
    weight = np.where(part, np.asarray(D, float), 0.0)
    force = weight * np.asarray(pressure, float)
    area = star @ weight
    recovered = (star @ np.atleast_2d(force).T).T / np.where(area > 0, area,
                                                              1.0)
    recovered[:, ~part] = 0.0
    return recovered.reshape(np.shape(pressure))
