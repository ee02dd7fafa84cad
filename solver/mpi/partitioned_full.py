r"""The full system (67) of a partitioned problem on Krylov (``mpiexec -n N
python -m solver DIR --engine petsc --system full --ksp gamg|hypre``): no
rank holds the whole problem, nor all of Γc.

Every rank reads its rows of K and f (``MatLoad`` / ``VecLoad``, as
:mod:`.distributed`) and, from the folder's ``contact/`` (sorted by node,
:func:`~solver.problem.partitioned.load_contact_slice`), the contact
geometry of the contact nodes in its own node range; rows are blocked by
nodes, so a node's frame, its normal row and its NCP row live on one
rank. Each rank makes its block of R (thesis (58)-(60)) and K̂ = R K Rᵀ
is one PETSc ``PtAP``, after which K is freed (K u = Rᵀ K̂ R u, R
orthogonal: one matrix of K's size less on every rank); the rigid-body
modes, rotated into the frames and
orthonormalised by a 6 × 6 Gram matrix summed over the ranks, are GAMG's
near-null space (from each rank's own nodes).

The semismooth Newton is the project's :func:`solver.ncp.solve_ncp`,
called on every rank at once on its own rows (φ_min, from u = 0 as the
serial full system; c = k̄, unit-free as the active set path): Φ's
pieces and the iterates are the rank's, the norms of the stopping test,
the line search and every other decision are summed over the ranks
(:class:`Reduction`), and each Newton system is
:mod:`.full`'s (:func:`~.full.newton_rows`: the Jacobian's rows in the
node frames, :func:`~.full.solve_newton_system`: the shifted, eliminated
K̂ by CG + GAMG or BoomerAMG), inexactly: to the in-process path's
forcing term, the last system of an active set to 10⁻¹², warm-started
(:class:`~.full.ForcingTerm`). The answer is verified on every node of
every rank, the measures reduced by MPI (:func:`verify_on_ranks`); each
rank writes its piece of ``result.pvtu`` with the contact fields read
from the ranks (:mod:`.distributed`'s writer)."""

import os
import time

import numpy as np
import scipy.sparse as sp

from ..contact.geometry import ContactGeometry, rotation
from ..contact.verify import (contact_scale, contact_weight,
                              describe_failure, force_scale,
                              verification_tolerance)
from ..errors import ProblemError
from ..ncp import MESSAGES, solve_ncp, stable_norm
from ..problem.partitioned import load_contact_slice, read_partitioned_meta
from .distributed import KEY, PartitionedResult, shares
from .full import (TWO_BODY_GAMG, ForcingTerm, set_defaults,
                   ksp_statistics, newton_ksp,
                   newton_rows, solve_newton_system)
from .mortar_folder import body_modes, coupled_map
from .service import command

__all__ = ["solve_partitioned_full", "Reduction", "LocalSystem",
           "verify_on_ranks", "set_up_ranks", "KRYLOV"]

#: The Krylov preconditioners of this path (``ksp=``).
KRYLOV = ("gamg", "hypre")

#: PETSc's algorithm of the distributed products PᵀAP (K̂ and, on one
#: body, GAMG's Galerkin coarse operators) on more than one rank:
#: "allatonce" keeps no intermediate AP, which the default builds on
#: every rank (benchmarks/README.md, "The full system on the partitioned
#: folder"). It costs time: on one body GAMG's set-ups took about twice
#: the default's, where the memory of 2 ranks stays within 0.6× of one.
PTAP_VIA = "allatonce"

#: GAMG's coarse products on two bodies: PETSc's default, "scalable".
#: With each body's rigid modes (twelve near-null vectors in 3D, so
#: twelve columns per aggregate in GAMG's prolongator) "allatonce" took
#: ten times as long, and those products were nine tenths of the Newton
#: loop (benchmarks/README.md, "GAMG's smoothers estimate their own
#: eigenvalues").
TWO_BODY_PTAP_VIA = "scalable"



def _ptap_via(service, value):
    """(every rank) PETSc's ``matptap_via`` = ``value`` on more than one
    rank ($PETSC_OPTIONS wins; a later solve resets what an earlier one
    set, as the Newton KSP's defaults)."""
    if service.size > 1:
        set_defaults("", {"matptap_via": value})


