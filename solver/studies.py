"""The thesis's Tables 1 and 2 as data, for scripts and notebooks.

Each function runs our solvers on given problems and returns rows (dicts)
with the thesis's numbers beside ours; nothing here prints or plots."""

from .contact import contact_geometry
from .front import solve_friction, solve_frictionless

import numpy as np

__all__ = ["THESIS_TABLE1", "THESIS_TABLE2", "table1", "table2",
           "system_comparison", "gradient_steps_by_load_step",
           "relative_difference", "tangential_displacement",
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
                result=r, steps_completed=r.steps_completed,
                gradient_steps=sum(x["gradient_steps"] for x in r.records),
                contact_nodes=int(r.in_contact[-1].sum())
                if r.steps_completed else None,
                stick=int(r.stick[-1].sum()) if r.steps_completed else None,
                slip=int(r.slip[-1].sum()) if r.steps_completed else None,
                time=r.time))
    return rows


def relative_difference(a, b):
    """max|a − b| / max|a|: how far two solutions (arrays) differ."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.abs(a - b).max() / np.abs(a).max())


def system_comparison(problems, methods=("fb", "min"), gap="obstacle"):
    """The thesis's full system from u = 0 against our default, condensed
    onto Γc with the nested start, for each of ``problems`` ({elements:
    ContactProblem}) and method: J/F counts of both (the condensed ones
    over all levels and on the full Γc, the last level) and the relative
    difference of the two displacement solutions."""
    rows = []
    for elements, problem in problems.items():
        geometry = contact_geometry(problem, gap)
        for method in methods:
            full = solve_frictionless(problem, method=method, gap=gap,
                                      geometry=geometry, condense=False)
            condensed = solve_frictionless(problem, method=method, gap=gap,
                                           geometry=geometry)
            last = condensed.levels[-1] if condensed.levels else condensed
            rows.append(dict(
                elements=elements, method=method, full_J=full.njev,
                full_F=full.nfev, condensed_start=condensed.start,
                condensed_J=condensed.njev, condensed_F=condensed.nfev,
                levels=len(condensed.levels),
                last_level_J=int(last["njev"]),
                du=relative_difference(full.u, condensed.u),
                converged=bool(full.success and condensed.success)))
    return rows


def tangential_displacement(problem, result):
    """u_t = u · γ at the nodes of Γc of a frictionless result, with the
    tangent γ = (−ν_y, ν_x) of the friction solver (NaN at supports)."""
    normal = np.asarray(result.normal)
    tangent = np.c_[-normal[:, 1], normal[:, 0]]
    return (result.displacement[problem.contact_nodes] * tangent).sum(axis=1)


def gradient_steps_by_load_step(result):
    """{load step κ: number of gradient steps} of a friction run (only the
    steps that took any)."""
    return {r["step"]: r["gradient_steps"] for r in result.records
            if r["gradient_steps"]}


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
