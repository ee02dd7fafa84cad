"""The notebooks: committed executed, re-executable, and their figure table
(``notebooks/README.md``) true.

Each notebook's cells assert the claims made in its prose, so re-executing
it checks them against the current code; and every number in its prose
must be one that the re-executed cells print (:mod:`notebook_prose`).
"""

import re

import nbformat
import pytest

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


#: The re-executions run in two lanes at once (each notebook in its own
#: kernel process; the machine has two cores), the longest first. The
#: notebooks that write the same export (table1 and table2: block_454.npz
#: under output/notebooks/) share a lane, so that they never run together.
LANES = (("sfepy_examples", "three_d", "verification"),
         ("two_bodies", "table2_friction", "table1_frictionless"))

_EXECUTE = """
import sys, nbformat
from nbclient import NotebookClient
source, target, folder = sys.argv[1:]
notebook = nbformat.read(source, as_version=4)
try:
    NotebookClient(notebook, timeout=900, kernel_name="python3",
                   resources={"metadata": {"path": folder}}).execute()
finally:
    nbformat.write(notebook, target)
"""


@pytest.fixture(scope="module")
def executed(request, tmp_path_factory):
    """Re-execute copies of the notebooks the session selected (the
    committed files are not touched), two lanes at once; each notebook's
    figure files go to its own temporary folder. Returns a function
    stem -> (executed notebook, figure folder, stderr of the run)."""
    import os
    import subprocess
    import sys
    import threading

    wanted = {item.callspec.params["path"].stem
              for item in request.session.items
              if item.originalname == "test_notebook_runs"}
    root = tmp_path_factory.mktemp("notebooks")
    done = {stem: threading.Event() for stem in FIGURES}
    runs = {}

    def run(stem):
        figures = root / stem
        figures.mkdir()
        target = root / f"{stem}.ipynb"
        # three_d.ipynb leaves out its a/h = 32 mesh (minutes) in this
        # re-run; sfepy_examples.ipynb sweeps two penalties, not five
        env = dict(os.environ, CONTACT_SSN_FIGURES=str(figures),
                   CONTACT_SSN_QUICK="1")
        source = ROOT / "notebooks" / f"{stem}.ipynb"
        proc = subprocess.run(
            [sys.executable, "-c", _EXECUTE, str(source), str(target),
             str(source.parent)], env=env, capture_output=True, text=True)
        runs[stem] = (target, figures, proc)

    def lane(stems):
        for stem in stems:
            if stem in wanted:
                try:
                    run(stem)
                finally:
                    done[stem].set()

    threads = [threading.Thread(target=lane, args=(stems,), daemon=True)
               for stems in LANES]
    for thread in threads:
        thread.start()

    def result(stem):
        done[stem].wait()
        assert stem in runs, f"{stem}: the re-execution did not start"
        return runs[stem]

    yield result
    for thread in threads:
        thread.join()


def test_lanes_cover_every_notebook():
    assert sorted(sum(LANES, ())) == sorted(FIGURES)


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_runs(path, executed):
    """Re-executed without an error; figure files go to a temporary
    folder, where every one named in the table for this notebook must
    appear; every number of the prose is one its cells print."""
    target, figures, proc = executed(path.stem)
    assert proc.returncode == 0, proc.stderr[-3000:]
    notebook = nbformat.read(target, as_version=4)
    assert images(notebook) >= FIGURES[path.stem]
    expected = {row["file"] for row in table() if row["notebook"] == path.stem}
    assert expected
    written = {p.name for p in figures.glob("*.png")}
    assert expected <= written, expected - written
    assert unbacked_numbers(notebook, path.stem) == []
