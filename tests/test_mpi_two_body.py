"""Two bodies by the dual mortar on the PETSc engine from a ``.npz``
(issue 33): the nodewise problem in v = Tu (solver/contact/two_body.py)
laid out by the bodies' mesh, condensed on MUMPS's Schur complement
(frictionless and with friction, projection formulation) or on the full
system by CG + GAMG with the two bodies' near-null space (and hypre,
MUMPS), on 1, 2 and 4 ranks (``mpiexec -n 4`` oversubscribed).

The reference is the serial engine in this process on the same problem
and options: the same u, contact forces, mortar tractions (and friction
tractions) to 1e-8 relative to their largest entry, the same contact and
stick sets in every load step, the serial run's own verification on every
node (finite, feasible, complementary, within the friction bound).
Problems assembled without SfePy (tests/tri_elasticity.py,
tests/tet_two_body.py): the non-matching 2D patch and the Hertz
cylinders squeezed then shifted, the jittered 3D boxes (510 DOFs)
squeezed then shifted, the lower box as slave with the upper box held by contact only
(six rigid modes, the engine's ``held_condensation``), the upper cylinder
held by contact only under friction (its frictionless twin is not
compared: the upper cylinder's spin is held only weakly, and the serial
backends' answers differ among themselves there). The command line under
mpiexec writes the serial run's files. Each rank count is one launch
(:data:`DRIVER`).
"""

import json
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

import solver
from test_floating_two_body import MATERIALS, P, R
from test_mpi import REASON, mpirun
from tet_two_body import stacked_boxes
from tri_elasticity import stacked_blocks, two_cylinders

pytestmark = pytest.mark.skipif(REASON is not None, reason=str(REASON))

RTOL = 1e-8

#: name -> (problem, options of solver.solve on the petsc engine)
CASES = {
    "patch": ("patch", {}),
    "patch-friction": ("patch", dict(friction=0.3)),
    "patch-gamg": ("patch", dict(system="full", ksp="gamg")),
    "patch-hypre": ("patch", dict(system="full", ksp="hypre")),
    "patch-mumps": ("patch", dict(system="full", ksp="mumps")),
    "cylinders": ("cylinders", {}),
    "cylinders-friction": ("cylinders", dict(friction=0.3)),
    "boxes": ("boxes", {}),
    "boxes-friction": ("boxes", dict(friction=0.3)),
    "boxes-gamg": ("boxes", dict(system="full", ksp="gamg")),
    "boxes-floating": ("floating-box", {}),
    "cylinder-floating-friction": ("floating-cylinder",
                                   dict(friction=0.3, steps=4)),
}

#: The result's arrays compared with the serial run's.
FIELDS = ("u", "contact_force", "traction", "in_contact")
FRICTION_FIELDS = ("friction_traction", "stick")

DRIVER = """
import json, sys, warnings
import numpy as np
import solver
from solver.mpi.engine import spmd

def main(paths, cases, fields, out):
    said, arrays = {}, {}
    for name, (problem, options) in cases.items():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = solver.solve(solver.load_problem(paths[problem]),
                             engine="petsc", **options)
        said[name] = [bool(r.success), r.message, r.engine["ranks"],
                      r.engine["system"], r.engine["ksp"],
                      r.verification["passed"],
                      len(r.engine.get("ksp_iterations", []))]
        for key in fields:
            if key in r:
                arrays[f"{name}/{key}"] = np.asarray(r[key], float)
    for name in ("discrete", "pulled"):  # refused: one line each
        problem = solver.examples.two_dof_bar() if name == "discrete" \
            else solver.load_problem(paths[name])
        try:
            solver.solve(problem, engine="petsc")
            said[name] = ["solved"]
        except solver.SolverError as exc:
            said[name] = [str(exc), type(exc).__name__]
    json.dump(said, open(out + ".json", "w"))
    np.savez(out + ".npz", **arrays)

spmd(main, *map(json.loads, sys.argv[1:4]), sys.argv[4])
"""


def problems():
    """name -> problem (assembled here, module docstring)."""
    return {
        "patch": stacked_blocks(n_upper=(12, 6), n_lower=(20, 8),
                                materials=((1.0, 0.3), (3.0, 0.2)),
                                slave="upper", shift=2e-4)[0],
        "cylinders": two_cylinders((1.0, 1.5), ((1.0, 0.3), (2.0, 0.25)),
                                   h0=0.008, squeeze=0.01,
                                   shift=0.004)[0],
        "boxes": stacked_boxes(n_upper=(5, 5, 2), n_lower=(6, 6, 2),
                               shift=(1e-3, 5e-4))[0],
        "floating-box": stacked_boxes(pressure=0.01, slave="lower",
                                      squeeze=0.0)[0],
        "floating-cylinder": two_cylinders(R, MATERIALS, force=P,
                                           h0=0.008)[0],
        "pulled": two_cylinders(R, MATERIALS, force=-P, h0=0.008)[0],
    }


