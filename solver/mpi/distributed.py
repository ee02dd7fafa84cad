r"""The frictionless solve of a partitioned problem (``mpiexec -n N python
-m solver DIR --engine petsc``): no rank ever holds all of K or f.

Every rank reads only its rows of K and f (PETSc's ``MatLoad`` /
``VecLoad`` of the folder of :mod:`solver.problem.partitioned`, rows
blocked by nodes as :class:`~solver.mpi.layout.Layout`). One distributed
MUMPS factorisation in its Schur mode gives S = K_cc − K_ci K_ii⁻¹ K_ic on
the DOFs c of the contact nodes (thesis (63)-(66)) on rank 0; one interior
solve gives the condensed load g̃ = f_c − K_ci K_ii⁻¹ f_i. Rank 0 holds
only these, the contact geometry and the Newton iterates on Γc. Without
friction only the normal unknowns carry a force, so rank 0 condenses S
once more onto Γc's normal rows in the node frames (:class:`NormalSchur`,
(m/d)² entries, as the serial condensation onto the candidates' normal
DOFs) and drops S; it solves the NCP (67) on them from the free start,
as the serial ``solver.solve(problem, start="free")``. A second
interior solve gives u = K⁻¹(f − Bᵀλ) on the ranks (u_i = K_ii⁻¹(f_i −
K_ic u_c)); the residual K u − f is checked on every row there (zero off
Γc, the contact forces on it), and each rank writes its piece of
``result.pvtu``.

What rank 0 keeps is recorded in a :class:`Ledger` (the ``engine``
entry's ``rank0_arrays``): every array its driver holds between the
collective steps, with its shape (the NCP's own work arrays are built
from S and are no larger), so that the claim "nothing of K's size on rank
0" is checked by the tests, not assumed; besides, rank 0 has its own
share of K's rows, as every rank."""

import os
import time

import numpy as np
import scipy.linalg as la

from ..contact.geometry import ContactGeometry, rotation
from ..contact.strategies.candidates import normal_line
from ..contact.frictionless.system import FrictionlessSystem
from ..contact.verify import (describe_failure, force_scale,
                              unit_free_options, verification_tolerance,
                              verify_contact)
from ..errors import ProblemError
from ..ncp import MESSAGES, solve_ncp
from ..problem.partitioned import (load_contact, original_nodes,
                                   read_partitioned_meta)
from .layout import gather_vector
from .mortar_folder import in_bodies
from .pivots import schur_cholesky
from .schur import interior
from .service import command

__all__ = ["Ledger", "PartitionedResult", "solve_partitioned", "write_pvtu",
           "KEY", "open_partitioned", "gather_rows", "node_ranges"]

#: The service's name of the loaded problem (its objects and MUMPS
#: options prefix ``d_``).
KEY = "D"


class Ledger:
    """The arrays rank 0's driver holds: name -> shape (:meth:`hold`
    returns the array); :meth:`largest` is the most entries of one."""

    def __init__(self):
        self.shapes = {}

    def hold(self, name, array):
        self.shapes[name] = list(np.shape(array))
        return array

    def largest(self):
        return max((int(np.prod(s)) for s in self.shapes.values()),
                   default=0)

    def summary(self):
        return dict(shapes=self.shapes, largest_entries=self.largest(),
                    largest_dimension=max((max(s, default=0) for s in
                                           self.shapes.values()),
                                          default=0))


def compact_geometry(geometry):
    """``geometry`` (padded rows) renumbered to the Schur set's positions,
    free DOF k of ``free_dofs()`` → k, −1 kept; by a binary search (no
    lookup table of K's size, unlike ``ContactGeometry.compact``)."""
    flat = geometry.free_dofs()
    order = np.argsort(flat, kind="stable")

    def lookup(rows):
        rows = np.asarray(rows, np.int64)
        out = np.full(rows.shape, -1, np.int64)
        used = rows >= 0
        out[used] = order[np.searchsorted(flat, rows[used], sorter=order)]
        return out

    return geometry.renumbered(lookup(geometry.dofs),
                               lookup(geometry.node_dofs))


