r"""Frictionless contact (67) on the PETSc engine.

``system="condensed"`` (default): the method of
:mod:`solver.contact.strategies.candidates` with the linear algebra distributed. K is
rotated into the node frames on rank 0 (K̂ = RKRᵀ, f̂ = Rf, sparse),
factorised once by MUMPS on all ranks (:class:`~solver.mpi.factor.PetscFactor`),
its Schur complement S on the candidates' normal rows by MUMPS's Schur
mode (:mod:`~solver.mpi.schur`), the NCP S u_n = g̃ + λ ⟂ s − u_n ≥ 0 solved on
rank 0 by the project's φ_min / φ_FB Newton (:func:`solver.ncp.solve_ncp`
on :class:`~solver.contact.frictionless.driver.FrictionlessSystem` of the normal
line), and u = Rᵀ(w + K̂⁻¹Pᵀ S(u_n − w_c)) by one distributed solve. The
screening rounds are the serial solver's own loop
(:func:`~solver.contact.strategies.candidates.solve_on_candidates`, on
:class:`PetscNormalCondensation`); the iterates are those of
``solver.solve_frictionless(problem, candidates=True, start="free")``.

``system="full"``: the thesis's system in all unknowns from u = 0 (c = 1),
each Newton system solved by KSP (:mod:`solver.mpi.full`): the iterates of
``solver.solve_frictionless(problem, condense=False)``.
"""

import time

import numpy as np

from ..contact.strategies.candidates import solve_on_candidates
from ..contact.frictionless.driver import STOPPING_TEST, _nodal_arrays
from ..contact.geometry import (contact_geometry, contact_stiffness,
                                rotate_stiffness, rotation)
from ..contact.result import ContactResult
from ..contact.verify import (describe_failure, unit_free_options,
                              verification_tolerance, verify_contact)
from ..errors import SolverError
from ..ncp import MESSAGES, stable_norm
from .engine import engine_summary, service
from .factor import SCHUR_BLOCK, PetscFactor
from .layout import Layout

__all__ = ["solve_frictionless", "KSPS", "SYSTEMS"]

KSPS = ("mumps", "gamg")
SYSTEMS = ("condensed", "full")


def check_problem(problem):
    if problem.kind != "mesh":
        raise SolverError("the petsc engine partitions a mesh by nodes: a "
                          "discrete problem (no mesh) runs on the serial "
                          "engine")


def solve_frictionless(problem, method="min", gap="obstacle", tol=1e-10,
                       max_iter=100, gap_scale=None, options=None,
                       geometry=None, system="condensed", ksp="mumps",
                       margin=None, schur_block=SCHUR_BLOCK):
    """Solve (67) on all ranks (call on rank 0 inside
    :func:`solver.mpi.engine.spmd`). Arguments as
    :func:`solver.contact.solve_frictionless`, plus ``system``
    ({"condensed", "full"}), ``ksp`` ({"mumps", "gamg"}: the full system's
    Newton solves) and ``schur_block`` (None: MUMPS's Schur mode, the
    default; k: S from the columns of K̂⁻¹, k right-hand sides per
    MatMatSolve, :mod:`~solver.mpi.factor`). Returns the serial solver's result with
    ``engine`` (ranks, per-rank counts and timings) added."""
    check_problem(problem)
    if system not in SYSTEMS or ksp not in KSPS:
        raise SolverError(f"system must be one of {SYSTEMS} and ksp one of "
                          f"{KSPS}, got {system!r}, {ksp!r}")
    clock = time.perf_counter()
    svc = service()
    svc.mark("start")
    if geometry is None:
        geometry = contact_geometry(problem, gap)
    geometry_time = time.perf_counter() - clock
    load_norm = stable_norm(problem.f)
    stiffness = contact_stiffness(problem.K, geometry)
    layout = Layout(problem, svc.size)
    svc.mark("geometry")
    svc.call("layout", layout.ranges())
    normal_rows = layout.red_to_pad[geometry.dofs[:, -1]]
    if system == "full":
        from .full import solve_full

        result, u, lam, un, extra = solve_full(
            svc, layout, problem, geometry, method, tol, max_iter,
            1.0 if gap_scale is None else gap_scale, stiffness, options,
            load_norm, ksp)
        screening, gap_scale = None, 1.0 if gap_scale is None else gap_scale
    else:
        gap_scale = stiffness if gap_scale is None else gap_scale
        options = unit_free_options(method, options, load_norm, stiffness,
                                    geometry.gap)
        result, u, lam, un, screening = _on_candidates(
            svc, layout, problem, geometry, method, tol, max_iter, gap_scale,
            stiffness, options, load_norm, margin, schur_block)
        extra = dict(schur="mumps" if schur_block is None else "solves",
                     schur_block=schur_block, factorizations=screening.pop(
                         "factorizations"))
    result.stopping["test"] = STOPPING_TEST
    result.x = u
    verification = verify_contact(
        problem.K, problem.f, u, geometry.node_dofs, geometry.normal,
        geometry.gap, lam, stiffness, verification_tolerance(tol))
    svc.mark("verify")
    if result.success and not verification["passed"]:
        result.update(success=False, status=6, message=(
            f"{MESSAGES[6]}: {describe_failure(verification)}"))
    result.update(_nodal_arrays(problem, geometry, u, lam, un, load_norm))
    owned = dict(contact_nodes_owned=normal_rows)
    if screening:
        owned["candidates_owned"] = normal_rows[screening.pop("nodes")]
    result.update(
        gap_mode=geometry.mode, gap_scale=float(gap_scale),
        geometry_time=geometry_time, condensed=system == "condensed",
        condensation=("normal candidates" if system == "condensed"
                      else "none"),
        candidates=screening, start="free" if system == "condensed"
        else "zero", linear_solver="petsc-mumps" if system == "condensed"
        else f"petsc-{ksp}", verification=verification,
        time=time.perf_counter() - clock)
    result["engine"] = engine_summary(svc, layout, dict(
        system=system, ksp=ksp if system == "full" else "mumps",
        owned=owned, **extra))
    return ContactResult(result)


