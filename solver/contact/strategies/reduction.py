r"""The space Newton iterates in: the full system or K condensed onto Γc.

Both drivers build their system on a *reduction* and never ask which:
:class:`FullSystem` (the thesis's system in all Ñ unknowns) or
:class:`CondensedSystem` (K → S, f → g̃ condensed exactly onto the free
DOFs of the contact nodes, :class:`solver.linalg.Condensation`, from one
factorisation by the engine). A reduction gives the system's ``K`` and
``geometry``, maps a load onto it, recovers u, restricts a displacement
to its unknowns and hands out the Jacobian of a system built on it."""

import numpy as np

__all__ = ["FullSystem", "CondensedSystem", "reduction", "condense_onto_contact"]


class FullSystem:
    """The system in all unknowns of ``problem`` (nothing condensed)."""

    name = "none"
    condensed = False

    def __init__(self, problem, geometry, engine):
        self.problem, self.geometry, self.engine = problem, geometry, engine
        self.K = problem.K
        self.linear_solver = engine.full_linear_solver()

    def load(self, f):
        """(f, None): the system takes the load as it is."""
        return f, None

    def restrict(self, u):
        """The unknowns of a reduced displacement u: all of it."""
        return np.asarray(u, float)

    def displacement(self, x, w=None):
        """u from the system's unknowns: x itself."""
        return x

    def jacobian(self, system):
        """The engine's Jacobian of ``system`` (K checked first)."""
        return self.engine.full_jacobian(system, self.problem, self.geometry)


class CondensedSystem:
    """K condensed onto the free DOFs of ``geometry``'s nodes, factorised
    once by ``engine``; ``geometry`` renumbered to the condensed DOFs."""

    name = "contact"
    condensed = True

    def __init__(self, problem, geometry, engine):
        self.condensation = engine.condensation(problem,
                                                geometry.free_dofs())
        self.K = self.condensation.S
        self.geometry = geometry.compact()
        self.dofs = self.condensation.dofs
        self.linear_solver = engine.linear_solver

    def load(self, f):
        """(g̃, w): the condensed load and w = K⁻¹f."""
        return self.condensation.load(f)

    def restrict(self, u):
        """u on the condensed DOFs."""
        return np.asarray(u, float)[self.dofs]

    def displacement(self, x, w):
        """u from the condensed unknowns x and w = K⁻¹f (one
        back-substitution; x, w may hold several columns)."""
        return self.condensation.displacement(x, w)

    def jacobian(self, system):
        """The system's own Jacobian (dense, LAPACK)."""
        return system.jacobian

    def free_start(self, system, w):
        """The free start: no contact force, u = K⁻¹f on the condensed
        DOFs."""
        return self.restrict(w)


def reduction(problem, geometry, engine, condensed, friction=None):
    """:class:`CondensedSystem` if ``condensed``, else :class:`FullSystem`;
    for a body with rigid-body modes :class:`~.floating.FloatingSystem`,
    or :class:`~.floating_full.FloatingFullSystem` on the full system
    (``friction``: the run's coefficient f_c, None if frictionless)."""
    if problem.floating:
        if condensed:
            from .floating import FloatingSystem

            return FloatingSystem(problem, geometry, engine, friction)
        from .floating_full import FloatingFullSystem

        return FloatingFullSystem(problem, geometry, engine, friction)
    return (CondensedSystem if condensed else FullSystem)(problem, geometry,
                                                          engine)


def condense_onto_contact(problem, geometry, backend="auto"):
    """(condensation, geometry renumbered to the condensed DOFs) of K onto
    the free DOFs of ``geometry``'s nodes with the serial engine's
    ``backend`` (:class:`CondensedSystem`)."""
    from ..engine import SerialEngine

    space = CondensedSystem(problem, geometry, SerialEngine(backend))
    return space.condensation, space.geometry
