"""Two elastic bodies on quadrilaterals in 2D (issue 35, point 1): the
2D segment mortar needs only the interface segments, and a quadrilateral's
edges are straight segments, so it carries over unchanged.

Reference: the contact patch test (``sfepy_problems/two_body_patch.py``,
SfePy assembling K on bilinear quadrilaterals): two blocks [0, 1] × [0,
0.5] (E0 = 2e5, ν0 = 0.3; 5 × 3 quadrilaterals) and [0, 1] × [0.5, 1]
(E1 = 1e5, ν1 = 0.2; 8 × 4), non-matching at y = 0.5, the top moved down
by δ: a uniform uniaxial stress, so every slave node carries the closed
form p = δ / (h0/E'0 + h1/E'1), E' = E/(1 − ν²) (plane strain;
``meta["p_exact"]``), which bilinear elements and the dual mortar
reproduce to round-off, fine slave on coarse master and the reverse. The
same on unstructured quadrilaterals: ``meshes/two_body_patch.mesh``'s
triangles cut into three quadrilaterals each (``meshes/structured.py
quads``)."""

import numpy as np
import pytest

from conftest import MESHES, ROOT, load_script
from test_export import export_module

import solver
from solver.problem import load_problem

PATCH = ROOT / "sfepy_problems" / "two_body_patch.py"


@pytest.fixture(scope="module")
def quad_patch(tmp_path_factory):
    """The patch on structured quadrilaterals and on the cut triangles of
    the repository's patch mesh, each with either slave."""
    structured = load_script("_contact_ssn_structured",
                             MESHES / "structured.py")
    lower, lower_cells = structured.grid((5, 3), (0, 0), (1, 0.5))
    upper, upper_cells = structured.grid((8, 4), (0, 0.5), (1, 1))
    nodes = np.concatenate([lower, upper]) + 0.0
    cells = np.concatenate([lower_cells, upper_cells + len(lower)])
    group = np.r_[np.ones(len(lower_cells), int),
                  np.full(len(upper_cells), 2)]  # body id + 1
    folder = tmp_path_factory.mktemp("quad_patch")
    meshes = {"structured": folder / "patch_quad.mesh",
              "cut": folder / "patch_cut.mesh"}
    structured.write(str(meshes["structured"]), nodes, cells,
                     groups=group)
    cut_nodes, cut_cells, cut_group = structured.read_quads(
        MESHES / "two_body_patch.mesh")
    structured.write(str(meshes["cut"]), cut_nodes, cut_cells,
                     groups=cut_group)
    problems = {}
    for name, mesh in meshes.items():
        for slave in ("upper", "lower"):
            out = folder / f"{name}_{slave}.npz"
            export_module().export_only(PATCH, mesh=str(mesh),
                                        output=str(out), slave=slave)
            problems[name, slave] = load_problem(out)
    return problems


@pytest.mark.parametrize("mesh", ["structured", "cut"])
@pytest.mark.parametrize("slave", ["upper", "lower"])
@pytest.mark.parametrize("options", [{}, dict(system="full"),
                                     dict(method="fb")],
                         ids=["default", "full", "fb"])
def test_quad_patch_test_is_uniform(quad_patch, mesh, slave, options):
    problem = quad_patch[mesh, slave]
    assert problem.cells.shape[1] == 4 and problem.is_mortar
    segments = (8, 5) if mesh == "structured" else (16, 10)  # halved
    assert len(problem.mortar_slave) == segments[slave == "lower"]
    result = solver.solve(problem, **options)
    assert result.success, result.message
    p = result.contact_pressure
    assert len(p) == len(problem.contact_nodes) == len(
        problem.mortar_slave) + 1
    np.testing.assert_allclose(p, problem.meta["p_exact"], rtol=1e-10)
