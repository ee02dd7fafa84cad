r"""Two elastic bodies in contact: dual mortar → nodewise NCP.

With the dual mortar coupling of :mod:`solver.geometry.mortar` (D
diagonal, M sparse, nodal slave normals n_j, weighted gaps g̃⁰_j) the
weighted gap of slave node j under displacements u is

.. math::
    g̃_j = g̃^0_j − n_j·(D_{jj} u_j − Σ_k M_{jk} u_k)
        = D_{jj}\,(s_j − n_j·v_j), \qquad v_j = u_j − Σ_k P_{jk} u_k,

P = D⁻¹M, s_j = g̃⁰_j / D_jj (Hüeber & Wohlmuth, CMAME 194 (2005) 3147;
Popp, Gee & Wall, IJNME 79 (2009) 1354; in 3D Popp, Gitterle, Gee & Wall,
IJNME 83 (2010) 1428). The change of variables
u = T⁻¹v, T⁻¹ = I + E with E the block P ⊗ I_d from the free master DOFs
to the free slave DOFs (E² = 0, so T = I − E), turns ½uᵀKu − fᵀu into
½vᵀK̃v − f̃ᵀv, K̃ = T⁻ᵀKT⁻¹ (sparse SPD), f̃ = T⁻ᵀf, and every contact
constraint into n_j·v_j ≤ s_j: a *discrete* problem (``M = diag(D)``)
that the whole core solves unchanged, friction included (on the weighted
slip). Its nodal contact force on v_j is D_jj λ_j, λ_j the dual
multiplier (the pressure); in u the mortar forces are D_jj λ_j n_j on
slave node j and −Σ_j M_jk λ_j n_j on master node k.

Dirichlet master DOFs coupled to a slave node enter s_j at the full load
(a friction run, whose steps scale them, refuses them); a slave node not
entirely covered by the master takes no part (``covered`` False)."""

import numpy as np
import scipy.sparse as sp

from ..errors import SolverError
from ..geometry.frames import tangent_basis
from ..geometry.mortar import (mortar_coupling, node_to_segment,
                               node_to_triangle, patch_pressure,
                               triangle_coupling)
from ..problem import ContactProblem

__all__ = ["VARIANTS", "interface_coupling", "symmetry_normals",
           "equivalent_problem", "interface_stiffness", "near_null_space",
           "TwoBodyMap"]

#: Couplings: the dual mortar, and node-to-segment (patch-test foil), by
#: dimension.
VARIANTS = {"mortar": {2: mortar_coupling, 3: triangle_coupling},
            "node-to-segment": {2: node_to_segment, 3: node_to_triangle}}

#: Overlaps of the undeformed bodies below this fraction of the local
#: slave element size h_j (the mean length of the slave edges at j) are
#: not reported: where two curved bodies touch, the weighted gap
#: ∫ψ_j g / D_jj is negative though g ≥ 0 (ψ_j = 3N_j − N_k − N_l < 0 on
#: the outer part of the support, where g grows as r²: O(κ h_j²), κ the
#: relative curvature; 4e-5 h_j at the apex of two spheres at a/h 22).
OVERLAP_TOLERANCE = 1e-3

#: |coverage − 1| above which a slave node takes no part.
COVERAGE_TOLERANCE = 1e-8

#: A slave node with a zero Dirichlet component c (a symmetry plane of a
#: half or quarter model) whose averaged normal has |n_c| at most this
#: lies on the plane: the whole model's normal there lies in the plane
#: (n_c = 0 by symmetry), and the one-sided average's n_c (of the order
#: of h/R on a curved surface) is set to 0 (:func:`symmetry_normals`).
SYMMETRY_NORMAL = 0.1


