r"""Frictionless contact condensed onto the normal DOFs of candidate nodes.

A dense Schur complement on every DOF of Γc has (d·Nc)² entries: in 3D,
with Nc = 10⁴-10⁵, it does not fit. Without friction the tangential
contact forces are zero, so only the normal unknown of a node that can
touch needs to stay: with K̂ = RKRᵀ, f̂ = Rf (SPD and as sparse as K), the
Schur complement S of K̂ on the normal rows of the *candidates* (m×m,
dense), w = K̂⁻¹f̂ and g̃ = S w_c from one factorisation; the NCP (67) on
the candidates, S u_n = g̃ + λ, λ ≥ 0 ⊥ s − u_n ≥ 0 (:func:`normal_line`);
then u = Rᵀ(w + K̂⁻¹Pᵀ S(u_n − w_c)), one back-substitution.

The screening rule. Round 0 takes the nodes whose initial gap is at most
δ₀ = ``margin``, by default max(s_min, 0) + :data:`GAP_FRACTION`·(s_max −
s_min) + a, a the largest prescribed nodal displacement (how far a body
driven by prescribed displacements moves before it deforms; every node
the obstacle penetrates at the start is one); in 2D every free
contact node (a curve's normals are few). If after a round's solve a
non-candidate penetrates (s − u_n < −tol_v·F/k̄), the set grows by every
node whose remaining gap is at most the deepest penetration and K̂ is
factorised again (at most :data:`MAX_ROUNDS`). Otherwise the answer is
exact for the whole of Γc: λ = 0 with a non-negative gap satisfies the
contact conditions at every non-candidate, so the KKT conditions of the
full (strictly convex) problem hold. The 3D default (benchmarks/README.md,
"Candidate screening").

References
----------
P. Wriggers, *Computational Contact Mechanics*, 2nd ed., Springer 2006,
§6.2.2 (condensation onto the contact DOFs) and its chapter on contact
search (a global screening with a margin, then the exact local check)."""

import numpy as np

from ...linalg import Condensation, dof_ordering, get_backend, resolve
from ...linalg.dense import DenseSchur
from ..geometry import ContactGeometry, rotate_stiffness, rotation

__all__ = ["GAP_FRACTION", "MAX_ROUNDS", "initial_candidates", "approach",
           "enlarge_candidates", "normal_line", "NormalCondensation",
           "NodalCondensation"]

#: Default round-0 margin: this fraction of the gap range above s_min.
GAP_FRACTION = 0.05

#: Rounds of candidate enlargement at most (each refactorises K̂).
MAX_ROUNDS = 8


def initial_candidates(gap, margin=None, approach=0.0):
    """Round 0: positions of the nodes with s_i ≤ δ₀ (module docstring:
    ``approach`` is a, a length) and δ₀ itself."""
    gap = np.asarray(gap, float)
    if not len(gap):
        return np.zeros(0, np.int64), 0.0
    if margin is None:  # from 0 if the obstacle penetrates the body
        low, high = float(gap.min()), float(gap.max())
        margin = max(low, 0.0) + GAP_FRACTION * (high - low) + approach
    return np.flatnonzero(gap <= margin), float(margin)


def approach(problem):
    """a of the module docstring: the largest prescribed nodal
    displacement of ``problem`` (0 without any; a two-body problem's
    nodewise form carries its bodies' as ``approach_length``)."""
    given = getattr(problem, "approach_length", None)
    if given is not None:
        return float(given)
    prescribed = getattr(problem, "u_prescribed", None)
    if prescribed is None or not np.size(prescribed):
        return 0.0
    return float(np.linalg.norm(prescribed, axis=1).max())


def enlarge_candidates(candidates, remaining, tol_length):
    """The next round's candidates, or None if no non-candidate penetrates:
    ``remaining`` (Nca,) is s − u_n at every free contact node, and every
    node with remaining ≤ the deepest penetration below −``tol_length`` is
    added."""
    outside = np.ones(len(remaining), bool)
    outside[candidates] = False
    worst = float(np.max(-remaining[outside], initial=-np.inf))
    if not worst > tol_length:
        return None
    grown = outside & (remaining <= worst)
    return np.union1d(candidates, np.flatnonzero(grown))


def normal_line(geometry, nodes):
    """The candidates ``nodes`` as a 1-DOF geometry: unknown k is the normal
    displacement of node ``nodes[k]``, its "normal" is +1 and it has no
    tangent, so (67) on it reads λ = −(S u_n − g̃), B = s − u_n."""
    m = len(nodes)
    foot = None if geometry.foot is None else geometry.foot[nodes]
    return ContactGeometry(geometry.index[nodes],
                           np.arange(m).reshape(m, 1), geometry.gap[nodes],
                           np.ones((m, 1)), foot, geometry.mode,
                           tangents=np.zeros((m, 0, 1)))


