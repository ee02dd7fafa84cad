"""Execute the notebooks end to end (their cells assert their claims)."""

import nbformat
import pytest
from nbclient import NotebookClient

from conftest import ROOT

NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))


#: Figures each notebook must produce.
FIGURES = {"table1_frictionless": 9, "table2_friction": 9, "verification": 3}


def test_notebooks_found():
    assert sorted(p.stem for p in NOTEBOOKS) == sorted(FIGURES)


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_runs(path):
    notebook = nbformat.read(path, as_version=4)
    # committed without outputs
    assert all(not cell.get("outputs") for cell in notebook.cells
               if cell.cell_type == "code")
    NotebookClient(notebook, timeout=900, kernel_name="python3",
                   resources={"metadata": {"path": str(path.parent)}}
                   ).execute()
    images = sum("image/png" in output.get("data", {})
                 for cell in notebook.cells if cell.cell_type == "code"
                 for output in cell.outputs)
    assert images >= FIGURES[path.stem]
