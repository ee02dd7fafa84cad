r"""Coulomb friction on the full system by Krylov under ``mpiexec``
(``mpiexec -n N python -m solver DIR --engine petsc --system full --ksp
gamg|hypre --friction F``): the primal–dual active set method of the
in-process AMG path (:mod:`solver.contact.friction.active_set`; Hüeber,
Stadler & Wohlmuth, SISC 30, 2008), lagged bound b = f_c p_{κ−1}, the
projection formulation, run on every rank at once on its own rows; no
rank holds all of K, f or Γc.

Each rank reads its rows of K and f and the contact nodes of its node
range and forms its block of R and K̂ = R K Rᵀ (``PtAP``) as the
frictionless full system (:mod:`.partitioned_full`), whose Newton KSP
(CG + GAMG with the rotated rigid modes as near-null space, or hypre's
BoomerAMG) solves every Newton system here too. Step κ loads κ/κc · f
and starts from u_{κ−1}. The step's system is the serial
:class:`~solver.contact.friction.active_set.LaggedProjection` on the
rank's rows (:class:`RankProjection`, either bound): its residual,
Coulomb rows and stopping measure are the serial code's, K u is PETSc's distributed
product and every norm of the stopping test is summed over the ranks
(:attr:`~solver.contact.friction.system.FrictionSystem.reduction`). The
sets are decided node by node by the serial code
(:class:`~solver.contact.friction.active_set.SlipRule`,
:func:`~solver.contact.friction.active_set.slip_loads`,
:func:`~solver.contact.friction.active_set.slip_springs`,
:func:`~solver.contact.friction.active_set.constrained_rows`): a node's
frame, its normal and tangent rows and its slip spring live on the rank
that owns the node, so each rank decides its nodes and only the stopping
test is reduced. Each Newton system is the eliminated SPD one of the
serial path's ``K_hat`` branch: K̂ plus the 3D slip springs (a 2 × 2 block
per slip node, inside K̂'s pattern), the active normal and stick tangent
rows of y = R u fixed symmetrically (``MatZeroRowsColumns``), solved by
:func:`~.full.solve_newton_system` for the correction from the iterate,
inexactly: to η_k·err_k/w (w the contact rows' weight in the stopping
measure) with the in-process path's forcing term (:class:`~.full.
ForcingTerm`, Eisenstat & Walker's choice 2 and its safeguards), as the
serial AMG path (:mod:`solver.contact.friction.active_set`), and once
the sets repeat to the relative 10⁻¹² as before. Warm starts as there: a
step from u_{κ−1}, each system from the iterate moved onto its
constraints (the correction 0 but at the fixed rows; the last step's
increment as the first system's start took more CG iterations,
benchmarks/README.md). The Newton path may differ from the serial one,
the answer of each step does not (the same stopping test).

Every converged step is verified on every node of every rank
(:func:`~.partitioned_full.verify_on_ranks`, the Coulomb bound
included) and written as the condensed friction path writes it
(``steps/step_KKKK-RANK.vtu`` and ``.pvtu``, ``result.pvd``, the step
fields in ``contact.npz``, the records in ``summary.json``).

The implicit bound (``coulomb="implicit"``) is the serial path's
nonsymmetric Newton system: the radii of the sets are
:func:`~solver.contact.friction.active_set.implicit_radius` at the
iterate, the slip nodes carry no load but the rows N of
:func:`~solver.contact.friction.active_set.bound_rows` (f_c ŵ times the
node's normal row in its tangent rows), so the matrix is K̂ + S + N K̂.
A node's normal row is owned by the rank that owns the node, so each
rank's rows of N K̂ are its N times its own rows of K̂
(:func:`_coupling`); :func:`~.full.solve_newton_system` eliminates the
fixed rows and columns from it and from its symmetric part alike and
solves by right-preconditioned GMRES with the preconditioner built on
the symmetric part, as the serial
:func:`~solver.linalg.amg.projected_gmres` with the V-cycle of K̂ + S.

The ``.npz`` under ``mpiexec`` runs here too, converted on the fly into
a temporary folder (:mod:`.on_the_fly`)."""