def solve_partitioned_full(svc, folder, ksp="gamg", tol=1e-10, max_iter=100):
    """(rank 0, inside :func:`~solver.mpi.engine.spmd`) Solve the
    partitioned problem ``folder`` on the full system by Krylov (module
    docstring); return its :class:`~.distributed.PartitionedResult` (u and
    the contact fields kept on the ranks until ``write_pieces``)."""
    clock = time.perf_counter()
    meta = set_up_ranks(svc, folder, ksp)
    out = svc.call("partitioned_full_newton", dict(
        tol=tol, max_iter=max_iter, stiffness=float(meta["stiffness"]),
        load_norm=float(meta["load_norm"])))
    krylov = ksp_statistics(svc, "gamg")
    verification = out.pop("verification")
    converged = bool(out["success"] and verification["passed"])
    message = out["message"] if verification["passed"] else \
        f"{MESSAGES[6]}: {describe_failure(verification)}"
    contact = out.pop("contact")
    summary = dict(
        problem=os.fspath(folder), kind="partitioned", status="converged"
        if converged else "not_converged", converged=converged,
        message=message, method="min", nit=out["nit"], njev=out["njev"],
        nfev=out["nfev"], n_dofs=int(meta["n_free"]),
        n_contact_dofs=out["n_contact_dofs"],
        n_in_contact=out["n_in_contact"],
        max_contact_force=out["max_contact_force"],
        verification=verification, time=None)
    stats = svc.call("stats")
    summary["time"] = round(time.perf_counter() - clock, 4)
    its = krylov["ksp_iterations"]
    summary["engine"] = dict(
        name="petsc", ranks=svc.size, system="full", ksp=ksp,
        input="partitioned", per_rank=stats, n=int(meta["n"]),
        krylov_per_newton=float(np.mean(its)) if its else 0.0, **krylov)
    result = PartitionedResult(summary, svc, folder, meta, contact)
    # the pieces cut as the rows: equal shares (rank 0 holds no Schur
    # complement here)
    result.write_options = dict(fields=True, threshold=out["threshold"],
                                root_share=1.0)
    return result


def set_up_ranks(svc, folder, ksp):
    """(rank 0) Every rank reads its rows of ``folder``'s K and f and its
    contact nodes, and sets up R, K̂ and the Newton systems' KSP
    (``partitioned_full_setup``); K̂ is tested by CG (``check_spd_cg``).
    Returns the folder's meta. Shared by friction on this system
    (:mod:`.krylov_friction`)."""
    meta = read_partitioned_meta(folder)
    dim, n_nodes = int(meta["dim"]), int(meta["n_nodes"])
    starts = shares(n_nodes, svc.size, 1.0) * dim  # no rank holds more
    ranges = [(int(a), int(b)) for a, b in zip(starts[:-1], starts[1:])]
    svc.mark("start")
    svc.call("load_partitioned", dict(folder=os.fspath(folder),
                                      ranges=ranges, dim=dim))
    svc.call("partitioned_full_setup", dict(
        folder=os.fspath(folder), dim=dim, ksp=ksp,
        gap_mode=meta["gap_mode"], mortar=bool(meta.get("mortar"))))
    svc.call("check_spd_cg", dict(key="newton"))  # K̂ SPD? (full.py)
    return meta


class Reduction:
    """:func:`solve_ncp`'s reductions over the ranks of ``comm`` (its
    ``reduction``): ‖v‖₂ of the rows of every rank, and a flag true on
    every rank."""

    def __init__(self, comm):
        self.comm = comm

    def norm(self, v):
        return float(np.sqrt(self.comm.allreduce(stable_norm(v) ** 2)))

    def all(self, flag):
        from mpi4py import MPI

        return bool(self.comm.allreduce(bool(flag), op=MPI.LAND))

    def max(self, value):
        from mpi4py import MPI

        return float(self.comm.allreduce(float(value), op=MPI.MAX))

    def min(self, value):
        from mpi4py import MPI

        return float(self.comm.allreduce(float(value), op=MPI.MIN))

    def sum(self, value):
        return self.comm.allreduce(value)