class NormalSchur:
    r"""Γc's Schur complement condensed onto its normal rows, on rank 0.

    MUMPS returns S (m, m) on every free DOF of the contact nodes and g̃.
    Without friction no tangential force acts, so only each node's normal
    unknown needs to stay in the NCP (as the serial
    :class:`~solver.contact.strategies.candidates.NormalCondensation`,
    which factorises K̂ = RKRᵀ with the normal rows as its Schur set).
    With R the nodes' frames (:func:`~solver.contact.geometry.rotation`,
    thesis (58)-(60)), Ŝ = R S Rᵀ, ĝ = R g̃, N the normal rows and T the
    others (the tangential rows and a roller's other free DOFs), the
    Schur complement of K̂ on N is the Schur complement of Ŝ on N (Schur
    complements compose):

        S_n = Ŝ_NN − Ŝ_NT Ŝ_TT⁻¹ Ŝ_TN,   g_n = ĝ_N − Ŝ_NT Ŝ_TT⁻¹ ĝ_T,

    and u_T = Ŝ_TT⁻¹(ĝ_T − Ŝ_TN u_N) gives the rest (no force on T). The
    NCP's dense work is then on (m/d)² entries, not m²; S is
    freed as soon as Ŝ's blocks are made (``work["S"]`` is taken out of
    ``work``). Both Choleskys are :func:`schur_cholesky`'s
    pivot checks: S is SPD iff Ŝ_TT and S_n are (Ŝ is congruent to S)."""

    def __init__(self, work, g, local, scale, ledger):
        S = work.pop("S")  # the caller's last reference: freed here
        m = len(g)
        self.R, _, _, normal = rotation(m, local)
        other = np.ones(m, bool)
        other[normal] = False
        self.normal, self.other = normal, np.flatnonzero(other)
        N, T = self.normal, self.other
        # Ŝ's blocks as R_X S R_Yᵀ, S symmetric: no m × m array besides S
        side = (self.R[N] @ S).T  # S R_Nᵀ
        nn, tn = self.R[N] @ side, self.R[T] @ side
        del side
        tt = ledger.hold("S_TT", self.R[T] @ (self.R[T] @ S).T)
        del S
        r = self.R @ g
        if len(T):
            cho = schur_cholesky(tt, scale)
            del tt
            self.X = ledger.hold("S_TT⁻¹S_TN", la.cho_solve(cho, tn))
            self.y = la.cho_solve(cho, r[T])
            del cho
        else:
            self.X, self.y = np.zeros((0, len(N))), np.zeros(0)
        self.S = ledger.hold("S_n", nn - tn.T @ self.X)
        self.S += self.S.T
        self.S *= 0.5
        self.g = ledger.hold("g_n", r[N] - tn.T @ self.y)
        del tn, nn
        cho = schur_cholesky(self.S, scale)
        self.start = la.cho_solve(cho, self.g)  # the free start, λ = 0

    def displacement(self, u_n):
        """u on Γc's free DOFs (S's numbering) from the normal rows' u_n."""
        u = np.empty(len(self.normal) + len(self.other))
        u[self.normal] = u_n
        u[self.other] = self.y - self.X @ u_n
        return self.R.T @ u


#: Rank 0's share of the rows (and of the cells it writes) relative to
#: another rank's: it also holds Γc's Schur complement, the NCP's dense
#: work on it and MUMPS's host part (benchmarks/README.md, "Distributed
#: from the file").
ROOT_SHARE = 0.5


def shares(count, size, root_share=ROOT_SHARE):
    """``count`` items cut into ``size`` consecutive ranges, rank 0's
    ``root_share`` times as long as each other's: the starts (size + 1)."""
    weights = np.r_[root_share if size > 1 else 1.0, np.ones(size - 1)]
    cut = np.floor(np.cumsum(weights) / weights.sum() * count + 0.5)
    return np.r_[0, cut].astype(np.int64)


