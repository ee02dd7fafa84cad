r"""A body held only by contact: the condensed system with its rigid-body
modes (a semicoercive problem, solved exactly).

K is singular; its kernel is spanned by the rigid motions R (n × r) that
the supports leave free (:meth:`solver.problem.ContactProblem.rigid_modes`).
With r DOFs F held (:func:`solver.linalg.kernel.fixing_dofs`) K_F is
positive definite and K⁺b = K_F⁻¹b₀ a generalised inverse; every solution
of K u = f + Pᵀr (r: the contact forces on the DOFs c of Γc) is

.. math:: u = K^+(f + P^T r) + Rα, \qquad R^T(f + P^T r) = 0

(TFETI: Dostál, Horák, Kučera, *Total FETI*, Commun. Numer. Meth. Engng
22 (2006) 1155-1162; Dostál, Kozubek, Markopoulos, Menšík, Appl. Math.
Comput. 217 (2011) 6067-6077). Condensed onto c with S_J the Schur
complement of K_F and g̃ its condensed load, the unknowns y = (u_c, α)
satisfy the symmetric positive semidefinite system

.. math::
    \begin{bmatrix} S_J & −S_J R_c \\ −R_c^T S_J & R_c^T S_J R_c
    \end{bmatrix} y = \begin{bmatrix} g̃ + r \\ R^T f − R_c^T g̃
    \end{bmatrix},

whose first rows are the condensed equilibrium of Γc (u_c − R_cα = K⁺'s
share) and whose last r rows are Rᵀ(f + Pᵀr) = 0, the load balanced by
the contact forces. It is the system of a supported body with r extra
unknowns that no contact touches, so the frictionless system (67), its
Newton directions and its verification run on it unchanged; no penalty,
no regularisation: the answer is exact to round-off. Its kernel (the
rigid motions) is removed by the active contact constraints; the Newton
matrices are regular exactly when those restrain every mode.

Before any solve (:func:`check_load`) the load is checked against the
contact: if a rigid motion d exists that moves no node into the obstacle
(N d ≤ 0, N the modes' normal components at the contact nodes) and along
which the load does work (Rᵀf · d > 0), no contact force can balance it
(Farkas' lemma) and the problem has no solution: refused, naming d and the
load's component along it (:mod:`solver.problem.rigid`). A motion V
that no contact node's normal sees (N V = 0, a frictionless flat pushed
along itself) with no load along it leaves the answer non-unique: the
term k̄ V Vᵀ added to the α block makes the Newton matrices regular
without changing any equation's solution (no contact force or load acts
along V), and the answer's share along V (of its best-fitting rigid
motion) is then removed: exact.

The start (:func:`rigid_start`): the rigid body's contact problem, a
linear programme (min −(Rᵀf)·α subject to N α ≤ s), puts the body onto
the obstacle at a vertex of r independent touching nodes; one primal-dual
active set step with those nodes active gives the first iterate, with
contact forces at the touching nodes that balance the load. In 2D it
starts the coarsest level of the nested start (:meth:`FloatingSystem.
nested`: every level keeps α), in 3D the Newton iteration on Γc, and
on the full system (:mod:`.floating_full`, the same unknowns α with
all DOFs kept) the Newton iteration in all unknowns.

Coulomb friction (the projection formulation's load steps on this
system, :mod:`solver.contact.friction`): the contact rows now carry the
tangential forces t too, so the last r rows read Rᵀ(f + Pᵀ(λ, t)) = 0
and the modes that no normal sees (a flat sliding along the floor) are
held by friction, not removed. Before the run
(:func:`check_friction_load`) every stage's load must lie in the cone of
the Coulomb cones of the contact nodes (the load-path stages are linear,
the cone convex: their ends suffice); under the lagged bound the first
step has no friction (no pressure before it) and each step's load must be
held with |t_i| ≤ f_c λ_{i,κ−1} (:meth:`FloatingSystem.begin_step`, a
failed step naming the motion otherwise). The first step starts from the
rigid body put onto the obstacle, each later one from the previous
answer (the K⁺ predictor holds the r DOFs F, not the contact). A step
or an iterate without a friction bound at any node (the lagged first
step, a frictionless stage) is singular along the sliding modes V:
:meth:`FloatingSystem._friction_jacobian` adds k̄ V Vᵀ to the Jacobian's
α rows only, which picks, among the exact Newton directions, the one
without sliding; the residual is unchanged, so the answer is exact."""