import os
import time
from types import SimpleNamespace

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from ..contact.friction.active_set import (LaggedProjection, SlipRule,
                                           bound_rows, constrained_rows,
                                           implicit_radius,
                                           iterate_measure, slip_loads,
                                           slip_springs, stopping)
from ..contact.friction.steps import FIELDS, STOPPING_TEST, step_fields
from ..contact.verify import (contact_weight, describe_failure,
                              verification_tolerance, worst_verification)
from ..ncp import MESSAGES
from ..problem.partitioned import load_mass
from .distributed import KEY, PartitionedResult, write_pvtu
from .full import ForcingTerm, ksp_statistics, solve_newton_system
from .partitioned_friction import STEP_FIELDS_SAVED
from .partitioned_full import Reduction, set_up_ranks, verify_on_ranks
from .service import command

__all__ = ["solve_partitioned_krylov_friction", "RankProjection"]

#: The service's key of the friction run's state on every rank.
STATE = "krylov_friction"


class RankProjection(LaggedProjection):
    """The projection formulation of one load step on this rank's rows
    (module docstring): the serial system with an empty local K (nothing
    of it is used), K u by the distributed ``A`` and the norms of the
    stopping test over the ranks (``reduction``). ``A`` is K̂ = R K Rᵀ
    (the folder's setup frees K once K̂ is made), so K u = Rᵀ K̂ R u, R
    orthogonal. Its residual is collective: every rank calls it
    together."""

    def __init__(self, A, f, geometry, lumped, friction, stiffness,
                 reduction, coulomb="lagged"):
        n = len(f)
        self.reduction = reduction
        super().__init__(sp.csr_matrix((n, n)), f, geometry, lumped,
                         friction, coulomb, 1.0, stiffness)
        self.A = A
        self.u_vec, self.Ku_vec = A.createVecRight(), A.createVecLeft()
        # c_t = k̄/mean(D) over all of Γc, as the serial full system's
        total = reduction.sum(np.array([self.lumped.sum(), self.m], float))
        self.c_t = self.stiffness / (total[0] / total[1]) if total[1] \
            else 1.0
        self.lumped_t = np.repeat(self.lumped, self.dim - 1)

    def Ku(self, u):
        """(K u) = Rᵀ K̂ R u on this rank's rows (collective)."""
        self.u_vec.setArray(self.R @ u)
        self.A.mult(self.u_vec, self.Ku_vec)
        return self.R.T @ self.Ku_vec.getArray()

    def _force(self, du):
        """r = R(K u − f_κ), u = u_{κ−1} + Δu, by the distributed product;
        the last one kept when every rank's Δu is unchanged."""
        last = self._last_force
        if self.reduction.all(last is not None
                              and np.array_equal(last[0], du)):
            return last[1]
        r = self.R @ self.Ku(self.u_previous + du) - self._Rf_step
        self._last_force = (np.array(du, float), r)
        return r

    def lambda_plus(self, lam):
        """‖λ⁺‖₂ over the ranks, as :func:`verify_on_ranks` reads it."""
        return self.gathered(np.maximum(lam, 0.0))


