r"""Per-node contact frames and gaps: all the contact systems see (§2.1).

A :class:`ContactGeometry` holds, at the free contact nodes, the DOFs, the
initial gap s along the unit normal ν (from the body towards the obstacle)
and the d − 1 tangents (:mod:`solver.geometry.frames`). :func:`rotation`
builds the sparse **R** of (58)-(60) from them for any d: at contact node
i its rows are the tangents, then the normal; R is the identity
elsewhere. The contact systems never ask the dimension anything else.

Rollers (symmetry planes). A contact node on a symmetry plane of a half
or quarter model has a Dirichlet DOF, u_c = 0, along the plane's normal
e_c. When its contact normal lies in the plane (|ν_c| ≤
:data:`ROLLER_TOLERANCE`) the constraint acts only along a tangent, where
a frictionless contact exerts no force, and the node's normal contact
force is half (quarter) that of the whole model there. Such a *roller*
takes part with ``contact_geometry(..., rollers=True)`` in the frame of
:func:`~solver.geometry.frames.roller_frames` (e_c first among the
tangents, with −1 in ``dofs``); otherwise it is a support with λ = 0.

Oblique nodes. When a constrained direction has a share of ν (e.g. a
plane-strain slab, u_z = 0, against an obstacle tilted in z), s − ν·u ≥ 0
reads, with the prescribed ū_c, s' − n'·u_f ≥ 0 on the free components:
n' = ν_f/|ν_f|, s' = (s − ν_c·ū_c)/|ν_f|, exact without friction (the
support carries the force along e_c). Such a node takes part with that
normal and gap, marked ``oblique``; friction, whose Coulomb cone the
projection does not preserve, refuses it. A node whose normal lies along
its constrained directions (|ν_f| < :data:`OBLIQUE_MIN`) is a support."""

import numpy as np
import scipy.sparse as sp

from ..errors import SolverError
from ..geometry.checks import warn_penetration
from ..geometry.frames import (ROLLER_TOLERANCE, frames, roller_frames,
                               tangent_basis)

__all__ = ["GAP_MODES", "ROLLER_TOLERANCE", "OBLIQUE_MIN", "ContactGeometry",
           "contact_geometry", "problem_dim", "rotation", "rotate_stiffness",
           "contact_stiffness", "node_displacement", "UNCOVERED"]

#: How gaps and normals are found (thesis §2.1.1 / §2.1.2).
GAP_MODES = ("obstacle", "body")

#: A node with Dirichlet components whose normal keeps less than this
#: length in its free components is a support (module docstring).
OBLIQUE_MIN = 1e-6

#: Why a node of Γc takes no part in contact (``ContactGeometry.excluded``).
SUPPORT = "support: every DOF prescribed"
SUPPORT_PARTIAL = "support: a DOF prescribed (rollers=False)"
SUPPORT_ALONG = "support: the normal lies along its prescribed DOFs"
NO_OBSTACLE = "no obstacle in reach (a bounded one ends before it)"
UNCOVERED = "slave node not covered by the master"