class LocalSystem:
    r"""This rank's rows of the frictionless system (67) in the padded
    numbering (as :class:`~solver.contact.frictionless.system.
    FrictionlessSystem`, which holds the whole K): E = X(RKu − Rf),
    A = −Y(RKu − Rf), B = c(s − YRu) on the rank's rows, from K̂ = RKRᵀ
    (``K_hat``, distributed: RKu = K̂Ru, R orthogonal; K itself is not
    kept); its Jacobian solves the Newton systems on every rank
    (:func:`~.full.solve_newton_system`). Every call is collective."""

    def __init__(self, service, K_hat, f, R, geometry, gap_scale, stiffness,
                 load_norm, reduction):
        self.service, self.A, self.R = service, K_hat, R
        self.geometry, self.gap_scale = geometry, float(gap_scale)
        self.stiffness, self.load_norm = float(stiffness), float(load_norm)
        self.reduction = reduction
        self.lo = K_hat.getOwnershipRange()[0]
        n = R.shape[0]
        _, _, _, self.y_rows = rotation(n, geometry)
        keep = np.ones(n, bool)
        keep[self.y_rows] = False
        self.x_rows = np.flatnonzero(keep)
        self.f = f.getArray().copy()
        self.Rf = R @ self.f
        self.u_vec = K_hat.createVecRight()
        self.Ku_vec = K_hat.createVecLeft()
        self.forcing, self._last = None, None

    def rotated(self, v):
        """(K̂ v) on this rank's rows, v in the node frames (collective)."""
        self.u_vec.setArray(v)
        self.A.mult(self.u_vec, self.Ku_vec)
        return self.Ku_vec.getArray().copy()

    def Ku(self, u):
        """(K u) = Rᵀ K̂ R u on this rank's rows (collective)."""
        return self.R.T @ self.rotated(self.R @ u)

    def residual(self, u):
        r = self.rotated(self.R @ u) - self.Rf
        gap = self.geometry.gap - (self.R @ u)[self.y_rows]
        parts = r[self.x_rows], -r[self.y_rows], self.gap_scale * gap
        self._last = (u, parts)
        return parts

    def jacobian(self, u):
        """The Jacobian at u, with the stopping measure there, its
        contact rows unweighted (the forcing term's err_k, in the Newton
        system's units; the last residual's when it was at u)."""
        last = self._last
        parts = last[1] if self.reduction.all(
            last is not None and np.array_equal(last[0], u)) \
            else self.residual(u)
        return _Jacobian(self, u, self.error(*parts, weighted=False))

    def lambda_plus(self, A):
        """‖λ⁺‖₂ over all ranks, as a one-entry array for the scales of
        :mod:`solver.contact.verify` (which read λ only through it)."""
        return np.array([self.reduction.norm(np.maximum(A, 0.0))])

    def error(self, E, A, B, weighted=True):
        """:meth:`FrictionlessSystem.error` over all ranks."""
        w = contact_weight(self.load_norm, self.lambda_plus(A)) \
            if weighted else 1.0
        return float(np.hypot(self.reduction.norm(E), w * self.reduction.norm(
            np.minimum(A, self.stiffness / self.gap_scale * B))))

    def scale(self, E, A, B):
        return force_scale(self.load_norm, self.lambda_plus(A))


class _Jacobian:
    def __init__(self, system, u, err):
        self.system, self.u, self.err = system, u, err

    def combine(self, wa, wb):
        return _Combined(self.system, np.asarray(wa, float),
                         np.asarray(wb, float), self)


class _Combined:
    def __init__(self, system, wa, wb, at):
        self.system, self.wa, self.wb = system, wa, wb
        self.u, self.err = at.u, at.err

    def direction(self, F):
        s = self.system
        rhs = np.zeros(s.R.shape[0])
        rows = newton_rows(rhs, s.x_rows, s.y_rows, F, self.wa, self.wb,
                           s.gap_scale)
        if not s.reduction.all(rows is not None):
            return None  # singular on some rank: on every rank
        for key in ("shift_rows", "fixed_rows"):
            rows[key] = rows[key] + s.lo  # global rows
        obj = s.service.objects["newton"]
        atol, guess = None, None
        if s.forcing is not None:  # inexact Newton, warm start (.full)
            final, guess = s.forcing.step(self.u, self.wa != 0.0)
            atol = s.forcing.tolerance(self.err, final)
            obj["forcing"].append(s.forcing.history[-1])
        obj["b"].setArray(rhs)
        solve_newton_system(obj, rows, atol=atol, start=np.zeros(
            len(rhs)) if guess is None else s.R @ guess)
        d = s.R.T @ obj["x"].getArray()
        if s.forcing is not None:
            s.forcing.target = self.u + d
        return d if s.reduction.all(np.all(np.isfinite(d))) else None