def node_ranges(n_nodes, dim, size):
    """Each rank's padded rows: whole nodes (a node's DOFs on one rank, as
    :class:`~solver.mpi.layout.Layout`), rank 0 a smaller share
    (:data:`ROOT_SHARE`)."""
    starts = shares(n_nodes, size) * dim
    return [(int(a), int(b)) for a, b in zip(starts[:-1], starts[1:])]


class PartitionedResult(dict):
    """The summary of a partitioned solve (what ``summary.json`` holds);
    ``contact`` the fields on Γc (rank 0), u stays on the ranks until
    :meth:`write_pieces`."""

    def __init__(self, summary, svc, folder, meta, contact):
        super().__init__(summary)
        self.svc, self.folder, self.meta = svc, folder, meta
        self.contact = contact
        #: ``partitioned_write``'s further payload (``fields``: the contact
        #: fields are on the ranks, :mod:`.partitioned_full`)
        self.write_options = {}

    @property
    def success(self):
        return bool(self["converged"])

    def piece_names(self):
        """The pieces' file names, one per rank."""
        return [f"result-{rank}.vtu" for rank in range(self.svc.size)]

    def write_pieces(self, outdir):
        """(collective) Every rank writes its piece ``result-RANK.vtu`` of
        ``outdir`` under a temporary name and renames it when complete;
        returns the pieces' paths. The ranks' statistics (``engine``'s
        ``per_rank``: peak memory, times) are taken again afterwards, so
        that each rank's peak includes writing its piece."""
        pieces = self.svc.call("partitioned_write", dict(
            folder=os.fspath(self.folder), outdir=os.fspath(outdir),
            kind=self.meta["cell_kind"], dim=int(self.meta["dim"]),
            **self.write_options), self.contact)
        self["engine"]["per_rank"] = self.svc.call("stats")
        return pieces


class Opened:
    """What :func:`open_partitioned` gives rank 0: ``meta``, the contact
    ``arrays`` and ``geometry`` (padded rows), the Schur set ``rows``, the
    pivot test's ``scale``, Γc's condensed load ``g`` and (until
    :meth:`pop_schur`) its Schur complement S."""

    def __init__(self, **items):
        self.__dict__.update(items)

    def pop_schur(self):
        """S, handed over: this object keeps no reference to it."""
        S, self.S = self.S, None
        return S


def open_partitioned(svc, folder, ledger):
    """(rank 0) The steps every solve of the partitioned problem
    ``folder`` starts with (module docstring, 1-2): read its meta and
    contact geometry, have every rank load its rows of K and f, factorise
    K with Γc's free DOFs as MUMPS's Schur set and make g̃ by one interior
    solve. Returns an :class:`Opened`; ``ledger`` records what rank 0
    holds."""
    meta = read_partitioned_meta(folder)
    dim = int(meta["dim"])
    arrays = load_contact(folder, dim)
    for name, array in arrays.items():
        ledger.hold(f"contact.{name}", array)
    geometry = ContactGeometry(
        arrays["index"], arrays["dofs"], arrays["gap"], arrays["normal"],
        mode=meta["gap_mode"], tangents=arrays["tangents"],
        node_dofs=arrays["node_dofs"], oblique=arrays["oblique"])
    rows = ledger.hold("schur_rows", geometry.free_dofs())
    if not len(rows):
        raise ProblemError(f"{folder}: no contact node takes part (every "
                           "node of Γc is a support): nothing to solve on "
                           "Γc; run the .npz")
    ranges = node_ranges(int(meta["n_nodes"]), dim, svc.size)
    svc.mark("start")
    scale = svc.call("load_partitioned", dict(folder=os.fspath(folder),
                                              ranges=ranges, dim=dim))
    S = ledger.hold("S", svc.call("factor", dict(key=KEY, schur=rows)))
    g = ledger.hold("g", svc.call("partitioned_rhs", dict(rows=rows)))
    return Opened(meta=meta, arrays=arrays, geometry=geometry, rows=rows,
                  scale=scale, S=S, g=g)