class ContactGeometry:
    """Gaps and frames at the contact nodes that take part (§2.1): those
    whose DOFs are all free, and the rollers (module docstring).

    Attributes
    ----------
    index : (Nca,) int
        Rows of ``problem.contact_dofs`` (positions along Γc) of the nodes.
    dofs, node_dofs : (Nca, d) int
        The reduced DOF of each row of the node's frame (tangents, then the
        normal; −1 for a roller's e_c), and the node's own DOFs (−1 where
        Dirichlet; the columns of R): equal for a free node.
    gap, normal, tangents : (Nca,), (Nca, d), (Nca, d − 1, d) float
        s (< 0: penetration), ν and the tangents.
    foot : (Nca,) or (Nca, d) float, or None
        The obstacle parameter t (2D) or point (3D; 2D with several
        curves) the gap is measured to.
    mode, dim : str, int
        ``"obstacle"``, ``"body"`` or ``"given"`` (discrete problems); d.
    rollers, oblique : (Nca,) bool
        Nodes with a Dirichlet component; those with projected gap and normal.
    excluded : dict
        The nodes of Γc that take no part: ``index``, ``reason``, ``gap`` and
        ``normal`` (NaN where not computed), for
        :func:`solver.contact.verify.verify_excluded`."""

    def __init__(self, index, dofs, gap, normal, foot=None, mode="given",
                 tangents=None, node_dofs=None, oblique=None):
        self.index, self.dofs = index, dofs
        self.node_dofs = dofs if node_dofs is None else node_dofs
        self.gap, self.normal, self.foot, self.mode = gap, normal, foot, mode
        self.dim = int(np.shape(normal)[1])
        self.tangents = tangent_basis(normal) if tangents is None \
            else np.asarray(tangents, float)
        self.rollers = (np.asarray(self.node_dofs) < 0).any(axis=1)
        self.oblique = np.zeros(len(self.gap), bool) if oblique is None \
            else np.asarray(oblique, bool)
        self.excluded = dict(index=np.zeros(0, np.int64), reason=[],
                             gap=np.zeros(0), normal=np.zeros((0, self.dim)))

    @property
    def has_rollers(self):
        """Whether any node is a roller."""
        return bool(self.rollers.any())

    def free_dofs(self):
        """The nodes' free reduced DOFs, node by node in component order
        (the Schur set of a condensation onto Γc)."""
        return self.node_dofs[self.node_dofs >= 0]

    def compact(self):
        """The same nodes renumbered to the condensed DOFs: free DOF k of
        :meth:`free_dofs` → k (all free: node i's DOFs → d·i, …,
        d·i + d − 1), −1 kept."""
        flat = self.free_dofs()
        if not self.has_rollers:
            m, d = self.dofs.shape
            return self.renumbered(np.arange(d * m).reshape(m, d))
        lookup = np.full(int(flat.max(initial=-1)) + 2, -1)
        lookup[flat] = np.arange(len(flat))  # lookup[-1] stays −1
        return self.renumbered(lookup[self.dofs], lookup[self.node_dofs])

    def rotation(self):
        """The per-node frames Q (Nca, d, d): rows the d − 1 tangents, then
        the normal (Q v = tangential components, then the normal one)."""
        return frames(self.normal, self.tangents)

    def renumbered(self, dofs, node_dofs=None):
        """The same nodes with other DOFs (a condensed numbering);
        ``node_dofs`` defaults to ``dofs`` (no rollers)."""
        out = ContactGeometry(self.index, dofs, self.gap, self.normal,
                              self.foot, self.mode, self.tangents,
                              node_dofs, self.oblique)
        out.excluded = self.excluded
        return out

    def subset(self, nodes, dofs=None):
        """The nodes ``nodes`` (positions in this geometry), with their own
        DOFs, or with ``dofs`` (a renumbering of nodes without rollers;
        :meth:`compact` renumbers any)."""
        foot = None if self.foot is None else self.foot[nodes]
        node_dofs = self.node_dofs[nodes] if dofs is None else None
        return ContactGeometry(
            self.index[nodes], self.dofs[nodes] if dofs is None else dofs,
            self.gap[nodes], self.normal[nodes], foot, self.mode,
            self.tangents[nodes], node_dofs, self.oblique[nodes])


def problem_dim(problem):
    """d of ``problem`` (its ``dim``, else the columns of contact_dofs)."""
    return int(getattr(problem, "dim", problem.contact_dofs.shape[1]))


def contact_geometry(problem, gap="obstacle", rollers=False):
    """Gaps and normals of ``problem`` (thesis §2.1), with ``gap``
    "obstacle" (nearest obstacle point, ν its normal, §2.1.1) or "body" (ν
    the body's outward normal, §2.1.2-2.1.3); discrete problems carry theirs.
    ``rollers``: False (the thesis's runs) makes a node with a Dirichlet DOF
    a support; True (:func:`solver.solve`'s default) lets the rollers and the
    oblique nodes take part (module docstring). The nodes left out are
    recorded in ``excluded``; an obstacle penetrating a node that takes part
    is reported by an :class:`~solver.errors.InitialPenetrationWarning`."""
    constrained = problem.contact_dofs < 0
    eligible = ~constrained.all(axis=1) if rollers \
        else ~constrained.any(axis=1)
    nodes = np.flatnonzero(eligible)
    if problem.kind != "discrete" and gap not in GAP_MODES:
        raise SolverError(f"gap mode must be one of {GAP_MODES}, got {gap!r}")
    s, normal, foot = _gaps(problem, gap, nodes)
    reach = s < np.inf  # +∞: no obstacle in reach (bounded obstacles)
    unreached = nodes[~reach]
    if not reach.all():
        nodes, s, normal = nodes[reach], s[reach], normal[reach]
        foot = None if foot is None else foot[reach]
    geometry = _frames(nodes, problem.contact_dofs[nodes], s, normal, foot,
                       "given" if problem.kind == "discrete" else gap,
                       _prescribed(problem, nodes))
    left = np.setdiff1d(np.arange(len(problem.contact_dofs)), geometry.index)
    reason = np.where(np.isin(left, unreached), NO_OBSTACLE,
                      np.where(constrained[left].all(axis=1), SUPPORT,
                               np.where(eligible[left], SUPPORT_ALONG,
                                        SUPPORT_PARTIAL))).tolist()
    geometry.excluded = dict(index=left, reason=reason,
                             **_support_gaps(problem, gap, left))
    if problem.kind != "discrete":
        ids = problem.contact_nodes[geometry.index]
        warn_penetration(geometry.gap, problem.nodes[ids], node_ids=ids)
    return geometry