class NormalCondensation:
    """K̂ = RKRᵀ of ``problem`` condensed onto candidate normal DOFs of
    the nodes of ``geometry`` (any d; a roller's normal row ``dofs[i, -1]``
    is one of its free DOFs), by the :mod:`solver.linalg` ``backend``. Call
    :meth:`factorize` with the candidates (positions in ``geometry``) for
    each round; K̂ and f̂ are built once.

    :class:`NodalCondensation` condenses K onto *every* free DOF of the
    candidates instead, for the screening of a friction run."""

    def __init__(self, problem, geometry, backend):
        self.problem, self.geometry = problem, geometry
        self.module = get_backend(backend)
        n = problem.n_dofs
        self.R = rotation(n, geometry)[0]
        self.K = rotate_stiffness(problem.K, self.R, geometry.free_dofs())
        self.f = self.R @ problem.f
        self.normal_rows = geometry.dofs[:, -1]
        self.factorizations = 0

    def factorize(self, nodes):
        """Factorise K̂ with the Schur set = normal rows c of ``nodes``.
        Returns (S, g̃, w_c): S (m, m), g̃ = S w_c, w = K̂⁻¹f̂ (rotated,
        kept for :meth:`displacement`)."""
        self.nodes = np.asarray(nodes, np.int64)
        c = self.normal_rows[self.nodes]
        order = dof_ordering(self.problem, last=c) \
            if self.module.USES_ORDER else None
        self.factor = self.module.factorize(
            self.K, order, c if len(c) else None, "K",
            self.factorizations == 0)  # no candidates: a plain factor
        self.factorizations += 1
        self.w = self.factor.solve(self.f)
        S = self.factor.S if len(c) else np.zeros((0, 0))
        return S, S @ self.w[c], self.w[c]

    def displacement(self, u_n):
        """(u, normal displacement at every free contact node) from the
        candidates' normal displacements u_n: one back-substitution."""
        c = self.normal_rows[self.nodes]
        u_hat = self.w if not len(c) else self.w + \
            self.factor.back_substitute(None, np.asarray(u_n, float)
                                        - self.w[c])
        return self.R.T @ u_hat, u_hat[self.normal_rows]


class NodalCondensation(NormalCondensation):
    r""":class:`NormalCondensation` from K condensed onto every free DOF c
    of the candidates (:class:`~solver.linalg.Condensation`, kept for later
    runs on the same K): the screening of a friction run, whose candidates
    lie within the screening's, so that the friction run takes its S from
    this factorisation (:meth:`~solver.linalg.Condensation.of`, a Schur
    complement of this S) instead of factorising K again. In the rotated components T = R_cc S
    R_ccᵀ (R orthogonal on each node's free DOFs), and the normal rows n
    are condensed from it with the tangential ones t free of force:

    .. math:: S_n = T_{nn} − T_{nt} Y, \quad Y = T_{tt}^{-1} T_{tn},

    û_t = ŵ_t − Y (u_n − ŵ_n) for :meth:`displacement`; ŵ = R K⁻¹f."""

    def __init__(self, problem, geometry, backend):
        self.problem, self.geometry = problem, geometry
        self.backend = resolve(backend)
        self.R = rotation(problem.n_dofs, geometry)[0]
        self.normal_rows = geometry.dofs[:, -1]
        self.factorizations = 0

    def factorize(self, nodes):
        """K condensed onto every free DOF of ``nodes``, then onto their
        normal rows (class docstring). Returns (S, g̃, w_c) as
        :meth:`NormalCondensation.factorize`."""
        self.nodes = np.asarray(nodes, np.int64)
        if not len(self.nodes):  # a plain factorisation of K̂
            NormalCondensation.__init__(self, self.problem, self.geometry,
                                        self.backend)
            return super().factorize(self.nodes)
        c = self.geometry.subset(self.nodes).free_dofs()
        self.condensation = Condensation.of(self.problem, c, self.backend)
        self.factorizations += 1
        lookup = np.full(self.problem.n_dofs, -1)
        lookup[c] = np.arange(len(c))
        n = lookup[self.normal_rows[self.nodes]]
        t = np.setdiff1d(np.arange(len(c)), n)
        R_cc = self.R[c][:, c]
        T = np.asarray(R_cc @ (R_cc @ self.condensation.S).T)  # symmetric
        self.schur = DenseSchur(T, n, t)  # S_n, and Y x for displacement
        S = self.schur.S
        _, self.w_full = self.condensation.load(self.problem.f)
        self.w = self.R @ self.w_full  # rotated, as K̂⁻¹f̂
        self.c, self.n, self.t, self.R_cc = c, n, t, R_cc
        w_n = self.w[c[n]]
        return S, S @ w_n, w_n

    def displacement(self, u_n):
        """(u, normal displacement at every free contact node) from the
        candidates' normal displacements u_n."""
        if not len(self.nodes):
            return super().displacement(u_n)
        c, n, t = self.c, self.n, self.t
        u_hat = self.w[c].copy()
        change = np.asarray(u_n, float) - u_hat[n]
        u_hat[n] += change
        u_hat[t] -= self.schur.response(change)
        u = self.condensation.displacement(self.R_cc.T @ u_hat, self.w_full)
        return u, (self.R @ u)[self.normal_rows]