def solve_partitioned(svc, folder, method="min", tol=1e-10, max_iter=100):
    """(rank 0, inside :func:`~solver.mpi.engine.spmd`) Solve the
    partitioned problem ``folder`` on every rank; return its
    :class:`PartitionedResult` (u kept on the ranks, written by
    :meth:`PartitionedResult.write_pieces`). Module docstring."""
    clock = time.perf_counter()
    ledger = Ledger()
    opened = open_partitioned(svc, folder, ledger)
    meta, arrays, geometry = opened.meta, opened.arrays, opened.geometry
    rows, scale, g = opened.rows, opened.scale, opened.g
    work = dict(S=opened.pop_schur())
    stiffness, load_norm = float(meta["stiffness"]), float(meta["load_norm"])
    local = compact_geometry(geometry)
    # rank 0 keeps only the normal rows' system from here on
    normal = NormalSchur(work, g, local, scale, ledger)
    nodes = np.arange(len(geometry.gap))
    system = FrictionlessSystem(normal.S, normal.g,
                                normal_line(geometry, nodes), stiffness,
                                stiffness, load_norm)
    options = unit_free_options(method, None, load_norm, stiffness,
                                geometry.gap)
    result = solve_ncp(system.residual, system.jacobian,
                       ledger.hold("start", normal.start), method=method,
                       tol=tol, max_iter=max_iter, options=options,
                       error=system.error, scale=system.scale)
    u_n = ledger.hold("u_n", result.x)
    lam = ledger.hold("lambda", system.contact_force(u_n))
    # in contact: λ above round-off, as the serial result's in_contact
    touching = lam > 1e-9 * force_scale(load_norm, lam)
    u_c = ledger.hold("u_c", normal.displacement(u_n))
    checked = svc.call("partitioned_displacement", dict(rows=rows), u_c)
    r_c = ledger.hold("residual_c", checked["residual_c"])
    verification = _verify(checked, r_c, u_c, local, geometry, lam,
                           stiffness, load_norm, tol)
    converged = bool(result.success and verification["passed"])
    message = result.message if verification["passed"] else \
        f"{MESSAGES[6]}: {describe_failure(verification)}"
    summary = dict(
        problem=os.fspath(folder), kind="partitioned", status="converged"
        if converged else "not_converged", converged=converged,
        message=message, method=method, nit=int(result.nit),
        njev=int(result.njev), nfev=int(result.nfev), n_dofs=int(
            meta["n_free"]), n_contact_dofs=int(len(rows)),
        n_in_contact=int(np.count_nonzero(touching)),
        max_contact_force=float(lam.max(initial=0.0)),
        verification=verification, time=None)
    contact = dict(node=arrays["node"], force=lam, u_n=u_n,
                   gap=geometry.gap, in_contact=touching)
    stats = svc.call("stats")
    summary["time"] = round(time.perf_counter() - clock, 4)
    summary["engine"] = dict(name="petsc", ranks=svc.size,
                             system="condensed", input="partitioned",
                             per_rank=stats, rank0_arrays=ledger.summary(),
                             n=int(meta["n"]))
    return PartitionedResult(summary, svc, folder, meta, contact)


def _verify(checked, r_c, u_c, local, geometry, lam, stiffness, load_norm,
            tol):
    """The answer checked on every row: Γc's rows of K u − f (= S u_c − g̃
    once the interior rows vanish) against the contact forces by
    :func:`~solver.contact.verify.verify_contact`, and the other rows'
    ‖K u − f‖/‖f‖ computed on the ranks (``interior_equilibrium``)."""
    tol_v = verification_tolerance(tol)
    verification = verify_contact(
        _Residual(r_c), np.zeros(len(r_c)), u_c, local.node_dofs,
        geometry.normal, geometry.gap, lam, stiffness, tol_v,
        load_norm=load_norm)
    interior_error = checked["interior_norm"] / max(load_norm, 1e-300)
    verification["interior_equilibrium"] = float(interior_error)
    verification["finite"] = bool(verification["finite"]
                                  and checked["finite"])
    if not interior_error <= tol_v or not checked["finite"]:
        verification["failed"].append("interior_equilibrium")
        verification["passed"] = False
    return verification


