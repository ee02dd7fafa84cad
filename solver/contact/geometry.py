r"""Per-node contact frames and gaps: all the contact systems see (§2.1).

A :class:`ContactGeometry` holds, at the free contact nodes, the DOFs, the
initial gap s along the unit normal ν (from the body towards the obstacle)
and the d − 1 tangents (:func:`solver.geometry.frames.tangent_basis`; in 2D
the thesis's γ = (−ν_y, ν_x)). :func:`rotation` builds the sparse **R** of
(58)-(60) from them for any d: at contact node i with DOFs (a_i, …, c_i)
its rows are the tangents, then the normal, so that (Ru) holds the
tangential components first and the normal one last; R is the identity
elsewhere. The contact systems never ask the dimension anything else.
"""

import numpy as np
import scipy.sparse as sp

from ..errors import SolverError
from ..geometry.frames import frames, tangent_basis

__all__ = ["GAP_MODES", "ContactGeometry", "contact_geometry",
           "problem_dim", "rotation", "contact_stiffness"]

#: How gaps and normals are found (thesis §2.1.1 / §2.1.2).
GAP_MODES = ("obstacle", "body")


class ContactGeometry:
    """Gaps and frames at the free contact nodes (evaluated once, §2.1).

    Attributes
    ----------
    index : (Nca,) int
        Rows of ``problem.contact_dofs`` (positions along Γc) of the free
        contact nodes.
    dofs : (Nca, d) int
        Their reduced DOFs (x, y[, z]).
    gap : (Nca,) float
        Initial signed gap s along ``normal`` (negative = penetration).
    normal : (Nca, d) float
        Unit normals ν from the body towards the obstacle.
    foot : (Nca,) or (Nca, d) float, or None
        Where the gap is measured to: the obstacle parameter t (2D) or the
        point on the obstacle surface (3D).
    mode : str
        ``"obstacle"``, ``"body"`` or ``"given"`` (discrete problems).
    dim : int
        d, the number of columns of ``normal``.
    tangents : (Nca, d − 1, d) float
        Orthonormal tangents (default :func:`tangent_basis` of ``normal``).
    """

    def __init__(self, index, dofs, gap, normal, foot=None, mode="given",
                 tangents=None):
        self.index, self.dofs = index, dofs
        self.gap, self.normal, self.foot, self.mode = gap, normal, foot, mode
        self.dim = int(np.shape(normal)[1])
        self.tangents = tangent_basis(normal) if tangents is None \
            else np.asarray(tangents, float)

    def rotation(self):
        """The per-node frames Q (Nca, d, d): rows the d − 1 tangents, then
        the normal (Q v = tangential components, then the normal one)."""
        return frames(self.normal, self.tangents)

    def renumbered(self, dofs):
        """The same nodes with other DOFs (a condensed numbering)."""
        return ContactGeometry(self.index, dofs, self.gap, self.normal,
                               self.foot, self.mode, self.tangents)

    def subset(self, nodes, dofs=None):
        """The nodes ``nodes`` (positions in this geometry), with ``dofs``
        (default: their own)."""
        foot = None if self.foot is None else self.foot[nodes]
        return ContactGeometry(
            self.index[nodes], self.dofs[nodes] if dofs is None else dofs,
            self.gap[nodes], self.normal[nodes], foot, self.mode,
            self.tangents[nodes])


def problem_dim(problem):
    """d of ``problem`` (its ``dim``, else the columns of contact_dofs)."""
    return int(getattr(problem, "dim", problem.contact_dofs.shape[1]))


def contact_geometry(problem, gap="obstacle"):
    """Gaps and normals of ``problem`` (thesis §2.1).

    ``gap="obstacle"``: nearest obstacle point, ν = obstacle normal there
    (§2.1.1). ``gap="body"``: ν = the body's outward normal (2D: from a
    natural cubic spline through Γc, §2.1.3; 3D: nodal normals of the
    contact triangles, :func:`solver.geometry.surface_normals`), gap along
    that line (§2.1.2). Discrete problems carry their gaps and normals;
    ``gap`` is ignored.
    """
    free = np.flatnonzero((problem.contact_dofs >= 0).all(axis=1))
    dofs = problem.contact_dofs[free]
    if problem.kind == "discrete":
        return ContactGeometry(free, dofs, problem.gap[free],
                               problem.normal[free])
    if gap not in GAP_MODES:
        raise SolverError(f"gap mode must be one of {GAP_MODES}, got {gap!r}")
    if problem_dim(problem) == 3:
        return _geometry_3d(problem, gap, free, dofs)
    from ..geometry.gap import gap_along_normals, gap_from_obstacle
    from ..geometry.normals import boundary_normals

    body = boundary_normals(problem.nodes, problem.cells,
                            problem.contact_nodes)[free]
    ids = problem.contact_nodes[free]
    points = problem.nodes[ids]
    if gap == "obstacle":
        s, normal, t = gap_from_obstacle(points, problem.obstacle, body,
                                         node_ids=ids)
    else:
        s, normal, t = gap_along_normals(points, body, problem.obstacle,
                                         node_ids=ids)
    return ContactGeometry(free, dofs, s, normal, t, gap)


def _geometry_3d(problem, gap, free, dofs):
    """3D: the obstacle surface's closest point ("obstacle": ν = −its
    outward normal there) or the ray along the body's outward normal
    ("body": ν = that normal); the 3D contract of issue 18."""
    points = problem.nodes[problem.contact_nodes[free]]
    if gap == "obstacle":
        s, normal, foot = problem.obstacle.gap_along_obstacle_normal(points)
    else:
        from ..geometry.surface_normals import surface_normals

        normal = surface_normals(problem.nodes, problem.contact_faces,
                                 problem.contact_nodes)[free]
        s, foot = problem.obstacle.gap_along_rays(points, normal)
    return ContactGeometry(free, dofs, np.asarray(s, float),
                           np.asarray(normal, float), foot, gap)


def rotation(n, geometry):
    """R of (58)-(60), sparse (n, n), for any d: at contact node i the rows
    of its DOFs are its tangents, then its normal (in 2D row a_i = γ_i =
    (−ν_y, ν_x), row b_i = ν_i); identity elsewhere.

    Returns (R, other DOFs, tangential rows, normal rows): the tangential
    rows are ``dofs[:, :-1]`` node by node ((Nca,) in 2D, (Nca·(d − 1),)
    in general), the normal rows ``dofs[:, -1]``.
    """
    dofs = geometry.dofs
    d = dofs.shape[1]
    other = np.setdiff1d(np.arange(n), dofs.ravel())
    Q = geometry.rotation()  # (m, d, d): Q[i, r, c] at (dofs[i, r], dofs[i, c])
    rows = np.concatenate([other] + [np.repeat(dofs[:, r], d)
                                     for r in range(d)])
    cols = np.concatenate([other] + [dofs.ravel()] * d)
    vals = np.concatenate([np.ones(len(other))] + [Q[:, r, :].ravel()
                                                   for r in range(d)])
    R = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
    return R, other, dofs[:, :-1].ravel(), dofs[:, -1]


def contact_stiffness(K, geometry):
    """k̄: the mean diagonal stiffness at the contact DOFs (1 if none), the
    force per unit gap of the stopping measures."""
    if not len(geometry.dofs):
        return 1.0
    return float(K.diagonal()[geometry.dofs].mean())
