"""Two bodies (dual mortar) on the partitioned folder under mpiexec
(issue 33, point 4 for mortar; solver/mpi/convert_mortar.py,
solver/mpi/mortar_folder.py): ``python -m solver convert X.npz DIR``
writes K and f unchanged plus E of T⁻¹ = I + E, and ``mpiexec -n N python
-m solver DIR --engine petsc --system full --ksp gamg`` solves the
nodewise problem in v = Tu on K̂ = PᵀKP, P = T⁻¹Rᵀ, every rank holding
only its rows of K, f and E and the contact nodes of its node range.

References, independent of the distributed path: the serial engine's
``solver.solve(problem)`` on the same ``.npz`` (the whole K̃ = T⁻ᵀKT⁻¹
condensed onto the slave nodes by scipy's factorisation): u over every
node (VTK's reader of the ``.pvtu``), the nodal contact forces D_jj λ_j
and the contact (and stick, slip) sets; the mortar forces in u against
K u − f of the serial u (the bodies' own K and f, on every free DOF: the
interface forces, slave and master, are all that is left of it). 2D here:
the curved block on a block (partial contact); 3D in
test_mpi_two_body_folder3d.py. PETSc runs only in the mpiexec
subprocesses."""

import json

import numpy as np
import pytest

from solver import load_problem, save_problem, solve
from tet_two_body import stacked_boxes
from test_mpi import REASON, mpirun
from test_mpi_distributed import read_pvtu
from tri_elasticity import stacked_blocks

pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))

RTOL = 1e-8
FRICTION, STEPS = 0.3, 3
FULL = ["--engine", "petsc", "--system", "full", "--ksp", "gamg"]


def converted(problem, root):
    """(the problem reloaded from its .npz, the folder) by the command
    line."""
    from solver.cli import main

    npz = root / "p.npz"
    save_problem(npz, problem)
    assert main(["convert", str(npz), str(root / "p")]) == 0
    return load_problem(npz), root / "p"


@pytest.fixture(scope="module")
def curved(tmp_path_factory):
    """2D: the upper block's bottom curved (contact in the middle only:
    15 of 25 slave nodes), E 1 on 3, ν 0.3 / 0.2."""
    return converted(stacked_blocks(
        n_upper=(24, 8), n_lower=(40, 10), materials=((1.0, 0.3),
                                                      (3.0, 0.2)),
        slave="upper", curvature=4e-3)[0], tmp_path_factory.mktemp("tb2"))


def run(folder, out, ranks, *options):
    code, stdout, err = mpirun(ranks, ["-m", "solver", folder, *FULL,
                                       "-o", out, *options])
    assert code == 0, err[-2000:]
    assert stdout.startswith("converged"), stdout
    return json.loads((out / "summary.json").read_text())


def point_field(path, name, n_nodes, dim):
    """The point array ``name`` over all nodes of the ``.pvtu``."""
    vtk = pytest.importorskip("vtk")
    from vtk.util.numpy_support import vtk_to_numpy

    reader = vtk.vtkXMLPUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    data = reader.GetOutput().GetPointData()
    out = np.full((n_nodes, dim), np.nan)
    out[vtk_to_numpy(data.GetArray("node"))] = vtk_to_numpy(
        data.GetArray(name))[:, :dim]
    return out


def positions(problem, nodes):
    order = np.argsort(problem.contact_nodes)
    return order[np.searchsorted(problem.contact_nodes, nodes, sorter=order)]


