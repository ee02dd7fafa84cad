"""The engine interface (solver/contact/engine.py): the drivers and
strategies take their linear algebra from the engine given to
:func:`solver.solve` (as the PETSc engine's condensations do), and give
the answer of the default engine (the reference: the same call on it)."""

import numpy as np

from solver import load_problem, solve, solve_frictionless
from solver.contact import SerialEngine
from solver.contact.geometry import contact_geometry
from solver.contact.strategies.candidates import NormalCondensation
from solver.linalg.condensation import Condensation


class CountingNormal(NormalCondensation):
    calls = 0

    def factorize(self, nodes):
        self.calls += 1
        return super().factorize(nodes)


class CountingCondensation(Condensation):
    loads = 0

    def load(self, f):
        self.loads += 1
        return super().load(f)


class CountingEngine(SerialEngine):
    """A serial engine whose condensations count their use."""

    name = "counting"

    def __init__(self, backend):
        super().__init__(backend)
        self.made = []

    def condensation(self, problem, dofs):
        made = CountingCondensation(problem, dofs, self.backend)
        self.made.append(made)
        return made

    def normal_condensation(self, problem, geometry):
        made = CountingNormal(problem, geometry, self.backend)
        self.made.append(made)
        return made


def test_candidates_loop_uses_the_engine(exported):
    problem = load_problem(exported(454)[0])
    engine = CountingEngine("superlu")
    result = solve(problem, method="min", candidates=True, engine=engine)
    reference = solve(problem, method="min", candidates=True,
                      start="free", backend="superlu")
    (given,) = engine.made
    assert given.calls == len(result.candidates["rounds"]) >= 1
    assert result.njev == reference.njev
    assert np.abs(result.u - reference.u).max() <= \
        1e-10 * np.abs(reference.u).max()


def test_friction_uses_the_engine(exported):
    problem = load_problem(exported(118)[0])
    engine = CountingEngine("superlu")
    options = dict(friction=0.3, steps=5, formulation="projection",
                   method="fb")
    result = solve(problem, engine=engine, **options)
    reference = solve(problem, backend="superlu", **options)
    (given,) = engine.made
    assert given.loads >= 1 and result.success
    assert result.njev == reference.njev
    scale = np.abs(reference.displacement).max()
    assert np.abs(result.displacement - reference.displacement).max() <= \
        1e-10 * scale


def test_2d_candidates_take_every_free_node_in_one_factorisation(exported):
    """In 2D the candidates' default round 0 is every free contact node:
    one factorisation (the 5 % screening grew once on the 1878 block), and
    the answer of the (x, y) condensation onto all of Γc (the independent
    reference: another Schur set, another Newton system, nested start).
    An explicit margin still screens."""
    problem = load_problem(exported(1878)[0])
    geometry = contact_geometry(problem, "obstacle")
    free = int(np.isfinite(geometry.gap).sum())
    result = solve_frictionless(problem, method="min", candidates=True,
                                start="free", backend="superlu",
                                geometry=geometry)
    screening = result.candidates
    assert len(screening["rounds"]) == 1
    assert screening["n_candidates"] == free
    reference = solve_frictionless(problem, method="min", backend="superlu",
                                   geometry=geometry)
    assert result.success and reference.success
    scale = np.abs(reference.u).max()
    assert np.abs(result.u - reference.u).max() <= 1e-8 * scale
    screened = solve_frictionless(problem, method="min", candidates=True,
                                  start="free", backend="superlu",
                                  geometry=geometry, margin=0.0)
    assert screened.candidates["n_candidates"] < free
    assert np.abs(screened.u - reference.u).max() <= 1e-8 * scale
