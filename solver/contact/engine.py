r"""The engine: who does the linear algebra of a contact solve.

The drivers and strategies never factorise K themselves: they ask an
*engine* (as a qpsolvers-style front hands a problem to a backend) for K
condensed onto a set of DOFs (:meth:`~SerialEngine.condensation`), K̂ =
RKRᵀ condensed onto candidate normal DOFs
(:meth:`~SerialEngine.normal_condensation`) or the full system's Jacobian
(:meth:`~SerialEngine.full_jacobian`). :class:`SerialEngine` runs in this
process on a :mod:`solver.linalg` backend,
:class:`IterativeEngine` in this process by AMG-preconditioned CG (no
factorisation), :class:`solver.mpi.engine.PetscEngine` on the ranks of
``mpiexec``."""

from ..linalg import Condensation, resolve

__all__ = ["SerialEngine", "IterativeEngine"]


class SerialEngine:
    """The linear algebra in this process, on the sparse direct solver
    ``backend`` ("auto": :func:`solver.linalg.resolve`)."""

    name = "serial"

    def __init__(self, backend="auto"):
        self.backend = resolve(backend)  # not installed: SolverError
        self.linear_solver = self.backend

    def condensation(self, problem, dofs):
        """K of ``problem`` condensed onto ``dofs`` (made once per K, DOF
        set and backend: :meth:`solver.linalg.Condensation.of`); the
        factorisation checks that K is positive definite."""
        condensation = Condensation.of(problem, dofs, self.backend)
        problem.mark_stiffness_checked()  # by that factorisation
        return condensation

    #: :meth:`normal_condensation` can condense onto the candidates'
    #: every DOF (``nodal``).
    nodal_condensation = True

    def normal_condensation(self, problem, geometry, nodal=False):
        """K̂ = RKRᵀ for condensations onto candidate normal DOFs; for two
        bodies on a backend that factorises bordered matrices, the same
        from K's own factor (:mod:`.strategies.bordered`); ``nodal``: from
        K condensed onto every free DOF of the candidates, for a friction
        run to reuse (:class:`~.strategies.candidates.NodalCondensation`)."""
        from .strategies import bordered
        from .strategies.candidates import (NodalCondensation,
                                            NormalCondensation)

        if bordered.supports(problem, self.backend):
            return bordered.BorderedCondensation(problem, geometry,
                                                 self.backend)
        kind = NodalCondensation if nodal else NormalCondensation
        return kind(problem, geometry, self.backend)

    def full_jacobian(self, system, problem, geometry):
        """The full system's Jacobian: the system's own (each Newton step one
        sparse LU by SciPy), after the check that K is positive definite
        (:meth:`~solver.problem.ContactProblem.check_stiffness`)."""
        problem.check_stiffness()
        return system.jacobian

    def full_linear_solver(self):
        """What solves the full system's Newton steps."""
        return "superlu"

    def summary(self):
        """Nothing to report beyond ``linear_solver``."""
        return None


class IterativeEngine:
    """The linear algebra in this process without a factorisation of K:
    one smoothed-aggregation hierarchy of K (:mod:`solver.linalg.amg`)
    preconditions CG on every Newton system of the active set methods,
    frictionless (:mod:`.frictionless.active_set`) and with friction, for
    all load steps (:mod:`.friction.active_set`). ``reason``: why it runs (the
    choice of ``backend="auto"``, or None when asked for by name)."""

    name = "serial"
    iterative = True
    backend = linear_solver = "amg"

    def __init__(self, reason=None):
        from ..linalg import amg

        if not amg.available():
            from ..errors import SolverError

            raise SolverError(f"linear solver 'amg' is not installed: pip "
                              f"install 'contact-ssn[{amg.EXTRA}]' "
                              f"({amg.REQUIRES})")
        self.reason = reason
        self._built = None  # (K, Multigrid)

    def multigrid(self, problem):
        """The AMG hierarchy of ``problem.K`` with its rigid-body modes
        (a two-body problem's nodewise equivalent gives its own,
        ``near_null_space``: :func:`~.two_body.near_null_space`; built
        once per K; a body held by contact only, K singular: its coarsest
        level by a pseudo-inverse, :class:`~solver.linalg.amg.Multigrid`)."""
        from ..linalg.amg import Multigrid, rigid_body_modes
        from ..linalg.threads import single_blas_thread

        if self._built is None or self._built[0] is not problem.K:
            near = getattr(problem, "near_null_space", None)  # two bodies
            modes = near() if near is not None else rigid_body_modes(
                problem.nodes[problem.dof_map[:, 0]], problem.dof_map[:, 1])
            with single_blas_thread():  # its dense parts are small
                self._built = (problem.K, Multigrid(
                    problem.K, modes,
                    singular=bool(getattr(problem, "floating", False))))
        return self._built[1]

    def summary(self):
        """The hierarchy: levels, operator complexity, setup time."""
        if self._built is None:
            return None
        mg = self._built[1]
        return dict(name="amg", levels=mg.levels,
                    operator_complexity=mg.operator_complexity,
                    setup_time=mg.setup_time)