def interface_coupling(problem, variant="mortar"):
    """The coupling of every contact pair of ``problem`` (``variant`` of
    :data:`VARIANTS`), stacked with rows in ``problem.contact_nodes``
    order (a slave node belongs to one pair: the loader checks it)."""
    if variant not in VARIANTS:
        raise SolverError(f"variant must be one of {tuple(VARIANTS)}, got "
                          f"{variant!r}")
    if problem.dim not in VARIANTS[variant]:
        raise SolverError(f"variant {variant!r} is 2D-only")
    coupling = VARIANTS[variant][problem.dim]
    slave_pair = _pairs(problem.mortar_slave_pair, problem.mortar_slave)
    master_pair = _pairs(problem.mortar_master_pair, problem.mortar_master)
    parts = []
    for pair in np.unique(slave_pair):
        slave = problem.mortar_slave[slave_pair == pair]
        master = problem.mortar_master[master_pair == pair]
        if not len(master):
            raise SolverError(f"contact pair {pair} has no master segment")
        ids = problem.contact_nodes[np.isin(problem.contact_nodes, slave)]
        parts.append(coupling(problem.nodes, slave, master, ids))
    if len(parts) == 1:
        return symmetry_normals(problem, parts[0])
    position = np.full(len(problem.nodes), -1)
    position[problem.contact_nodes] = np.arange(problem.n_contact)
    order = np.argsort(position[np.concatenate([p.slave_nodes
                                                for p in parts])])
    join = (lambda name: np.concatenate([getattr(p, name) for p in parts])
            [order])
    first = parts[0]
    return symmetry_normals(problem, type(first)(
        join("slave_nodes"), join("D"),
        sp.vstack([p.M for p in parts]).tocsr()[order], join("normal"),
        join("gap"), join("coverage"), first.variant))


def symmetry_normals(problem, coupling):
    """``coupling`` with the normals of the slave nodes on symmetry planes
    in the plane (:data:`SYMMETRY_NORMAL`; then such a node is an exact
    roller, which friction accepts, not an oblique node) and their weighted
    gaps g̃_j = n_j·(Σ_k M_jk x_k − D_jj x_j) recomputed."""
    prescribed = np.asarray(problem.u_prescribed)[problem.contact_nodes]
    plane = (problem.contact_dofs < 0) & (prescribed == 0) \
        & (np.abs(coupling.normal) <= SYMMETRY_NORMAL)
    if not plane.any():
        return coupling
    normal = np.where(plane, 0.0, coupling.normal)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    nodes = problem.nodes
    gap = np.einsum("ij,ij->i", normal, coupling.M @ nodes - coupling.D[
        :, None] * nodes[coupling.slave_nodes])
    return type(coupling)(coupling.slave_nodes, coupling.D, coupling.M,
                          normal, gap, coupling.coverage, coupling.variant)


def _pairs(pairs, segments):
    return np.zeros(len(segments), np.int64) if pairs is None \
        else np.asarray(pairs)