class _Residual:
    """``K @ u`` for :func:`~solver.contact.verify.verify_contact` when
    the residual K u − f on Γc's rows was computed on the ranks: returns
    it, whatever u (f is then 0)."""

    def __init__(self, residual):
        self.residual = residual

    def __matmul__(self, u):
        return self.residual


#: VTK type names of the pieces' arrays (NumPy kind, bytes) -> name.
VTK_TYPES = {("f", 8): "Float64", ("i", 8): "Int64", ("i", 4): "Int32",
             ("u", 1): "UInt8"}


def write_pvtu(path, pieces, mortar=False):
    """The ``.pvtu`` index of the pieces ``pieces`` (file names beside it,
    one per rank; point arrays as :func:`piece_mesh` writes them) that
    ParaView opens as one unstructured grid; ``mortar``: a two-body
    folder's, whose pieces also hold the mortar forces."""
    fields = "".join(
        f'      <PDataArray type="{kind}" Name="{name}" '
        f'NumberOfComponents="{components}"/>\n'
        for name, kind, components in POINT_ARRAYS
        + (MORTAR_ARRAYS if mortar else ()))
    sources = "".join(f'    <Piece Source="{os.path.basename(p)}"/>\n'
                      for p in pieces)
    text = ('<?xml version="1.0"?>\n'
            '<VTKFile type="PUnstructuredGrid" version="0.1" '
            'byte_order="LittleEndian">\n'
            '  <PUnstructuredGrid GhostLevel="0">\n'
            f'    <PPointData>\n{fields}    </PPointData>\n'
            '    <PPoints>\n      <PDataArray type="Float64" '
            'NumberOfComponents="3"/>\n    </PPoints>\n'
            f'{sources}  </PUnstructuredGrid>\n</VTKFile>\n')
    with open(path, "w") as stream:
        stream.write(text)


#: The pieces' point arrays: (name, VTK type, components).
POINT_ARRAYS = (("u", "Float64", 3), ("node", "Int64", 1),
                ("contact_force", "Float64", 1),
                ("in_contact", "Int32", 1),
                ("initial_gap", "Float64", 1))

#: A two-body folder's further point array: the mortar forces in u, K u − f
#: (:func:`~.mortar_folder.in_bodies`).
MORTAR_ARRAYS = (("mortar_force", "Float64", 3),)


def _reader(path, comm):
    """A binary viewer through MPI-IO: each rank reads its own part of the
    file (PETSc's plain binary viewer reads every part on rank 0 and sends
    it on)."""
    from petsc4py import PETSc

    return PETSc.Viewer().createMPIIO(path, "r", comm=comm)


@command("load_partitioned")
def _load(service, payload, local):
    """Every rank: its rows of K and f by MatLoad / VecLoad (the rows
    ``ranges[rank]``); returns K's largest diagonal entry (the pivot
    test's scale)."""
    from petsc4py import PETSc

    comm = PETSc.COMM_WORLD
    ranges = [tuple(r) for r in payload["ranges"]]
    service.objects["ranges"] = ranges
    old = service.objects.pop(KEY, {})  # an earlier solve's in this process
    for item in old.values():  # PETSc's objects; the rest (R, the
        if hasattr(item, "destroy"):  # geometry) goes with the dict
            item.destroy()
    a, b = ranges[service.rank]
    n = ranges[-1][1]
    folder = payload["folder"]
    A = PETSc.Mat().create(comm=comm)
    A.setSizes(((b - a, n), (b - a, n)), bsize=payload["dim"])
    A.setType(PETSc.Mat.Type.AIJ)
    viewer = _reader(os.path.join(folder, "K.petsc"), comm)
    A.load(viewer)
    viewer.destroy()
    service.mark("load_partitioned.K")
    f = PETSc.Vec().create(comm=comm)
    f.setSizes((b - a, n))
    f.setType(PETSc.Vec.Type.MPI)
    viewer = _reader(os.path.join(folder, "f.petsc"), comm)
    f.load(viewer)
    viewer.destroy()
    x, rhs = A.createVecs()
    service.objects[KEY] = dict(A=A, x=x, b=rhs, f=f)
    service.objects.setdefault("counts", {}).update(
        rows=b - a, nnz=int(A.getInfo(PETSc.Mat.InfoType.LOCAL)[
            "nz_used"]))
    d = A.getDiagonal()
    scale = d.max()[1]
    d.destroy()
    return float(scale)