def _gaps(problem, gap, nodes):
    """(s, ν, foot) at the positions ``nodes`` of Γc."""
    if problem.kind == "discrete":
        return problem.gap[nodes], problem.normal[nodes], None
    if problem_dim(problem) == 3:
        return _geometry_3d(problem, gap, nodes)
    from ..geometry.curves import SeveralCurves, obstacle_gaps
    from ..geometry.curves.normals import boundary_normals

    body = boundary_normals(problem.nodes, problem.cells,
                            problem.contact_nodes)
    if isinstance(problem.obstacle, SeveralCurves):  # oriented by all of Γc
        ids = problem.contact_nodes
        s, normal, foot = obstacle_gaps(problem.nodes[ids], problem.obstacle,
                                        body, gap, node_ids=ids, warn=False)
        return s[nodes], normal[nodes], foot[nodes]
    ids = problem.contact_nodes[nodes]
    return obstacle_gaps(problem.nodes[ids], problem.obstacle, body[nodes],
                         gap, node_ids=ids, warn=False)


def _support_gaps(problem, gap, left):
    """The gaps and normals of the excluded nodes ``left`` (for the check
    that they do not penetrate), NaN where they cannot be computed (a
    normal line that misses the obstacle at a support is no error)."""
    from ..errors import GeometryError

    out = dict(gap=np.full(len(left), np.nan),
               normal=np.full((len(left), problem_dim(problem)), np.nan))
    if not len(left):
        return out
    try:
        s, normal, _ = _gaps(problem, gap, left)
    except GeometryError:
        return out
    out.update(gap=np.asarray(s, float), normal=np.asarray(normal, float))
    return out


def _prescribed(problem, nodes):
    """The prescribed displacements ū at the positions ``nodes`` of Γc
    (zero where free, and for a discrete problem)."""
    prescribed = getattr(problem, "u_prescribed", None)
    if problem.kind == "discrete" or prescribed is None:
        return np.zeros((len(nodes), problem_dim(problem)))
    return np.asarray(prescribed)[problem.contact_nodes[nodes]]


def node_displacement(problem, u, positions):
    """The displacement (k, d) of the nodes of Γc at ``positions`` for the
    reduced u: free DOFs from u, prescribed ones their values."""
    dofs = problem.contact_dofs[positions]
    padded = np.append(np.asarray(u, float), 0.0)
    out = padded[dofs]
    fixed = dofs < 0
    if fixed.any():
        out[fixed] = _prescribed(problem, positions)[fixed]
    return out


def _geometry_3d(problem, gap, nodes):
    """3D: the obstacle surface's closest point ("obstacle": ν = −its
    outward normal there) or the ray along the body's outward normal
    ("body": ν = that normal)."""
    points = problem.nodes[problem.contact_nodes[nodes]]
    if gap == "obstacle":
        s, normal, foot = problem.obstacle.gap_along_obstacle_normal(points)
    else:
        from ..geometry.surfaces.normals import surface_normals

        normal = surface_normals(problem.nodes, problem.contact_faces,
                                 problem.contact_nodes)[nodes]
        s, foot = problem.obstacle.gap_along_rays(points, normal)
    return np.asarray(s, float), np.asarray(normal, float), foot