def verify_on_ranks(system, u, lam, tol, friction=None):
    """The answer checked on every node of every rank, the measures of
    :func:`solver.contact.verify.verify_contact` (the same names and
    scales) with their maxima, minima and norms reduced over the ranks:
    penetration, sign of λ, complementarity, and the equilibrium
    ‖K u − f − f_c‖/(‖f‖ + ‖f_c‖) on every row (f_c = −λν at Γc), and as
    the direct path's ``interior_equilibrium`` ‖K u − f‖/‖f‖ off Γc.
    ``friction``: (f, t, bound) of a friction step, its load f_κ, the
    nodal friction forces t (m, d − 1) along the geometry's tangents and
    the bound D f_c p: f_c then adds Σ t_k τ_k, F counts ‖t‖ and
    ``friction_bound_violation`` is max(|t| − bound, 0)/F
    (:mod:`.krylov_friction`)."""
    red, g = system.reduction, system.geometry
    f, t, bound = (system.f, None, None) if friction is None else friction
    finite = red.all(np.all(np.isfinite(u)) and np.all(np.isfinite(lam)))
    F = contact_scale(system.load_norm, system.lambda_plus(lam),
                      None if t is None else [red.norm(t)]) \
        if finite else np.inf
    L = F / system.stiffness
    padded = np.append(u, 0.0)  # −1 (a roller's Dirichlet component): 0
    dofs = g.node_dofs
    un = (g.normal * padded[dofs]).sum(axis=1) if len(dofs) \
        else np.zeros(0)
    remaining = g.gap - un
    contact = np.zeros(len(u) + 1)
    if len(dofs):
        contact[dofs] = -lam[:, None] * g.normal
        if t is not None:
            contact[dofs] += (t[:, :, None] * g.tangents).sum(axis=1)
    system.contact_force = contact[:-1]  # f_v (two bodies' outputs)
    r = system.Ku(u) - f - contact[:-1]
    off = r.copy()  # the rows off Γc: ‖·‖/‖f‖ as the direct path's
    off[dofs[dofs >= 0]] = 0.0
    tol_v = verification_tolerance(tol)
    f_norm = system.load_norm if friction is None else red.norm(f)

    def relative(value, size):
        return max(value, 0.0) if value <= 0.0 else (
            value / size if size > 0 else np.inf)

    with np.errstate(all="ignore"):
        checks = dict(
            max_penetration=relative(red.max(np.max(-remaining,
                                                    initial=0.0)), L),
            min_multiplier=-relative(-red.min(np.min(lam, initial=0.0)), F),
            complementarity=relative(red.max(np.max(np.abs(np.minimum(
                lam, system.stiffness * remaining)), initial=0.0)), F),
            equilibrium=relative(red.norm(r), f_norm
                                 + red.norm(contact[:-1])),
            interior_equilibrium=relative(red.norm(off), f_norm))
        if t is not None:
            size = np.linalg.norm(t, axis=1) if len(t) else np.zeros(0)
            checks["friction_bound_violation"] = relative(red.max(np.max(
                size - bound, initial=0.0)), F)
    failed = [] if finite else ["finite"]
    for name, value in checks.items():
        if (value < -tol_v) if name == "min_multiplier" else \
                not value <= tol_v:
            failed.append(name)
    tolerances = {name: tol_v for name in checks}
    tolerances["min_multiplier"] = -tol_v
    out = dict(passed=not failed, finite=bool(finite))
    out.update({k: float(v) for k, v in checks.items()})
    out.update(force_scale=float(F), length_scale=float(L),
               tolerances=tolerances, failed=failed, reduced_over_ranks=True)
    return out


