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
reproduce to round-off, fine slave on coarse master and the reverse."""

import meshio
import numpy as np
import pytest

from conftest import MESHES, ROOT, load_script
from test_export import export_module

import solver
from solver.problem import load_problem

PATCH = ROOT / "sfepy_problems" / "two_body_patch.py"


@pytest.fixture(scope="module")
def quad_patch(tmp_path_factory):
    structured = load_script("_contact_ssn_structured",
                             MESHES / "structured.py")
    lower, lower_cells = structured.grid((5, 3), (0, 0), (1, 0.5))
    upper, upper_cells = structured.grid((8, 4), (0, 0.5), (1, 1))
    nodes = np.concatenate([lower, upper]) + 0.0
    cells = np.concatenate([lower_cells, upper_cells + len(lower)])
    group = np.r_[np.ones(len(lower_cells), int),
                  np.full(len(upper_cells), 2)]  # body id + 1
    folder = tmp_path_factory.mktemp("quad_patch")
    mesh = folder / "patch_quad.mesh"
    meshio.write(str(mesh), meshio.Mesh(
        nodes, [("quad", cells)],
        point_data={"medit:ref": np.zeros(len(nodes), int)},
        cell_data={"medit:ref": [group]}), file_format="medit")
    problems = {}
    for slave in ("upper", "lower"):
        out = folder / f"patch_{slave}.npz"
        export_module().export_only(PATCH, mesh=str(mesh), output=str(out),
                                    slave=slave)
        problems[slave] = load_problem(out)
    return problems


@pytest.mark.parametrize("slave", ["upper", "lower"])
@pytest.mark.parametrize("options", [{}, dict(system="full"),
                                     dict(method="fb")],
                         ids=["default", "full", "fb"])
def test_quad_patch_test_is_uniform(quad_patch, slave, options):
    problem = quad_patch[slave]
    assert problem.cells.shape[1] == 4 and problem.is_mortar
    assert len(problem.mortar_slave) == (8 if slave == "upper" else 5)
    result = solver.solve(problem, **options)
    assert result.success, result.message
    p = result.contact_pressure
    assert len(p) == len(problem.contact_nodes) == len(
        problem.mortar_slave) + 1
    np.testing.assert_allclose(p, problem.meta["p_exact"], rtol=1e-10)
