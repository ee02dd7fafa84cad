"""Every combination the front accepts works, every other is refused by a
documented rule (issue 30, "every combination either works or says so").

The enumeration: problem (2D and 3D against a rigid obstacle, with and
without roller nodes; two bodies in 2D; the discrete §6 bar) × contact
(frictionless; friction: projection/thesis × lagged/implicit) × method
(min, fb) × system (auto, condensed, full) × start (default, nested,
free) × backend (every installed one, and the iterative ``amg``), on the
serial engine here and on the PETSc engine under ``mpiexec`` on 1 and 2
ranks
(:func:`test_petsc_combinations`, where petsc4py is installed).

For each: either :func:`solver.solve` returns a converged answer and an
independent check of it passes on **every** contact or slave node — from
K, f and the contact geometry alone, not from the solver's own λ or
verification: the reaction r = K u − f at each node gives its normal force
λ = −r·ν ≥ 0 and tangential force t; the gap s − ν·u ≥ 0, λ·gap = 0, and
|t| = 0 frictionless or |t| ≤ f_c λ (the bound of the step: the previous
step's λ if lagged) with friction; r = 0 at every other DOF; a node left
out (a support) does not penetrate — or it raises SolverError with one
line that a rule of :data:`solver.front.cases.RULES` (or a geometry rule)
produced. The tolerances are relative to the contact forces: F =
max(‖f‖, ‖λ⁺‖), lengths F/k̄ (k̄ the mean contact stiffness).
"""

import itertools
import json
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))
from tet_elasticity import box, mesh_problem, stiffness  # noqa: E402
from tri_elasticity import stacked_blocks  # noqa: E402

import solver  # noqa: E402
from solver import load_problem, save_problem, two_dof_bar  # noqa: E402
from solver.contact import TwoBodyMap, contact_geometry  # noqa: E402
from solver.front.cases import RULES  # noqa: E402
from solver.geometry.surfaces import surface_from_spec  # noqa: E402
from solver.linalg import amg, available_backends  # noqa: E402

TOL = 1e-7  # of the check, relative to F (solver: tol 1e-10, tol_v 1e-9)
STEPS = 3
CONTACTS = [None, ("projection", "lagged"), ("projection", "implicit"),
            ("thesis", "lagged"), ("thesis", "implicit")]
METHODS = ("min", "fb")
SYSTEMS = ("auto", "condensed", "full")
STARTS = (None, "nested", "free")
BACKENDS = ("auto",) + tuple(available_backends()) + (
    ("amg",) if amg.available() else ())  # the iterative path, issue 33


def quarter_block_3d(n=2, nz=1):
    """A quarter of a block (rollers on x = 0 and y = 0) pressed onto a
    sphere (a JSON surface spec, so that the file can be saved)."""
    nodes, cells = box((n, n, nz))
    x, y, z = nodes.T
    prescribed = np.full(nodes.shape, np.nan)
    prescribed[np.isclose(x, 0.0), 0] = 0.0
    prescribed[np.isclose(y, 0.0), 1] = 0.0
    prescribed[np.isclose(z, 1.0)] = [0.0, 0.0, -0.02]
    contact = np.flatnonzero(np.isclose(z, 0.0))
    faces = np.sort(cells[:, [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]]
                    .reshape(-1, 3), axis=1)
    faces = faces[np.isclose(z[faces], 0.0).all(axis=1)]
    a, b, c = (nodes[faces[:, k]] for k in range(3))
    inward = np.cross(b - a, c - a)[:, 2] > 0  # outward is −z
    faces[inward] = faces[inward][:, [0, 2, 1]]
    problem = mesh_problem(nodes, cells, stiffness(nodes, cells, 100.0, 0.3),
                           prescribed, contact, faces)
    problem.obstacle = surface_from_spec({"kind": "sphere",
                                          "center": [0, 0, -2.0],
                                          "radius": 2.0})
    problem.contact_faces = faces
    problem.meta = {"E": 100.0, "nu": 0.3, "load": "top moved down",
                    "mesh": "tests/test_combinations.py"}
    return problem


