r"""Dual mortar coupling of two 2D bodies on a line interface, computed once
on the undeformed interface (small deformation and small sliding).

On each slave segment (a, b) the *dual* basis ψ_a = 2N_a − N_b,
ψ_b = 2N_b − N_a is biorthogonal to the P1 basis (∫ψ_a N_b = 0,
∫ψ_a N_a = ∫N_a; Wohlmuth 2000, (2.1)). Then

.. math::
    D_{jj} = \int_{Γ_s} ψ_j N_j = \int_{Γ_s} N_j, \qquad
    M_{jk} = \int_{Γ_s} ψ_j\, N^m_k(η(ξ)),

D diagonal (the slave node's tributary length), M sparse, integrated
segment to segment (Popp, Gee & Wall, IJNME 79 (2009) 1354, §3.2-3.3):
master end points projected onto the slave segment along the interpolated
slave normal n(ξ) = N_a n_a + N_b n_b (a quadratic in ξ, solved in closed
form), the overlap cut in ξ, and on it Gauss points whose master
coordinate η is where x(ξ) + α n(ξ) meets the master segment. n_j is the
average of the unit outward normals (t_y, −t_x)/|t| of the slave segments
at j (the body lies left of a → b). Only facing master segments
(n_s·n_m < 0) near a slave segment are projected onto
(:func:`candidate_pairs`; Yang & Laursen, Comput. Mech. 41 (2008) 189).

The weighted gap of slave node j (Hüeber & Wohlmuth, CMAME 194 (2005)
3147, (3.4)) is g̃_j = n_j·(Σ_k M_jk x_k − D_jj x_j) ≥ 0 in the reference
configuration. ``coverage`` = Σ_k M_jk / D_jj is 1 (the partition of
unity) where the master covers node j's whole support; elsewhere the node
takes no part. :func:`node_to_segment` builds the classical coupling in
the same form; it fails the contact patch test on non-matching meshes
(Taylor & Papadopoulos, IJNME 31 (1991) 1087)."""

import numpy as np

from .coupling import PAIR_CHUNK, assemble_coupling
from .search import candidate_pairs, default_reach

__all__ = ["segment_normals", "nodal_normals", "chain_order",
           "mortar_coupling", "node_to_segment"]

#: Gauss-Legendre points on [0, 1] used on every overlap cell (3: exact
#: for the quadratic ψ_j N_k of a flat interface, near-exact when curved).
N_GAUSS = 3


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def segment_normals(nodes, segments):
    """Unit outward normals (t_y, −t_x)/|t| and lengths of ``segments``."""
    t = nodes[segments[:, 1]] - nodes[segments[:, 0]]
    length = np.hypot(t[:, 0], t[:, 1])
    return np.column_stack([t[:, 1], -t[:, 0]]) / length[:, None], length


def nodal_normals(nodes, segments, node_ids):
    """Averaged unit segment normals at ``node_ids`` (renormalised)."""
    normal, _ = segment_normals(nodes, segments)
    total = np.zeros((len(nodes), 2))
    np.add.at(total, segments[:, 0], normal)
    np.add.at(total, segments[:, 1], normal)
    total = total[node_ids]
    return total / np.hypot(total[:, 0], total[:, 1])[:, None]


def _project_onto_slave(xa, xb, na, nb, xm):
    """ξ with (x(ξ) − x_m) × n(ξ) = 0 (pairs vectorised): the root of the
    quadratic c0 + c1 ξ + c2 ξ² nearest the linear one."""
    A, B, C = xa - xm, xb - xa, nb - na
    c0, c1, c2 = _cross(A, na), _cross(A, C) + _cross(B, na), _cross(B, C)
    with np.errstate(divide="ignore", invalid="ignore"):
        linear = -c0 / c1
        root = np.sqrt(np.maximum(c1 * c1 - 4 * c2 * c0, 0.0))
        q = -0.5 * (c1 + np.copysign(root, c1))   # stable roots q/c2, c0/q
        r1, r2 = q / c2, c0 / q
    best = np.where(np.abs(r1 - linear) < np.abs(r2 - linear), r1, r2)
    flat = np.abs(c2) <= 1e-12 * (np.abs(c1) + np.abs(c0))
    return np.where(flat | ~np.isfinite(best), linear, best)