import dataclasses

import numpy as np
import scipy.optimize as opt
import scipy.sparse as sp

from ...errors import ProblemError
from ...ncp.direction import newton_direction
from ...problem.rigid import (check_rigid_friction, check_rigid_load,
                              mode_text, step_unheld, weakly_held)
from ..geometry import rotation

__all__ = ["FloatingSystem", "check_load", "check_friction_load",
           "held_condensation", "placed", "placement", "rigid_start",
           "unresisted", "warn_weakly_held", "RigidPlacement",
           "lagged_unheld"]

#: Gaps below this × the body's size count as touching in the start.
TOUCH_RTOL = 1e-9


def _normal_rows(problem, geometry):
    """N (Nca, r): the normal displacement of each free contact node of
    ``geometry`` (problem's DOFs) under each rigid mode."""
    R, _ = problem.rigid_modes()
    n = problem.n_dofs
    Q, _, _, normal_rows = rotation(n, geometry)
    return np.asarray(Q[normal_rows] @ R)


def _tangential_rows(problem, geometry):
    """T (Nca, d − 1, r): the tangential displacements of each free
    contact node of ``geometry`` under each rigid mode (0 along a roller's
    constrained tangent)."""
    R, _ = problem.rigid_modes()
    Q, _, tangential, _ = rotation(problem.n_dofs, geometry)
    free = tangential >= 0
    T = np.zeros((len(tangential), R.shape[1]))
    T[free] = np.asarray(Q[tangential[free]] @ R)
    return T.reshape(len(geometry.gap), -1, R.shape[1])


def unresisted(N, rtol=1e-10):
    """An orthonormal basis (r, k) of the modes that no contact normal
    sees (N d = 0 to round-off)."""
    if N.shape[1] == 0:
        return np.zeros((0, 0))
    _, s, Vt = np.linalg.svd(N, full_matrices=True)
    s = np.concatenate([s, np.zeros(N.shape[1] - len(s))])
    return Vt[s <= rtol * max(s.max(initial=0.0), 1e-300)].T


def check_load(problem, geometry):
    """Raise :class:`ProblemError` if the load of a floating ``problem``
    has a component along a rigid-body mode that no contact of
    ``geometry`` can resist (module docstring; frictionless contact), or
    if it presses the body onto nothing (no resultant along the modes):
    :func:`solver.problem.rigid.check_rigid_load` on the modes' normal
    components at the nodes of ``geometry``."""
    check_rigid_load(problem, _normal_rows(problem, geometry))


def check_friction_load(problem, geometry, friction, coulomb="lagged",
                        steps=None):
    """Raise :class:`ProblemError` if a load step of a floating
    ``problem`` with Coulomb friction ``friction`` has a load that no
    contact forces within the Coulomb cones balance (module docstring of
    :mod:`solver.problem.rigid`). The loads of a stage are linear between
    its ends and the balanced loads a convex cone: both ends of every
    stage are checked with the stage's coefficient. The lagged bound
    gives the first step no friction (no pressure before it): its load is
    checked as frictionless."""
    N = _normal_rows(problem, geometry)
    T = _tangential_rows(problem, geometry)
    if problem.load_path is None:
        stages = [(problem.f, 1.0)]
        first = problem.f / problem.n_load_steps(steps)
    else:
        stages = list(zip(problem.load_path, problem.load_path_friction))
        first = problem.load_path[0] / problem.load_path_steps[0]
    start = np.zeros_like(problem.f)
    for end, factor in stages:
        for load in (start, end):
            if np.any(load):
                check_rigid_friction(problem, N, T, friction * factor, load)
        start = end
    if coulomb == "lagged":
        check_rigid_load(problem, N, first, why=(
            "coulomb='lagged' bounds the first load step's friction by "
            "the pressure before it, none; apply the tangential load after "
            "the normal one, a load path, or use coulomb='implicit'"))


def held_condensation(engine, problem, dofs):
    """(F, K_F condensed onto ``dofs``): K with the r DOFs F held
    (:meth:`~solver.problem.ContactProblem.held_stiffness`) condensed by
    ``engine``, or by the engine's own ``held_condensation(problem, dofs)``
    if it has one (the petsc engine builds K_F only while it distributes
    it, :meth:`solver.mpi.engine.PetscEngine.held_condensation`)."""
    own = getattr(engine, "held_condensation", None)
    if own is not None:
        return own(problem, dofs)
    fixed, K_F = problem.held_stiffness()
    return fixed, engine.condensation(dataclasses.replace(problem, K=K_F),
                                      dofs)
