"""The ``condensation=`` keywords that let the PETSc engine (solver/mpi)
run the serial loops on its own factorisation (task MPI20B's clean-ups):
:func:`solver.contact.strategies.candidates.solve_on_candidates` and
:func:`solver.contact.solve_friction` use the object given, and give the
answer of their default path (the reference: the same call without it)."""

import numpy as np

from solver import load_problem, solve_friction, solve_frictionless
from solver.contact.strategies.candidates import NormalCondensation, solve_on_candidates
from solver.contact.geometry import contact_geometry, contact_stiffness
from solver.contact.verify import unit_free_options
from solver.linalg.condensation import Condensation
from solver.ncp import stable_norm


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


def test_candidates_loop_uses_given_condensation(exported):
    problem = load_problem(exported(454)[0])
    geometry = contact_geometry(problem, "obstacle")
    stiffness = contact_stiffness(problem.K, geometry)
    load_norm = stable_norm(problem.f)
    options = unit_free_options("min", None, load_norm, stiffness,
                                geometry.gap)
    given = CountingNormal(problem, geometry, "superlu")
    result, u, lam, un, screening = solve_on_candidates(
        problem, geometry, "min", 1e-10, 100, None, stiffness, stiffness,
        options, load_norm, "superlu", condensation=given)
    reference = solve_frictionless(problem, method="min", candidates=True,
                                   start="free", backend="superlu")
    assert given.calls == len(screening["rounds"]) >= 1
    assert result.njev == reference.njev
    assert np.abs(u - reference.u).max() <= 1e-10 * np.abs(reference.u).max()


def test_friction_uses_given_condensation(exported):
    problem = load_problem(exported(118)[0])
    geometry = contact_geometry(problem, "obstacle", rollers=False)
    given = CountingCondensation(problem, geometry.free_dofs(), "superlu")
    options = dict(steps=5, formulation="projection", method="fb",
                   geometry=geometry)
    result = solve_friction(problem, 0.3, condensation=given, **options)
    reference = solve_friction(problem, 0.3, backend="superlu", **options)
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
