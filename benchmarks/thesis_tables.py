"""Print the thesis's Tables 1 and 2 next to ours.

Usage (after exporting the three meshes, see the README)::

    python benchmarks/thesis_tables.py output/block_118.npz \
        output/block_454.npz output/block_1878.npz

The meshes are taken in the order of their element counts, whatever the
order of the paths (a shell glob gives 118, 1878, 454). Table 2 is run on
every given mesh (the thesis does not say which of its meshes Table 2
used). A run that does not converge is listed with its solver's message
under the table. Counts are deterministic; times are indicative only.
"""

import sys

from solver import load_problem
from solver.studies import table1, table2

TABLE1_COLUMNS = ["method", "elements", "gap", "thesis_J", "thesis_F", "J",
                  "F", "line_search_failures", "contact_nodes",
                  "max_pressure", "time"]
TABLE2_COLUMNS = ["friction", "formulation", "coulomb", "method",
                  "thesis_J", "thesis_F", "J", "F", "converged",
                  "gradient_steps", "contact_nodes", "stick", "slip", "time"]


def show(rows, columns, label):
    """The rows as a table, then one line per run that did not converge:
    ``label(row)`` and its message."""
    widths = [max(len(c), *(len(_fmt(r[c])) for r in rows)) for c in columns]
    print("  ".join(c.rjust(w) for c, w in zip(columns, widths)))
    for r in rows:
        print("  ".join(_fmt(r[c]).rjust(w) for c, w in zip(columns, widths)))
    for r in rows:
        if not r["converged"]:
            print(f"not converged: {label(r)}: {r['result'].message}")


def _fmt(value):
    if isinstance(value, float):
        return f"{value:.3g}"
    return "-" if value is None else str(value)


def by_elements(paths):
    """{elements: problem}, in increasing element count."""
    problems = [load_problem(path) for path in paths]
    return {len(p.cells): p for p in sorted(problems,
                                            key=lambda p: len(p.cells))}


def main(paths):
    problems = by_elements(paths)
    print("Table 1 (frictionless, J / F evaluations)")
    show(table1(problems), TABLE1_COLUMNS,
         lambda r: f"{r['method']}, {r['elements']} elements, gap from "
                   f"{r['gap']}")
    for elements, problem in problems.items():
        print(f"\nTable 2 (friction, 100 load steps), {elements} elements")
        show(table2(problem), TABLE2_COLUMNS,
             lambda r: f"f_c = {r['friction']:g}, {r['formulation']}, "
                       f"{r['coulomb']}, {r['method']}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
