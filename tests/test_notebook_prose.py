"""The notebooks' prose (issue 34, point 23).

- Every number in a notebook's Markdown is one that a cell of it prints
  (:mod:`notebook_prose`), in the committed notebooks; tests/test_notebooks.py
  checks the same on each re-executed notebook.
- Each notebook states its units (a "**Units.**" paragraph).
- (That they solve through the public front: tests/test_public_front.py.)
- notebooks/README.md counts the notebooks right.
"""

import re

import nbformat
import pytest

from conftest import ROOT
from notebook_prose import unbacked_numbers

NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))
README = (ROOT / "notebooks" / "README.md").read_text()


def load(path):
    return nbformat.read(path, as_version=4)


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_prose_numbers_are_printed(path):
    assert unbacked_numbers(load(path), path.stem) == []


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_units_stated(path):
    notebook = load(path)
    units = [c for c in notebook.cells if c.cell_type == "markdown"
             and c.source.startswith("**Units.**")]
    assert len(units) == 1
    assert "mm" in units[0].source and "MPa" in units[0].source


def test_readme_counts_the_notebooks():
    words = {3: "three", 4: "four", 5: "five", 6: "six", 7: "seven"}
    count = words[len(NOTEBOOKS)]
    said = re.findall(r"\b(two|three|four|five|six|seven) notebooks\b"
                      r"|\ball (two|three|four|five|six|seven)\b", README)
    assert said and {a or b for a, b in said} == {count}
    listed = re.findall(r"^\| `(\w+)\.ipynb` \|", README, flags=re.M)
    assert sorted(listed) == [p.stem for p in NOTEBOOKS]


def test_readme_three_d_levels():
    """The row of three_d.ipynb names the a/h it runs."""
    row = next(line for line in README.splitlines()
               if line.startswith("| `three_d.ipynb`"))
    first, last = map(int, re.search(r"a/h = (\d+)…(\d+)", row).groups())
    source = "".join(c.source for c in load(ROOT / "notebooks" /
                                            "three_d.ipynb").cells)
    levels = re.search(r"ALL_LEVELS = \(([\d, ]+)\)", source).group(1)
    levels = [int(v) for v in levels.split(",")]
    assert (levels[0], levels[-1]) == (first, last)


def synthetic(prose, printed):
    return {"cells": [
        {"cell_type": "markdown", "source": prose},
        {"cell_type": "code", "source": "",
         "outputs": [{"output_type": "stream", "text": printed}]}]}


@pytest.mark.parametrize("prose, printed, unbacked", [
    # the cases: quoted numbers no cell computes
    ("which moves u by 3.5e-3", "| 3.6e-03 |\n| 3.4e-03 |", ["3.5e-3"]),
    ("(3e-5 with vertices every 0.1 in the test)", "0.1", ["3e-5"]),
    ("agree as h² (the 1878 block: 7.7e-4)", "1878", ["7.7e-4"]),
    # backed: other notations of the same value, rounding, sign
    ("E = 2·10⁵, ν = 0.3", "E = 200000 MPa, ν = 0.3", []),
    ("K = 10⁴·diag(9, 9)", "K = 10000·diag(9, 9)", []),
    ("within 0.54 % and 0.25 %", "| -0.54 % | +0.25 % |", []),
    ("the gap closes in step 45", "step 45.0", []),
    # not numbers: references, names, code
    ("Fig. 4–9 and Table 2, §2.1.1, its (110)/(111), 3D, R₁, `block_454`,"
     " Wohlmuth 2000, CMAME 194", "", []),
])
def test_the_check_itself(prose, printed, unbacked):
    found = [token for _, token in
             unbacked_numbers(synthetic(prose, printed), "test")]
    assert found == unbacked