def warn_weakly_held(problem, N, G, friction=None):
    """Warn (:class:`~solver.errors.WeaklyHeldWarning`, one line each)
    of the rigid motions that the contact normals see only weakly
    (:func:`solver.problem.rigid.weakly_held`; N, G the modes' normal
    displacements and DOFs at the contact nodes), when some load of the
    run is carried without friction (``friction`` None, or a frictionless
    stage of the load path): friction holds them otherwise. Returns
    [{"motion", "ratio"}] of those warned about ([] if none)."""
    import warnings

    from ...errors import WeaklyHeldWarning

    stages = problem.load_path_friction
    if friction and (stages is None or np.all(np.asarray(stages) > 0)):
        return []
    found = []
    for text, ratio in weakly_held(problem, N, G):
        warnings.warn(
            f"the rigid-body motion {text} is held by the contact only "
            f"weakly: it moves the contact nodes along their normals by "
            f"{ratio:.2g} of their motion (frictionless contact between "
            "round surfaces does not resist it, only the mesh's facets "
            "do), so the answer's share along it is set by the "
            "discretisation; hold it by a support (e.g. u_x = 0 at two "
            "nodes on an axis of symmetry) or give the contact friction",
            WeaklyHeldWarning, stacklevel=2)
        found.append({"motion": text, "ratio": ratio})
    return found


