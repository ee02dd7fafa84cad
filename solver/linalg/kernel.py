r"""The rigid-body modes left in ker K, and a generalised inverse of K.

A body held only by contact has a singular stiffness: the rigid-body
motions that its Dirichlet conditions leave free (3 in 2D, 6 in 3D, minus
those the supports and rollers remove) are its kernel. :func:`rigid_modes`
finds them from the geometry: the infinitesimal rigid motions of the DOFs'
points (translations and rotations about the centroid, on the free DOFs
only) span a space G; the combinations with K G c = 0 are the kernel,
read from the SVD of the n × (3 or 6) matrix K G (a combination that moves
a prescribed DOF leaves forces of the size of K there, far above the
round-off of a true rigid motion).

:func:`fixing_dofs` chooses r DOFs where the modes are best conditioned
(QR with column pivoting of Rᵀ, i.e. far-apart points); with them held,

.. math:: K_F = \begin{bmatrix} K_{JJ} & 0 \\ 0 & \mathrm{diag}(K_{FF})
          \end{bmatrix}, \qquad K^+ b = K_F^{-1} b_0 \quad (b_0 = b
          \text{ with } b_F = 0),

is positive definite, and K⁺ is a generalised inverse of K (K K⁺ K = K):
for a load with Rᵀb = 0, u = K⁺b + Rα solves K u = b for every α
(Dostál, Kozubek, Markopoulos, Menšík, *Cholesky decomposition of a
positive semidefinite matrix with known kernel*, Appl. Math. Comput. 217
(2011) 6067-6077; Farhat & Géradin 1998). The factorisation of K_F checks
that K had no other kernel: a mechanism or a disconnected part leaves a
zero pivot, refused as for any K that is not positive definite."""

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = ["KERNEL_RTOL", "rigid_motions", "rigid_modes", "pinned",
           "fixing_dofs", "held_stiffness"]

#: A rigid motion c counts as in ker K if ‖K G c‖ ≤ this × ‖K‖‖G c‖.
KERNEL_RTOL = 1e-8


def rigid_motions(points, components, centre=None, length=None):
    """The infinitesimal rigid motions of DOFs at ``points`` (n, d) in
    ``components`` (n,): (n, 3) in 2D (u_x, u_y, rotation), (n, 6) in 3D
    (three translations, rotations about x, y, z), rotations about
    ``centre`` (default the centroid) scaled by 1/``length`` (default the
    extent) so that every column moves a point by at most about 1."""
    points = np.asarray(points, float)
    comp = np.asarray(components, np.int64)
    n, d = points.shape
    centre = points.mean(axis=0) if centre is None else np.asarray(centre)
    x = points - centre
    if length is None:
        length = float(np.abs(x).max(initial=0.0)) or 1.0
    x = x / length
    G = np.zeros((n, 3 if d == 2 else 6))
    for k in range(d):
        G[comp == k, k] = 1.0
    if d == 2:  # ω × r = ω(−y, x)
        G[:, 2] = np.where(comp == 0, -x[:, 1], x[:, 0])
    else:  # ω_a e_a × r for a = x, y, z
        for a, (i, j) in enumerate(((1, 2), (2, 0), (0, 1))):
            G[comp == j, 3 + a] = x[comp == j, i]
            G[comp == i, 3 + a] = -x[comp == i, j]
    return G


def rigid_modes(K, points, components, rtol=KERNEL_RTOL, groups=None):
    """(R, C): an orthonormal basis R (n, r) of the rigid motions in ker K
    (r = 0 for a supported body) and their coefficients C (3 or 6, r) on
    :func:`rigid_motions` (R = G C). ``groups`` (n,): the body of each DOF
    (several bodies, K block diagonal): each body's modes from its own
    block, with its own scale (a body 10⁶ times stiffer does not hide a
    soft body's supports), C then (B·3 or B·6, r), body by body."""
    if groups is not None:
        return _modes_by_body(K, points, components, rtol, groups)
    G = rigid_motions(points, components)
    norms = np.linalg.norm(G, axis=0)
    used = norms > 0
    if not used.any():
        return np.zeros((len(G), 0)), np.zeros((G.shape[1], 0))
    Q, T = np.linalg.qr(G[:, used] / norms[used])
    keep = np.abs(np.diag(T)) > 1e-10  # points on a line: fewer motions
    Q, T = Q[:, keep], T[np.ix_(keep, keep)]
    KQ = np.asarray(K @ Q)
    _, s, Vt = np.linalg.svd(KQ, full_matrices=False)
    scale = spla.norm(sp.csr_matrix(K), np.inf)  # ≥ ‖K‖₂ (symmetric K)
    null = s <= rtol * max(scale, np.finfo(float).tiny)
    V = Vt[null].T
    R = Q @ V
    C = np.zeros((G.shape[1], R.shape[1]))
    rows = np.flatnonzero(used)[keep]
    C[rows] = sla.solve_triangular(T, V) / norms[rows, None]
    return R, C