def half_block_2d(n=4, ny=2):
    """The 2D half block of tests/test_rollers.py (a roller on x = 0)."""
    from tet_elasticity import rectangle

    nodes, cells = rectangle((n, ny))
    x, y = nodes.T
    prescribed = np.full(nodes.shape, np.nan)
    prescribed[np.isclose(x, 0.0), 0] = 0.0
    prescribed[np.isclose(y, 1.0)] = [0.0, -0.05]
    contact = np.flatnonzero(np.isclose(y, 0.0))
    contact = contact[np.argsort(x[contact])]
    problem = mesh_problem(nodes, cells, stiffness(nodes, cells, 100.0, 0.3),
                           prescribed, contact,
                           np.column_stack([contact[:-1], contact[1:]]))
    problem.obstacle = solver.ParametricCurve("t", "-0.25*t**2")
    problem.meta = {"E": 100.0, "nu": 0.3, "plane": "strain",
                    "load": "top moved down",
                    "mesh": "tests/test_combinations.py"}
    return problem


def patch_with_rollers():
    """Two stacked blocks (8 against 5 interface segments, non-matching),
    u_x = 0 on the left side of both: the slave's end node there is a
    roller."""
    problem, _, _ = stacked_blocks(n_upper=(8, 2), n_lower=(5, 2),
                                   fix_x=False, side_rollers=True)
    return problem


@pytest.fixture(scope="module")
def problems(exported):
    return {"2d-rigid": load_problem(exported(118)[0]),
            "2d-rollers": half_block_2d(),
            "3d-rollers": quarter_block_3d(),
            "2d-two-body": patch_with_rollers(),
            "2d-discrete": two_dof_bar()}


# ------------------------------------------------------------ the check


def _reaction_check(problem, u, f, friction=None, bound_force=None):
    """Max violations (relative) of the contact conditions at every node
    of Γc of ``problem`` for the reduced u under the load f, from K, f and
    the geometry only. ``bound_force``: the friction bound's normal force
    per node of the geometry (the previous step's λ if lagged)."""
    geometry = contact_geometry(problem, "obstacle", rollers=True)
    r = problem.K @ u - f
    padded_r, padded_u = np.append(r, 0.0), np.append(u, 0.0)
    dofs = geometry.node_dofs
    n = geometry.normal
    force = padded_r[dofs]          # contact force on the body, free DOFs
    lam = -np.einsum("ij,ij->i", force, n)
    tangential = force + lam[:, None] * n
    gap = geometry.gap - np.einsum("ij,ij->i", n, padded_u[dofs])
    k = float(problem.K.diagonal()[geometry.free_dofs()].mean()) \
        if len(dofs) else 1.0
    F = max(np.linalg.norm(f), np.linalg.norm(np.maximum(lam, 0)), 1e-300)
    L = F / k
    other = np.ones(len(u), bool)
    other[geometry.free_dofs()] = False
    out = dict(
        multiplier=max(0.0, -lam.min(initial=0.0)) / F,
        penetration=max(0.0, -gap.min(initial=0.0)) / L,
        complementarity=np.abs(np.minimum(lam, k * gap)).max(initial=0.0)
        / F,
        equilibrium=np.abs(r[other]).max(initial=0.0) / F)
    size = np.linalg.norm(tangential, axis=1)
    if friction is None:
        out["tangential"] = size.max(initial=0.0) / F
    else:
        bound = friction * np.maximum(bound_force, 0.0)
        out["coulomb"] = np.maximum(size - bound, 0.0).max(initial=0.0) / F
    excluded = geometry.excluded
    known = np.isfinite(excluded["gap"])
    if known.any():
        from solver.contact.geometry import node_displacement

        moved = node_displacement(problem, u, excluded["index"][known])
        depth = np.einsum("ij,ij->i", excluded["normal"][known], moved) \
            - excluded["gap"][known]
        out["support_penetration"] = max(0.0, depth.max()) / L
    return out, lam, geometry


def check_answer(problem, result, friction=None, coulomb=None):
    """Solve-independent check of a result (every node of Γc)."""
    if problem.is_mortar:  # in the mortar's variables v: nodewise
        mapping = TwoBodyMap(problem)
        target, u = mapping.equivalent, np.asarray(result.v)
        loads = [mapping.T_inv.T @ load for load, _, _, _ in
                 problem.load_steps(STEPS if friction is not None else None)]
    else:
        target, u = problem, np.asarray(result.u)
        loads = [load for load, _, _, _ in problem.load_steps(
            STEPS if friction is not None else None)]
    if friction is None:
        violations, _, _ = _reaction_check(target, u, target.f)
    else:
        lam_steps = []
        for x, f in zip(u, loads):
            _, lam, _ = _reaction_check(target, x, f)
            lam_steps.append(lam)
        bound = lam_steps[-1] if coulomb == "implicit" or len(u) == 1 \
            else lam_steps[-2]
        violations, _, _ = _reaction_check(target, u[-1], loads[-1],
                                           friction, bound)
    bad = {k: v for k, v in violations.items() if not v <= TOL}
    assert not bad, bad


