r"""A body held only by contact on the full system (``system="full"``):
all DOFs stay unknowns, the r DOFs F that :func:`solver.linalg.kernel.
fixing_dofs` picks are replaced by the rigid-body modes' amplitudes α.

Every displacement is u = ũ + Rα with ũ_F = 0 (R_F is regular, so the
split is unique), hence u_J = y_J and u_F = R_F α for the unknowns
y = (u_J, α), u = W y with W = [[I, 0], [0, R_F]] (rows J, then F).
Equilibrium K u = f + Pᵀr (r: the contact forces) in these unknowns is
the system of a body with the stiffness and load

.. math::
    \hat K = W^T K W = \begin{bmatrix} K_{JJ} & K_{JF} R_F \\
    R_F^T K_{FJ} & R_F^T K_{FF} R_F \end{bmatrix}, \qquad
    \hat f = W^T f = (f_J, R_F^T f_F),

sparse like K (K_JF is non-zero next to the r DOFs F only). Its J rows
are K's; its last r rows are the equilibrium of the rigid body,
R_Fᵀ(Ku − f)_F = −Rᵀ(f + r_J) for every y, since RᵀK = 0 and
(Ku − f)_J = r_J: the contact forces read from the J rows, as the system
(67) reads them, must balance the load, Rᵀ(f − Bᵀλ − Tᵀt) = 0 (TFETI,
Dostál, Horák, Kučera 2006). The contact nodes lie in J (F avoids Γc),
so the gaps B = c(s − YRu) and the friction rows are those of a supported
body renumbered: the frictionless system (67), the projection and the
thesis's split formulations run on K̂, f̂ unchanged, and the answer is
exact (no penalty, no regularisation of the equations).

K̂ is singular (its kernel is the rigid motions, (R_J β, β)); the Newton
matrices are regular exactly when the active contact constraints
restrain every mode (a direction d with K̂d = Y-rows only and the
active gaps unchanged has dᵀK̂d = 0, so d is a rigid motion no active
normal sees). Hence the start: the rigid body put onto the obstacle
(:func:`~.floating.placed`, a linear programme) and one active set
step with its touching nodes active (:func:`~.floating.rigid_start`),
which hold every mode the contact can hold. The modes no normal sees
(a frictionless flat on a flat: the load has no share along them,
checked before) are handled as on the condensed system
(:mod:`.floating`): k̄ V Vᵀ in the α block, the answer's share along
them removed; with friction, the Jacobian's α rows gain k̄ V Vᵀ where no
node has a friction bound (the residual untouched). A Newton matrix that
is singular all the same ends the solve with status 3 (singular
Jacobian), nothing that looks like a solution."""

import numpy as np
import scipy.sparse as sp

from ...ncp.direction import newton_direction
from ..frictionless.system import FrictionlessSystem
from ..geometry import rotation
from .floating import FloatingSystem, check_load, placed

__all__ = ["FloatingFullSystem"]