class FloatingSystem:
    """The reduction of a body with rigid-body modes (module docstring):
    K condensed onto the free DOFs of ``geometry``'s nodes with the modes'
    amplitudes α as r more unknowns; the same interface as
    :class:`~solver.contact.strategies.reduction.CondensedSystem`."""

    name = "contact + rigid-body modes"
    condensed = True
    #: φ_FB's watchdog (option of :func:`solver.ncp.solve_ncp`) in the
    #: friction steps: each starts from the previous answer with every
    #: node sticking (no predictor: K⁺ holds the DOFs F, not Γc), and the
    #: Newton step from there, the bonded answer, asks the contact edge
    #: for tractions far above f_c p; ψ rises a small fraction along that
    #: step (where the first node passes its bound), so the monotone search
    #: crawls and, with the implicit bound, stalls (CHANGELOG.md). Full
    #: steps as φ_min's, checked against ψ after at most this many.
    watchdog = 4

    def __init__(self, problem, geometry, engine, friction=None):
        R, _ = problem.rigid_modes()
        self.problem, self.modes = problem, R
        # the factorisation of K_F refuses a K with more than rigid modes
        self.fixed, self.condensation = held_condensation(
            engine, problem, geometry.free_dofs())
        if friction is None:  # a load no contact holds: refused
            check_load(problem, geometry)  # (friction: by the front)
        self.dofs = self.condensation.dofs
        self.m, self.r = len(self.dofs), R.shape[1]
        S = self.condensation.S
        Rc = R[self.dofs]
        SR = S @ Rc
        K = np.empty((self.m + self.r,) * 2)
        K[:self.m, :self.m] = S
        K[:self.m, self.m:] = -SR
        K[self.m:, :self.m] = -SR.T
        K[self.m:, self.m:] = Rc.T @ SR
        self._contact_modes(problem, geometry, friction)
        if self.free_modes.size:  # α ⊥ modes no normal sees (exact)
            k = float(np.mean(np.diag(S))) if self.m else 1.0
            K[self.m:, self.m:] += k * self.free_modes @ self.free_modes.T
        self.K = 0.5 * (K + K.T)
        self._k = float(np.mean(np.diag(S))) if self.m else 1.0
        self.geometry = geometry.compact()
        self.linear_solver = engine.linear_solver
        self._Rc = Rc
        self.start_nodes = None

    def _contact_modes(self, problem, geometry, friction):
        """N and T (the modes' normal and tangential displacements at
        the contact nodes), ``sliding`` (the modes no normal sees) and
        ``free_modes`` (those no contact resists: with friction, those no
        normal or tangent sees); warns of the motions the normals see only
        weakly (``weakly_held``)."""
        self.N = _normal_rows(problem, geometry)
        self.T = _tangential_rows(problem, geometry)
        self.friction = friction
        #: the motions the normals see only weakly (warned about)
        self.weakly_held = warn_weakly_held(
            problem, self.N, self.modes[geometry.free_dofs()], friction)
        #: modes no normal sees: with friction, held by it alone
        self.sliding = unresisted(self.N)
        self.free_modes = self.sliding if not friction else unresisted(
            np.concatenate([self.N, self.T.reshape(-1, self.N.shape[1])]))

    def load(self, f):
        """(f̃, w): the augmented load (g̃, Rᵀf − R_cᵀg̃) and w = K⁺f."""
        f = np.asarray(f, float)
        f0 = f.copy()
        f0[self.fixed] = 0.0
        g, w = self.condensation.load(f0)
        return np.concatenate([g, self.modes.T @ f - self._Rc.T @ g]), w

    def restrict(self, u):
        """(u_c, α) of a displacement u: α with (u − Rα)_F = 0."""
        u = np.asarray(u, float)
        alpha = np.linalg.solve(self.modes[self.fixed], u[self.fixed])
        return np.concatenate([u[self.dofs], alpha])

    def displacement(self, x, w):
        """u = K⁺(f + Pᵀr) + Rα from y = (u_c, α) and w = K⁺f."""
        x = np.asarray(x, float)
        u_c, alpha = x[:self.m], x[self.m:]
        u = self.condensation.displacement(u_c - self._Rc @ alpha, w) \
            + self.modes @ alpha
        if self.free_modes.size:  # no share along motions no normal sees
            V = self.modes @ self.free_modes
            u = u - V @ (V.T @ u)
        return u

    def alpha(self, x):
        """The rigid-body amplitudes α of the unknowns x."""
        return np.asarray(x, float)[self.m:]

    def jacobian(self, system):
        """The system's own Jacobian (dense, LAPACK); with friction, at an
        iterate where no node has a friction bound (the lagged bound of
        the first step, a frictionless stage, no contact yet) the modes
        only friction resists are singular: :meth:`_friction_jacobian`."""
        if not self.friction or not self.sliding.size:
            return system.jacobian
        return lambda x: self._friction_jacobian(system, x)

    def _friction_jacobian(self, system, x):
        r"""The Jacobian of a friction ``system`` at x; where every
        node's bound is 0 the rows of α along the sliding modes V (no
        normal sees them) gain k̄ V Vᵀ. Exact: there J is singular along
        the sliding of the rigid body (z = (R_cV, V, 0) ∈ ker J), the
        step's load has no share along V (checked before the step) and
        the residual is not changed, so the direction is a Newton
        direction of the step, the one with no sliding (Δα_V = 0): the
        body does not slide when nothing pushes it along the floor."""
        JE, JA, JB = system.jacobian(x)
        b, _ = system.bound(system._force(x[:system.n]), derivative=False)
        if np.any(b > 0.0):
            return JE, JA, JB
        return self._hold_sliding(system, JE), JA, JB

    def _hold_sliding(self, system, JE):
        """JE (the "other" rows, which open the Jacobian) with k̄ V Vᵀ
        added to the rows and columns of α along the sliding modes V
        (:meth:`_friction_jacobian`)."""
        V, m, r = self.sliding, self.m, self.r
        # α's rows: the last r of the "other" rows X, which open JE
        alpha_rows = np.searchsorted(system.x_rows, m + np.arange(r))
        rows = np.repeat(alpha_rows, r)
        cols = np.tile(np.arange(m, m + r), r)
        add = sp.csr_matrix((self._k * (V @ V.T).ravel(), (rows, cols)),
                            shape=JE.shape)
        return (JE + add).tocsr()

    def begin_step(self, system, load, step_friction, state, lumped,
                   coulomb):
        """Before a friction load step: None, or the one-line reason why
        no answer exists (the body slides away: :func:`~solver.problem.
        rigid.step_unheld` with the lagged bound f_c λ_{κ−1}; the implicit
        bound's cones were checked before the run)."""
        return lagged_unheld(self.problem, self.N, self.T, load,
                             step_friction, state, lumped, coulomb)

    def step_start(self, system, du, u_previous, load):
        """The first iterate of a friction load step: the predictor
        ``du``, or, before any contact (u_{κ−1} = 0), the rigid body put
        onto the obstacle by the linear programme of :func:`rigid_start`
        for the step's load, not deformed and sliding along no mode no
        normal sees."""
        if np.any(u_previous):
            return np.zeros_like(du)
        alpha = placement(self.N, self.geometry.gap,
                          self.modes.T @ np.asarray(load, float),
                          self.sliding)
        if alpha is None:
            return du
        return np.concatenate([self._Rc @ alpha, alpha])

    def free_start(self, system, w):
        """The first iterate (module docstring): the rigid body put onto
        the obstacle by a linear programme, then one active set step with
        the touching nodes active."""
        y, self.start_nodes = rigid_start(system, self.N, self.geometry.gap,
                                          self._Rc, self.problem)
        if y is None:
            raise ProblemError("f: the body cannot be put onto the "
                               "obstacle as a rigid body")
        return y

    def nested(self, system, method, tol, max_iter, gap_scale, stiffness,
               options, load_norm):
        """Nested iteration (:mod:`.nested`'s, with α kept on every
        level): the coarsest level from :func:`rigid_start`, each finer
        one from the coarser answer prolonged by equilibrium. Returns the
        finest level's result with the counts of all levels and
        ``levels`` as :func:`.nested.solve_nested`."""
        from ...linalg.threads import single_blas_thread
        from ..frictionless.system import FrictionlessSystem
        from .nested import COARSEST, run_level

        levels = [_Level(np.arange(len(self.geometry.gap)), self.K,
                         system.f, self.geometry, self._Rc, self.N)]
        with single_blas_thread():
            while len(levels[-1].nodes) > COARSEST:
                levels.append(levels[-1].coarsen(self.geometry))
        y, report, budget = None, [], max_iter
        totals, history = dict(nit=0, njev=0, nfev=0), {}
        for depth in range(len(levels) - 1, -1, -1):
            level = levels[depth]
            sub = system if depth == 0 else FrictionlessSystem(
                level.K, level.f, level.geometry, gap_scale, stiffness,
                load_norm)
            if y is None:
                y, touching = rigid_start(sub, level.N, level.geometry.gap,
                                          level.Rc, self.problem)
                if y is None:  # these nodes cannot hold the body
                    continue
                self.start_nodes = touching
            else:
                y = level.prolong(y)
            if depth and not budget:
                continue
            result = run_level(sub, y, len(level.nodes), method, tol,
                               budget, options, (totals, history, report))
            budget -= result.nit
            y = result.x if result.success or result.status == 1 else None
        result.update(totals, history=history, levels=report)
        return result


