r"""Frictionless contact (67) on the PETSc engine.

``system="condensed"`` (default): the method of
:mod:`solver.contact.candidates` with the linear algebra distributed. K is
rotated into the node frames on rank 0 (K̂ = RKRᵀ, f̂ = Rf, sparse),
factorised once by MUMPS on all ranks (:class:`~solver.mpi.factor.PetscFactor`),
its Schur complement S on the candidates' normal rows formed by blocked
many-right-hand-side solves, the NCP S u_n = g̃ + λ ⟂ s − u_n ≥ 0 solved on
rank 0 by the project's φ_min / φ_FB Newton (:func:`solver.ncp.solve_ncp`
on :class:`~solver.contact.frictionless.FrictionlessSystem` of the normal
line), and u = Rᵀ(w + K̂⁻¹Pᵀ S(u_n − w_c)) by one distributed solve. The
same screening rounds as the serial solver (enlarged candidates cost a new
S, not a new factorisation); the iterates are those of
``solver.solve_frictionless(problem, candidates=True, start="free")``.

``system="full"``: the thesis's system in all unknowns from u = 0 (c = 1),
each Newton system solved by KSP (:mod:`solver.mpi.full`): the iterates of
``solver.solve_frictionless(problem, condense=False)``.
"""

import time

import numpy as np

from ..contact.candidates import (MAX_ROUNDS, enlarge_candidates,
                                  initial_candidates, normal_line)
from ..contact.frictionless import (STOPPING_TEST, FrictionlessSystem,
                                    _nodal_arrays)
from ..contact.geometry import contact_geometry, contact_stiffness, rotation
from ..contact.result import ContactResult
from ..contact.verify import (describe_failure, force_scale,
                              unit_free_options, verification_tolerance,
                              verify_contact)
from ..errors import SolverError
from ..ncp import MESSAGES, solve_ncp, stable_norm
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
    Newton solves) and ``schur_block`` (right-hand sides per KSPMatSolve;
    1 = column by column). Returns the serial solver's result with
    ``engine`` (ranks, per-rank counts and timings) added."""
    check_problem(problem)
    if system not in SYSTEMS or ksp not in KSPS:
        raise SolverError(f"system must be one of {SYSTEMS} and ksp one of "
                          f"{KSPS}, got {system!r}, {ksp!r}")
    clock = time.perf_counter()
    svc = service()
    if geometry is None:
        geometry = contact_geometry(problem, gap)
    geometry_time = time.perf_counter() - clock
    load_norm = stable_norm(problem.f)
    stiffness = contact_stiffness(problem.K, geometry)
    layout = Layout(problem, svc.size)
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
        extra = dict(schur_block=int(schur_block))
    result.stopping["test"] = STOPPING_TEST
    result.x = u
    verification = verify_contact(
        problem.K, problem.f, u, geometry.node_dofs, geometry.normal,
        geometry.gap, lam, stiffness, verification_tolerance(tol))
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


def _on_candidates(svc, layout, problem, geometry, method, tol, max_iter,
                   gap_scale, stiffness, options, load_norm, margin, block):
    """The screening rounds of :func:`solver.contact.candidates.
    solve_on_candidates` on one PETSc factorisation of K̂."""
    R = rotation(problem.n_dofs, geometry)[0]
    K_hat = (R @ problem.K @ R.T).tocsr()
    K_hat = 0.5 * (K_hat + K_hat.T)
    normal = geometry.dofs[:, -1]
    nodes, delta = initial_candidates(geometry.gap, margin)
    clock = time.perf_counter()
    factor = PetscFactor(svc, layout, K_hat, normal[nodes], block=block)
    w = factor.solve(R @ problem.f)
    tol_v = verification_tolerance(tol)
    rounds, history, budget, start_un = [], {}, max_iter, None
    totals = dict(nit=0, njev=0, nfev=0)
    exhausted = False
    for k in range(MAX_ROUNDS):
        S = factor.S if k == 0 else factor.schur(normal[nodes], block)
        factorize_time = time.perf_counter() - clock
        c = normal[nodes]
        system = FrictionlessSystem(S, S @ w[c], normal_line(geometry, nodes),
                                    gap_scale, stiffness, load_norm)
        start = w[c] if start_un is None else start_un[nodes]
        result = solve_ncp(system.residual, system.jacobian, start,
                           method=method, tol=tol, max_iter=budget,
                           options=options, error=system.error,
                           scale=system.scale)
        budget -= result.nit
        for key in totals:
            totals[key] += result[key]
        for key, values in result.history.items():
            history.setdefault(key, []).extend(values)
        history.setdefault("round", []).extend([k] * result.nit)
        lam = np.zeros(len(geometry.gap))
        lam[nodes] = system.contact_force(result.x)
        u_hat = w + factor.back_substitute(None, result.x - w[c])
        un = u_hat[normal]
        length = tol_v * force_scale(load_norm, lam) / stiffness
        grown = enlarge_candidates(nodes, geometry.gap - un, length)
        outside = np.setdiff1d(np.arange(len(lam)), nodes)
        rounds.append(dict(
            n_candidates=len(nodes), nit=result.nit, njev=result.njev,
            nfev=result.nfev, success=bool(result.success),
            penetrating=int(np.count_nonzero(
                geometry.gap[outside] - un[outside] < -length)),
            factorize_time=factorize_time,
            time=time.perf_counter() - clock))
        clock = time.perf_counter()
        if grown is None or not result.success:
            break
        if k == MAX_ROUNDS - 1:
            exhausted = True
            break
        nodes, start_un = grown, un
    result.update(totals, history=history, levels=[])
    screening = dict(margin=delta, rounds=rounds, n_candidates=len(nodes),
                     enlarged=len(rounds) - 1, exhausted=exhausted,
                     nodes=nodes)
    return result, R.T @ u_hat, lam, un, screening