def equivalent_problem(problem, coupling, friction=False):
    """(discrete problem in v, T⁻¹ sparse, covered): module docstring.
    The problem in v carries ``bodies`` (``problem``, whose ``nodes`` and
    ``dof_map`` number its DOFs too) and ``near_null_space``. Without a floating body the problem in v also carries
    ``change_of_variables`` = (K, f, E) of the bodies, from which its
    candidates can be condensed with K's own factor
    (:mod:`solver.contact.strategies.bordered`)."""
    n, nc = problem.n_dofs, problem.n_contact
    if not np.array_equal(coupling.slave_nodes, problem.contact_nodes):
        raise SolverError("the mortar slave nodes are not the problem's "
                          "contact nodes")
    reduced = np.full(problem.nodes.shape, -1, np.int64)
    reduced[problem.dof_map[:, 0], problem.dof_map[:, 1]] = np.arange(n)
    covered = np.abs(coupling.coverage - 1) <= COVERAGE_TOLERANCE
    P = coupling.P.tocoo()
    keep = covered[P.row]
    j, k, p = P.row[keep], P.col[keep], P.data[keep]
    prescribed = problem.u_prescribed
    shift = np.zeros(nc)
    rows, cols, vals = [], [], []
    for c in range(problem.dim):
        r, q = reduced[problem.contact_nodes[j], c], reduced[k, c]
        free = (r >= 0) & (q >= 0)
        rows.append(r[free]), cols.append(q[free]), vals.append(p[free])
        fixed = (r >= 0) & (q < 0)
        np.add.at(shift, j[fixed], coupling.normal[j[fixed], c] * p[fixed]
                  * prescribed[k[fixed], c])
        own = reduced[problem.contact_nodes, c] < 0
        shift[own] -= coupling.normal[own, c] * prescribed[
            problem.contact_nodes[own], c]
    if friction and np.any(shift != 0):
        raise SolverError("friction steps scale the Dirichlet values; "
                          "prescribed displacements at the interface are "
                          "not supported with friction")
    E = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows),
                                              np.concatenate(cols))),
                      shape=(n, n))
    T_inv = (sp.identity(n, format="csr") + E).tocsr()
    extra = interface_stiffness(problem.K, E)
    K = (problem.K + extra).tocsr()
    contact_dofs = reduced[problem.contact_nodes].copy()
    contact_dofs[~covered] = -1
    load_path = None if problem.load_path is None \
        else np.asarray((T_inv.T @ problem.load_path.T).T)
    equivalent = ContactProblem(
        K=K.tocsr(), f=T_inv.T @ problem.f, M=sp.diags(coupling.D).tocsr(),
        contact_dofs=contact_dofs, meta=dict(problem.meta or {}),
        gap=coupling.gap / coupling.D + shift, normal=coupling.normal,
        load_path=load_path, load_path_steps=problem.load_path_steps,
        load_path_friction=problem.load_path_friction,
        source=problem.source)
    equivalent.node_graph = lambda: _node_graph(problem, extra)
    # v keeps the bodies' reduced DOF numbering: the petsc engine lays it
    # out by their mesh's nodes (solver.mpi.layout.mesh_of)
    equivalent.bodies = problem
    equivalent.near_null_space = lambda: near_null_space(problem, E)
    if problem.floating:  # a body held by contact only: its modes in v
        _floating_modes(equivalent, problem, T_inv, E)
    else:  # K SPD: the candidates may be condensed from K's own factor
        equivalent.change_of_variables = (problem.K, problem.f, E)
    # how far the prescribed displacements move the bodies before they
    # deform: the candidates' screening margin (strategies.candidates)
    equivalent.approach_length = float(np.linalg.norm(
        prescribed, axis=1).max(initial=0.0))
    return equivalent, T_inv, covered


def _floating_modes(equivalent, problem, T_inv, E):
    """Give the problem in v the rigid-body modes of the bodies held by
    contact only: v = Tu, T = I − E, so K̃ T R = T⁻ᵀ K R = 0 and ker K̃ is
    spanned by T R, orthonormalised (T R = Q S, coefficients C S⁻¹ on
    the bodies' translations and rotations); ``original`` and ``T_inv``
    name the motions on the bodies' mesh
    (:mod:`solver.problem.rigid`)."""
    R, C = problem.rigid_modes()
    Q, S = np.linalg.qr(R - E @ R)
    equivalent._modes = (equivalent.K, (Q, C @ np.linalg.inv(S)))
    equivalent.original, equivalent.T_inv = problem, T_inv


def near_null_space(problem, E):
    """The near-null space of K̃ for algebraic multigrid
    (:class:`solver.linalg.amg.Multigrid`): each body's rigid-body modes
    (:func:`solver.linalg.amg.rigid_body_modes` on its own DOFs, zero on
    the other body's; 3 per body in 2D, 6 in 3D) in the variables
    v = Tu = (I − E)u, i.e. T B: K̃ T B = T⁻ᵀ K B, which vanishes away
    from the supports as K B does (Wiesner et al., IJNME 122, 2021, build
    their mortar AMG on the same modes)."""
    from ..linalg.amg import rigid_body_modes

    node, comp = problem.dof_map[:, 0], problem.dof_map[:, 1]
    body = _body(problem)[node]
    points = problem.nodes[node]
    blocks = []
    for b in np.unique(body):
        mine = body == b
        block = np.zeros((problem.n_dofs, 3 if problem.dim == 2 else 6))
        block[mine] = rigid_body_modes(points[mine], comp[mine])
        blocks.append(block)
    B = np.hstack(blocks)
    return B - E @ B