class _Level:
    """One level of the nested start of a floating body: ``nodes``
    (positions in the finest level's list), ``K`` (the augmented system
    condensed onto their DOFs and α), ``f`` (its load), ``geometry``,
    ``Rc`` (the modes at its DOFs), ``N`` (the modes' normal
    displacements at its nodes); ``keep``, ``X`` = K_rr⁻¹K_rk and
    ``z`` = K_rr⁻¹f_r prolong the next coarser level's iterate."""

    def __init__(self, nodes, K, f, geometry, Rc, N):
        self.nodes, self.K, self.f, self.geometry = nodes, K, f, geometry
        self.Rc, self.N = Rc, N
        self.keep = self.X = self.z = None

    def prolong(self, y_coarse):
        """This level's y from the coarser level's: the kept DOFs and α
        take it, the dropped DOFs follow from equilibrium without contact
        force, u_r = K_rr⁻¹(f_r − K_rk u_k)."""
        kept = self._kept()
        y = np.empty(len(self.f))
        y[kept] = y_coarse
        y[~kept] = self.z - self.X @ y_coarse
        return y

    def _kept(self):
        counts = (self.geometry.node_dofs >= 0).sum(axis=1)
        owner = np.repeat(np.arange(len(counts)), counts)
        return np.concatenate([self.keep[owner],
                               np.ones(len(self.f) - len(owner), bool)])

    def coarsen(self, fine_geometry):
        """The next coarser level: every other node (and the last) kept,
        the others condensed out with no contact force on them."""
        import scipy.linalg as sla

        keep = np.zeros(len(self.nodes), bool)
        keep[::2] = keep[-1] = True
        self.keep = keep
        kept = self._kept()
        k, r = np.flatnonzero(kept), np.flatnonzero(~kept)
        K_rk = self.K[np.ix_(r, k)]
        cho = sla.cho_factor(self.K[np.ix_(r, r)])
        self.X = sla.cho_solve(cho, K_rk)
        self.z = sla.cho_solve(cho, self.f[r])
        K = self.K[np.ix_(k, k)] - K_rk.T @ self.X
        f = self.f[k] - K_rk.T @ self.z
        nodes = self.nodes[keep]
        m = int(kept[:len(kept) - self.Rc.shape[1]].sum())
        return _Level(nodes, 0.5 * (K + K.T), f,
                      fine_geometry.subset(nodes).compact(),
                      self.Rc[kept[:len(self.Rc)]][:m], self.N[keep])


