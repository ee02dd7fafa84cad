"""The notebooks: committed executed, re-executable, and their figure table
(``notebooks/README.md``) true.

Each notebook's cells assert the claims made in its prose, so re-executing
it checks them against the current code; and every number in its prose
must be one that the re-executed cells print (:mod:`notebook_prose`).
"""

import re

import nbformat
import pytest
from nbclient import NotebookClient

from conftest import ROOT
from notebook_prose import unbacked_numbers

NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))
README = ROOT / "notebooks" / "README.md"

#: Figures each notebook must show (inline images).
FIGURES = {"table1_frictionless": 10, "table2_friction": 14, "verification": 3,
           "three_d": 2, "two_bodies": 4, "sfepy_examples": 2}

#: A row of the figure table: | thesis figure | what | `nb.ipynb` [n] | `figures/x.png` |
ROW = re.compile(r"^\| (?P<thesis>[^|]+?) \| [^|]+ \| `(?P<notebook>\w+)\.ipynb` "
                 r"\[(?P<cell>\d+)\] \| `figures/(?P<file>[\w.]+\.png)` \|$", re.M)


def table():
    return [m.groupdict() for m in ROW.finditer(README.read_text())]


def code_cells(notebook):
    return [c for c in notebook.cells if c.cell_type == "code"]


def images(notebook):
    return sum("image/png" in output.get("data", {})
               for cell in code_cells(notebook) for output in cell.outputs)


def test_notebooks_found():
    assert sorted(p.stem for p in NOTEBOOKS) == sorted(FIGURES)


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_committed_executed(path):
    """Committed with outputs (so the figures show on the code host), run
    top to bottom in one kernel, without errors, and small."""
    notebook = nbformat.read(path, as_version=4)
    cells = code_cells(notebook)
    assert [c.execution_count for c in cells] == list(range(1, len(cells) + 1))
    assert not any(o.output_type == "error" for c in cells for o in c.outputs)
    assert images(notebook) >= FIGURES[path.stem]
    assert path.stat().st_size < 1.5e6


def test_figure_table_covers_every_thesis_figure():
    """Fig. 1-27 of the thesis each have a row (the thesis lists 27)."""
    covered = set()
    for row in table():
        if re.fullmatch(r"[\d, ()ab]+", row["thesis"]):
            covered |= {int(n) for n in re.findall(r"\d+", row["thesis"])}
    assert covered == set(range(1, 28))


def test_figure_table_points_at_committed_files_and_cells():
    rows = table()
    notebooks = {p.stem: nbformat.read(p, as_version=4) for p in NOTEBOOKS}
    for row in rows:
        assert (ROOT / "notebooks" / "figures" / row["file"]).is_file(), row
        cell = next(c for c in code_cells(notebooks[row["notebook"]])
                    if c.execution_count == int(row["cell"]))
        printed = "".join(o.get("text", "") for o in cell.outputs)
        assert f"notebooks/figures/{row['file']}" in printed, row


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_runs(path, tmp_path, monkeypatch):
    """Re-execute a copy (the committed file is not touched); figure files
    go to a temporary folder, where every one named in the table for this
    notebook must appear."""
    monkeypatch.setenv("CONTACT_SSN_FIGURES", str(tmp_path))
    # three_d.ipynb leaves out its a/h = 32 mesh (minutes) in this re-run
    monkeypatch.setenv("CONTACT_SSN_QUICK", "1")
    notebook = nbformat.read(path, as_version=4)
    NotebookClient(notebook, timeout=900, kernel_name="python3",
                   resources={"metadata": {"path": str(path.parent)}}
                   ).execute()
    assert images(notebook) >= FIGURES[path.stem]
    expected = {row["file"] for row in table() if row["notebook"] == path.stem}
    assert expected
    written = {p.name for p in tmp_path.glob("*.png")}
    assert expected <= written, expected - written
    assert unbacked_numbers(notebook, path.stem) == []
