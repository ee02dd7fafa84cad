"""benchmarks/thesis_tables.py (issue 34, point 24): the meshes in the
order of their element counts whatever the order of the paths (a shell
glob gives block_118, block_1878, block_454), and a run that did not
converge listed with its message, not only as ``False`` in a column.

The studies themselves (:mod:`solver.studies`) are replaced by stubs that
record what they were given: their numbers are tested elsewhere
(tests/test_readme.py, tests/test_studies.py)."""

import sys
from types import SimpleNamespace

from conftest import ROOT

sys.path.insert(0, str(ROOT / "benchmarks"))

import thesis_tables  # noqa: E402


def test_meshes_sorted_and_failures_named(monkeypatch, capsys):
    sizes = {"block_118.npz": 118, "block_1878.npz": 1878,
             "block_454.npz": 454}
    monkeypatch.setattr(thesis_tables, "load_problem", lambda path: (
        SimpleNamespace(cells=[None] * sizes[path])))
    table1_given, table2_given = [], []

    def table1(problems):
        table1_given.append(list(problems))
        return [dict(method="fb", elements=n, gap="obstacle", thesis_J=1,
                     thesis_F=2, J=3, F=4, line_search_failures=0,
                     contact_nodes=4, max_pressure=1.0, time=0.1,
                     converged=True, result=None) for n in problems]

    def table2(problem):
        n = len(problem.cells)
        table2_given.append(n)
        failed = SimpleNamespace(
            message=f"load step 28 of 100 did not converge ({n})")
        return [dict(friction=0.3, formulation="thesis", coulomb="lagged",
                     method="fb", thesis_J=504, thesis_F=1014, J=30, F=1258,
                     converged=n != 1878, gradient_steps=30,
                     contact_nodes=None, stick=None, slip=None, time=1.0,
                     result=failed)]

    monkeypatch.setattr(thesis_tables, "table1", table1)
    monkeypatch.setattr(thesis_tables, "table2", table2)
    thesis_tables.main(sorted(sizes))          # the shell's order
    assert table1_given == [[118, 454, 1878]]
    assert table2_given == [118, 454, 1878]
    out = capsys.readouterr().out
    headings = [line for line in out.splitlines()
                if line.startswith("Table 2")]
    assert [h.split(", ")[-1] for h in headings] == [
        "118 elements", "454 elements", "1878 elements"]
    failures = [line for line in out.splitlines()
                if line.startswith("not converged")]
    assert failures == ["not converged: f_c = 0.3, thesis, lagged, fb: "
                        "load step 28 of 100 did not converge (1878)"]
