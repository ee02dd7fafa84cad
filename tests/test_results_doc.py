"""docs/results.md against what runs write (issue 34, point 19).

A 2D body on the thesis's obstacle (the 118 block), a 3D one (the 118
slab against the parabolic cylinder) and two bodies (the patch test),
each frictionless and with friction, through the command line: the keys
of ``summary.json`` and ``result.npz`` and the point data of the ``.vtu``
files must be exactly those of the document's tables for that case
(every documented key written, every written key documented; a key whose
meaning says "(only ..." may be absent), and each array's shape the
documented one. The 3D tangential fields are checked against their
frames: ``tangents`` turns ``tangential_displacement`` into the nodes'
displacements, and the step files' ``friction_traction`` is the vector
Σ_k g_k τ_k."""

import json
import re
import sys
from pathlib import Path

import meshio
import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

from conftest import MESHES, ROOT, run_cli  # noqa: E402
from test_export_two_body import export  # noqa: E402
from solver import load_problem  # noqa: E402

DOC = ROOT / "docs" / "results.md"
STEPS = 3


def tables():
    """{(section, subsection): [(keys, shape, meaning)]} of results.md:
    every table row, its backquoted keys from the first column, the
    shape column if the table has one."""
    out, h2, h3 = {}, None, None
    for line in DOC.read_text().splitlines():
        if line.startswith("## "):
            h2, h3 = line[3:].strip(), None
        elif line.startswith("### "):
            h3 = line[4:].strip()
        elif line.startswith("| `") and h2:
            cells = [c.strip() for c in re.split(r"(?<!\\)\|", line)[1:-1]]
            keys = re.findall(r"`([^`]+)`", cells[0])
            shape = cells[1] if len(cells) == 3 else None
            out.setdefault((h2, h3), []).append((keys, shape, cells[-1]))
    return out


def documented(*sections):
    """(required keys, optional keys, {key: shape}) of these sections."""
    doc = tables()
    required, optional, shapes = set(), set(), {}
    for section in sections:
        assert section in doc, section
        for keys, shape, meaning in doc[section]:
            (optional if "(only " in meaning else required).update(keys)
            shapes.update({key: shape for key in keys})
    return required, optional, shapes


def check_keys(written, sections):
    required, optional, _ = documented(*sections)
    assert not required - set(written), ("documented, not written",
                                         sorted(required - set(written)))
    assert not set(written) - required - optional, (
        "written, not documented", sorted(set(written) - required - optional))


def expected_shape(text, sizes, dim, per_step):
    """The shape a table cell gives: "(steps, Nc); 3D (steps, Nc, d − 1)"
    -> a tuple for this run; ", per step" puts the steps first."""
    if "; 3D " in text:
        text = text.split("; 3D ")[1 if dim == 3 else 0]
    steps_first = text.endswith(", per step")
    text = text.removesuffix(", per step").strip().strip("()")
    values = tuple(int(eval(token.replace("−", "-").replace("Ñ", "Nt"),
                            {}, sizes))
                   for token in text.split(",") if token.strip())
    if steps_first and per_step:
        values = (sizes["steps"],) + values
    return values


CASES = {"2D": dict(dim=2, bodies=1), "3D": dict(dim=3, bodies=1),
         "two bodies": dict(dim=2, bodies=2)}


@pytest.fixture(scope="module")
def problems(exported, tmp_path_factory):
    folder = tmp_path_factory.mktemp("problems")
    export(folder, "block3d_obstacle.py", "slab",
           mesh=str(MESHES / "block3d_118_slab.mesh"), slab=True)
    export(folder, "two_body_patch.py", "patch",
           mesh=str(MESHES / "two_body_patch.mesh"))
    return {"2D": exported(118)[0], "3D": folder / "slab.npz",
            "two bodies": folder / "patch.npz"}


@pytest.fixture(scope="module")
def runs(problems, tmp_path_factory):
    """{(case, friction?): output folder} of command-line runs."""
    capsys = _NoCapture()
    out = {}
    for case, path in problems.items():
        for friction in (False, True):
            folder = tmp_path_factory.mktemp("run")
            argv = [path, "-o", folder]
            if friction:
                argv += ["--friction", "0.3", "--steps", str(STEPS)]
            code, text, _ = run_cli(argv, capsys)
            assert code == 0, text
            out[case, friction] = folder
    return out


class _NoCapture:
    """run_cli's capsys for a module fixture: nothing to read back."""

    def readouterr(self):
        from types import SimpleNamespace

        return SimpleNamespace(out="", err="")


def summary_sections(case, friction):
    sections = [("`summary.json`", "Every run"),
                ("`summary.json`", "A friction run" if friction
                 else "A frictionless solve")]
    if CASES[case]["bodies"] == 2:
        sections.append(("`summary.json`", "Two bodies, added"))
    return sections


def npz_sections(case, friction):
    sections = [("`result.npz`", "A friction run" if friction
                 else "A frictionless solve")]
    if CASES[case]["bodies"] == 2:
        sections.append(("`result.npz`", "Two bodies, added"))
    return sections