def _frames(index, node_dofs, gap, normal, foot, mode, prescribed):
    """The ContactGeometry of the nodes ``index``: the rollers' frames
    built, the oblique nodes' gaps and normals projected onto their free
    components, the nodes whose normal lies along their constrained
    directions dropped as supports (module docstring); vectorised per
    pattern of constrained components (at most 2^d − 2)."""
    gap, normal = np.asarray(gap, float), np.asarray(normal, float)
    fixed = node_dofs < 0
    if not fixed.any():  # every node free: exactly as without rollers
        return ContactGeometry(index, node_dofs, gap, normal, foot, mode)
    free_part = np.linalg.norm(np.where(fixed, 0.0, normal), axis=1)
    keep = ~fixed.any(axis=1) | (free_part >= OBLIQUE_MIN)
    index, node_dofs, gap = index[keep], node_dofs[keep], gap[keep].copy()
    foot = None if foot is None else foot[keep]
    fixed, normal = fixed[keep], normal[keep].copy()
    prescribed, free_part = prescribed[keep], free_part[keep]
    oblique = (fixed & (np.abs(normal) > ROLLER_TOLERANCE)).any(axis=1)
    # s' = (s − ν_c·ū_c)/|ν_f| (exact: the constraint on the free DOFs)
    shift = np.where(fixed, normal * prescribed, 0.0).sum(axis=1)
    gap[oblique] = (gap[oblique] - shift[oblique]) / free_part[oblique]
    roll = fixed.any(axis=1)
    tangents = tangent_basis(normal)
    normal[roll], tangents[roll] = roller_frames(normal[roll], fixed[roll])
    dofs = node_dofs.copy()
    for pattern in np.unique(fixed[roll], axis=0):  # ≤ 2^d − 2 patterns
        rows = np.flatnonzero((fixed == pattern).all(axis=1))
        k = int(pattern.sum())
        dofs[rows] = np.column_stack([np.full((len(rows), k), -1),
                                      node_dofs[rows][:, ~pattern]])
    return ContactGeometry(index, dofs, gap, normal, foot, mode, tangents,
                           node_dofs, oblique)


def rotation(n, geometry):
    """R of (58)-(60), sparse (n, n), for any d: at contact node i the rows
    of its DOFs are its tangents, then its normal; identity elsewhere. A
    roller's rows e_c (``dofs`` −1) and its Dirichlet columns are left out: on
    its free DOFs R is still orthogonal. Returns (R, other DOFs, tangential
    rows ``dofs[:, :-1]`` node by node, normal rows ``dofs[:, -1]``)."""
    dofs = geometry.dofs
    d = dofs.shape[1]
    keep = np.ones(n, bool)  # a mask: np.setdiff1d would sort
    keep[geometry.free_dofs()] = False
    other = np.flatnonzero(keep)
    Q = geometry.rotation()  # (m, d, d): Q[i, r, c] at (dofs[i, r],
    # node_dofs[i, c])
    rows = np.concatenate([other] + [np.repeat(dofs[:, r], d)
                                     for r in range(d)])
    cols = np.concatenate([other] + [geometry.node_dofs.ravel()] * d)
    vals = np.concatenate([np.ones(len(other))] + [Q[:, r, :].ravel()
                                                   for r in range(d)])
    if geometry.has_rollers:
        used = (rows >= 0) & (cols >= 0)
        rows, cols, vals = rows[used], cols[used], vals[used]
    R = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
    return R, other, dofs[:, :-1].ravel(), dofs[:, -1]


def rotate_stiffness(K, R, dofs):
    """K̂ = R K Rᵀ (thesis (60)) for R of :func:`rotation`, the identity
    outside the contact DOFs ``dofs`` (``geometry.free_dofs()``): only the
    rows X = R_cc K_{dofs,:} Rᵀ change (their block on ``dofs``
    symmetrised), so K̂ is K with those rows replaced by X and those columns
    by Xᵀ, in one pass over K; ½(RKRᵀ + (RKRᵀ)ᵀ) to rounding."""
    K = sp.csr_matrix(K)
    n = K.shape[0]
    c = np.unique(np.asarray(dofs, np.int64))
    if not len(c):
        return K.copy()
    in_c = np.zeros(n, bool)
    in_c[c] = True
    X = (R[c][:, c] @ K[c] @ R.T).tocoo()  # rows c of R K Rᵀ
    block = in_c[X.col]
    Xcc = sp.csr_matrix((X.data[block], (X.row[block], X.col[block])),
                        shape=(len(c), n))[:, c]
    Xcc = (0.5 * (Xcc + Xcc.T)).tocoo()
    off = ~block  # X off the block: rows c and, transposed, columns c
    rows = np.concatenate([c[X.row[off]], X.col[off], c[Xcc.row]])
    cols = np.concatenate([X.col[off], c[X.row[off]], c[Xcc.col]])
    vals = np.concatenate([X.data[off], X.data[off], Xcc.data])
    changed = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
    kept = np.where(np.repeat(in_c, np.diff(K.indptr)) | in_c[K.indices],
                    0.0, K.data)
    return (sp.csr_matrix((kept, K.indices, K.indptr), shape=(n, n))
            + changed).tocsr()


def contact_stiffness(K, geometry):
    """k̄: the mean diagonal stiffness at the contact DOFs (1 if none), the
    force per unit gap of the stopping measures."""
    if not len(geometry.dofs):
        return 1.0
    return float(K.diagonal()[geometry.free_dofs()].mean())
