r"""Coulomb friction on a partitioned problem (``mpiexec -n N python -m
solver DIR --engine petsc --friction F``): the serial friction driver
(:func:`solver.contact.friction.driver.run_friction`, thesis §5-§6, the
projection formulation of Alart & Curnier 1991 / Hüeber, Stadler &
Wohlmuth 2008) runs unchanged on rank 0, on Γc's Schur complement, while
no rank holds all of K or f.

The ranks read their rows and factorise K with Γc's free DOFs as MUMPS's
Schur set (:func:`~solver.mpi.distributed.open_partitioned`): rank 0 gets
S = K_cc − K_ci K_ii⁻¹ K_ic on *every* free DOF of Γc (the tangential
ones carry the friction forces, so S is not reduced to the normal rows as
without friction) and g̃ = f_c − K_ci K_ii⁻¹ f_i. The loads of the steps
are κ/κc · f (the Dirichlet values scaled alike, as a problem file without
a load path), so step κ's condensed load is t g̃ and its w_c = (K⁻¹f_κ)_c
is t S⁻¹g̃, t = κ/κc: no solve with K per step.

The driver sees the problem through :class:`GammaProblem`, whose unknowns
are Γc's free DOFs (S's numbering) and one more, the load factor t: its
"displacement" of a step is the pair (u_c, t), which determines u
(u_i = K_ii⁻¹(t f_i − K_ic u_c)) and stays that small on rank 0. Its
condensation (:class:`PartitionedCondensation`, the interface of
:class:`solver.linalg.Condensation`) recovers u on the ranks, for a batch
of steps at once, and computes K u − t f there; its stiffness
(:class:`GammaStiffness`) hands the driver's check "against the original K
and f" (:func:`~solver.contact.verify.verify_contact`) that residual:
Γc's rows as they are, the other rows by their norm. So every step is
checked as on the serial engine (Coulomb bound included), and the last
step on every row of K.

What the serial path checks beyond that and this one cannot from Γc: the
excluded nodes (supports of Γc, none take part here) and the small-sliding
warning on a curved obstacle (it needs the mesh on rank 0)."""

import os
import time

import numpy as np
import scipy.linalg as la

from ..contact.friction.driver import run_friction
from ..contact.verify import verification_tolerance
from ..problem.partitioned import load_mass
from .distributed import (KEY, Ledger, PartitionedResult, compact_geometry,
                          gather_rows, open_partitioned, write_pvtu)
from .pivots import schur_cholesky
from .schur import interior
from .service import command

__all__ = ["GammaProblem", "GammaStiffness", "PartitionedCondensation",
           "solve_partitioned_friction", "STEP_FIELDS_SAVED"]

#: The per-step fields on Γc's nodes that ``contact.npz`` keeps (first
#: axis the step), as ``step_<name>``.
STEP_FIELDS_SAVED = ("load_factor", "contact_force", "contact_pressure",
                     "contact_pressure_consistent", "friction_traction",
                     "friction_bound", "tangential_displacement",
                     "in_contact", "stick", "slip")


