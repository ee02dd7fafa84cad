r"""PETSc's own SNESVI on the rotated bound-constrained form: a cross-check.

In the node frames (K̂ = RKRᵀ, f̂ = Rf, v = Ru) the frictionless problem
(67) is the box-constrained variational inequality

.. math:: F(v) = K̂v − f̂, \quad v_{n_i} \le s_i \text{ (normal rows of
          the free contact nodes), other rows free.}

``vinewtonrsls`` (reduced-space active set Newton, Benson & Munson 2006)
solves it with MUMPS LU on each reduced Jacobian: an independent solver,
but one that refactorises every iteration. Stopping: ‖F‖ ≤ rtol·‖f̂‖;
full Newton steps (the VI is linear). ``vinewtonssls`` rescales the
Jacobian in place: it gets its own copy of K̂."""

import numpy as np

from ..contact.geometry import contact_geometry, rotate_stiffness, rotation
from .layout import Layout, gather_vector, scatter_matrix, scatter_vector
from .service import EngineError, Service, command

__all__ = ["solve_snesvi", "LINE_SEARCH"]

#: SNES line search of the VI solve (module docstring).
LINE_SEARCH = "basic"


def solve_snesvi(problem, gap="obstacle", geometry=None, rtol=1e-12,
                 kind="vinewtonrsls"):
    """(u, iterations) of SNESVI (call on rank 0 inside
    :func:`~solver.mpi.engine.spmd`); u is the reduced displacement."""
    if problem.kind != "mesh":
        raise EngineError("SNESVI partitions a mesh by nodes")
    svc = Service.current
    if svc is None:
        raise EngineError("the petsc engine is not running: call "
                          "solve_snesvi inside solver.mpi.engine.spmd")
    geometry = geometry or contact_geometry(problem, gap)
    layout = Layout(problem, svc.size)
    svc.call("layout", layout.ranges())
    R = rotation(problem.n_dofs, geometry)[0]
    K_hat = rotate_stiffness(problem.K, R, geometry.free_dofs())
    upper = np.full(layout.n, np.inf)
    upper[layout.red_to_pad[geometry.dofs[:, -1]]] = geometry.gap
    v, its = svc.call("snesvi", dict(bsize=layout.dim, rtol=rtol,
                                     kind=kind),
                      (layout.matrix(K_hat), layout.pad(R @ problem.f),
                       upper))
    return R.T @ layout.unpad(v), its


@command("snesvi")
def _snesvi(service, payload, local):
    from petsc4py import PETSc

    A_pad, f_pad, upper = local if service.root else (None, None, None)
    A = scatter_matrix(service, A_pad, payload["bsize"])
    J = A.duplicate(copy=True)
    f, x = A.createVecs()
    scatter_vector(service, f_pad, f)
    xl, xu = f.duplicate(), f.duplicate()
    xl.set(PETSc.NINFINITY)
    if upper is not None:
        upper = np.where(np.isfinite(upper), upper, PETSc.INFINITY)
    scatter_vector(service, upper, xu)

    def residual(snes, v, F):
        A.mult(v, F)
        F.axpy(-1.0, f)

    def jacobian(snes, v, Jm, P):
        A.copy(Jm, structure=PETSc.Mat.Structure.SAME_NONZERO_PATTERN)

    snes = PETSc.SNES().create(comm=A.getComm())
    snes.setType(payload["kind"])
    snes.setFunction(residual, f.duplicate())
    snes.setJacobian(jacobian, J, J)
    snes.setVariableBounds(xl, xu)
    snes.setTolerances(rtol=payload["rtol"], atol=payload["rtol"] *
                       f.norm(), stol=0.0, max_it=100)
    PETSc.Options().setValue("vi_snes_linesearch_type", LINE_SEARCH)
    ksp = snes.getKSP()
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    ksp.getPC().setFactorSolverType("mumps")
    snes.setOptionsPrefix("vi_")
    snes.setFromOptions()
    x.set(0.0)
    snes.solve(None, x)
    if snes.getConvergedReason() <= 0:
        raise EngineError(f"SNESVI did not converge (reason "
                          f"{snes.getConvergedReason()})")
    return gather_vector(service, x), snes.getIterationNumber()
