"""Numbers in the README's prose beside Table 1 and in the captions of its
key figures, recomputed (issue 34, point 23): the sentence on smaller
lower bounds of α (φ_min, the thesis's full system, 454 block) and the
captions of docs/figures' φ_min convergence, bar and f_c = 0.3 figures
(the runs of docs/make_figures.py)."""

import re

import numpy as np
import pytest

from conftest import ROOT
from solver import DEFAULT_OPTIONS, load_problem, solve, two_dof_bar
from solver.studies import THESIS_TABLE1

README = " ".join((ROOT / "README.md").read_text().split())
SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")
WORDS = {1: "one", 2: "two", 3: "three", 4: "four", 5: "five", 6: "six",
         7: "seven", 8: "eight", 9: "nine", 10: "ten"}


def power(exponent):
    """2⁻¹⁶ for -16."""
    return "2" + str(exponent).translate(SUPERSCRIPT)


@pytest.fixture(scope="module")
def block(exported):
    return load_problem(exported(454)[0])


def test_smaller_bounds_on_alpha(block):
    default = DEFAULT_OPTIONS["min"]["alpha_min"]
    assert f"than our {power(int(np.log2(default)))}" in README
    thesis = THESIS_TABLE1["min", 454]
    sentence = README.split("Smaller bounds do add residual evaluations", 1)
    assert len(sentence) == 2
    sentence = sentence[1].split("`notebooks/", 1)[0]
    assert f"the thesis's {thesis[0]} / {thesis[1]} on our 454 mesh" in \
        sentence
    quoted = re.findall(r"2([⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+) (?:gives )?(\d+) / (\d+)",
                        sentence)
    assert len(quoted) == 3
    reference = solve(block, method="min", system="full")
    for exponent, J, F in quoted:
        bound = 2.0 ** int(exponent.translate(
            str.maketrans("⁻⁰¹²³⁴⁵⁶⁷⁸⁹", "-0123456789")))
        assert bound < default
        r = solve(block, method="min", system="full",
                  options={"alpha_min": bound})
        assert r.success and (r.njev, r.nfev) == (int(J), int(F))
        # "each the same solution"
        assert np.abs(r.u - reference.u).max() <= 1e-8 * np.abs(
            reference.u).max()
        # "none gives the thesis's counts"
        assert (r.njev, r.nfev) != thesis


def test_convergence_caption(block):
    caption = README.split("(docs/figures/frictionless_convergence_min.png)",
                           1)[1].split("![", 1)[0]
    r = solve(block, method="min", system="full")
    failed = np.flatnonzero(r.history["line_search_failed"])
    halvings = int(-np.log2(DEFAULT_OPTIONS["min"]["alpha_min"]))
    assert list(failed) == [1]
    assert f"In iteration {failed[0]} no α down to {power(-halvings)}" in \
        caption
    assert f"{WORDS[halvings]} halvings tried" in caption
    assert f"converges in {WORDS[r.njev]} Jacobians" in caption


def test_bar_caption():
    caption = README.split("(docs/figures/bar_fc10.png)", 1)[1].split(
        "![", 1)[0]
    r = solve(two_dof_bar(), friction=10.0, steps=100, formulation="thesis")
    assert r.coulomb == "lagged" and "lagged normal force, 100 steps" in \
        caption
    force = r.contact_force[:, 0]
    closes = int(np.flatnonzero(force > 0)[0])   # the step before λ > 0
    slides = np.flatnonzero(r.slip[:, 0]) + 1
    sticks = np.flatnonzero(r.stick[:, 0]) + 1
    assert f"The gap closes in step {closes}" in caption
    assert list(slides) == [closes + 1]
    assert f"in step {closes + 1} A slides freely" in caption
    assert r.friction_bound[closes, 0] == 0
    assert list(sticks) == list(range(closes + 2, 101))


def test_block_friction_caption(block):
    caption = README.split("(docs/figures/friction_tractions_fc0.3.png)",
                           1)[1].split("More in", 1)[0]
    r = solve(block, friction=0.3, steps=100, formulation="thesis")
    n_contact, n_slip = int(r.in_contact[-1].sum()), int(r.slip[-1].sum())
    assert r.success and n_slip == n_contact
    assert f"all {WORDS[n_contact]} contact nodes slip" in caption