def interface_stiffness(K, E):
    """K̃ − K for K̃ = (I + E)ᵀ K (I + E) = K + A + Aᵀ + EᵀKE, A = K E,
    from the rows s of K at the slave DOFs alone (E_s those rows of E):
    A = K[s, :]ᵀ E_s, EᵀKE = E_sᵀ K[s, s] E_s, both O(interface); K̃ is then
    as symmetric as K (the small EᵀKE symmetrised)."""
    s = np.flatnonzero(np.diff(E.indptr))
    E_s = E[s]
    B = K[s]                               # = K[:, s]ᵀ (K symmetric)
    A = (B.T @ E_s).tocsr()
    C = E_s.T @ (B[:, s] @ E_s)
    return (A + A.T + 0.5 * (C + C.T)).tocsr()


def _node_graph(problem, extra):
    """The nodes of ``problem`` with an edge wherever K̃ = K + ``extra``
    couples two nodes: the mesh's edges (those of K) and the nonzeros of
    the interface part (slave–master couplings), for the fill-reducing
    order of :func:`solver.linalg.dof_ordering`."""
    cells = np.asarray(problem.cells, np.int64)
    k = cells.shape[1]
    mesh = [cells[:, [a, b]] for a in range(k) for b in range(a + 1, k)]
    rows, cols = extra.nonzero()
    node = problem.dof_map[:, 0]
    edges = np.concatenate(mesh + [np.c_[node[rows], node[cols]]])
    return problem.nodes, edges, problem.dof_map