def placement(N, gap, e, free):
    """α of the rigid body put onto the obstacle by the load e = Rᵀf: the
    linear programme min −e·α subject to N α ≤ s, α ⊥ ``free`` (modes no
    normal sees); None if it has no solution."""
    scale = np.abs(N).max(initial=1.0)
    extra = {}
    if free.size:
        extra = dict(A_eq=free.T, b_eq=np.zeros(free.shape[1]))
    found = opt.linprog(-e / max(np.abs(e).max(), 1e-300), A_ub=N / scale,
                        b_ub=gap / scale, bounds=[(None, None)] * len(e),
                        method="highs", **extra)
    return found.x if found.status == 0 else None


def placed(N, gap, e, Rc):
    """(y0, touching): the unknowns (u_c = R_c α, α) of the rigid body put
    onto the obstacle by the load e = Rᵀf (:func:`placement`, not sliding
    along the modes no normal sees) and the nodes it touches there;
    (None, None) if the programme has no solution."""
    alpha = placement(N, gap, e, unresisted(N))
    if alpha is None:
        return None, None
    remaining = gap - N @ alpha
    size = np.abs(gap).max(initial=0.0) + np.abs(N @ alpha).max(initial=0.0)
    touching = remaining <= TOUCH_RTOL * max(size, 1e-300)
    return np.concatenate([Rc @ alpha, alpha]), touching


def rigid_start(system, N, gap, Rc, problem):
    """(y, touching nodes): the rigid body put onto the obstacle by the
    linear programme min −(Rᵀf)·α subject to N α ≤ s (:func:`placed`),
    then one primal-dual active set step of ``system`` with the touching
    nodes active (module docstring); None if the programme has no
    solution (these nodes do not hold the body). The step is solved on
    the system's structured Jacobian (condensed) or on its sparse rows
    [JE; w_a JA + w_b JB] (the full system); a condensed system without
    the structured one starts from the placement."""
    R, _ = problem.rigid_modes()
    x0, touching = placed(N, gap, R.T @ problem.f, Rc)
    if x0 is None:
        return None, 0
    E, A, B = system.residual(x0)
    wa, wb = (~touching).astype(float), touching.astype(float)
    J = system.jacobian(x0)
    rhs = np.concatenate([E, wa * A + wb * B])
    if hasattr(J, "combine"):
        step = J.combine(wa, wb).direction(rhs)
    elif not sp.issparse(J[0]):  # dense blocks, not reduced: no step
        step = None
    else:
        JE, JA, JB = (sp.csr_matrix(block) for block in J)
        step = newton_direction(sp.vstack(
            [JE, sp.diags(wa) @ JA + sp.diags(wb) @ JB], format="csc"), rhs)
    return (x0 if step is None else x0 + step), int(touching.sum())


def _rank(N, rtol=1e-10):
    """The rank of N with :func:`unresisted`'s tolerance."""
    if not N.size:
        return 0
    s = np.linalg.svd(N, compute_uv=False)
    return int((s > rtol * s.max()).sum()) if s.max() > 0 else 0


