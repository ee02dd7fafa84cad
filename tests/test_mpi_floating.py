"""Bodies held only by contact on the PETSc engine (issue 31): K_F (K
with r DOFs held, solver/linalg/kernel.py) factorised by MUMPS with its
Schur set on Γc, the modes' amplitudes α and the equilibrium
Rᵀ(f + Pᵀr) = 0 of solver/contact/strategies/floating.py, on 1 and 2
ranks (``mpiexec -n 1``, ``-n 2``).

References: the serial engine in this process on the same problem and
the same iteration (the same u to 1e-8 relative to max|u|, the same
Newton counts); statics (the contact forces balance the load: the force
P on the Hertz half-cylinder, the weight of the block on the floor, to
1e-10); a K with a kernel beyond the rigid motions (two blocks in one
body, six zero pivots, three rigid motions of the whole) refused by
MUMPS's own null-pivot count as any singular K; the full system refused
by its rule. Each rank count runs every case in one launch (:data:`DRIVER`).
"""

import json
import pathlib

import numpy as np
import pytest

import solver
from test_export3d import export_module
from test_mpi import REASON, mpirun
from tri_elasticity import floor_block, two_floor_blocks

pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))

ROOT = pathlib.Path(__file__).resolve().parents[1]
P = 1739.6  # the Hertz cylinder's load (tests/test_floating.py)
P_SPHERE = 36.63  # the whole sphere's, its quarter model carries P/4
RTOL = 1e-8

#: name -> (problem, options of solver.solve)
CASES = {
    "hertz": ("hertz", {}),
    "sphere": ("sphere", {}),
    "block": ("block", {}),
    "block-friction": ("block", dict(friction=0.3, steps=3)),
    "held-by-friction": ("pushed", dict(friction=0.5, coulomb="implicit",
                                        steps=3)),
}

DRIVER = """
import json, sys, warnings
import numpy as np
import solver
from solver.mpi.engine import spmd

def main(paths, cases, out):
    said, arrays = {}, {}
    for name, (problem, options) in cases.items():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = solver.solve(solver.load_problem(paths[problem]),
                             engine="petsc", **options)
        said[name] = [bool(r.success), r.message, int(r.njev),
                      r.engine["ranks"], r.rigid_body["modes"]]
        arrays[name + "/u"] = r.u
        arrays[name + "/lambda"] = np.asarray(r.contact_force)
        if "total_contact_force" in r:
            arrays[name + "/total"] = r.total_contact_force
    for name, problem, options in (("two-blocks", "two", {}),
                                   ("full", "block", dict(system="full"))):
        try:
            solver.solve(solver.load_problem(paths[problem]),
                         engine="petsc", **options)
            said[name] = ["solved"]
        except solver.SolverError as exc:
            said[name] = [str(exc), isinstance(exc, solver.errors.
                                               ProblemError)]
    json.dump(said, open(out + ".json", "w"))
    np.savez(out + ".npz", **arrays)

spmd(main, json.loads(sys.argv[1]), json.loads(sys.argv[2]), sys.argv[3])
"""


@pytest.fixture(scope="module")
def paths(tmp_path_factory):
    """The force-loaded Hertz half-cylinder and quarter sphere (a/h = 4;
    load='force'), the thesis
    block on the floor under its weight (block_on_floor.py), the 2 × 1
    block pushed sideways and down, two blocks in one body."""
    folder = tmp_path_factory.mktemp("floating_mpi")
    out = dict(hertz=folder / "hertz.npz", sphere=folder / "sphere.npz",
               block=folder / "block.npz")
    export_module().export_only(
        ROOT / "sfepy_problems" / "hertz_cylinder.py",
        mesh=str(ROOT / "meshes" / "hertz.mesh"), output=str(out["hertz"]),
        load="force", P=P)
    export_module().export_only(
        ROOT / "sfepy_problems" / "hertz_sphere.py",
        mesh=str(ROOT / "meshes" / "hertz_sphere_4.mesh"),
        output=str(out["sphere"]), load="force", P=P_SPHERE)
    export_module().export_only(
        ROOT / "sfepy_problems" / "block_on_floor.py",
        mesh=str(ROOT / "meshes" / "block_454.mesh"),
        output=str(out["block"]))
    out["pushed"] = solver.save_problem(folder / "pushed.npz",
                                        floor_block(load=(0.2, -1.0)))
    out["two"] = solver.save_problem(folder / "two.npz", two_floor_blocks())
    return {k: str(v) for k, v in out.items()}


