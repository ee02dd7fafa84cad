r"""Normals from local polynomial fits ("jets") over each node's 2-ring
(Cazals & Pouget 2005, CAGD 22, 121-146), vectorised over all nodes.

Around node *i* with the angle-weighted normal :math:`n_0` and tangents
:math:`t_1, t_2`, each 2-ring neighbour *j* on the node's side of any edge
of the body (normals within ``CORNER_ANGLE``) has local coordinates
:math:`(\xi, \eta, \zeta) = (x_j - x_i)\cdot(t_1, t_2, n_0)`, scaled by
the RMS of :math:`\sqrt{\xi^2 + \eta^2}`. The jet through the node,

.. math::  \zeta \approx a\xi + b\eta + c_{20}\xi^2 + c_{11}\xi\eta
           + c_{02}\eta^2 + c_{30}\xi^3 + \dots + c_{03}\eta^3,

is fitted by least squares (normal equations by :func:`numpy.bincount`,
solved as one batch); its normal is :math:`(n_0 - a t_1 - b t_2)/\sqrt{1
+ a^2 + b^2}`, on the side of :math:`n_0`."""

import numpy as np
import scipy.sparse as sp

from ..curves.normals import CORNER_ANGLE

__all__ = ["two_rings", "tangent_pair", "jet_normals"]

#: Fewest 2-ring neighbours for the cubic (9 coefficients) and the
#: quadratic (5) jet.
MIN_CUBIC, MIN_QUADRATIC = 12, 7

#: Largest accepted condition number of the scaled normal equations.
MAX_CONDITION = 1e10


def two_rings(faces, n, rows):
    """(row, neighbour) pairs: the 2-ring of node ``rows[row]`` (the node
    itself excluded), from the face adjacency."""
    i = faces.ravel()
    j = np.roll(faces, -1, axis=1).ravel()
    adjacency = sp.coo_matrix(
        (np.ones(2 * len(i)), (np.r_[i, j], np.r_[j, i])), shape=(n, n)).tocsr()
    first = adjacency[rows]
    ring = (first + first @ adjacency).tocoo()
    keep = ring.col != rows[ring.row]
    return ring.row[keep], ring.col[keep]


def tangent_pair(normal):
    """Orthonormal t1, t2 with t1 × t2 = normal (rows of (m, 3))."""
    axis = np.eye(3)[np.argmin(np.abs(normal), axis=1)]
    t1 = np.cross(normal, axis)
    t1 /= np.linalg.norm(t1, axis=1)[:, None]
    return t1, np.cross(normal, t1)


def _monomials(xi, eta):
    return np.stack([xi, eta, xi * xi, xi * eta, eta * eta, xi ** 3,
                     xi * xi * eta, xi * eta * eta, eta ** 3], axis=1)


def _solve(rows, basis, zeta, m, k):
    """Least-squares coefficients of the first ``k`` monomials per row, and
    whether each row's system is well conditioned."""
    A = np.empty((m, k, k))
    b = np.empty((m, k))
    for p in range(k):
        b[:, p] = np.bincount(rows, basis[:, p] * zeta, minlength=m)
        for q in range(p, k):
            A[:, p, q] = A[:, q, p] = np.bincount(
                rows, basis[:, p] * basis[:, q], minlength=m)
    eig = np.linalg.eigvalsh(A)
    good = eig[:, 0] > eig[:, -1] / MAX_CONDITION
    A[~good] = np.eye(k)
    return np.linalg.solve(A, b[..., None])[..., 0], good


def jet_normals(nodes, faces, contact_nodes, normals,
                corner_angle=CORNER_ANGLE):
    """Jet-fit normals at ``contact_nodes`` (module docstring); ``normals``
    (n, 3) are the reference normals of all nodes, kept where no jet fits; a
    neighbour whose reference normal turns by more than ``corner_angle``
    degrees from the node's is left out of its fit."""
    m = len(contact_nodes)
    reference = normals[contact_nodes]
    rows, cols = two_rings(faces, len(nodes), contact_nodes)
    same_side = np.sum(reference[rows] * normals[cols], axis=1) \
        >= np.cos(np.radians(corner_angle))
    rows, cols = rows[same_side], cols[same_side]
    t1, t2 = tangent_pair(reference)
    d = nodes[cols] - nodes[contact_nodes[rows]]
    xi, eta, zeta = (np.sum(d * v[rows], axis=1) for v in (t1, t2, reference))
    count = np.bincount(rows, minlength=m)
    h = np.sqrt(np.bincount(rows, xi * xi + eta * eta, minlength=m)
                / np.maximum(count, 1))
    h = np.where(h > 0, h, 1.0)[rows]
    basis = _monomials(xi / h, eta / h)
    slope = np.zeros((m, 2))
    done = np.zeros(m, bool)
    for k, least in ((9, MIN_CUBIC), (5, MIN_QUADRATIC)):
        coef, good = _solve(rows, basis, zeta / h, m, k)
        use = good & ~done & (count >= least)
        slope[use] = coef[use, :2]
        done |= use
    normal = reference - slope[:, :1] * t1 - slope[:, 1:] * t2
    return normal / np.linalg.norm(normal, axis=1)[:, None]