def vtk_sections(case, friction):
    sections = [("VTK", "`steps/step_NNNN.vtu` of a friction run" if friction
                 else "`result.vtu` of a frictionless solve")]
    if CASES[case]["bodies"] == 2:
        sections.append(("VTK", "Two bodies, added"))
    return sections


@pytest.mark.parametrize("friction", [False, True],
                         ids=["frictionless", "friction"])
@pytest.mark.parametrize("case", list(CASES))
def test_summary_keys(runs, case, friction):
    summary = json.loads((runs[case, friction] / "summary.json").read_text())
    assert summary["dim"] == CASES[case]["dim"]
    check_keys(summary, summary_sections(case, friction))


@pytest.mark.parametrize("friction", [False, True],
                         ids=["frictionless", "friction"])
@pytest.mark.parametrize("case", list(CASES))
def test_result_npz_keys_and_shapes(problems, runs, case, friction):
    folder = runs[case, friction]
    summary = json.loads((folder / "summary.json").read_text())
    problem = load_problem(problems[case])
    dim = CASES[case]["dim"]
    sizes = dict(Nc=problem.n_contact, d=dim, nodes=len(problem.nodes),
                 Nt=problem.n_dofs, iterations=summary["iterations"],
                 steps=summary.get("steps_completed", 0))
    sections = npz_sections(case, friction)
    _, _, shapes = documented(*sections)
    with np.load(folder / "result.npz") as data:
        check_keys(data.files, sections)
        for key in data.files:
            assert data[key].shape == expected_shape(
                shapes[key], sizes, dim, friction), key


@pytest.mark.parametrize("friction", [False, True],
                         ids=["frictionless", "friction"])
@pytest.mark.parametrize("case", list(CASES))
def test_vtu_point_data(runs, case, friction):
    folder = runs[case, friction]
    name = f"steps/step_{STEPS:04d}.vtu" if friction else "result.vtu"
    mesh = meshio.read(folder / name)
    check_keys(mesh.point_data, vtk_sections(case, friction))
    assert mesh.point_data["u"].shape[1] == 3
    assert ("body" in mesh.cell_data) == (CASES[case]["bodies"] == 2)


def test_three_dimensional_frames(runs):
    """The exported tangents are the frames of the tangential fields:
    u_t,k = τ_k · u at every node that takes part; orthonormal and
    orthogonal to the normal."""
    with np.load(runs["3D", True] / "result.npz") as data:
        part = np.isfinite(data["gap"])
        tangents, normal = data["tangents"][part], data["normal"][part]
        u = data["displacement"][-1][data["contact_nodes"][part]]
        ut = data["tangential_displacement"][-1][part]
        assert np.isnan(data["tangents"][~part]).all()
    assert part.sum() >= 3 and tangents.shape[1:] == (2, 3)
    np.testing.assert_allclose(np.einsum("ikd,id->ik", tangents, u), ut,
                               atol=1e-12 * np.abs(u).max())
    gram = np.einsum("ikd,ild->ikl", tangents, tangents)
    np.testing.assert_allclose(gram, np.broadcast_to(np.eye(2), gram.shape),
                               atol=1e-12)
    np.testing.assert_allclose(np.einsum("ikd,id->ik", tangents, normal), 0,
                               atol=1e-12)


def test_three_dimensional_step_files_hold_traction_vectors(problems,
                                                            tmp_path):
    """A 3D friction run streamed as the command line does (prepare, then
    StepOutputs given the plan's geometry): each step file's
    friction_traction is the 3-vector Σ_k g_k τ_k of result.npz's
    components and frames, tangential (⟂ ν) and as long as g."""
    from solver.front import prepare
    from solver.output import StepOutputs
    from solver.output.folder import OutputFolder

    problem = load_problem(problems["3D"])
    plan = prepare(problem, friction=0.3, steps=STEPS)
    folder = OutputFolder(str(tmp_path / "out"))
    outputs = StepOutputs(folder, problem, STEPS, geometry=plan.geometry)
    result = plan.run(on_step=outputs, keep_steps=False)
    outputs.finish(plan.geometry, result)
    assert result.success
    with np.load(tmp_path / "out" / "result.npz") as data:
        g = np.nan_to_num(data["friction_traction"])
        tangents = np.nan_to_num(data["tangents"])
        normal = np.nan_to_num(data["normal"])
        nodes = data["contact_nodes"]
    slipping = 0
    for k in range(STEPS):
        mesh = meshio.read(tmp_path / "out" / "steps" / f"step_{k + 1:04d}.vtu")
        vector = mesh.point_data["friction_traction"]
        assert vector.shape == (len(problem.nodes), 3)
        expected = np.einsum("ik,ikd->id", g[k], tangents)
        np.testing.assert_allclose(vector[nodes], expected, atol=1e-12)
        np.testing.assert_allclose(np.linalg.norm(vector[nodes], axis=1),
                                   np.linalg.norm(g[k], axis=1), rtol=1e-12)
        np.testing.assert_allclose((vector[nodes] * normal).sum(axis=1), 0,
                                   atol=1e-9 * np.abs(g).max())
        others = np.setdiff1d(np.arange(len(problem.nodes)), nodes)
        assert not vector[others].any()
        slipping += int((np.linalg.norm(g[k], axis=1) > 0).sum())
    assert slipping > 0   # the check is not about zeros only