@pytest.fixture(scope="module", params=[1, 2])
def runs(request, paths, tmp_path_factory):
    out = str(tmp_path_factory.mktemp("runs") / f"n{request.param}")
    code, _, err = mpirun(request.param, ["-c", DRIVER, json.dumps(paths),
                                          json.dumps(CASES), out])
    assert code == 0, err[-3000:]
    with np.load(out + ".npz") as data:
        arrays = dict(data)
    return request.param, json.loads(open(out + ".json").read()), arrays


@pytest.fixture(scope="module")
def serial(paths):
    """The serial engine's answers, the reference."""
    out = {}
    for name, (problem, options) in CASES.items():
        r = solver.solve(solver.load_problem(paths[problem]), **options)
        assert r.success, r.message
        out[name] = r
    return out


@pytest.mark.parametrize("name", list(CASES))
def test_same_answer_as_the_serial_engine(runs, serial, name):
    """The same u to 1e-8 and the same Newton count, on every rank count;
    the same rigid-body modes (2 for the half-cylinder pinned in u_x at
    its top centre, 1 for the quarter sphere free along its axis, 3 for
    the blocks)."""
    n, said, arrays = runs
    success, message, njev, ranks, modes = said[name]
    assert success, message
    ref = serial[name]
    u = arrays[name + "/u"]
    assert np.abs(u - ref.u).max() <= RTOL * np.abs(ref.u).max()
    assert njev == ref.njev and ranks == n
    assert modes == ref.rigid_body["modes"] == dict(hertz=2, sphere=1).get(
        name, 3)


@pytest.mark.parametrize("name", ["hertz", "sphere", "block"])
def test_contact_force_balances_the_load(runs, paths, name):
    """Total contact force = the load to 1e-10: P on the half-cylinder,
    P/4 on the quarter sphere, the weight (−Σ f_y) of the block; nothing
    in the other directions."""
    _, _, arrays = runs
    problem = solver.load_problem(paths[name])
    load = dict(hertz=P, sphere=P_SPHERE / 4).get(name) or \
        -problem.f[problem.dof_map[:, 1] == 1].sum()
    total = arrays[name + "/total"]
    axis = problem.dim - 1
    assert abs(total[axis] - load) <= 1e-10 * load
    assert np.abs(np.delete(total, axis)).max() <= 1e-10 * load


def test_friction_normal_forces_balance_the_weight(runs, paths):
    """With friction too, the last step's normal forces sum to the
    block's weight (flat floor: the normals are vertical)."""
    _, _, arrays = runs
    problem = solver.load_problem(paths["block"])
    weight = -problem.f[problem.dof_map[:, 1] == 1].sum()
    total = arrays["block-friction/lambda"][-1].sum()
    assert abs(total - weight) <= 1e-10 * weight


def test_kernel_beyond_the_rigid_modes_is_refused(runs):
    """Two blocks in one body: K_F (three DOFs held) is still singular;
    MUMPS's null-pivot count refuses it with the serial engine's words
    (a ProblemError: the command line's exit 2)."""
    _, said, _ = runs
    text, input_error = said["two-blocks"]
    assert input_error
    assert text.startswith("K_data: K is not positive definite (singular "
                           "stiffness: is the body supported?)"), text
    assert "pivot(s) of MUMPS's LDLᵀ factorisation" in text, text


def test_full_system_is_refused(runs):
    text, input_error = runs[1]["full"]
    assert not input_error and "\n" not in text
    assert text.startswith("system='full' is not supported for 2D, rigid, "
                           "held by contact only, frictionless, petsc "
                           "engine"), text


def test_command_line_prints_the_contact_force(paths, tmp_path):
    """``mpiexec -n 2 python -m solver block.npz --engine petsc``: exit 0,
    the total contact force and the rigid-body motion printed once and in
    summary.json, as on the serial engine."""
    out = tmp_path / "o"
    code, stdout, err = mpirun(2, ["-m", "solver", paths["block"],
                                   "--engine", "petsc", "-o", out])
    assert code == 0, err
    assert stdout.count("verification      passed") == 1
    assert "3 modes held by contact only" in stdout
    summary = json.loads((out / "summary.json").read_text())
    problem = solver.load_problem(paths["block"])
    weight = -problem.f[problem.dof_map[:, 1] == 1].sum()
    np.testing.assert_allclose(summary["total_contact_force"],
                               [0.0, weight], rtol=0, atol=1e-10 * weight)
    assert summary["rigid_body_motion"]["modes"] == 3
    assert summary["engine"]["ranks"] == 2