class PartitionedCondensation:
    r"""K condensed onto Γc's free DOFs from the ranks' Schur-mode
    factorisation, with :class:`solver.linalg.Condensation`'s interface
    for the serial friction driver. The loads it is given are
    :class:`GammaProblem`'s (t‖f‖ in the last entry, 0 elsewhere), its w
    the pair (w_c, t‖f‖), its displacements (u_c, t‖f‖); :meth:`displacement`
    recovers u on the ranks."""

    backend = "petsc-mumps"

    def __init__(self, svc, rows, S, g, load_norm, scale, keep_steps):
        self.svc, self.rows = svc, rows
        self.S = S
        m = len(rows)
        self.dofs = np.arange(m)
        self.g, self.load_norm = g, float(load_norm)
        # the pivot test of the serial backends, on S (SPD iff K is)
        self.w_c = la.cho_solve(schur_cholesky(S, scale), g)
        self.keep_steps = keep_steps  # the ranks hold each batch's u
        self.n_solves = 2  # g̃, then one back-substitution per step
        self.tokens = np.zeros((m + 1, 0))  # the batch held on the ranks
        self.checks = []  # K u − t f of each: (Γc's rows, the others' norm)

    def factor(self, f):
        """t of a :class:`GammaProblem` load, w or displacement (t‖f‖ in
        its last entry)."""
        return np.asarray(f, float)[..., -1] / self.load_norm

    def load(self, f):
        """(t g̃, (t w_c, t‖f‖)) for the load t f: thesis (66)'s condensed
        load and w = K⁻¹f_κ as the pair that determines it."""
        t = float(self.factor(f))
        return t * self.g, np.r_[t * self.w_c, t * self.load_norm]

    def displacement(self, u_c, w):
        """u with u_c on Γc for the load factor of w (one or several
        columns): recovered on the ranks (one interior solve each) and
        checked there (K u − t f); returns the pair (u_c, t‖f‖) per
        column."""
        u_c, w = np.asarray(u_c, float), np.asarray(w, float)
        columns = u_c.ndim == 2
        U = u_c if columns else u_c[:, None]
        T = np.atleast_1d(self.factor(w.T if columns else w))
        self.checks = self.svc.call(
            "partitioned_friction_u", dict(rows=self.rows,
                                           keep=self.keep_steps), (U, T))
        self.n_solves += len(T)
        self.tokens = np.vstack([U, T[None, :] * self.load_norm])
        return self.tokens if columns else self.tokens[:, 0]

    def column(self, token):
        """Which column of the batch on the ranks ``token`` is."""
        hits = np.flatnonzero((self.tokens == np.asarray(token)[:, None])
                              .all(axis=0))
        if not len(hits):
            return None
        return int(hits[-1])

    def residual(self, token):
        """[(K u − t f) on Γc's rows; t‖f‖ + ‖(K u − t f) elsewhere‖] for
        the pair ``token``: minus :class:`GammaProblem`'s load t f it is
        the residual with the other rows' norm in one entry."""
        j = self.column(token)
        if j is None:
            self.displacement(token[:-1], token)
            j = 0
        r_c, rest, _ = self.checks[j]
        return np.r_[r_c, token[-1] + rest]


class GammaStiffness:
    """What the driver asks of "the original K" of a :class:`GammaProblem`:
    ``K @ (u_c, t)``, the residual computed on the ranks plus the load
    (:meth:`PartitionedCondensation.residual`), and ``diagonal()``, whose
    mean over Γc is k̄ (the conversion's, from K's diagonal there)."""

    def __init__(self, condensation, stiffness):
        self.condensation, self.stiffness = condensation, float(stiffness)
        m = len(condensation.dofs) + 1
        self.shape = (m, m)

    def diagonal(self):
        return np.full(self.shape[0], self.stiffness)

    def __matmul__(self, u):
        return self.condensation.residual(np.asarray(u, float))


class GammaProblem:
    """The partitioned problem as the friction driver sees it on rank 0:
    unknowns Γc's free DOFs and the load factor t (module docstring),
    load f = (0, ‖f‖), steps κ/κc · f; Γc's mass matrix ``M``."""

    kind = "partitioned"
    floating = False
    load_path = None
    u_prescribed = None

    def __init__(self, condensation, stiffness, M, dim):
        m = len(condensation.dofs)
        self.n_dofs, self.dim = m + 1, dim
        self.f = np.zeros(m + 1)
        self.f[m] = condensation.load_norm
        self.K = GammaStiffness(condensation, stiffness)
        self.M = M
        self.n_contact = M.shape[0]
        self.contact_dofs = np.arange(m)

    def n_load_steps(self, steps=None):
        return 100 if steps is None else int(steps)

    def load_steps(self, steps=None):
        """(κ/κc · f, 1, None, 0) for κ = 1 … κc (one stage)."""
        steps = self.n_load_steps(steps)
        for k in range(1, steps + 1):
            yield k / steps * self.f, 1.0, None, 0


class _Engine:
    """The driver's engine: the one condensation (made by the ranks)."""

    name = "petsc"
    linear_solver = "petsc-mumps"

    def __init__(self, condensation):
        self.made = condensation

    def condensation(self, problem, dofs):
        return self.made