def _local_geometry(arrays, lo, mode):
    """The slice's geometry in this rank's row numbering (−1 kept)."""
    def local(rows):
        rows = np.asarray(rows, np.int64)
        return np.where(rows >= 0, rows - lo, -1)

    return ContactGeometry(
        arrays["index"], local(arrays["dofs"]), arrays["gap"],
        arrays["normal"], mode=mode, tangents=arrays["tangents"],
        node_dofs=local(arrays["node_dofs"]), oblique=arrays["oblique"])


def _rigid_modes(folder, lo, hi, dim, R, comm):
    """The rigid-body modes on this rank's rows (2D: 3, 3D: 6), from its
    own nodes, rotated into the node frames (R) and orthonormal over all
    ranks (their Gram matrix summed, then its Cholesky factor)."""
    x = np.array(np.load(os.path.join(folder, "nodes.npy"),
                         mmap_mode="r")[lo // dim:hi // dim], float)[:, :dim]
    total = comm.allreduce(x.sum(axis=0))
    count = comm.allreduce(len(x))
    x = x - total / max(count, 1)
    n = len(x)
    modes = [np.eye(dim)[k][None, :].repeat(n, 0) for k in range(dim)]
    for a, b in ([(0, 1)] if dim == 2 else [(0, 1), (1, 2), (2, 0)]):
        m = np.zeros((n, dim))
        m[:, a], m[:, b] = -x[:, b], x[:, a]
        modes.append(m)
    Z = R @ np.column_stack([m.ravel() for m in modes])
    gram = comm.allreduce(Z.T @ Z)
    return np.linalg.solve(np.linalg.cholesky(gram), Z.T).T


@command("partitioned_full_setup")
def _setup(service, payload, local):
    """Every rank: its contact nodes' geometry, its block of R, K̂ = R K Rᵀ
    (``PtAP``), the near-null space and the Newton systems' KSP
    (:func:`~.full.newton_ksp`)."""
    from petsc4py import PETSc

    obj = service.objects[KEY]
    A, dim = obj["A"], payload["dim"]
    lo, hi = A.getOwnershipRange()
    arrays = load_contact_slice(payload["folder"], dim, lo // dim,
                                hi // dim)
    red = Reduction(service.comm)
    if not red.all(not arrays["oblique"].any()):
        raise ProblemError("a roller whose normal is not in its free "
                           "components (oblique): the full system on the "
                           "petsc engine needs orthogonal node frames; run "
                           "without --system full")
    if red.sum(len(arrays["gap"])) == 0:
        raise ProblemError(f"{payload['folder']}: no contact node takes "
                           "part (every node of Γc is a support): nothing "
                           "to solve on Γc; run the .npz")
    geometry = _local_geometry(arrays, lo, payload["gap_mode"])
    R = rotation(hi - lo, geometry)[0].tocsr()
    defect = abs(sp.linalg.norm(R @ R.T - sp.identity(hi - lo)))
    if red.max(defect) > 1e-12:
        raise ProblemError("the full system on the petsc engine needs "
                           "orthogonal node frames")
    n = A.getSize()[0]
    RT = R.T.tocsr()
    P = PETSc.Mat().createAIJ(
        size=((hi - lo, n), (hi - lo, n)), bsize=dim,
        csr=(RT.indptr.astype(PETSc.IntType),
             (RT.indices + lo).astype(PETSc.IntType), RT.data),
        comm=A.getComm())
    P.assemble()
    if payload.get("mortar"):  # two bodies: P = T⁻¹Rᵀ, f̃ = T⁻ᵀf
        RT_mat, P = P, coupled_map(obj, payload["folder"], A, P)
        RT_mat.destroy()
    _ptap_via(service, PTAP_VIA)
    product = A.ptap(P)  # Pᵀ K P = R K Rᵀ
    P.destroy()
    # a copy without the product's data: PETSc's product keeps K, P and
    # PtAP's intermediates for a numeric re-product that never comes, so
    # K would outlive its own destroy (petsc4py 3.18 has no productClear)
    K_hat = product.duplicate(copy=True)
    product.destroy()
    service.mark("partitioned_full_setup.ptap")
    if K_hat.getBlockSize() != dim:
        K_hat.setBlockSize(dim)
    diagonal = K_hat.getDiagonal()
    scale = diagonal.sum() / n
    diagonal.destroy()
    vecs = []
    if payload["ksp"] == "gamg":
        Z = body_modes(payload["folder"], lo, hi, dim, R, obj["T_inv"],
                       service.comm) if payload.get("mortar") else \
            _rigid_modes(payload["folder"], lo, hi, dim, R, service.comm)
        for j in range(Z.shape[1]):
            v = K_hat.createVecLeft()
            v.setArray(np.ascontiguousarray(Z[:, j]))
            vecs.append(v)
    service.mark("partitioned_full_setup.modes")
    _ptap_via(service, TWO_BODY_PTAP_VIA if payload.get("mortar") else
              PTAP_VIA)  # GAMG's products
    newton_ksp(service, K_hat, payload["ksp"], float(scale), vecs,
               gamg=TWO_BODY_GAMG if payload.get("mortar") else None)
    # K̂ stands for K from here on (LocalSystem): K and the direct path's
    # work vectors are freed
    for key in ("A", "x", "b"):
        obj.pop(key).destroy()
    obj.update(R=R, geometry=geometry, arrays=arrays)
    service.objects.setdefault("counts", {}).update(
        contact_nodes=int(len(arrays["gap"])),
        E_entries=int(obj.pop("E_entries", 0)))


@command("partitioned_full_newton")
def _newton(service, payload, local):
    """Every rank: :func:`solve_ncp` on its rows (module docstring), u and
    the contact fields kept on the ranks; rank 0 returns the counts, the
    verification and Γc's fields gathered for ``contact.npz``."""
    obj = service.objects[KEY]
    red = Reduction(service.comm)
    k = payload["stiffness"]
    K_hat = service.objects["newton"]["A"]
    system = LocalSystem(service, K_hat, obj["f"], obj["R"],
                         obj["geometry"], k, k, payload["load_norm"], red)
    system.forcing = ForcingTerm(red)
    result = solve_ncp(system.residual, system.jacobian,
                       np.zeros(obj["R"].shape[0]), method="min",
                       tol=payload["tol"], max_iter=payload["max_iter"],
                       error=system.error, scale=system.scale,
                       reduction=red)
    u = result.x
    _, lam, _ = system.residual(u)
    threshold = 1e-9 * force_scale(system.load_norm,
                                   system.lambda_plus(lam))
    verification = verify_on_ranks(system, u, lam, payload["tol"])
    obj["force_v"] = system.contact_force  # the writer's mortar forces
    if "u" in obj:
        obj.pop("u").destroy()
    obj["u"] = K_hat.createVecRight()
    obj["u"].setArray(u)
    # (λ, s) at each contact node's first row, NaN elsewhere: the writer's
    g, dim = obj["geometry"], K_hat.getBlockSize()
    fields = np.full(len(u), np.nan)
    first = (obj["arrays"]["node"] * dim - system.lo).astype(np.int64)
    fields[first] = lam
    fields[first + 1] = g.gap
    if "fields" in obj:
        obj.pop("fields").destroy()
    obj["fields"] = K_hat.createVecRight()
    obj["fields"].setArray(fields)
    u_n = (system.R @ u)[system.y_rows]
    touching = lam > threshold
    pieces = service.comm.gather((obj["arrays"]["node"], lam, u_n, g.gap,
                                  touching), root=0)
    count = red.sum(int(np.count_nonzero(touching)))
    m = red.sum(int(np.count_nonzero(g.free_dofs() >= 0)))
    top = red.max(np.max(lam, initial=0.0))
    if not service.root:
        return None
    contact = {key: np.concatenate([p[i] for p in pieces]) for i, key in
               enumerate(("node", "force", "u_n", "gap", "in_contact"))}
    return dict(success=bool(result.success), message=result.message,
                nit=int(result.nit), njev=int(result.njev),
                nfev=int(result.nfev), verification=verification,
                contact=contact, threshold=float(threshold),
                n_in_contact=int(count), n_contact_dofs=int(m),
                max_contact_force=float(top))