def _on_rows(vec, rows):
    """(positions in ``rows`` this rank owns, their values of ``vec``)."""
    a, b = vec.getOwnershipRange()
    mine = np.flatnonzero((rows >= a) & (rows < b))
    return mine, vec.getArray()[rows[mine] - a].copy()


def _gather_rows(service, vec, rows):
    """``vec`` at the global ``rows`` on rank 0 (None elsewhere)."""
    parts = service.comm.gather(_on_rows(vec, rows), root=0)
    if not service.root:
        return None
    out = np.zeros(len(rows))
    for idx, vals in parts:
        out[idx] = vals
    return out


#: :func:`_gather_rows` for the other modules of the partitioned solve.
gather_rows = _gather_rows


@command("partitioned_rhs")
def _rhs(service, payload, local):
    """g̃ = f_c − K_ci K_ii⁻¹ f_i on rank 0 (thesis (66)'s condensed load)
    from the loaded f: one interior solve, K y, and Γc's rows gathered."""
    obj, rows = service.objects[KEY], np.asarray(payload["rows"])
    y = interior(service, obj, obj["f"].copy(), rows, np.zeros(len(rows)))
    t = obj["f"].duplicate()
    obj["A"].mult(y, t)  # (K y)_c = K_ci y_i
    t.aypx(-1.0, obj["f"])  # f − K y
    out = _gather_rows(service, t, rows)
    t.destroy()
    return out


@command("partitioned_displacement")
def _displacement(service, payload, local):
    """u with u_c (``local`` on rank 0) and K_ii u_i = f_i − K_ic u_c, kept
    on the ranks as ``objects[KEY]["u"]``; returns, on rank 0, Γc's rows of
    K u − f, the norm of the others and whether u is finite."""
    obj, rows = service.objects[KEY], np.asarray(payload["rows"])
    u_c = service.comm.bcast(local, root=0)
    x = interior(service, obj, obj["f"].copy(), rows, u_c)
    if "u" in obj:
        obj.pop("u").destroy()
    obj["u"] = x.copy()
    r = obj["f"].duplicate()
    obj["A"].mult(obj["u"], r)
    r.axpy(-1.0, obj["f"])
    residual_c = _gather_rows(service, r, rows)
    a, b = r.getOwnershipRange()
    values = r.getArray().copy()
    mine = rows[(rows >= a) & (rows < b)] - a
    values[mine] = 0.0
    from mpi4py import MPI

    square = service.comm.reduce(float(values @ values), op=MPI.SUM, root=0)
    finite = service.comm.reduce(bool(np.isfinite(obj["u"].getArray()).all()),
                                 op=MPI.LAND, root=0)
    r.destroy()
    if not service.root:
        return None
    return dict(residual_c=residual_c, interior_norm=float(np.sqrt(square)),
                finite=bool(finite))


