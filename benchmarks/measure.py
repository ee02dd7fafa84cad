"""One measurement of the benchmark, run in a fresh process by ``run.py``.

Usage::

    python benchmarks/measure.py PROBLEM.npz STAGE [BACKEND] [STEPS
                                 [COULOMB [METHOD]]]

Loads the problem (not timed), loads the backend's library (not timed:
``get_backend`` opens MKL or kvxopt before the clock starts in every stage
alike), runs the stage, and prints one JSON line: ``time`` (the stage
alone, wall clock), what the stage reports, and ``peak_rss_mb``, this
process's peak resident memory (``ru_maxrss``; it includes the loaded
problem, which every stage holds). Stages:

* ``floor``: factorise K and solve K u = f once, nothing else: SuperLU
  and CHOLMOD with our nested dissection order (the ordering timed; the
  order their contact solves use, less the contact DOFs last; CHOLMOD's
  own choice, ``nmethods = 0``, took 4.8 s against 1 + 2.9 s at 4.8·10⁵
  DOFs), PARDISO with its own METIS order; no pivot check;
* ``schur``: gap geometry (not timed), then the condensation of K onto Γc
  alone (:func:`solver.contact.strategies.reduction.condense_onto_contact`:
  the factorisation with the contact DOFs last and the dense S);
* ``min``, ``fb``: ``solve(problem, method=..., backend=...)``
  with every other argument at its default (geometry, condensation,
  nested start, Newton, back-substitution, verification all timed); the
  solution is saved next to the problem for the peers to compare with;
* ``friction``: ``solve(problem, friction=0.3, ...)``, STEPS load steps,
  projection formulation, φ_min and the lagged bound unless COULOMB
  ("lagged", "implicit") and METHOD ("min", "fb") say otherwise;
  ``friction_read``: the same, then reading ``result.displacement`` (every
  step's field in all unknowns, recovered on first read) inside the clock;
* ``friction3d``: the ``friction`` stage (φ_min, lagged) with NEWTON
  ("reduced", the default path, or "whole": the LU of the whole Newton
  system, ``solver.contact.friction.disc.REDUCED`` off) in place of
  COULOMB; u saved next to the problem (``PROBLEM.friction.NEWTON.npy``)
  and, if the other's is there, ``agreement`` = max|u − u_other|/max|u|;
  ``J_steps`` the Jacobians of every load step, ``load_average`` the
  machine's 1-minute load average at the end;
* ``amg``: ``solve(problem, backend="amg")`` (the iterative path, issue
  33): Newton systems, CG iterations in all and per system, the AMG
  hierarchy; ``agreement`` is ‖u − u_direct‖₂/‖u_direct‖₂ against the
  ``min`` stage's saved solution of BACKEND (3rd argument), if there;
  ``hertz``: on a Hertz sphere (``meta`` has R), its a and p0 against
  Hertz's (``solver.studies3d.hertz_sphere_row``);
* ``amg_friction``: ``solve(problem, friction=0.3, steps=STEPS,
  backend="amg")`` (lagged bound, the active set method of
  ``solver.contact.friction.active_set``): Newton systems and CG
  iterations per step, stick and slip counts; u saved
  (``PROBLEM.friction.amg.npy``) and, if the ``friction3d`` stage's
  ``reduced`` answer is there, ``agreement`` = ‖u − u_direct‖₂/‖u_direct‖₂;
* ``amg_floor``: build the AMG hierarchy of K and solve K u = f once by
  AMG-preconditioned CG to 1e-8 (relative): the iterative path's floor;
* ``clarabel``, ``sfepy``: the peers of ``peers.py`` on the same K, f and
  gaps; ``agreement`` is their max-norm distance to our φ_min solution
  (relative).

Only the public front solves (``solver.solve``, ``solver.contact_geometry``);
the ``floor`` and ``schur`` stages measure what lies below it on purpose
(a backend's factorisation, the condensation alone), so they import
``solver.linalg`` and ``solver.contact.strategies.reduction``.
"""

import json
import os
import resource
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(1, str(Path(__file__).resolve().parent.parent))