class _Steps:
    """``on_step`` of the driver on rank 0: keeps each step's fields on
    Γc's nodes (``contact.npz``) and, given ``outdir``, has every rank
    write the step's piece ``steps/step_KKKK-RANK.vtu`` (rank 0 the
    ``.pvtu``) of the u it holds."""

    def __init__(self, svc, condensation, index, contact, meta, outdir,
                 folder):
        self.svc, self.condensation = svc, condensation
        self.index, self.contact = index, contact
        self.meta, self.outdir, self.folder = meta, outdir, folder
        self.kept = {key: [] for key in STEP_FIELDS_SAVED}
        self.timesteps, self.files = [], []

    def __call__(self, fields):
        for key in STEP_FIELDS_SAVED:
            value = np.asarray(fields[key])
            self.kept[key].append(value if key == "load_factor"
                                  else value[self.index])
        if self.outdir is None:
            return
        k = len(self.kept["load_factor"])
        name = f"step_{k:04d}"
        steps = os.path.join(self.outdir, "steps")
        os.makedirs(steps, exist_ok=True)
        j = self.condensation.column(fields["u"])
        self.svc.call("partitioned_friction_hold", dict(column=j))
        contact = dict(self.contact, force=fields["contact_force"][
            self.index], in_contact=fields["in_contact"][self.index])
        pieces = self.svc.call("partitioned_write", dict(
            folder=os.fspath(self.folder), outdir=steps,
            kind=self.meta["cell_kind"], dim=int(self.meta["dim"]),
            name=name), contact)
        path = os.path.join(steps, f"{name}.pvtu")
        write_pvtu(path, pieces)
        self.files += [os.path.join("steps", os.path.basename(p))
                       for p in pieces + [path]]
        self.timesteps.append((float(fields["load_factor"]),
                               os.path.join("steps", f"{name}.pvtu")))

    def arrays(self):
        return {f"step_{key}": np.array(values)
                for key, values in self.kept.items()}


def solve_partitioned_friction(svc, folder, friction, steps=None,
                               formulation="projection", coulomb="lagged",
                               method="min", tol=1e-10, max_iter=100,
                               outdir=None, progress=None):
    """(rank 0, inside :func:`~solver.mpi.engine.spmd`) Coulomb friction
    with coefficient ``friction`` in ``steps`` load steps on the
    partitioned problem ``folder`` (module docstring); with ``outdir``,
    each step's pieces are written to ``outdir/steps/`` as it completes.
    Returns a :class:`~solver.mpi.distributed.PartitionedResult` (the last
    step's u kept on the ranks for ``write_pieces``; ``contact`` the last
    step's fields and every step's, ``step_*``)."""
    clock = time.perf_counter()
    ledger = Ledger()
    opened = open_partitioned(svc, folder, ledger)
    meta, arrays, geometry = opened.meta, opened.arrays, opened.geometry
    M = load_mass(folder, int(meta["n_contact"]))  # checked by the front
    load_norm, stiffness = float(meta["load_norm"]), float(meta["stiffness"])
    condensation = PartitionedCondensation(
        svc, opened.rows, opened.pop_schur(), opened.g, load_norm,
        opened.scale, keep_steps=outdir is not None)
    ledger.hold("S⁻¹g̃", condensation.w_c)
    local = compact_geometry(geometry)
    problem = GammaProblem(condensation, stiffness, M, int(meta["dim"]))
    index = np.asarray(arrays["index"])
    contact = dict(node=arrays["node"], gap=geometry.gap)
    recorder = _Steps(svc, condensation, index, contact, meta, outdir,
                      folder)
    result = run_friction(problem, local, _Engine(condensation), friction,
                          steps=steps, formulation=formulation,
                          coulomb=coulomb, method=method, tol=tol,
                          max_iter=max_iter, progress=progress,
                          condense=True, on_step=recorder, keep_steps=False,
                          candidates=False)
    if not condensation.checks:  # no step completed: the pieces show u = 0
        m = len(condensation.dofs)
        condensation.displacement(np.zeros(m), np.zeros(m + 1))
    verification = dict(result["verification"])
    if result["steps_completed"]:  # the last step's rows off Γc: K u − f
        _, rest, finite = condensation.checks[-1]
        t = float(condensation.factor(condensation.tokens[:, -1]))
        interior = rest / max(abs(t) * load_norm, 1e-300)
        verification["interior_equilibrium"] = float(interior)
        if not (finite and interior <= verification_tolerance(tol)):
            verification["passed"] = False
            verification["failed"] = list(verification.get("failed", [])) \
                + ["interior_equilibrium"]
    converged = bool(result.success and verification.get("passed", False))
    kept = recorder.arrays()
    records = result["records"]
    last = {key: values[-1] for key, values in kept.items()} if \
        len(kept["step_load_factor"]) else None
    n = int(result["steps_completed"])
    summary = dict(
        problem=os.fspath(folder), kind="partitioned",
        status="converged" if converged else "not_converged",
        converged=converged, message=result.message,
        friction=float(friction), steps=int(result["steps"]),
        steps_completed=n, failed_step=result["failed_step"],
        formulation=formulation, coulomb=coulomb, method=method,
        nit=int(result.nit), njev=int(result.njev), nfev=int(result.nfev),
        n_dofs=int(meta["n_free"]), n_contact_dofs=int(len(opened.rows)),
        n_in_contact=int(last["step_in_contact"].sum()) if last else 0,
        n_stick=int(last["step_stick"].sum()) if last else 0,
        n_slip=int(last["step_slip"].sum()) if last else 0,
        max_contact_force=float(last["step_contact_force"].max(
            initial=0.0)) if last else 0.0,
        records=records, verification=verification,
        stopping=result["stopping"], time=None,
        files=recorder.files)
    if not converged and result.success:
        summary["message"] = ("the last load step fails verification on "
                              "the ranks: interior_equilibrium")
    final = dict(contact, force=last["step_contact_force"] if last else
                 np.zeros(len(index)), in_contact=last["step_in_contact"]
                 if last else np.zeros(len(index), bool))
    final.update(kept)
    stats = svc.call("stats")
    summary["time"] = round(time.perf_counter() - clock, 4)
    summary["engine"] = dict(name="petsc", ranks=svc.size,
                             system="condensed", input="partitioned",
                             per_rank=stats, rank0_arrays=ledger.summary(),
                             n=int(meta["n"]),
                             back_substitutions=condensation.n_solves - 1)
    out = PartitionedResult(summary, svc, folder, meta, final)
    out.timesteps = recorder.timesteps
    return out