def fragile(options):
    """The combinations whose Newton may stop unconverged (then they say
    so, exit 3): the thesis's split, degenerate where p = 0, condensed
    onto Γc (φ_FB runs on gradient steps there) or with φ_min (no gradient
    fallback: a singular Jacobian); documented in the README's "What
    works where"."""
    return options.get("formulation") == "thesis" \
        and (options.get("system") == "condensed"
             or options.get("method") == "min")


def expect_refusal(exc):
    """A refusal is one line, from a documented rule (``exc``: the error
    or its text)."""
    text = str(exc)
    assert "\n" not in text
    known = [f"{rule.option}=" for rule in RULES] + [
        "formulation='thesis' is not supported",
        "system='full' is not supported", "friction is not supported",
        "friction coefficient", "the load path"]
    assert any(text.startswith(prefix) or prefix in text
               for prefix in known), text


# -------------------------------------------------------------- serial


def combinations():
    for contact, method, system, start, backend in itertools.product(
            CONTACTS, METHODS, SYSTEMS, STARTS, BACKENDS):
        yield contact, method, system, start, backend


@pytest.mark.parametrize("name", ["2d-rigid", "2d-rollers", "3d-rollers",
                                  "2d-two-body", "2d-discrete"])
def test_serial_combinations(problems, name):
    problem = problems[name]
    solved, refused = 0, 0
    for contact, method, system, start, backend in combinations():
        options = dict(method=method, system=system, start=start,
                       backend=backend)
        if contact is not None:
            options.update(friction=0.3, formulation=contact[0],
                           coulomb=contact[1], steps=STEPS)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", solver.errors.SolverWarning)
                result = solver.solve(problem, **options)
        except solver.SolverError as exc:
            expect_refusal(exc)
            refused += 1
            continue
        label = f"{name} {options}"
        if fragile(options) and not result.success:
            assert "did not converge" in result.message, label
            continue
        assert result.success, (label, result.message)
        check_answer(problem, result, None if contact is None else 0.3,
                     None if contact is None else contact[1])
        solved += 1
    assert solved and refused, (solved, refused)


def test_what_is_refused_is_refused_for_a_reason(problems):
    """The refusals that must happen, one by one (each with its rule)."""
    cases = [
        ("2d-rigid", dict(steps=5), "steps=5 is not supported for 2D, "
         "rigid, frictionless"),
        ("2d-rigid", dict(friction=0.3, start="free"), "start='free'"),
        ("2d-rigid", dict(formulation="thesis"), "formulation='thesis'"),
        ("2d-rigid", dict(coulomb="implicit"), "coulomb='implicit'"),
        ("2d-rigid", dict(system="full", backend="cholmod"),
         "backend='cholmod' is not supported"),
        ("2d-rigid", dict(ksp="gamg"), "ksp='gamg'"),
        ("2d-rigid", dict(system="full", start="nested"), "start='nested'"),
        ("2d-rigid", dict(system="full", start="free"), "start='free'"),
        ("3d-rollers", dict(start="nested"), "3D starts free"),
        ("3d-rollers", dict(friction=0.3, formulation="thesis"),
         "2D-only"),
        ("3d-rollers", dict(search_interval=(0, 1)), "search_interval"),
        ("2d-discrete", dict(gap="body"), "gap='body' is not supported"),
        ("2d-two-body", dict(gap="obstacle"), "gap='obstacle'"),
        ("2d-rigid", dict(variant="mortar"), "variant='mortar'"),
        ("2d-two-body", dict(friction=0.3, formulation="thesis"),
         "does not take roller nodes"),
        ("2d-rollers", dict(friction=0.3, formulation="thesis"),
         "does not take roller nodes"),
        ("2d-rigid", dict(margin=0.1), "margin=0.1"),
        ("2d-discrete", dict(engine="petsc"), "engine='petsc'"),
    ]
    for name, options, phrase in cases:
        with pytest.raises(solver.SolverError) as info:
            solver.solve(problems[name], **options)
        assert phrase in str(info.value), (options, str(info.value))
        expect_refusal(info.value)