from solver import contact_geometry, load_problem, solve  # noqa: E402
from solver.linalg import dof_ordering, get_backend, resolve  # noqa: E402


class Clock:
    """Wall and CPU time (all threads) of a ``with`` block, as a dict."""

    def __enter__(self):
        self.wall, self.cpu = time.perf_counter(), time.process_time()
        return self

    def __exit__(self, *exc):
        self.times = {"time": time.perf_counter() - self.wall,
                      "cpu": time.process_time() - self.cpu}


def floor(problem, backend):
    module = get_backend(backend)
    with Clock() as clock:
        order = dof_ordering(problem) if module.USES_ORDER else None
        factor = module.factorize(problem.K, order, None, "K", False)
        factor.solve(problem.f)
    return {**clock.times, "nnz": factor.nnz}


def schur(problem, backend):
    from solver.contact.strategies.reduction import condense_onto_contact
    geometry = contact_geometry(problem, "obstacle")
    get_backend(backend)
    with Clock() as clock:
        condensation, _ = condense_onto_contact(problem, geometry, backend)
    return {**clock.times, "m": int(condensation.S.shape[0])}


def frictionless(problem, method, backend, path):
    get_backend(backend)
    with Clock() as clock:
        r = solve(problem, method=method, backend=backend)
    np.save(f"{path}.{method}.{backend}.npy", r.u)
    return {**clock.times, "J": r.njev, "F": r.nfev,
            "converged": bool(r.success), "contact": r.n_contact,
            "levels": len(r.levels),
            "J_finest": r.levels[-1]["njev"] if r.levels else r.njev,
            "backend": r.linear_solver,
            "candidates": (r.get("candidates") or {}).get("n_candidates")}


def friction(problem, backend, steps, coulomb="lagged", method="min",
             read=False):
    get_backend(backend)
    with Clock() as clock:
        r = solve(problem, friction=0.3, steps=steps,
                  formulation="projection", method=method, coulomb=coulomb,
                  backend=backend)
        if read:  # every step's displacement in all unknowns, timed too
            r.displacement
    screening = r.get("candidates") or {}
    return {**clock.times, "J": r.njev, "F": r.nfev,
            "converged": bool(r.success),
            "contact": r.records[-1]["n_contact"] if r.records else None,
            "candidates": screening.get("n_candidates"),
            "enlarged": screening.get("enlarged"), "message": r.message}


def friction3d(problem, backend, steps, newton, path, coulomb="lagged"):
    from solver.contact.friction import disc

    disc.REDUCED = newton == "reduced"
    get_backend(resolve(backend))
    with Clock() as clock:
        r = solve(problem, friction=0.3, steps=steps, backend=backend,
                  coulomb=coulomb)
    tag = "" if coulomb == "lagged" else f".{coulomb}"
    np.save(f"{path}.friction{tag}.{newton}.npy", r.u)
    other = Path(f"{path}.friction{tag}."
                 f"{'whole' if newton == 'reduced' else 'reduced'}.npy")
    out = {**clock.times, "J": r.njev, "F": r.nfev,
           "converged": bool(r.success),
           "verified": bool(r.verification["passed"]),
           "contact": r.records[-1]["n_contact"] if r.records else None,
           "J_max": max((x["njev"] for x in r.records), default=0),
           "J_steps": [int(x["njev"]) for x in r.records],
           "load_average": os.getloadavg()[0],
           "candidates": (r.get("candidates") or {}).get("n_candidates"),
           "backend": r.linear_solver}
    if other.exists():
        u = np.load(other)
        out["agreement"] = float(np.abs(r.u - u).max() / np.abs(u).max())
    return out


def iterative(problem, path, reference):
    with Clock() as clock:
        r = solve(problem, backend="amg")
    np.save(f"{path}.min.amg.npy", r.u)
    krylov = r.history["krylov"]
    out = {**clock.times, "J": r.njev, "krylov": r.krylov,
           "krylov_max": max(krylov), "krylov_mean": r.krylov / len(krylov),
           "krylov_per_system": krylov, "active": r.history["active"],
           "krylov_decades": r.history.get("krylov_decades"),
           "setup_per_system": r.history.get("setup"),
           "converged": bool(r.success),
           "verified": bool(r.verification["passed"]),
           "contact": r.n_contact, "amg": r.engine,
           "reason": r.get("linear_solver_reason")}
    if "R" in (problem.meta or {}):  # a Hertz sphere: a and p0 against Hertz
        from solver.studies3d import hertz_sphere_row

        out["hertz"] = hertz_sphere_row(problem, r)
    if Path(reference).exists():
        direct = np.load(reference)
        out["agreement"] = float(np.linalg.norm(r.u - direct)
                                 / np.linalg.norm(direct))
    return out