def chain_order(segments):
    """The nodes of oriented segment chains in walking order (a → b),
    chain after chain (each from its node that ends no segment)."""
    segments = np.asarray(segments, np.int64)
    after = dict(zip(segments[:, 0].tolist(), segments[:, 1].tolist()))
    starts = sorted(set(after) - set(segments[:, 1].tolist()),
                    key=lambda a: np.flatnonzero(segments[:, 0] == a)[0])
    order, seen = [], set()
    for node in starts or segments[:1, 0].tolist():  # a closed loop: any
        while node is not None and node not in seen:
            order.append(node)
            seen.add(node)
            node = after.get(node)
    return np.array(order, np.int64)


def _gauss(n):
    p, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (p + 1), 0.5 * w


def _interface(nodes, slave, master, slave_nodes):
    """What both couplings start from: nodes, slave, master, slave_nodes,
    each node's row ``pos`` (−1 off the slave side), the segment normals and
    lengths, the slave nodal normals and D (the tributary lengths)."""
    nodes = np.asarray(nodes, float)
    slave, master = np.asarray(slave, np.int64), np.asarray(master, np.int64)
    slave_nodes = chain_order(slave) if slave_nodes is None \
        else np.asarray(slave_nodes, np.int64)
    pos = np.full(len(nodes), -1)
    pos[slave_nodes] = np.arange(len(slave_nodes))
    n_s, ls = segment_normals(nodes, slave)
    n_m, _ = segment_normals(nodes, master)
    normal = nodal_normals(nodes, slave, slave_nodes)
    D = np.zeros(len(slave_nodes))
    np.add.at(D, pos[slave[:, 0]], ls / 2)
    np.add.at(D, pos[slave[:, 1]], ls / 2)
    return nodes, slave, master, slave_nodes, pos, n_s, ls, n_m, normal, D


def mortar_coupling(nodes, slave, master, slave_nodes=None,
                    n_gauss=N_GAUSS, search=None):
    """The dual mortar D, M, n_j, g̃_j of slave segments ``slave`` against
    master segments ``master`` (module docstring), vectorised over the facing
    segment pairs of :func:`candidate_pairs` (in chunks of
    :data:`PAIR_CHUNK`), rows in the order ``slave_nodes`` (default
    :func:`chain_order`); pairs farther apart than ``search`` (default
    :func:`default_reach`) along the slave normal are left out."""
    nodes, slave, master, slave_nodes, pos, n_s, ls, n_m, normal, D = \
        _interface(nodes, slave, master, slave_nodes)
    reach = default_reach(nodes, slave, master) if search is None \
        else float(search)
    I, J = candidate_pairs(nodes, slave, master, reach)
    facing = np.einsum("ij,ij->i", n_s[I], n_m[J]) < -1e-8
    I, J = I[facing], J[facing]
    parts = [_overlaps(nodes, slave, master, I[i:i + PAIR_CHUNK],
                       J[i:i + PAIR_CHUNK], ls, normal, pos, n_gauss,
                       np.inf if search is None else reach)
             for i in range(0, max(len(I), 1), PAIR_CHUNK)]
    rows, cols, vals = (np.concatenate([p[k] for p in parts])
                        for k in range(3))
    return assemble_coupling(slave_nodes, len(nodes), D, rows, cols, vals, nodes,
                     normal, "mortar")


