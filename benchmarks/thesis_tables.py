"""Print the thesis's Tables 1 and 2 next to ours.

Usage (after exporting the three meshes, see the README)::

    python benchmarks/thesis_tables.py output/block_118.npz \
        output/block_454.npz output/block_1878.npz

Table 2 is run on every given mesh (the thesis does not say which of its
meshes Table 2 used). Counts are deterministic; times are indicative only.
"""

import sys

from solver import load_problem
from solver.studies import table1, table2


def show(rows, columns):
    widths = [max(len(c), *(len(_fmt(r[c])) for r in rows)) for c in columns]
    print("  ".join(c.rjust(w) for c, w in zip(columns, widths)))
    for r in rows:
        print("  ".join(_fmt(r[c]).rjust(w) for c, w in zip(columns, widths)))


def _fmt(value):
    if isinstance(value, float):
        return f"{value:.3g}"
    return "-" if value is None else str(value)


def main(paths):
    problems = {len(p.cells): p for p in map(load_problem, paths)}
    print("Table 1 (frictionless, J / F evaluations)")
    show(table1(problems), ["method", "elements", "gap", "thesis_J",
                            "thesis_F", "J", "F", "line_search_failures",
                            "contact_nodes", "max_pressure", "time"])
    for elements, problem in problems.items():
        print(f"\nTable 2 (friction, 100 load steps), {elements} elements")
        show(table2(problem), ["friction", "formulation", "coulomb",
                               "method", "thesis_J", "thesis_F", "J", "F",
                               "converged", "gradient_steps",
                               "contact_nodes", "stick", "slip", "time"])


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