def _destroy_held(obj):
    for vec in obj.pop("steps", []):
        vec.destroy()


@command("partitioned_friction_u")
def _steps_u(service, payload, local):
    """Every rank: u of each column (u_c, t) of ``local`` (rank 0's), with
    K_ii u_i = t f_i − K_ic u_c (one interior solve each); K u − t f
    checked on every row. The last u becomes ``objects[KEY]["u"]`` (the
    pieces' ``result``), all of them are held with ``keep`` (the steps'
    pieces). Returns, on rank 0, per column (Γc's rows of K u − t f, the
    norm of the others, whether u is finite)."""
    from mpi4py import MPI

    obj, rows = service.objects[KEY], np.asarray(payload["rows"])
    U, T = service.comm.bcast(local, root=0)
    _destroy_held(obj)
    held, out = [], []
    a, b = obj["A"].getOwnershipRange()
    mine = rows[(rows >= a) & (rows < b)] - a
    for j, t in enumerate(T):
        rhs = obj["f"].copy()
        rhs.scale(float(t))
        u = interior(service, obj, rhs, rows, U[:, j]).copy()
        rhs.destroy()
        r = obj["f"].duplicate()
        obj["A"].mult(u, r)
        r.axpy(-float(t), obj["f"])
        residual_c = gather_rows(service, r, rows)
        values = r.getArray().copy()
        values[mine] = 0.0
        r.destroy()
        square = service.comm.reduce(float(values @ values), op=MPI.SUM,
                                     root=0)
        finite = service.comm.reduce(bool(np.isfinite(u.getArray()).all()),
                                     op=MPI.LAND, root=0)
        if service.root:
            out.append((residual_c, float(np.sqrt(square)), bool(finite)))
        if payload["keep"] or j == len(T) - 1:
            held.append(u)
        else:
            u.destroy()
    if "u" in obj:
        obj.pop("u").destroy()
    obj["u"] = held[-1].copy()
    if payload["keep"]:
        obj["steps"] = held
    else:
        held[-1].destroy()
    return out if service.root else None


@command("partitioned_friction_hold")
def _hold(service, payload, local):
    """Every rank: the held step ``column`` becomes ``objects[KEY]["u"]``
    (what ``partitioned_write`` writes)."""
    obj = service.objects[KEY]
    if "u" in obj:
        obj.pop("u").destroy()
    obj["u"] = obj["steps"][payload["column"]].copy()