def _overlaps(nodes, slave, master, I, J, ls, normal, pos, n_gauss,
              search):
    """Triplets of M from the facing segment pairs (slave I, master J):
    the overlap cut in ξ, Gauss on it."""
    a, b = slave[I, 0], slave[I, 1]
    xa, xb, na, nb = nodes[a], nodes[b], normal[pos[a]], normal[pos[b]]
    with np.errstate(divide="ignore", invalid="ignore"):
        xi_c = _project_onto_slave(xa, xb, na, nb, nodes[master[J, 0]])
        xi_d = _project_onto_slave(xa, xb, na, nb, nodes[master[J, 1]])
    lo = np.clip(np.minimum(xi_c, xi_d), 0, 1)
    hi = np.clip(np.maximum(xi_c, xi_d), 0, 1)
    first = hi - lo > 1e-12                           # overlapping pairs
    I, J, a, b, xa, xb, na, nb, lo, hi = (
        v[first] for v in (I, J, a, b, xa, xb, na, nb, lo, hi))
    c, d = master[J, 0], master[J, 1]
    p, w = _gauss(n_gauss)
    xi = lo[:, None] + (hi - lo)[:, None] * p          # (pairs, g)
    x = xa[:, None] * (1 - xi)[..., None] + xb[:, None] * xi[..., None]
    n = na[:, None] * (1 - xi)[..., None] + nb[:, None] * xi[..., None]
    e = (nodes[d] - nodes[c])[:, None]
    rel, det = x - nodes[c][:, None], _cross(e, n)
    with np.errstate(divide="ignore", invalid="ignore"):
        eta, alpha = _cross(rel, n) / det, _cross(rel, e) / det
    keep = np.isfinite(eta).all(axis=1) & \
        (np.abs(alpha).min(axis=1) <= search)
    W = (w * (hi - lo)[:, None] * ls[I][:, None])[keep]
    xi, eta = xi[keep], np.clip(eta[keep], 0, 1)
    psi = (2 - 3 * xi, 3 * xi - 1)
    N = (1 - eta, eta)
    rows = np.concatenate([pos[s[keep]] for s in (a, b) for _ in (c, d)])
    cols = np.concatenate([m[keep] for _ in (a, b) for m in (c, d)])
    vals = np.concatenate([(W * ps * Nm).sum(axis=1) for ps in psi
                           for Nm in N])
    return rows, cols, vals


def node_to_segment(nodes, slave, master, slave_nodes=None):
    """The node-to-segment coupling in the same form: D_jj the tributary
    length of slave node j, M_jk = D_jj N^m_k(η_j) on the facing master
    segment nearest x_j (closest point η_j); coverage 0 where that point is
    an end of the master chain outside it. Dense over node × segment (a
    comparison tool for the patch test, not for large interfaces)."""
    nodes, slave, master, slave_nodes, _, _, _, n_m, normal, D = \
        _interface(nodes, slave, master, slave_nodes)
    x = nodes[slave_nodes][:, None]                    # (ns, 1, 2)
    xc, e = nodes[master[:, 0]], nodes[master[:, 1]] - nodes[master[:, 0]]
    t = np.einsum("ijk,jk->ij", x - xc, e) / (e * e).sum(axis=1)
    foot = xc + np.clip(t, 0, 1)[..., None] * e
    dist = np.linalg.norm(x - foot, axis=2)
    dist[normal @ n_m.T >= 0] = np.inf                 # facing only
    k = np.argmin(dist, axis=1)
    j = np.arange(len(slave_nodes))
    eta = t[j, k]
    inside = (eta > -1e-9) & (eta < 1 + 1e-9) & np.isfinite(dist[j, k])
    eta = np.clip(eta, 0, 1)
    rows = np.concatenate([j, j])
    cols = np.concatenate([master[k, 0], master[k, 1]])
    vals = np.concatenate([D * (1 - eta), D * eta]) * np.tile(inside, 2)
    return assemble_coupling(slave_nodes, len(nodes), D, rows, cols, vals, nodes,
                     normal, "node-to-segment")
