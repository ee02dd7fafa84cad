"""The system of one load step of Coulomb friction: what the thesis's
split formulation (110)/(111) (:class:`~.split.SplitSystem`) and the
projection formulation (:class:`~.projection.ProjectionSystem`; in 3D on a
condensed S :class:`~.disc.DiscSystem`) share — the rotated forces
r = R(Ku − f_κ) of the step, the lumped pressure, the Coulomb bound f_c p
and the stopping test's scale. The formulations, the bound and the
references are described in :mod:`solver.contact.friction.driver`, whose
driver builds one system per run and moves it from step to step."""

import numpy as np
import scipy.sparse as sp

from ...errors import SolverError
from ...ncp import stable_norm
from ..geometry import contact_stiffness, rotation
from ..verify import contact_weight, force_scale

__all__ = ["FORMULATIONS", "COULOMB", "FrictionSystem"]

FORMULATIONS = ("thesis", "projection")
COULOMB = ("lagged", "implicit")


class FrictionSystem:
    """Residual and Jacobian of one load step, for :func:`solver.ncp.
    solve_ncp`: the part both formulations share. K, f: the reduced stiffness
    and the full load; ``geometry`` the gaps and frames of the free contact
    nodes; ``lumped`` D_ii = Σ_j M_ij there; ``friction`` f_c ≥ 0;
    ``coulomb`` "lagged" or "implicit"; ``gap_scale`` c of the normal pair's
    B = c(s − YRu) (1 = thesis); ``stiffness`` k̄ of the stopping measure and
    of c_t (default: mean of diag K at the contact DOFs; a condensed system
    passes that of the full K)."""

    #: "thesis" or "projection" (:data:`FORMULATIONS`)
    formulation = None
    #: Newton systems reduced to the free components (:mod:`.newton`)
    reduced = False
    #: The norms of the stopping test over the ranks of a distributed run
    #: (:class:`solver.mpi.partitioned_full.Reduction`), or None: this
    #: process holds every row.
    reduction = None

    def __init__(self, K, f, geometry, lumped, friction, coulomb="lagged",
                 gap_scale=1.0, stiffness=None):
        if coulomb not in COULOMB:
            raise SolverError(f"coulomb must be one of {COULOMB}, got "
                              f"{coulomb!r}")
        self.dim = int(geometry.dim)
        n = K.shape[0]
        self.n, self.m = n, len(geometry.dofs)
        self.K, self.f = sp.csr_matrix(K), np.asarray(f, float)
        self.geometry, self.lumped = geometry, np.asarray(lumped, float)
        self.friction, self.coulomb = float(friction), coulomb
        self.gap_scale = float(gap_scale)
        self.R, other, a, b = rotation(n, geometry)
        self.RT = self.R.T  # once: SciPy makes a new transpose per ``.T``
        self.x_rows, self.t_rows, self.n_rows = other, a, b  # X, Z, Y
        #: condensed onto Γc: K is the dense S, no other rows
        self.dense_schur = isinstance(K, np.ndarray) and not len(other)
        #: tangential unknowns: m(d − 1), node by node (the tangent basis)
        self.mt = len(a)
        #: the tangential unknowns with an equilibrium row: False at a
        #: roller's constrained tangent e_c (``dofs`` −1), whose g is 0
        self.t_free = a >= 0
        self.rollers = not bool(self.t_free.all())
        self.lumped_t = np.repeat(self.lumped, self.dim - 1)
        self.RK = (self.R @ self.K).tocsr()
        self.Rf = self.R @ self.f
        self.stiffness = contact_stiffness(self.K, geometry) \
            if stiffness is None else float(stiffness)
        # c_t of the projection: stiffness per unit contact length.
        self.c_t = self.stiffness / float(self.lumped.mean()) \
            if self.m else 1.0
        self.load_norm = stable_norm(self.f)
        #: D g of the last residual: the friction forces the contact
        #: weight of the stopping measure counts (ProjectionSystem.error)
        self.last_friction_force = None
        self.set_step(np.zeros(n), 1.0, np.zeros(self.m))

    def set_step(self, u_previous, load, p_previous, friction=None,
                 load_norm=None):
        """Fix u_{κ−1}, the step's ``load`` (its vector f_κ, or a number
        κ/κc meaning κ/κc · f), the lagged pressure p_{κ−1} and optionally
        the step's friction coefficient and the ‖f‖₂ of :meth:`scale` (a
        condensed system is given that of the problem's load)."""
        if load_norm is not None:
            self.load_norm = float(load_norm)
        self.u_previous = np.asarray(u_previous, float)
        load = np.asarray(load, float)
        self._Rf_step = (float(load) * self.Rf if load.ndim == 0
                         else self.R @ load)
        self.p_previous = np.asarray(p_previous, float)
        if friction is not None:
            self.friction = float(friction)
        self._r_previous = self.RK @ self.u_previous
        self._last_force = None  # (Δu, r) of the last :meth:`_force`

    def traction(self, x):
        """g_t from the unknown vector x ((m,), or m(d − 1) node by node in the
        tangent basis), which holds ĝ = g_t / c_t: a length like every other
        unknown, so that the FB method's descent test (26), ∇ψᵀd ≤ −ρ‖d‖ᵖ, does
        not compare displacements with tractions."""
        return self.c_t * x[self.n:self.n + self.mt]

    def _force(self, du):
        """r = R(Ku − f_κ) with u = u_{κ−1} + Δu. The last one is kept:
        the Jacobian at the iterate whose residual was just evaluated, and
        the step's check, reuse it."""
        last = self._last_force
        if last is not None and np.array_equal(last[0], du):
            return last[1]
        r = self._r_previous + self.RK @ du - self._Rf_step
        self._last_force = (np.array(du, float), r)
        return r

    def pressure(self, r):
        """Lumped contact pressure of the current iterate, ≥ 0."""
        return np.maximum(-r[self.n_rows], 0.0) / self.lumped

    def bound(self, r, derivative=True):
        """f_c p and its derivative rows (None if lagged or not
        ``derivative``)."""
        if self.coulomb == "lagged":
            return self.friction * self.p_previous, None
        if not derivative:
            return self.friction * self.pressure(r), None
        active = (-r[self.n_rows] > 0.0) / self.lumped
        d = -self.friction * (sp.diags(active) @ self.RK[self.n_rows])
        return self.friction * self.pressure(r), d

    def _shared_rows(self, du, g):
        """What both residuals share: (r, X rows, tangential equilibrium
        rows r_t − D g_t (none along a roller's e_c), λ, the gap rows
        c(s − YRu), the bound f_c p)."""
        r = self._force(du)
        gap = self.gap_scale * (self.geometry.gap - (
            self.R @ (self.u_previous + du))[self.n_rows])
        self.last_friction_force = self.lumped_t * g
        tangential = r[self.t_rows] - self.lumped_t * g
        if self.rollers:
            tangential = tangential[self.t_free]
        b, _ = self.bound(r, derivative=False)
        return r, r[self.x_rows], tangential, -r[self.n_rows], gap, b

    def tangential(self, v):
        """The tangential components v[Z] of a rotated vector v = R·(…),
        node by node; 0 along a roller's e_c (u_c = 0 is prescribed)."""
        out = v[self.t_rows]
        return np.where(self.t_free, out, 0.0) if self.rollers else out

    def jacobian(self, x):
        """(JE, JA, JB) of the formulation's sparse Jacobian with respect
        to x (its ĝ columns scaled by c_t)."""
        scale = np.ones(self.n_unknowns)
        scale[self.n:self.n + self.mt] = self.c_t
        S = sp.diags(scale)
        return tuple((J @ S).tocsr() for J in self._jacobian(x))

    def scale(self, E, A, B):
        """Force scale F = max(‖f‖₂, ‖λ⁺‖₂) of the stopping test error ≤
        tol·F (A[:m] = λ in both formulations;
        :mod:`solver.contact.verify`)."""
        return force_scale(self.load_norm,
                           self.gathered(np.maximum(A[:self.m], 0.0)))

    def norm(self, v):
        """‖v‖₂ of the rows of every rank (:attr:`reduction`)."""
        return stable_norm(v) if self.reduction is None else \
            self.reduction.norm(v)

    def gathered(self, v):
        """v as the scales of :mod:`solver.contact.verify` read it, only
        through ‖v‖₂: v itself, or over the ranks (:attr:`reduction`) a
        one-entry array holding the norm of every rank's v."""
        if v is None or self.reduction is None:
            return v
        return np.array([self.reduction.norm(np.ravel(v))])

    def initial_guess(self, g_previous, du=None):
        """Each step starts from the previous solution: the same g_t and
        Δu = 0, or Δu = ``du``, the step's predictor (a condensed system:
        Γc moving as the unconstrained body, its normal contact forces
        corrected by :func:`~.start.contact_corrected`)."""
        x = np.zeros(self.n_unknowns)
        x[self.n:self.n + self.mt] = np.ravel(g_previous) / self.c_t
        if du is not None:
            x[:self.n] = du
        return x