def test_roller_and_support_nodes_are_verified(problems):
    """The nodes that take no part are counted in the verification, with
    their reason; a roller made a support (rollers=False) that the answer
    drives into the other body is named by a warning."""
    problem = problems["2d-two-body"]
    result = solver.solve(problem, friction=0.3, steps=STEPS)
    assert result.success
    assert result.verification["excluded"]["nodes"] == 0
    check_answer(problem, result, 0.3, "lagged")
    with pytest.warns(solver.errors.PenetrationWarning,
                      match="penetrates the other body"):
        support = solver.solve(problem, friction=0.3, steps=STEPS,
                               rollers=False)
    excluded = support.verification["excluded"]
    assert excluded["reasons"] == {
        "support: a DOF prescribed (rollers=False)": 1}
    assert excluded["penetrating"] == [0]
    rigid = solver.solve(problems["2d-rigid"])
    assert rigid.verification["excluded"]["reasons"] == {
        "support: every DOF prescribed": 1}


# --------------------------------------------------------------- PETSc

PETSC_DRIVER = """
import json, sys, warnings
import numpy as np
import solver
from solver.mpi.engine import spmd

def main(paths, combos, out):
    said = {}
    for name, path in paths.items():
        p = solver.load_problem(path)
        for i, options in enumerate(combos):
            key = f"{name}/{i}"
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    r = solver.solve(p, engine="petsc", **options)
            except solver.SolverError as exc:
                said[key] = ["refused", str(exc)]
                continue
            said[key] = ["solved", bool(r.success), r.message,
                         np.asarray(r.u).tolist(),
                         np.asarray(r.get("v", r.u)).tolist()]
    json.dump(said, open(out, "w"))

spmd(main, json.loads(sys.argv[1]), json.loads(sys.argv[2]), sys.argv[3])
"""


def petsc_combinations():
    combos = []
    for method, system, start, ksp in itertools.product(
            METHODS, ("auto", "full"), (None, "nested", "free"),
            (None, "gamg")):
        combos.append(dict(method=method, system=system, start=start,
                           ksp=ksp))
    for formulation, coulomb in CONTACTS[1:]:
        combos.append(dict(friction=0.3, formulation=formulation,
                           coulomb=coulomb, steps=STEPS))
    combos.append(dict(backend="cholmod"))
    return combos


@pytest.mark.parametrize("ranks", [1, 2])
def test_petsc_combinations(problems, tmp_path, ranks):
    from solver.mpi import missing

    reason = missing()
    if reason:
        pytest.skip(f"the petsc engine is not installed: {reason}")
    paths = {}
    for name in ("2d-rigid", "3d-rollers", "2d-two-body"):
        paths[name] = str(save_problem(tmp_path / f"{name}.npz",
                                       problems[name]))
    combos = petsc_combinations()
    out = tmp_path / "said.json"
    env = dict(os.environ, OMP_NUM_THREADS="1")
    done = subprocess.run(
        ["mpiexec", "--allow-run-as-root", "--oversubscribe", "-n",
         str(ranks), sys.executable, "-c", PETSC_DRIVER, json.dumps(paths),
         json.dumps(combos), str(out)], capture_output=True, text=True,
        timeout=900, env=env)
    assert done.returncode == 0, done.stderr[-3000:]
    said = json.loads(out.read_text())
    solved = 0
    for name, path in paths.items():
        problem = load_problem(path)
        for i, options in enumerate(combos):
            answer = said[f"{name}/{i}"]
            if answer[0] == "refused":
                expect_refusal(answer[1])
                continue
            _, success, message, u, v = answer
            if fragile(options) and not success:
                continue
            assert success, (name, options, message)
            result = dict(u=np.array(u), v=np.array(v))
            friction = options.get("friction")
            check_answer(problem, type("R", (), result), friction,
                         options.get("coulomb"))
            solved += 1
    assert solved >= 16, solved


def test_displacement_driven_3d_candidates_factorise_once():
    """A body moved onto a nearly flat obstacle by a prescribed displacement
    (the gaps' range, 0.05, is small next to the motion, 0.02): the round-0
    candidates take the approach into account, so one factorisation
    serves (issue 34, point 5; two before, the first round missing every
    node the motion brings into contact), and the answer is that of the
    condensation onto every DOF of Γc (the reference: another Schur set,
    another Newton system)."""
    problem = quarter_block_3d(n=8, nz=2)
    problem.obstacle = surface_from_spec({"kind": "sphere",
                                          "center": [0, 0, -20.0],
                                          "radius": 20.0})
    result = solver.solve(problem)
    assert result.success and len(result.candidates["rounds"]) == 1
    assert result.n_contact > 20
    reference = solver.solve(problem, candidates=False)
    scale = np.abs(reference.u).max()
    assert np.abs(result.u - reference.u).max() <= 1e-10 * scale
