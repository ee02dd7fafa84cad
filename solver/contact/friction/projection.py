r"""The projection onto the Coulomb disc and its derivative, shared by
the load step's sparse Jacobian (:mod:`.system`) and the condensed 3D
direction (:mod:`.disc`).

With w = g − c_t ZRΔu the projection form's row is g − P(w), P(w) =
w·min(1, b/|w|) onto the disc |·| ≤ b = f_c p of R^{d−1} (Alart & Curnier,
CMAME 92 (1991) 353; Hüeber, Stadler & Wohlmuth, SIAM J. Sci. Comput. 30
(2008) 572). Its generalised derivative: at a stick node (|w| < b)
∂P/∂w = I; at a slip node ∂P/∂w = (b/|w|)(I − ŵŵᵀ) and ∂P/∂b = ŵ. In 2D
(d − 1 = 1) this is the clip onto [−b, b]. At a roller, w_c ≡ 0 along
its constrained tangent e_c, so the e_c column of ∂P/∂w drops.
"""

import numpy as np
import scipy.sparse as sp

__all__ = ["project_disc", "disc_derivative", "block_diagonal"]


def project_disc(w, b, k):
    """P(w) onto the disc (ball) |·| ≤ b of R^k, per node: w flat (m·k,)
    node by node, b (m,); w·min(1, b/|w|)."""
    w = np.reshape(w, (len(b), k))
    size = np.linalg.norm(w, axis=1)
    ratio = np.minimum(1.0, np.divide(b, size, out=np.ones_like(size),
                                      where=size > b))
    return (w * ratio[:, None]).ravel()


def disc_derivative(w, b, t_free=None):
    """∂P/∂w of the projection at w (m, k) for the radii b (m,).

    Returns (P, stick, ratio, slip_hat): the (m, k, k) blocks ∂P/∂w (the
    e_c columns dropped where ``t_free``, (m·k,) bool, is False), the stick
    mask |w| < b, b/|w| (1 at stick nodes) and ŵ at slip nodes (0 at
    stick nodes), which is ∂P/∂b."""
    m, k = w.shape
    size = np.linalg.norm(w, axis=1)
    stick = size < b
    ratio = np.where(stick, 1.0, np.divide(
        b, size, out=np.zeros(m), where=size > 0))
    hat = np.divide(w, size[:, None], out=np.zeros_like(w),
                    where=size[:, None] > 0)
    slip_hat = np.where(stick[:, None], 0.0, hat)
    P = ratio[:, None, None] * (np.eye(k) - slip_hat[:, :, None]
                                * slip_hat[:, None, :])
    if t_free is not None:
        P *= np.asarray(t_free, float).reshape(m, 1, k)
    return P, stick, ratio, slip_hat


def block_diagonal(P):
    """Sparse block diagonal of the (m, k, k) blocks P."""
    m, k, _ = P.shape
    rows = np.repeat(np.arange(m * k).reshape(m, k), k, axis=1).ravel()
    cols = np.tile(np.arange(m * k).reshape(m, k), (1, k)).ravel()
    return sp.csr_matrix((P.ravel(), (rows, cols)), shape=(m * k, m * k))