class RigidPlacement:
    r"""What a Krylov path needs of a body held by contact only (the
    iterative active set method, :mod:`solver.contact.frictionless.
    active_set`), with nothing factorised: the load checked as on the
    factorisation paths (:func:`check_load`: a load no contact holds is
    refused in the same line), ``u`` the rigid body put onto the obstacle
    (:func:`placed`, u = Rα, not sliding along a mode no normal sees) and
    ``touching`` its nodes there, the first active set (they hold every
    mode the contact can hold: the programme's vertex), ``free`` the
    modes no normal sees in u (n, k; orthonormal, R being so), ``N`` the
    modes' normal displacements at the contact nodes, ``start_nodes`` and
    ``weakly_held`` as :class:`FloatingSystem`'s.

    :meth:`hold` keeps every later active set holding the modes the
    contact holds: a set A whose N_A has lower rank than N on the held
    modes leaves K̂_FF singular along a rigid motion that the load pushes
    (its system has no solution), so the nodes of largest λ − c(s − u_n)
    are added until the rank is N's; this shapes only the Newton path
    (the stopping test is the method's)."""

    def __init__(self, problem, geometry, friction=None):
        if friction is None:  # friction: checked by the front
            check_load(problem, geometry)
        R, _ = problem.rigid_modes()
        self.modes, self._gap = R, geometry.gap
        self._problem, self._fixed = problem, None
        self.N = _normal_rows(problem, geometry)
        self.T = _tangential_rows(problem, geometry)
        self.weakly_held = warn_weakly_held(
            problem, self.N, R[geometry.free_dofs()], friction)
        self.free = R @ unresisted(self.N)
        self._rank = _rank(self.N)
        self.u, self.touching = self.place(problem.f)
        if self.u is None and friction is None:
            raise ProblemError("f: the body cannot be put onto the "
                               "obstacle as a rigid body")
        self.start_nodes = None if self.touching is None \
            else int(self.touching.sum())

    def place(self, load):
        """(u, touching): the rigid body put onto the obstacle by ``load``
        (:func:`placed`) and the nodes it touches; (None, None) if the
        programme has no solution."""
        y, touching = placed(self.N, self._gap, self.modes.T @ load,
                             self.modes)
        if y is None:
            return None, None
        return y[:self.modes.shape[0]], touching

    def unheld(self, rows):
        """Z (k, n) sparse, or None: for the k modes that the sparse
        ``rows`` (constraints or springs, on u) do not see, the rows that
        read their amplitudes α_V = Vᵀ R_F⁻¹ u_F from the r DOFs F of
        K⁺ (:meth:`~solver.problem.ContactProblem.held_stiffness`), as the
        factorisation path's unknowns α do (:meth:`FloatingSystem.
        _friction_jacobian` keeps Δα_V = 0); Z R V = I, so a Newton
        system held at Z u = Z u_start is regular."""
        V = unresisted(np.asarray(rows @ self.modes)) if rows.shape[0] \
            else np.eye(self.modes.shape[1])
        if not V.size:
            return None
        if self._fixed is None:
            self._fixed = self._problem.fixed_dofs()
        Z = np.linalg.solve(self.modes[self._fixed].T, V).T  # (k, r)
        n, k, r = self.modes.shape[0], V.shape[1], len(self._fixed)
        return sp.csr_matrix((Z.ravel(), (np.repeat(np.arange(k), r),
                                          np.tile(self._fixed, k))),
                             shape=(k, n))

    def hold(self, active, score):
        """``active`` (a boolean mask of the contact nodes), with the nodes
        of largest ``score`` (λ − c(s − u_n)) added until the active
        normals see every mode the contact can hold (class docstring)."""
        if _rank(self.N[active]) >= self._rank:
            return active
        active = active.copy()
        for node in np.argsort(-score, kind="stable"):
            if active[node]:
                continue
            active[node] = True
            if _rank(self.N[active]) >= self._rank:
                break
        return active


def lagged_unheld(problem, N, T, load, step_friction, state, lumped,
                  coulomb):
    """Before a friction load step of a floating ``problem`` (N, T the
    modes' normal and tangential displacements at the contact nodes):
    None, or the one-line reason why no answer exists under the lagged
    bound f_c λ_{κ−1} (:func:`~solver.problem.rigid.step_unheld`; the
    implicit bound's cones were checked before the run)."""
    if coulomb != "lagged":
        return None
    bounds = step_friction * lumped * np.asarray(state.p, float)
    found = step_unheld(problem, N, T, load, bounds)
    if found is None:
        return None
    motion, component = found
    return (f"the load has a component {component:.6g} along the "
            f"rigid-body motion {mode_text(problem, motion)} "
            "that the previous step's contact pressure cannot hold "
            "by friction (coulomb='lagged' bounds the friction by "
            "it): the body would slide away; apply the tangential "
            "load after the normal one (a load path), in more steps, "
            "or use coulomb='implicit'")