class FloatingFullSystem(FloatingSystem):
    """The full system of a body with rigid-body modes (module
    docstring), in the unknowns y = (u_J, α); the interface of
    :class:`~.reduction.FullSystem`, with the floating body's starts and
    friction Jacobian of :class:`~.floating.FloatingSystem`."""

    name = "none (rigid-body modes' amplitudes for r DOFs)"
    condensed = False

    def __init__(self, problem, geometry, engine, friction=None):
        R, _ = problem.rigid_modes()
        n = problem.n_dofs
        self.problem, self.modes = problem, R
        self.fixed, _ = problem.held_stiffness()
        held = np.zeros(n, bool)
        held[self.fixed] = True
        self.dofs = np.flatnonzero(~held)
        self.m, self.r = len(self.dofs), R.shape[1]
        m, r = self.m, self.r
        if friction is None:  # a load no contact holds: refused
            check_load(problem, geometry)
        # W: y → u (u_J = y_J, u_F = R_F α)
        RF = R[self.fixed]
        rows = np.concatenate([self.dofs, np.repeat(self.fixed, r)])
        cols = np.concatenate([np.arange(m), np.tile(m + np.arange(r), r)])
        self._W = sp.csr_matrix((np.concatenate([np.ones(m), RF.ravel()]),
                                 (rows, cols)), shape=(n, m + r))
        K = (self._W.T @ sp.csr_matrix(problem.K) @ self._W).tocsr()
        self._contact_modes(problem, geometry, friction)
        self._k = float(np.mean(problem.K.diagonal()[
            geometry.free_dofs()])) if len(geometry.gap) else 1.0
        if self.free_modes.size:  # α ⊥ modes no contact sees (exact)
            block = self._k * self.free_modes @ self.free_modes.T
            K = K + sp.csr_matrix(
                (block.ravel(), (np.repeat(m + np.arange(r), r),
                                 np.tile(m + np.arange(r), r))),
                shape=K.shape)
        self.K = (0.5 * (K + K.T)).tocsr()
        lookup = np.full(n + 1, -1)  # lookup[-1] stays −1
        lookup[self.dofs] = np.arange(m)
        self.geometry = geometry.renumbered(lookup[geometry.dofs],
                                            lookup[geometry.node_dofs])
        self.engine = engine
        self.linear_solver = engine.full_linear_solver()
        self._Rc = R[self.dofs]
        self.start_nodes = None

    def load(self, f):
        """(f̂, None): f̂ = Wᵀf (no K⁺f: nothing is condensed)."""
        return self._W.T @ np.asarray(f, float), None

    def restrict(self, u):
        """y = (u_J, α) of a displacement u: α with (u − Rα)_F = 0."""
        u = np.asarray(u, float)
        alpha = np.linalg.solve(self.modes[self.fixed], u[self.fixed])
        return np.concatenate([u[self.dofs], alpha])

    def displacement(self, x, w=None):
        """u = W y, without a share along the modes no contact sees."""
        u = self._W @ np.asarray(x, float)
        if self.free_modes.size:
            V = self.modes @ self.free_modes
            u = u - V @ (V.T @ u)
        return u

    def jacobian(self, system):
        """The system's sparse Jacobian (one SuperLU per Newton step),
        after the check that K's kernel is the rigid modes (K with F held
        positive definite); with friction, :meth:`~.floating.
        FloatingSystem._friction_jacobian`."""
        self.problem.check_stiffness()
        return super().jacobian(system)

    def step_start(self, system, du, u_previous, load):
        """The first iterate of a friction load step: before any contact
        (u_{κ−1} = 0) the rigid body put onto the obstacle by the step's
        load (:func:`~.floating.placed`), then one Newton step with its
        touching nodes in contact and stuck (s − u_n = 0 and Δu_t = 0
        there): they hold every mode the contact can hold, normal and
        tangential, so the step is regular and its contact forces balance
        the step's load, tangential part included. Its rigid slide along
        the modes no normal sees is taken out, as the condensed system's
        start has none (a step without friction bound keeps the start's
        slide, :meth:`_friction_jacobian`). After the first contact,
        None (the previous answer, Δu = 0)."""
        if np.any(u_previous):
            return None
        y0, touching = placed(self.N, self.geometry.gap,
                              self.modes.T @ np.asarray(load, float),
                              self._Rc)
        if y0 is None:
            return None
        gap = self.geometry.gap
        start = FrictionlessSystem(self.K, self.load(load)[0],
                                   self.geometry, system.gap_scale,
                                   system.stiffness)
        E, A, B = start.residual(y0)
        JE, JA, JB = (sp.csr_matrix(block) for block in start.jacobian(y0))
        _, _, tangential, _ = rotation(len(y0), self.geometry)
        stuck = tangential.reshape(len(gap), -1)[touching].ravel()
        stuck = stuck[stuck >= 0]  # not a roller's constrained tangent
        rows = np.searchsorted(start.x_rows, stuck)
        keep = np.ones(JE.shape[0])
        keep[rows] = 0.0
        stick = sp.csr_matrix((np.ones(len(rows)), (rows, stuck)),
                              shape=JE.shape) @ start.R
        wa, wb = (~touching).astype(float), touching.astype(float)
        J = sp.vstack([sp.diags(keep) @ JE + stick,
                       sp.diags(wa) @ JA + sp.diags(wb) @ JB], format="csc")
        step = newton_direction(J, np.concatenate([keep * E,
                                                   wa * A + wb * B]))
        if step is None:
            return y0
        slide = self.sliding @ (self.sliding.T @ step[self.m:])
        return y0 + step - np.concatenate([self._Rc @ slide, slide])