def solve_partitioned_krylov_friction(svc, folder, friction, steps=None,
                                      ksp="gamg", tol=1e-10, max_iter=100,
                                      outdir=None, progress=None,
                                      coulomb="lagged"):
    """(rank 0, inside :func:`~solver.mpi.engine.spmd`) Coulomb friction,
    ``coulomb`` bound (lagged or implicit), with coefficient ``friction``
    in ``steps`` load steps
    on the partitioned problem ``folder`` by Krylov (module docstring);
    with ``outdir`` each step's pieces go to ``outdir/steps/`` as it
    completes. Returns a :class:`~.distributed.PartitionedResult`."""
    clock = time.perf_counter()
    steps = 100 if steps is None else int(steps)
    meta = set_up_ranks(svc, folder, ksp)
    dim = int(meta["dim"])
    n_contact = int(meta["n_contact"])
    M = load_mass(folder, n_contact)  # checked by the front
    mass = sla.splu(M.tocsc())  # Γc's: M⁻¹λ of (87)
    load_norm = float(meta["load_norm"])
    svc.call(f"{STATE}_setup", dict(
        folder=os.fspath(folder), n_contact=n_contact, friction=friction,
        stiffness=float(meta["stiffness"]), load_norm=load_norm,
        coulomb=coulomb))
    kept = {key: [] for key in STEP_FIELDS_SAVED}
    records, checks, stoppings, timesteps, files = [], [], [], [], []
    totals = dict(njev=0, nfev=0, nit=0, krylov=0)
    failed, message, contact = None, "all load steps converged", None
    tol_v = verification_tolerance(tol)
    for kappa in range(1, steps + 1):
        out = svc.call(f"{STATE}_step", dict(
            factor=kappa / steps, tol=tol, max_iter=max_iter,
            friction=friction))
        record, fields = out["record"], out["fields"]
        record["step"] = kappa
        records.append(record)
        for key in totals:
            totals[key] += int(record[key])
        if not record["converged"]:
            failed = kappa
            message = (f"load step {kappa} of {steps} did not converge: "
                       f"{record['message']}")
            break
        checks.append(out["verification"])
        stoppings.append(dict(out["stopping"], test=STOPPING_TEST,
                              step=kappa))
        index = fields.pop("index")
        full = np.zeros(n_contact)
        full[index] = fields["contact_force"]
        fields["contact_pressure_consistent"] = mass.solve(full)[index] \
            + 0.0
        fields["load_factor"] = kappa / steps
        for key in STEP_FIELDS_SAVED:
            kept[key].append(fields[key])
        contact = dict(node=fields["node"], gap=fields["gap"],
                       force=fields["contact_force"],
                       in_contact=fields["in_contact"])
        if outdir is not None:
            name = f"step_{kappa:04d}"
            where = os.path.join(outdir, "steps")
            os.makedirs(where, exist_ok=True)
            pieces = svc.call("partitioned_write", dict(
                folder=os.fspath(folder), outdir=where,
                kind=meta["cell_kind"], dim=dim, name=name,
                root_share=1.0), contact)
            path = os.path.join(where, f"{name}.pvtu")
            write_pvtu(path, pieces, bool(meta.get("mortar")))
            files += [os.path.join("steps", os.path.basename(p))
                      for p in pieces + [path]]
            timesteps.append((kappa / steps,
                              os.path.join("steps", f"{name}.pvtu")))
        if progress is not None:
            progress(record)
    verification = worst_verification(checks, tol_v) if checks else dict(
        passed=False, failed=["no step completed"])
    if checks:
        verification["interior_equilibrium"] = max(
            c["interior_equilibrium"] for c in checks)
        verification["reduced_over_ranks"] = True
    if failed is None and not verification["passed"]:
        failed = len(records)
        message = (f"load step {failed} of {steps} fails verification: "
                   f"{describe_failure(verification)}")
    converged = failed is None
    last = records[-1] if records and records[-1]["converged"] else None
    n_done = len(kept["load_factor"])
    stopping = max(stoppings, key=lambda s: s["relative"]) if stoppings \
        else dict(test=STOPPING_TEST, tol=float(tol), scale=np.nan,
                  absolute=np.nan, relative=np.nan, step=None)
    krylov = ksp_statistics(svc, ksp)
    its = krylov["ksp_iterations"]
    if contact is None:  # no step completed: u = 0 in the pieces
        contact = dict(node=np.zeros(0, np.int64), gap=np.zeros(0),
                       force=np.zeros(0), in_contact=np.zeros(0, bool))
    final = dict(contact)
    final.update({f"step_{key}": np.array(values)
                  for key, values in kept.items()})
    summary = dict(
        problem=os.fspath(folder), kind="partitioned",
        status="converged" if converged else "not_converged",
        converged=converged, message=message, friction=float(friction),
        steps=steps, steps_completed=n_done, failed_step=failed,
        formulation="projection", coulomb=coulomb, method="active set",
        nit=totals["nit"], njev=totals["njev"], nfev=totals["nfev"],
        n_dofs=int(meta["n_free"]), n_contact_dofs=out["n_contact_dofs"],
        n_in_contact=int(last["n_contact"]) if last else 0,
        n_stick=int(last["n_stick"]) if last else 0,
        n_slip=int(last["n_slip"]) if last else 0,
        max_contact_force=float(np.max(contact["force"], initial=0.0)),
        records=records, verification=verification, stopping=stopping,
        time=None, files=files)
    stats = svc.call("stats")
    summary["time"] = round(time.perf_counter() - clock, 4)
    summary["engine"] = dict(
        name="petsc", ranks=svc.size, system="full", ksp=ksp,
        input="partitioned", per_rank=stats, n=int(meta["n"]),
        krylov_per_newton=float(np.mean(its)) if its else 0.0, **krylov)
    result = PartitionedResult(summary, svc, folder, meta, final)
    # every piece cut as the rows (equal shares, as the frictionless full
    # system's): with the direct path's ROOT_SHARE rank 1 of 2 wrote 2/3
    # of the cells and fetched u of rank 0's rows for them
    result.write_options = dict(root_share=1.0)
    result.timesteps = timesteps
    return result