def solve_on_candidates(problem, geometry, method, tol, max_iter, x0,
                        gap_scale, stiffness, options, load_norm, margin,
                        condensation):
    """Solve (67) condensed onto the candidates' normal DOFs, enlarging
    the candidates until no other node penetrates (module docstring).

    ``x0`` (reduced u, optional) gives the first round's normal
    displacements at the candidates (default: the free start λ = 0, u_n =
    w_c); each later round starts from the previous one's. ``max_iter``
    bounds the iterations of all rounds together. ``condensation``: the
    engine's :meth:`~solver.contact.engine.SerialEngine.normal_condensation`
    (a :class:`NormalCondensation`, or the PETSc engine's).

    Returns (OptimizeResult, u, λ, u_n, screening): the last round's NCP
    result with the counts and ``history`` of all rounds (``history
    ["round"]``), the reduced displacement, λ and u_n at every free contact
    node, and ``screening``: ``margin`` δ₀, ``rounds`` (per round:
    ``n_candidates``, counts, ``success``, ``penetrating`` non-candidates,
    ``factorize_time``, ``time``), ``n_candidates`` (final), ``enlarged``
    (rounds − 1) and ``exhausted`` (:data:`MAX_ROUNDS` rounds still left a
    penetration)."""
    import time

    from ...ncp import solve_ncp
    from ..frictionless.system import FrictionlessSystem
    from ..verify import contact_scale, verification_tolerance
    from .nested import add_run

    if margin is None and geometry.dim == 2:
        margin = np.inf  # every free node of the curve Γc (docstring)
    nodes, delta = initial_candidates(geometry.gap, margin,
                                      approach(problem))
    tol_v = verification_tolerance(tol)
    start_un = None if x0 is None else \
        (condensation.R @ np.asarray(x0, float))[condensation.normal_rows]
    rounds, history, budget = [], {}, max_iter
    totals = dict(nit=0, njev=0, nfev=0)
    exhausted = False
    for k in range(MAX_ROUNDS):
        clock = time.perf_counter()
        S, g, w_c = condensation.factorize(nodes)
        problem.mark_stiffness_checked()  # by round 0's factorisation
        factorize_time = time.perf_counter() - clock
        system = FrictionlessSystem(S, g, normal_line(geometry, nodes),
                                    gap_scale, stiffness, load_norm)
        start = w_c if start_un is None else start_un[nodes]
        result = solve_ncp(system.residual, system.jacobian, start,
                           method=method, tol=tol, max_iter=budget,
                           options=options, error=system.error,
                           scale=system.scale)
        budget -= result.nit
        add_run(totals, history, result, "round", k)
        lam = np.zeros(len(geometry.gap))
        lam[nodes] = system.contact_force(result.x)
        u, un = condensation.displacement(result.x)
        length = tol_v * contact_scale(load_norm, lam) / stiffness
        grown = enlarge_candidates(nodes, geometry.gap - un, length)
        outside = np.setdiff1d(np.arange(len(lam)), nodes)
        rounds.append(dict(
            n_candidates=len(nodes), nit=result.nit, njev=result.njev,
            nfev=result.nfev, success=bool(result.success),
            penetrating=int(np.count_nonzero(
                geometry.gap[outside] - un[outside] < -length)),
            factorize_time=factorize_time,
            time=time.perf_counter() - clock))
        if grown is None or not result.success:
            break
        if k == MAX_ROUNDS - 1:
            exhausted = True
            break
        nodes, start_un = grown, un
    result.update(totals, history=history, levels=[])
    screening = dict(margin=delta, rounds=rounds, n_candidates=len(nodes),
                     enlarged=len(rounds) - 1, exhausted=exhausted)
    return result, u, lam, un, screening