def _local_mesh(folder, rank, size, root_share=ROOT_SHARE):
    """This rank's share of the cells (:func:`shares` of the cells sorted
    by their smallest node: each cell in one piece, neighbours together;
    rank 0's ``root_share``, as its share of the rows) and their nodes,
    memory-mapped from the folder."""
    cells = np.load(os.path.join(folder, "cells.npy"), mmap_mode="r")
    lo, hi = shares(len(cells), size, root_share)[rank:rank + 2]
    cells = np.array(cells[lo:hi])
    points = np.unique(cells)
    coordinates = np.array(np.load(os.path.join(folder, "nodes.npy"),
                                   mmap_mode="r")[points])
    return points, np.searchsorted(points, cells), coordinates


def _values_at(service, vec, rows):
    """``vec`` (distributed) at the global ``rows`` on this rank: its own
    rows read, the others through one PETSc scatter (collective)."""
    from petsc4py import PETSc

    target = PETSc.Vec().createSeq(len(rows), comm=PETSc.COMM_SELF)
    index = PETSc.IS().createGeneral(np.asarray(rows, PETSc.IntType),
                                     comm=PETSc.COMM_SELF)
    scatter = PETSc.Scatter().create(vec, index, target, None)
    scatter.scatter(vec, target, addv=PETSc.InsertMode.INSERT,
                    mode=PETSc.ScatterMode.FORWARD)
    out = target.getArray().copy()
    for item in (scatter, index, target):
        item.destroy()
    return out


@command("partitioned_write")
def _write(service, payload, local):
    """Every rank writes ``result-RANK.vtu``: its share of the cells, u, and
    the contact
    fields at its contact nodes (broadcast from rank 0: Γc only). Returns
    the pieces' paths on rank 0."""
    import meshio

    folder, dim = payload["folder"], payload["dim"]
    points, cells, coordinates = _local_mesh(
        folder, service.rank, service.size,
        payload.get("root_share", ROOT_SHARE))
    rows = (points[:, None] * dim + np.arange(dim)).ravel()
    u_vec, force = in_bodies(service.objects[KEY])  # two bodies: T⁻¹v
    u = _values_at(service, u_vec, rows).reshape(-1, dim)
    n = len(points)
    if payload.get("fields"):  # on the ranks: (λ, s) at a node's 1st rows
        values = _values_at(service, service.objects[KEY]["fields"],
                            rows).reshape(-1, dim)
        touched = ~np.isnan(values[:, 1])
        contact = dict(node=points[touched], force=values[touched, 0],
                       gap=values[touched, 1], in_contact=values[
                           touched, 0] > payload["threshold"])
    else:
        contact = service.comm.bcast(local, root=0)
    at = np.searchsorted(points, contact["node"])
    mine = (at < n) & (points[np.minimum(at, n - 1)] == contact["node"])
    data = dict(u=np.c_[u, np.zeros((n, 3 - dim))], node=original_nodes(
        folder, points), contact_force=np.zeros(n), in_contact=np.zeros(
            n, np.int32), initial_gap=np.full(n, np.nan))
    data["contact_force"][at[mine]] = contact["force"][mine]
    data["in_contact"][at[mine]] = contact["in_contact"][mine]
    data["initial_gap"][at[mine]] = contact["gap"][mine]
    if force is not None:  # two bodies: the mortar forces in u
        data["mortar_force"] = np.c_[_values_at(service, force, rows)
                                     .reshape(-1, dim), np.zeros((n, 3 - dim))]
    if u_vec is not service.objects[KEY]["u"]:
        u_vec.destroy()
        if force is not None:
            force.destroy()
    name = payload.get("name", "result")  # a friction step's: step_KKKK
    path = os.path.join(payload["outdir"], f"{name}-{service.rank}.vtu")
    # a temporary name until complete (swept by the output folder if cut
    # short), so that no piece looks complete before it is
    tmp = os.path.join(payload["outdir"], f".tmp-{name}-{service.rank}.vtu")
    try:
        meshio.write(tmp, meshio.Mesh(
            np.c_[coordinates, np.zeros((n, 3 - dim))],
            [(payload["kind"], cells)], point_data=data), file_format="vtu")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    names = service.comm.gather(path, root=0)
    return names
