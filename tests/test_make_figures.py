"""``python docs/make_figures.py``, the README's regenerate command,
reproduces the committed docs/figures/ (issue 34, point 22).

It is run into a temporary folder (``--out``) and each PNG compared with
the committed one pixel by pixel: the same size, and in every band of 20
pixel rows at most 2 % of the pixels differing by more than 0.1 (of 1)
in some channel. What moves between runs is round-off in the last Newton
iterate (measured: a residual of 1.5e-10 against 2e-10 shifts a point and
the tick labels of the convergence plot, at most 0.6 % of a band); a
changed curve, or a changed word in a title (the bar run with the
projection formulation instead of the thesis's: the same curves, 11 % of
the title's band), is caught.
"""

import importlib.util

import matplotlib.image as mpimg
import numpy as np
import pytest

from conftest import ROOT

COMMITTED = ROOT / "docs" / "figures"
#: Share of the pixels of a band allowed to differ by more than 0.1.
TOLERANCE = 0.02
BAND = 20


@pytest.fixture(scope="module")
def regenerated(tmp_path_factory):
    spec = importlib.util.spec_from_file_location(
        "make_figures", ROOT / "docs" / "make_figures.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    out = tmp_path_factory.mktemp("figures")
    module.main(["--out", str(out)])
    return out


def test_the_same_files(regenerated):
    assert sorted(p.name for p in regenerated.glob("*.png")) == \
        sorted(p.name for p in COMMITTED.glob("*.png"))


@pytest.mark.parametrize("name", sorted(p.name for p in
                                        COMMITTED.glob("*.png")))
def test_figure_reproduced(regenerated, name):
    new = mpimg.imread(regenerated / name)
    old = mpimg.imread(COMMITTED / name)
    assert new.shape == old.shape, name
    differs = np.abs(new - old).max(axis=-1) > 0.1
    worst = max(differs[row:row + BAND].mean()
                for row in range(0, len(differs), BAND))
    assert worst <= TOLERANCE, f"{name}: {worst:.1%} of a band differs"