class TwoBodyMap:
    """A two-body problem as the nodewise problem in v (module docstring),
    and the way back to u: ``problem``, ``equivalent`` (the discrete problem
    in v that the drivers solve), ``T_inv`` (u = T⁻¹v), ``covered`` (the
    slave nodes that take part), ``coupling`` (D, M, normals, gaps)."""

    def __init__(self, problem, variant="mortar", friction=False):
        self.problem, self.variant = problem, variant
        self.coupling = interface_coupling(problem, variant)
        self.equivalent, self.T_inv, self.covered = equivalent_problem(
            problem, self.coupling, friction=friction)
        #: (Nc, d − 1, d): the tangents of the friction traction's
        #: components (those of the contact geometry, :meth:`mark_uncovered`)
        self.tangents = tangent_basis(self.coupling.normal)

    def mark_uncovered(self, geometry):
        """Record the uncovered slave nodes among ``geometry``'s excluded
        nodes (their gaps are not the bodies': not checked), and warn
        (:class:`~solver.errors.InitialPenetrationWarning`) where the
        undeformed bodies overlap at a slave node that takes part."""
        from ..geometry.checks import warn_penetration
        from .geometry import UNCOVERED

        self.tangents[geometry.index] = geometry.tangents
        excluded = geometry.excluded
        uncovered = ~self.covered[excluded["index"]]
        excluded["reason"] = [UNCOVERED if u else r for u, r in
                              zip(uncovered, excluded["reason"])]
        excluded["gap"] = np.where(uncovered, np.nan, excluded["gap"])
        ids = self.problem.contact_nodes[geometry.index]
        nodes = self.problem.nodes
        warn_penetration(geometry.gap, nodes[ids], node_ids=ids,
                         what="the undeformed bodies overlap",
                         floor=OVERLAP_TOLERANCE * _local_size(
                             nodes, self.problem.mortar_slave)[ids])
        return geometry

    def _traction(self, pressure, friction_traction=None):
        """−λ_j n_j + Σ_a g_t,ja τ_ja on the slave surface (…, Nc, d)."""
        traction = -np.asarray(pressure)[..., None] * self.coupling.normal
        if friction_traction is not None:
            g = np.asarray(friction_traction, float)
            if self.tangents.shape[1] == 1:  # 2D: one scalar per node
                g = g[..., None]
            traction = traction + np.einsum("...ia,iad->...id", g,
                                            self.tangents)
        return traction

    def step_fields(self, prescribed):
        """A wrapper of a friction run's ``on_step`` callback that hands
        it each step's fields in u (``u``, ``displacement`` over both
        bodies, ``v``, ``traction``, ``contact_pressure_patch``); ``prescribed`` iterates over the
        Dirichlet values of every step in order
        (:meth:`ContactProblem.load_steps`)."""
        prescribed = iter(prescribed)

        def convert(fields):
            fields = dict(fields)  # the driver keeps its own (in v)
            v = fields["u"]
            u = self.T_inv @ v
            fields.update(
                v=v, u=u, traction=self._traction(
                    fields["contact_pressure"],
                    fields["friction_traction"]),
                displacement=self.problem.full_displacement(
                    u, next(prescribed)),
                contact_pressure_patch=patch_pressure(
                    self.problem.mortar_slave, self.coupling.slave_nodes,
                    self.coupling.D, fields["contact_pressure"],
                    self.covered))
            return fields
        return convert

    def result(self, result, friction=None, steps=None):
        """The drivers' ``result`` on the equivalent problem mapped back to
        u, with the two-body fields (docs/results.md, "Two bodies, added";
        ``contact_pressure`` is the dual multiplier λ_j = z_j / D_jj,
        ``contact_pressure_patch`` its patch recovery,
        :func:`~solver.geometry.mortar.patch_pressure`)."""
        problem = self.problem
        extra = dict(covered=self.covered, mortar_D=self.coupling.D,
                     body=_body(problem), variant=self.coupling.variant,
                     gap_mode=("mortar" if self.variant == "mortar"
                               else self.variant),
                     weighted_gap=self.coupling.gap)
        pressure = result.get("contact_pressure")
        if pressure is not None and np.size(pressure):  # (no step kept)
            extra["contact_pressure_patch"] = patch_pressure(
                problem.mortar_slave, self.coupling.slave_nodes,
                self.coupling.D, pressure, self.covered)
        if friction is not None and ("u" not in result  # steps not kept
                                     or not np.size(result.u)):  # or none
            result.update(extra)
            return result
        if friction is None:
            u = self.T_inv @ result.u
            displacement = problem.full_displacement(u)
            traction = self._traction(result.contact_pressure)
        else:
            u = np.asarray(self.T_inv @ np.atleast_2d(result.u).T).T
            prescribed = [p for _, _, p, _ in problem.load_steps(steps)]
            displacement = np.array([problem.full_displacement(x, p)
                                     for x, p in zip(u, prescribed)])
            traction = self._traction(result.contact_pressure,
                                      result.friction_traction)
        result.update(v=result.u, u=u, displacement=displacement,
                      traction=traction, **extra)
        verification = result.get("verification")
        if verification is not None and result.get("success", False):
            verification["kinematics"] = list(verification.get(
                "kinematics") or []) + self.sliding_breaches(
                    np.atleast_2d(result.v)[-1],
                    np.atleast_2d(result.in_contact)[-1])
        return result

    def sliding_breaches(self, v, in_contact):
        """:func:`~.kinematics.relative_sliding` of the answer v (in the
        solved variables, one state) at the slave nodes in contact: where
        the coupling's pairing of the meshes carries the answer (an open
        node may move with its body far from the master, as the upper
        cylinder's spin does, without touching it)."""
        from .kinematics import relative_sliding

        dofs = np.asarray(self.equivalent.contact_dofs)
        moved = np.where(dofs >= 0, np.asarray(v, float)[np.maximum(dofs, 0)],
                         0.0)
        normal = np.asarray(self.coupling.normal, float)
        tangential = moved - np.einsum("ij,ij->i", moved,
                                       normal)[:, None] * normal
        ids = np.asarray(self.problem.contact_nodes)
        h = _local_size(self.problem.nodes, self.problem.mortar_slave)[ids]
        keep = np.asarray(self.covered, bool) & np.asarray(in_contact, bool)
        return relative_sliding(np.linalg.norm(tangential, axis=1)[keep],
                                h[keep], ids[keep])


def _local_size(nodes, facets):
    """h_j at every node (0 off ``facets``): the mean over the facets
    (segments or triangles) at j of their mean edge length."""
    p = nodes[facets]
    edge = np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2).mean(axis=1)
    count = np.bincount(facets.ravel(), minlength=len(nodes))
    total = np.bincount(facets.ravel(), np.repeat(edge, facets.shape[1]),
                        minlength=len(nodes))
    return total / np.maximum(count, 1)


def _body(problem):
    body = getattr(problem, "body", None)
    return np.zeros(len(problem.nodes), np.int64) if body is None else body