class PetscNormalCondensation:
    """:class:`solver.contact.strategies.candidates.NormalCondensation`'s interface
    (``R``, ``normal_rows``, ``factorize(nodes)``, ``displacement(u_n)``)
    on one distributed MUMPS factor (:class:`PetscFactor`), so that the
    serial screening rounds (:func:`~solver.contact.strategies.candidates.
    solve_on_candidates`) run unchanged. K̂ = RKRᵀ is built and scattered
    once (:meth:`rotated`); each
    round's candidate set is a new Schur-mode factorisation (``block``
    None) or only new solves (``block`` = k)."""

    def __init__(self, svc, layout, problem, geometry, block=SCHUR_BLOCK):
        self.svc, self.layout, self.block = svc, layout, block
        self.R = rotation(problem.n_dofs, geometry)[0]
        self.problem = problem
        self.f = self.R @ problem.f
        self.normal_rows = geometry.dofs[:, -1]
        self.free_dofs = geometry.free_dofs()
        self.factor, self.nodes = None, None

    def rotated(self):
        """K̂ = RKRᵀ (:func:`~solver.contact.geometry.rotate_stiffness`;
        built when scattered: rank 0 holds it only while padding, not
        under MUMPS's factor)."""
        K = rotate_stiffness(self.problem.K, self.R, self.free_dofs)
        self.svc.mark("rotate")
        return K

    def factorize(self, nodes):
        """(S, g̃, w_c) on the normal rows c of ``nodes``, w = K̂⁻¹f̂: g̃ from
        one interior solve of the Schur-mode factor and w_c = S⁻¹g̃ (w
        itself is never formed: :meth:`displacement` back-substitutes with
        f̂, one interior solve, where u = w + K̂⁻¹Pᵀ S(u_n − w_c) took two
        more)."""
        self.nodes = np.asarray(nodes, np.int64)
        c = self.normal_rows[self.nodes]
        if self.factor is None:
            self.factor = PetscFactor(self.svc, self.layout, self.rotated,
                                      c, block=self.block)
        else:
            self.factor.schur(c)
        S = self.factor.S
        if not len(c):
            self.w = self.factor.solve(self.f)
            return S, np.zeros(0), np.zeros(0)
        g = self.factor.condensed_rhs(self.f)
        return S, g, self.factor.solve_schur(g)

    def displacement(self, u_n):
        """(u, u_n at every free contact node): one back-substitution."""
        c = self.normal_rows[self.nodes]
        u_hat = self.w if not len(c) else self.factor.back_substitute(
            self.f, np.asarray(u_n, float))
        return self.R.T @ u_hat, u_hat[self.normal_rows]


def _on_candidates(svc, layout, problem, geometry, method, tol, max_iter,
                   gap_scale, stiffness, options, load_norm, margin, block):
    """:func:`solver.contact.strategies.candidates.solve_on_candidates` on a
    :class:`PetscNormalCondensation`."""
    condensation = PetscNormalCondensation(svc, layout, problem, geometry,
                                           block)
    result, u, lam, un, screening = solve_on_candidates(
        problem, geometry, method, tol, max_iter, None, gap_scale,
        stiffness, options, load_norm, None, margin, condensation)
    screening["nodes"] = condensation.nodes
    screening["factorizations"] = condensation.factor.factorizations
    return result, u, lam, un, screening
