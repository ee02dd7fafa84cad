"""The thesis's Tables 1 and 2 as data, for scripts and notebooks.

Each function runs our solvers on given problems and returns rows (dicts)
with the thesis's numbers beside ours; nothing here prints or plots.
"""

from .contact import contact_geometry, solve_friction, solve_frictionless

__all__ = ["THESIS_TABLE1", "THESIS_TABLE2", "table1", "table2",
           "markdown_table"]

#: Thesis Table 1: (method, elements) -> (J evaluations, F evaluations).
THESIS_TABLE1 = {("fb", 118): (18, 80), ("min", 118): (6, 61),
                 ("fb", 454): (22, 117), ("min", 454): (8, 65),
                 ("fb", 1878): (29, 169), ("min", 1878): (10, 69)}

#: Thesis Table 2 (φ_FB, 100 load steps): f_c -> (J, F evaluations).
THESIS_TABLE2 = {0.05: (664, 3554), 0.3: (504, 1014), 10.0: (308, 616)}


def table1(problems, methods=("fb", "min"), gaps=("obstacle", "body"),
           condense=False):
    """Frictionless solves of ``problems`` ({elements: ContactProblem}),
    by default in the thesis's full system (``condense=False``: the counts
    comparable with Table 1)."""
    rows = []
    for elements, problem in problems.items():
        for gap in gaps:
            geometry = contact_geometry(problem, gap)
            for method in methods:
                r = solve_frictionless(problem, method=method, gap=gap,
                                       geometry=geometry, condense=condense)
                thesis = THESIS_TABLE1.get((method, elements), (None, None))
                rows.append(dict(
                    method=method, elements=elements, gap=gap,
                    thesis_J=thesis[0], thesis_F=thesis[1], J=r.njev,
                    F=r.nfev, iterations=r.nit, converged=bool(r.success),
                    result=r,
                    line_search_failures=sum(r.history["line_search_failed"]),
                    contact_nodes=r.n_contact,
                    max_pressure=float(r.contact_pressure.max()),
                    time=r.time))
    return rows


def table2(problem, frictions=(0.05, 0.3, 10.0), steps=100,
           variants=(("thesis", "lagged", "fb"),
                     ("projection", "lagged", "fb"),
                     ("projection", "implicit", "min")), condense=False):
    """Friction runs of ``problem`` for each f_c and (formulation, coulomb,
    method) variant, by default in the full system (comparable with
    Table 2)."""
    rows = []
    geometry = contact_geometry(problem, "obstacle")
    for fc in frictions:
        thesis = THESIS_TABLE2.get(fc, (None, None))
        for formulation, coulomb, method in variants:
            r = solve_friction(problem, fc, steps=steps,
                               formulation=formulation, coulomb=coulomb,
                               method=method, geometry=geometry,
                               condense=condense)
            rows.append(dict(
                friction=fc, formulation=formulation, coulomb=coulomb,
                method=method, thesis_J=thesis[0], thesis_F=thesis[1],
                J=r.njev, F=r.nfev, converged=bool(r.success),
                steps_completed=r.steps_completed,
                gradient_steps=sum(x["gradient_steps"] for x in r.records),
                contact_nodes=int(r.in_contact[-1].sum())
                if r.steps_completed else None,
                stick=int(r.stick[-1].sum()) if r.steps_completed else None,
                slip=int(r.slip[-1].sum()) if r.steps_completed else None,
                time=r.time))
    return rows


def markdown_table(rows, columns, headers=None):
    """Rows (dicts) as a Markdown table of the given columns."""
    headers = headers or columns

    def text(value):
        if isinstance(value, float):
            return f"{value:.3g}"
        return "–" if value is None else str(value)

    lines = ["| " + " | ".join(headers) + " |",
             "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join(text(r[c]) for c in columns) + " |"
              for r in rows]
    return "\n".join(lines)