@command(f"{STATE}_setup")
def _setup(service, payload, local):
    """Every rank: its contact nodes' lumped D (row sums of Γc's mass
    matrix at them) and the step system on its rows
    (:class:`RankProjection`); u_{κ−1} = 0, p_{κ−1} = 0."""
    obj = service.objects[KEY]
    arrays = obj["arrays"]
    M = load_mass(payload["folder"], payload["n_contact"])
    lumped = np.asarray(M[np.asarray(arrays["index"], np.int64)].sum(
        axis=1)).ravel()
    red = Reduction(service.comm)
    system = RankProjection(service.objects["newton"]["A"],
                            obj["f"].getArray().copy(),
                            obj["geometry"], lumped, payload["friction"],
                            payload["stiffness"], red,
                            payload.get("coulomb", "lagged"))
    service.objects[STATE] = dict(
        system=system, u=np.zeros(system.n), p=np.zeros(system.m),
        load_norm=float(payload["load_norm"]))


@command(f"{STATE}_step")
def _step(service, payload, local):
    """Every rank: one load step (module docstring) from the state's
    u_{κ−1}, p_{κ−1}; u of the step becomes ``objects[KEY]["u"]`` (what
    ``partitioned_write`` writes). Rank 0 returns the step's record, its
    verification and stopping measure and Γc's step fields gathered."""
    state, obj = service.objects[STATE], service.objects[KEY]
    system = state["system"]
    red = system.reduction
    factor, friction = float(payload["factor"]), float(payload["friction"])
    load_norm = state["load_norm"]  # max(‖f‖, ‖f_κ‖) = ‖f‖, κ ≤ κc
    system.set_step(state["u"], factor, state["p"], friction, load_norm)
    K_hat = service.objects["newton"]["A"]
    result = _iterate(system, service.objects["newton"], K_hat,
                      payload["tol"], payload["max_iter"], state)
    u = state["u"] + result["du"]
    r = system._force(result["du"])
    lam = -r[system.n_rows]
    g = result["g"]
    shared = SimpleNamespace(lumped=system.lumped, coulomb=system.coulomb,
                             geometry=system.geometry)
    fields = step_fields(shared, lam, g, friction, state["p"], load_norm,
                         system)
    k = system.dim - 1
    t = (system.lumped[:, None] * g.reshape(-1, k))
    check = verify_on_ranks(system, u, lam, payload["tol"], friction=(
        factor * system.f, t, system.lumped * fields["friction_bound"]))
    obj["force_v"] = system.contact_force  # the writer's mortar forces
    verified = bool(check["passed"])
    success = result["success"] and verified
    status = result["status"] if not result["success"] else \
        (0 if verified else 6)
    message = result["message"] if verified or not result["success"] \
        else f"{MESSAGES[6]}: {describe_failure(check)}"
    if success:
        state["u"], state["p"] = u, fields["contact_pressure"]
    if "u" in obj:
        obj.pop("u").destroy()
    obj["u"] = K_hat.createVecRight()
    obj["u"].setArray(u)
    fields["tangential_displacement"] = system.tangential(system.R @ u)
    arrays = obj["arrays"]
    mine = dict(node=np.asarray(arrays["node"]), index=np.asarray(
        arrays["index"]), gap=system.geometry.gap, **{
            key: np.asarray(fields[key]).reshape(system.m, k)
            if key in ("friction_traction", "tangential_displacement")
            else np.asarray(fields[key]) for key in FIELDS})
    pieces = service.comm.gather(mine, root=0)
    counts = red.sum(np.array([fields["in_contact"].sum(),
                               fields["stick"].sum(), fields["slip"].sum(),
                               np.count_nonzero(system.geometry.free_dofs()
                                                >= 0)], np.int64))
    top = red.max(np.max(fields["contact_pressure"], initial=0.0))
    if not service.root:
        return None
    gathered = {key: np.concatenate([p[key] for p in pieces])
                for key in pieces[0]}
    if k == 1:  # (m,) in 2D, as the serial result's
        for key in ("friction_traction", "tangential_displacement"):
            gathered[key] = gathered[key][:, 0]
    record = dict(converged=success, verified=verified, status=int(status),
                  njev=result["njev"], nfev=result["nfev"],
                  nit=result["njev"], error=result["error"],
                  relative=result["relative"], message=message,
                  gradient_steps=0, krylov=result["krylov"], stage=0,
                  n_contact=int(counts[0]), n_stick=int(counts[1]),
                  n_slip=int(counts[2]), max_pressure=float(top))
    return dict(record=record, fields=gathered, verification=check,
                stopping=result["stopping"], n_contact_dofs=int(counts[3]))