def iterative_friction(problem, steps, path, coulomb="lagged"):
    with Clock() as clock:
        r = solve(problem, friction=0.3, steps=steps, backend="amg",
                  coulomb=coulomb)
    tag = "" if coulomb == "lagged" else f".{coulomb}"
    np.save(f"{path}.friction{tag}.amg.npy", r.u)
    out = {**clock.times, "J": r.njev, "converged": bool(r.success),
           "verified": bool(r.verification["passed"]),
           "J_steps": [x["njev"] for x in r.records],
           "krylov_steps": [x.get("krylov") for x in r.records],
           "contact": r.records[-1]["n_contact"] if r.records else None,
           "stick": [x["n_stick"] for x in r.records],
           "slip": [x["n_slip"] for x in r.records], "amg": r.engine,
           "message": r.message}
    direct = Path(f"{path}.friction{tag}.reduced.npy")
    if direct.exists():  # the friction3d stage's (factorisation) answer
        u = np.load(direct)
        out["agreement"] = float(np.linalg.norm(r.u - u)
                                 / np.linalg.norm(u))
    return out


def iterative_floor(problem):
    from solver.linalg import amg, threads

    with Clock() as clock, threads.single_blas_thread():
        modes = amg.rigid_body_modes(problem.nodes[problem.dof_map[:, 0]],
                                     problem.dof_map[:, 1])
        multigrid = amg.Multigrid(problem.K, modes)
        out = amg.projected_cg(problem.K, problem.f, multigrid,
                               np.zeros(problem.n_dofs),
                               atol=1e-8 * np.linalg.norm(problem.f))
    return {**clock.times, "krylov": out.iterations,
            "converged": out.converged, "setup": multigrid.setup_time}


def peer(problem, name, reference):
    import peers

    geometry = contact_geometry(problem, "obstacle")
    with Clock() as clock:
        if name == "clarabel":
            u, status = peers.clarabel_qp(problem, geometry)
            out = {"converged": status == "Solved"}
        else:
            u, J, converged = peers.sfepy_semismooth_newton(problem,
                                                            geometry)
            out = {"J": J, "converged": bool(converged)}
    out.update(clock.times)
    ours = np.load(reference)
    out["agreement"] = float(np.abs(u - ours).max() / np.abs(ours).max())
    return out


def main(argv):
    path, stage = argv[0], argv[1]
    backend = argv[2] if len(argv) > 2 else "auto"
    problem = load_problem(path)
    out = {"dofs": problem.n_dofs, "nc": problem.n_contact}
    if stage == "floor":
        out.update(floor(problem, backend))
    elif stage == "schur":
        out.update(schur(problem, backend))
    elif stage in ("min", "fb"):
        out.update(frictionless(problem, stage, backend, path))
    elif stage in ("friction", "friction_read"):
        out.update(friction(problem, backend, int(argv[3]), *argv[4:6],
                            read=stage == "friction_read"))
    elif stage == "friction3d":
        out.update(friction3d(problem, backend, int(argv[3]), argv[4], path,
                              *argv[5:6]))
    elif stage == "amg":
        out.update(iterative(problem, path, f"{path}.min.{backend}.npy"))
    elif stage == "amg_friction":
        out.update(iterative_friction(problem, int(argv[3]), path,
                                      *argv[4:5]))
    elif stage == "amg_floor":
        out.update(iterative_floor(problem))
    elif stage in ("clarabel", "sfepy"):
        out.update(peer(problem, stage, f"{path}.min.{backend}.npy"))
    else:
        raise SystemExit(f"unknown stage {stage!r}")
    out["peak_rss_mb"] = \
        resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