@pytest.fixture(scope="module")
def paths(tmp_path_factory):
    folder = tmp_path_factory.mktemp("two_body_mpi")
    return {name: str(solver.save_problem(folder / f"{name}.npz", problem))
            for name, problem in problems().items()}


@pytest.fixture(scope="module")
def serial(paths):
    """The serial engine's answers (the reference), from the same files."""
    out = {}
    for name, (problem, options) in CASES.items():
        options = {k: v for k, v in options.items() if k != "ksp"}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = solver.solve(solver.load_problem(paths[problem]), **options)
        assert r.success and r.verification["passed"], (name, r.message)
        out[name] = r
    return out


@pytest.fixture(scope="module", params=[1, 2, 4])
def runs(request, paths, tmp_path_factory):
    out = str(tmp_path_factory.mktemp("runs") / f"n{request.param}")
    code, _, err = mpirun(request.param, [
        "-c", DRIVER, json.dumps(paths), json.dumps(CASES),
        json.dumps(FIELDS + FRICTION_FIELDS), out])
    assert code == 0, err[-3000:]
    with np.load(out + ".npz") as data:
        arrays = dict(data)
    return request.param, json.loads(open(out + ".json").read()), arrays


@pytest.mark.parametrize("name", list(CASES))
def test_same_answer_as_the_serial_engine(runs, serial, name):
    """u (in the bodies' DOFs), the contact forces and the mortar
    tractions (friction: the friction tractions too, every load step)
    within 1e-8 of the serial run's, relative to the largest entry; the
    same contact set (and stick set) in every step; verified on every
    node; the engine entry names the ranks and the system."""
    n, said, arrays = runs
    success, message, ranks, system, ksp, passed, solves = said[name]
    assert success and passed, message
    assert ranks == n
    options = CASES[name][1]
    assert system == ("full" if options.get("system") == "full"
                      else "condensed")
    assert ksp == options.get("ksp", "mumps")
    if system == "full":
        assert solves >= 1
    ref = serial[name]
    friction = "friction" in options
    for key in FIELDS + (FRICTION_FIELDS if friction else ()):
        mine, theirs = arrays[f"{name}/{key}"], np.asarray(ref[key], float)
        assert mine.shape == theirs.shape, key
        if key in ("in_contact", "stick"):
            assert np.array_equal(mine, theirs), key
        else:
            scale = np.abs(theirs).max()
            assert np.abs(mine - theirs).max() <= RTOL * scale, key
    if friction:  # at the end: 13 stick (patch); 6 stick, 9 slip
        # (cylinders); 2 stick, 34 slip (boxes); 17 stick, 3 slip
        assert np.asarray(ref.stick)[-1].any()


def test_refusals_are_the_serial_ones(runs, paths):
    """A problem without a mesh stays on the serial engine, by its row
    (one line); the upper cylinder pulled away from the lower one (no
    contact resists its upward motion) is refused by the serial engine's
    ProblemError, the same line."""
    said = runs[1]
    message, kind = said["discrete"]
    assert message.startswith("engine='petsc' is not supported for 2D, "
                              "discrete"), message
    assert "partitions a mesh by nodes" in message
    message, kind = said["pulled"]
    with pytest.raises(solver.errors.ProblemError) as info:
        solver.solve(solver.load_problem(paths["pulled"]))
    assert kind == "ProblemError" and message == str(info.value)
    assert "\n" not in message


def test_command_line_writes_the_serial_outputs(paths, tmp_path):
    """``mpiexec -n 2 python -m solver X.npz --engine petsc --friction
    0.3`` on the 2D patch (12 load steps): exit 0, the same files as the
    serial command line (each step's in steps/), summary.json with the
    engine entry and the verification passed, the same u, contact forces,
    mortar and friction tractions (result.npz) to 1e-8."""
    env = dict(os.environ, OMP_NUM_THREADS="1")
    serial_dir, petsc_dir = tmp_path / "serial", tmp_path / "petsc"
    name, options = "patch", ["--friction", "0.3"]
    done = subprocess.run([sys.executable, "-m", "solver", paths[name],
                           "-o", str(serial_dir)] + options,
                          capture_output=True, text=True, env=env,
                          timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    code, _, err = mpirun(2, ["-m", "solver", paths[name], "--engine",
                              "petsc", "-o", str(petsc_dir)] + options)
    assert code == 0, err[-2000:]
    files = sorted(str(p.relative_to(serial_dir))
                   for p in serial_dir.rglob("*"))
    assert files == sorted(str(p.relative_to(petsc_dir))
                           for p in petsc_dir.rglob("*"))
    summary = json.loads((petsc_dir / "summary.json").read_text())
    assert summary["engine"]["name"] == "petsc"
    assert summary["engine"]["ranks"] == 2
    assert summary["verification"]["passed"]
    with np.load(serial_dir / "result.npz") as a, \
            np.load(petsc_dir / "result.npz") as b:
        for key in ("u", "contact_force", "traction",
                    "friction_traction"):
            if key not in a:
                continue
            ref = np.asarray(a[key], float)
            assert np.abs(b[key] - ref).max() <= RTOL * np.abs(ref).max()

