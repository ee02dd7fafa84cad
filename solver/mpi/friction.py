r"""Coulomb friction (projection formulation, load steps) on the engine.

:func:`solver.contact.solve_friction` unchanged — the project's Newton on
the system condensed onto every DOF of Γc (thesis (110)/(111) in the
projection form) — given, through its ``condensation`` keyword, a
:class:`PetscCondensation`: S, K⁻¹ of each step's load and the
back-substitutions from one distributed MUMPS factorisation in its Schur
mode (:class:`~solver.mpi.factor.PetscFactor`). The thesis's split
formulation runs on the full system only: the engine refuses it.
"""

import numpy as np

from ..contact import contact_geometry
from ..contact import solve_friction as serial_friction
from ..errors import SolverError
from ..linalg.condensation import Condensation
from .engine import engine_summary, service
from .factor import PetscFactor
from .frictionless import check_problem
from .layout import Layout
from .service import EngineError

__all__ = ["solve_friction", "PetscCondensation"]


class PetscCondensation(Condensation):
    """:class:`~solver.linalg.Condensation` of ``problem.K`` onto
    ``dofs`` whose factorisation is a :class:`PetscFactor` (all ranks);
    ``load`` and ``displacement`` are Condensation's own."""

    def __init__(self, svc, layout, problem, dofs):  # noqa: D107
        dofs = np.asarray(dofs, np.int64).ravel()
        super().__init__(problem, dofs, "petsc-mumps",
                         PetscFactor(svc, layout, problem.K, dofs))


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
    made = PetscCondensation(svc, layout, problem, geometry.free_dofs())
    result = serial_friction(problem, friction, formulation=formulation,
                             gap=gap, geometry=geometry, condense=True,
                             condensation=made, **options)
    if made.n_solves == 0:  # solve_friction made its own: a bug here
        raise EngineError("the PETSc condensation was not used")
    result["linear_solver"] = "petsc-mumps"
    rows = layout.red_to_pad[geometry.free_dofs()]
    result["engine"] = engine_summary(svc, layout, dict(
        system="condensed", ksp="mumps", schur="mumps",
        solves=made.n_solves, owned=dict(contact_dofs_owned=rows)))
    return result
