r"""Coulomb friction (projection formulation, load steps) on the engine.

:func:`solver.contact.solve_friction` unchanged — the project's Newton on
the system condensed onto every DOF of Γc — with its condensation
(:class:`solver.linalg.Condensation`: S, K⁻¹ of each step's load, the
back-substitutions) computed by one distributed MUMPS factorisation
(:class:`~solver.mpi.factor.PetscFactor`). ``solve_friction`` takes no
condensation argument; it gets one from :meth:`Condensation.of`, whose
per-K cache this module fills for the duration of the call (and empties
after). A ``condensation=`` keyword of ``solve_friction`` would replace
that (the one thing missing from its interface). The thesis's split
formulation runs on the full system only: the engine refuses it.
"""

import numpy as np

from ..contact import contact_geometry
from ..contact import solve_friction as serial_friction
from ..errors import SolverError
from ..linalg import condensation as cache
from ..linalg.condensation import Condensation
from .engine import engine_summary, service
from .factor import PetscFactor
from .frictionless import check_problem
from .layout import Layout
from .service import EngineError

__all__ = ["solve_friction", "petsc_condensation"]

#: The serial backend name the seeded condensation answers to.
_SEED_BACKEND = "superlu"


def petsc_condensation(svc, layout, problem, dofs):
    """A :class:`Condensation` of ``problem.K`` onto ``dofs`` whose
    factorisation is a :class:`PetscFactor` (all ranks)."""
    made = Condensation.__new__(Condensation)
    made.dofs = np.asarray(dofs, np.int64).ravel()
    made.backend = _SEED_BACKEND
    made.factorization = PetscFactor(svc, layout, problem.K, made.dofs)
    made.S = made.factorization.S
    made._solved, made.n_solves = [], 0
    return made


def solve_friction(problem, friction, formulation="projection",
                   gap="obstacle", geometry=None, **options):
    """:func:`solver.contact.solve_friction` on all ranks (call on rank 0
    inside :func:`~solver.mpi.engine.spmd`); same arguments and result,
    plus ``engine``. Only the condensed projection formulation."""
    check_problem(problem)
    if formulation != "projection" or options.get("condense") is False:
        raise SolverError("friction on the petsc engine needs the condensed "
                          "projection formulation (--formulation projection)")
    options.pop("backend", None)
    svc = service()
    if geometry is None:
        geometry = contact_geometry(problem, gap, rollers=False)
    layout = Layout(problem, svc.size)
    svc.call("layout", layout.ranges())
    made = petsc_condensation(svc, layout, problem, geometry.free_dofs())
    key, saved = id(problem.K), cache._MADE.get(id(problem.K))
    cache._MADE[key] = made
    try:
        result = serial_friction(problem, friction, formulation=formulation,
                                 gap=gap, geometry=geometry, condense=True,
                                 backend=_SEED_BACKEND, **options)
    finally:
        if saved is None:
            cache._MADE.pop(key, None)
        else:
            cache._MADE[key] = saved
    if made.n_solves == 0:  # solve_friction made its own: a bug here
        raise EngineError("the PETSc condensation was not used")
    result["linear_solver"] = "petsc-mumps"
    rows = layout.red_to_pad[geometry.free_dofs()]
    result["engine"] = engine_summary(svc, layout, dict(
        system="condensed", ksp="mumps", solves=made.n_solves,
        owned=dict(contact_dofs_owned=rows)))
    return result