def _iterate(system, newton, A, tol, max_iter, state):
    """The active set iteration of one load step on every rank (the serial
    ``K_hat`` branch of :mod:`solver.contact.friction.active_set`, module
    docstring); returns Δu, g and the counts. ``state``: the rank's run
    state, which keeps its rows of K̂ for the implicit bound's coupling."""
    from petsc4py import PETSc

    red = system.reduction
    n, m, k = system.n, system.m, system.dim - 1
    R, lo = system.R, A.getOwnershipRange()[0]
    t_rows, n_rows, t_free = system.t_rows, system.n_rows, system.t_free
    free_rows = t_rows[t_free]
    c_t = system.c_t
    s, c = system.geometry.gap, system.stiffness
    u_previous = system.u_previous
    y_previous = R @ u_previous
    implicit = system.coulomb == "implicit"
    b, _ = system.bound(np.zeros(n), derivative=False)  # f_c p_{κ−1}
    Rf = system._Rf_step
    rule = SlipRule(k)
    u = u_previous.copy()
    status, detail, njev, nfev, krylov = 1, "", 0, 0, 0
    its = newton["its"]
    forcing, previous_sets = ForcingTerm(red), None
    while True:
        du = u - u_previous
        r = system._force(du)
        g, _, err, scale = iterate_measure(system, u, r)
        nfev += 1
        end = stopping(err, scale, tol, red.all(
            np.isfinite(err) and np.all(np.isfinite(u))), njev, max_iter)
        if end is not None:
            status, detail = end
            break
        lam = -r[n_rows]
        y = R @ u
        active = lam - c * (s - y[n_rows]) > 0
        if implicit:  # f_c p at the iterate, by the active set's measure
            b = implicit_radius(system, lam, y[n_rows])
        slide = np.zeros(system.mt)
        slide[t_free] = (R @ du)[free_rows]
        w = ((g - c_t * slide) * t_free).reshape(m, k)
        stick, slip, hat, size = rule(w, b)
        sets = (active, stick, slip)
        final = red.all(previous_sets is not None and all(
            np.array_equal(a, p) for a, p in zip(sets, previous_sets)))
        previous_sets = sets
        weight = contact_weight(system.load_norm, system.lambda_plus(lam),
                                system.gathered(system.lumped_t * g))
        atol = forcing.tolerance(err, final, weight, final and k == 2
                                 and not red.all(not slip.any()))
        newton["forcing"].append(forcing.history[-1])
        rhs = Rf.copy()
        if not implicit:  # the lagged bound's loads
            force = slip_loads(system.lumped, b, hat, slip)
            rhs[free_rows] += force[t_free]
        springs = None
        if k == 2 and not red.all(not slip.any()):  # collective
            E, stiff, _ = slip_springs(system, b, slip, hat, size,
                                       capped=True)
            S = (E.T @ sp.diags(stiff) @ E).tocsr()
            S.sort_indices()
            rhs += S @ y_previous
            springs = PETSc.Mat().createAIJ(
                size=((n, A.getSize()[0]), (n, A.getSize()[0])),
                csr=(S.indptr.astype(PETSc.IntType),
                     (S.indices + lo).astype(PETSc.IntType), S.data),
                comm=A.getComm())
            springs.assemble()
        fixed = constrained_rows(system, active, stick)
        values = np.concatenate([s[active],
                                 y_previous[fixed[int(active.sum()):]]])
        # the correction dy from y = R u: its residual (K̂ + S)y − rhs,
        # K̂ y = R K u = r + R f_κ, so CG's relative tolerance applies to
        # what is left at the iterate, not to the whole right-hand side
        # (a floor ~1e-12 ‖rhs‖ stalled the stopping test on 4 ranks)
        rhs -= r + Rf
        if springs is not None:
            rhs -= S @ y
        coupling = None
        if implicit and not red.all(not slip.any()):  # collective
            # the rows N r of the slip nodes' bound (serial bound_rows),
            # in the correction's residual and as N K̂ in its matrix
            N = bound_rows(system, slip, hat, n)
            rhs -= N @ r
            coupling = _coupling(N, newton["A"], state)
        newton["b"].setArray(rhs)
        solve_newton_system(newton, dict(
            shift_rows=np.zeros(0, np.int64), shift=np.zeros(0),
            fixed_rows=fixed + lo, fixed=values - y[fixed]), springs,
            coupling, atol=atol, start=np.zeros(n))
        for matrix in (springs, coupling):
            if matrix is not None:
                matrix.destroy()
        krylov += its[-1]
        u = R.T @ (y + newton["x"].getArray())
        njev += 1
    message = MESSAGES[status] + (f": {detail}" if detail else "")
    return dict(du=u - u_previous, g=g, success=status == 0,
                status=status, message=message, njev=njev, nfev=nfev,
                krylov=int(krylov), error=float(err),
                relative=float(err / scale) if scale > 0 else 0.0,
                stopping=dict(tol=float(tol), scale=float(scale),
                              absolute=float(err),
                              relative=float(err / scale) if scale > 0
                              else 0.0))


def _coupling(N, A, state):
    """(every rank) N K̂ as a distributed matrix (module docstring): N
    (the rank's rows and columns, :func:`~solver.contact.friction.
    active_set.bound_rows`) couples a slip node's tangent rows to its own
    normal row, which this rank owns, so the rank's rows of N K̂ are N
    times its own rows of K̂ (kept in ``state`` from the first call)."""
    from petsc4py import PETSc

    if "K_hat_rows" not in state:
        indptr, indices, data = A.getValuesCSR()
        state["K_hat_rows"] = sp.csr_matrix(
            (data, indices, indptr), shape=(A.getLocalSize()[0],
                                            A.getSize()[1]))
    C = (N @ state["K_hat_rows"]).tocsr()
    C.sort_indices()
    matrix = PETSc.Mat().createAIJ(
        size=(A.getSizes()[0], A.getSizes()[1]),
        csr=(C.indptr.astype(PETSc.IntType), C.indices.astype(PETSc.IntType),
             C.data), comm=A.getComm())
    matrix.assemble()
    return matrix