def pinned(points, components, rtol=KERNEL_RTOL):
    """Whether the prescribed DOFs at ``points`` (n, d) in ``components``
    (n,) of one connected elastic body stop every rigid motion: their rows
    of :func:`rigid_motions` have full column rank (smallest singular
    value of the column-normalised rows above ``rtol`` × the largest).
    Then K (the free DOFs' block of a stiffness whose kernel is the rigid
    motions) has none in its kernel: a rigid motion c with K G_f c = 0
    extended by zero on the prescribed DOFs has zero energy, so it is a
    rigid motion of the whole body, which must then leave every prescribed
    DOF at rest (G_x c = 0), impossible at full rank. A cheap sufficient
    test of a supported body (no product with K, no factorisation); False
    says nothing (:func:`rigid_modes` decides)."""
    points = np.asarray(points, float)
    if len(points) < (3 if points.shape[1] == 2 else 6):
        return False  # (none: a body with no Dirichlet DOF)
    G = rigid_motions(points, components)
    norms = np.linalg.norm(G, axis=0)
    if not (norms > 0).all():
        return False
    s = np.linalg.svd(G / norms, compute_uv=False)
    return bool(s[-1] > rtol * s[0])


def _modes_by_body(K, points, components, rtol, groups):
    """:func:`rigid_modes` of each body (``groups``), block by block."""
    K = sp.csr_matrix(K)
    groups = np.asarray(groups, np.int64)
    k = 3 if points.shape[1] == 2 else 6
    bodies = int(groups.max(initial=-1)) + 1
    Rs, Cs = [], []
    for b in range(bodies):
        mine = np.flatnonzero(groups == b)
        R_b, C_b = rigid_modes(K[mine][:, mine], points[mine],
                               components[mine], rtol)
        R = np.zeros((len(groups), R_b.shape[1]))
        R[mine] = R_b
        C = np.zeros((bodies * k, R_b.shape[1]))
        C[b * k:(b + 1) * k] = C_b
        Rs.append(R)
        Cs.append(C)
    return np.concatenate(Rs, axis=1), np.concatenate(Cs, axis=1)


def fixing_dofs(R, allowed):
    """r DOFs among ``allowed`` whose rows of R (n, r) are best
    conditioned (QR with column pivoting of R_allowedᵀ): holding them
    removes the kernel. Returns (dofs, the condition number of their
    r × r block)."""
    allowed = np.asarray(allowed, np.int64)
    r = R.shape[1]
    _, T, pivots = sla.qr(R[allowed].T, mode="economic", pivoting=True)
    dofs = allowed[pivots[:r]]
    cond = np.linalg.cond(R[dofs]) if r else 1.0
    return dofs, float(cond)


def held_stiffness(K, fixed):
    """K_F of the module docstring: K with the rows and columns of
    ``fixed`` replaced by their diagonal entries (CSR)."""
    K = sp.csr_matrix(K, copy=True)
    n = K.shape[0]
    fixed = np.asarray(fixed, np.int64)
    diagonal = K.diagonal()[fixed]
    held = np.zeros(n, bool)
    held[fixed] = True
    rows = np.repeat(held, np.diff(K.indptr))
    K.data[rows | held[K.indices]] = 0.0  # K's structure kept
    return sp.csr_matrix(K + sp.csr_matrix((diagonal, (fixed, fixed)),
                                           shape=(n, n)))