def check_rows(folder, summary, dim):
    """Every rank holds its own rows of E and the contact nodes of its
    node range, no more (as one body's folder)."""
    per_rank = summary["engine"]["per_rank"]
    starts = np.r_[0, np.cumsum([r["rows"] for r in per_rank])]
    rows = np.load(folder / "mortar" / "E_row.npy")
    nodes = np.load(folder / "contact" / "node.npy")
    assert [r["E_entries"] for r in per_rank] == [
        int(np.count_nonzero((rows >= a) & (rows < b)))
        for a, b in zip(starts[:-1], starts[1:])]
    assert [r["contact_nodes"] for r in per_rank] == [
        int(np.count_nonzero((nodes >= a // dim) & (nodes < b // dim)))
        for a, b in zip(starts[:-1], starts[1:])]


def check_frictionless(problem, reference, folder, out, summary):
    n_nodes, dim = problem.nodes.shape
    u, cells = read_pvtu(out / "result.pvtu", n_nodes, dim)
    ref = reference.displacement
    assert np.abs(u - ref).max() <= RTOL * np.abs(ref).max()
    assert cells == len(problem.cells)
    # the mortar forces in u: K u − f of the serial u on every free DOF
    force = point_field(out / "result.pvtu", "mortar_force", n_nodes, dim)
    residual = np.zeros((n_nodes, dim))
    node, comp = problem.dof_map[:, 0], problem.dof_map[:, 1]
    residual[node, comp] = problem.K @ reference.u - problem.f
    assert np.abs(force[node, comp] - residual[node, comp]).max() \
        <= RTOL * np.abs(residual).max()
    with np.load(out / "contact.npz") as contact:
        at = positions(problem, contact["node"])
        z = reference.mortar_D[at] * reference.contact_pressure[at]
        assert np.abs(contact["force"] - z).max() <= RTOL * np.abs(z).max()
        assert np.array_equal(contact["in_contact"],
                              reference.in_contact[at])
    assert reference.in_contact.sum() == summary["n_in_contact"]
    v = summary["verification"]
    assert v["passed"] and v["reduced_over_ranks"]
    check_rows(folder, summary, dim)


def frictionless_on(problem, folder, tmp_path, rank_counts, krylov=None):
    """The serial run's answer on each of ``rank_counts`` (check_…), the
    same Newton count on every rank count; returns the reference.
    ``krylov``: a dict that receives each rank count's CG iterations per
    Newton system."""
    reference = solve(problem)
    assert reference.success
    counts = set()
    for ranks in rank_counts:
        out = tmp_path / f"n{ranks}"
        summary = run(folder, out, ranks)
        check_frictionless(problem, reference, folder, out, summary)
        counts.add(summary["nit"])
        if krylov is not None:
            krylov[ranks] = summary["engine"]["krylov_per_newton"]
    assert len(counts) == 1
    return reference


def test_frictionless_1_2_4_ranks_as_the_serial_engine(curved, tmp_path):
    """2D: u, the contact forces (in v: D_jj λ_j; in u: the mortar
    forces) and the contact set (partial: 15 of 25 slave nodes) of the
    serial run to 1e-8 on 1, 2 and 4 ranks (measured ≤ 1.3e-13)."""
    problem, folder = curved
    reference = frictionless_on(problem, folder, tmp_path, (1, 2, 4))
    assert 0 < reference.in_contact.sum() < problem.n_contact


def check_friction(problem, reference, out, summary):
    n_nodes, dim = problem.nodes.shape
    assert summary["converged"] and summary["steps_completed"] == STEPS
    for k in range(STEPS):
        u, _ = read_pvtu(out / "steps" / f"step_{k + 1:04d}.pvtu",
                         n_nodes, dim)
        ref = reference.displacement[k]
        assert np.abs(u - ref).max() <= RTOL * np.abs(ref).max()
    force = point_field(out / "result.pvtu", "mortar_force", n_nodes, dim)
    residual = np.zeros((n_nodes, dim))
    node, comp = problem.dof_map[:, 0], problem.dof_map[:, 1]
    residual[node, comp] = problem.K @ reference.u[-1] - problem.f
    assert np.abs(force[node, comp] - residual[node, comp]).max() \
        <= RTOL * np.abs(residual).max()
    with np.load(out / "contact.npz") as contact:
        at = positions(problem, contact["node"])
        for key in ("friction_traction", "contact_force"):
            theirs = np.asarray(reference[key])[:, at]
            assert np.abs(contact[f"step_{key}"] - theirs).max() \
                <= RTOL * np.abs(theirs).max(), key
        for key in ("stick", "slip", "in_contact"):
            assert np.array_equal(contact[f"step_{key}"], np.asarray(
                reference[key])[:, at]), key
    assert summary["n_stick"] > 0 and summary["n_slip"] > 0
    v = summary["verification"]
    assert v["passed"] and v["friction_bound_violation"] <= 1e-8


def friction_on(problem, folder, tmp_path, coulomb, ranks):
    """f_c 0.3 over 3 load steps on ``ranks`` against the serial run
    (check_friction)."""
    reference = solve(problem, friction=FRICTION, steps=STEPS,
                      coulomb=coulomb)
    assert reference.success
    out = tmp_path / "fric"
    summary = run(folder, out, ranks, "--friction", str(FRICTION),
                  "--steps", str(STEPS), "--coulomb", coulomb)
    check_friction(problem, reference, out, summary)
    check_rows(folder, summary, problem.dim)


def test_friction_lagged_2_ranks_as_the_serial_engine(curved, tmp_path):
    """2D, f_c 0.3 over 3 load steps: every step's u, the friction and
    contact forces and the last step's mortar forces to 1e-8, the same
    stick, slip and contact sets, stick and slip nodes both present."""
    friction_on(*curved, tmp_path, "lagged", 2)


def test_refusals_are_one_line(curved, tmp_path, capsys):
    """The condensed path on a two-body folder (its Schur complement is of
    K, not of the coupled K̃) and the conversion of a body held by contact
    only: each one line, exit code 2, before any collective step."""
    from solver import SolverError
    from solver.cli import main

    _, folder = curved
    with pytest.raises(SolverError, match="does not take the coupling"):
        solve(load_problem(folder), engine="petsc")
    floating = stacked_boxes(slave="upper", pressure=1e-3)[0]
    npz = tmp_path / "floating.npz"
    save_problem(npz, floating)
    assert main(["convert", str(npz), str(tmp_path / "f")]) == 2
    err = capsys.readouterr().err
    assert "held by contact only" in err and len(err.strip().splitlines()) \
        == 1
    # a two-body folder missing a file of mortar/: one line at load
    import shutil

    broken = tmp_path / "broken"
    shutil.copytree(folder, broken)
    (broken / "mortar" / "E_val.npy").unlink()
    with pytest.raises(SolverError, match="missing mortar/E_val.npy"):
        load_problem(broken)


#: Three solves in one mpiexec launch, each followed by the product
#: algorithm PETSc's options then hold for GAMG's Galerkin products.
PRODUCTS = """
import json, sys
import solver
from solver.mpi.engine import spmd

def main(folders, out):
    from petsc4py import PETSc

    said = []
    for folder in folders:
        r = solver.solve(solver.load_problem(folder), engine="petsc",
                         system="full", ksp="gamg")
        said.append([bool(r.success),
                     PETSc.Options().getString("matptap_via", "")])
    with open(out, "w") as stream:
        json.dump(said, stream)

spmd(main, json.loads(sys.argv[1]), sys.argv[2])
"""


def test_gamg_products_by_body_count(curved, refined_block, tmp_path,
                                     monkeypatch):
    """GAMG's Galerkin products on 2 ranks: PETSc's "scalable" on two
    bodies (each body's rigid modes make GAMG's prolongator twice as wide,
    where "allatonce" took ten times as long: benchmarks/README.md), the
    memory-lean "allatonce" on one body (issue 33's 0.6× memory at 2
    ranks), switched back and forth by solves in one launch; a user's
    ``-matptap_via`` in $PETSC_OPTIONS wins over both."""
    _, two = curved
    (tmp_path / "one").mkdir()
    _, one = converted(refined_block(1), tmp_path / "one")
    script = tmp_path / "products.py"
    script.write_text(PRODUCTS)
    folders = json.dumps([str(two), str(one), str(two)])
    for user, expected in ((None, ["scalable", "allatonce", "scalable"]),
                           ("nonscalable", ["nonscalable"] * 3)):
        if user:
            monkeypatch.setenv("PETSC_OPTIONS", f"-matptap_via {user}")
        out = tmp_path / f"said-{user}.json"
        code, _, err = mpirun(2, [script, folders, out])
        assert code == 0, err[-2000:]
        said = json.loads(out.read_text())
        assert [ok for ok, _ in said] == [True] * 3, said
        assert [via for _, via in said] == expected, said
