"""3D friction's reduced Newton systems (:mod:`solver.contact.friction.disc`,
``REDUCED``: the primal or dual system of the primal–dual active set
structure, a Cholesky of about half the order) against the LU of the whole
n×n system with the tractions eliminated.

References: that whole system's LU (``REDUCED = False``, the solver's path
before), and for the backward error the sparse Jacobian that
:class:`~solver.contact.friction.system.FrictionSystem` assembles on its
own (tests/test_friction_candidates_rollers.py checks it against the disc
system). The reduction is exact block elimination: the directions agree to
round-off, so the runs take the same Newton steps and give the same
answers.

Problems: tests/test_rollers.py's half and quarter blocks on a paraboloid,
pressed, then dragged (rollers stick and slip; slip nodes with ŵ off the
tangent axes turn their frames).
"""

import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

sys.path.insert(0, str(Path(__file__).resolve().parent))

from test_friction_candidates import assert_same_run  # noqa: E402
# the half and quarter dragged blocks (a module fixture) and their options
from test_friction_candidates_rollers import RUN, problems  # noqa: E402,F401
from test_rollers import FC  # noqa: E402
from solver import solve_friction  # noqa: E402
from solver.contact.friction import disc  # noqa: E402
from solver.contact.friction.projection import ProjectionSystem  # noqa: E402


def _sparse_jacobian(combined):
    """J = [D JE; w_a JA + w_b JB] from FrictionSystem's sparse assembly
    at the Jacobian's iterate (DiscSystem's projection rows are D(g − P))."""
    jac = combined.jac
    system, x = jac.system, jac.x
    JE, JA, JB = ProjectionSystem.jacobian(system, x)
    rows = sp.diags(np.concatenate([np.ones(JE.shape[0] - system.mt),
                                    system.lumped_t]))
    return sp.vstack([rows @ JE, sp.diags(combined.wa) @ JA
                      + sp.diags(combined.wb) @ JB]).toarray()


@pytest.mark.parametrize("coulomb, form", [
    ("lagged", "smaller"), ("lagged", "primal"), ("lagged", "dual"),
    ("implicit", "smaller")])
@pytest.mark.parametrize("method", ["min", "fb"])
@pytest.mark.parametrize("part", ["half", "quarter"])
def test_reduced_direction_is_the_whole_systems(problems, monkeypatch, part,
                                                method, coulomb, form):
    """At every iterate of a run: the reduced direction (the smaller
    system, or always the primal, or always the dual; with the implicit
    bound the primal, its slip rows coupled to the normal forces) equals
    the whole system's LU direction to 1e-9 and solves the sparse
    J d = −F with a backward error at round-off; the forms asked for are
    the ones taken."""
    monkeypatch.setattr(disc, "FORM", form)
    direction = disc._DiscCombined.direction
    forward, backward, seen = [], [], {"primal": 0, "dual": 0}

    def checked(self, F):
        d = direction(self, F)
        monkeypatch.setattr(disc, "REDUCED", False)
        whole = direction(self, F)
        monkeypatch.setattr(disc, "REDUCED", True)
        J = _sparse_jacobian(self)
        norm = np.linalg.norm
        forward.append(norm(d - whole) / norm(whole))
        backward.append(norm(J @ d + F) / (norm(J, 2) * norm(d) + norm(F)))
        return d

    solve = ProjectionSystem._reduced_solve

    def counted(self, A, h, symmetric, kind):
        seen[kind] += 1
        return solve(self, A, h, symmetric, kind)

    monkeypatch.setattr(disc._DiscCombined, "direction", checked)
    monkeypatch.setattr(disc.DiscSystem, "_reduced_solve", counted,
                        raising=False)
    result = solve_friction(problems[part], FC, method=method,
                            coulomb=coulomb, **RUN)
    assert result.success and forward
    # measured: forward ≤ 3.8e-15, backward ≤ 2.9e-16
    assert max(forward) <= 1e-9
    assert max(backward) <= 1e-13
    # these small blocks touch on most candidates: "smaller" is the primal
    taken = {"smaller": "primal"}.get(form, form)
    assert seen[taken] == len(forward) and sum(seen.values()) == len(forward)


@pytest.mark.parametrize("coulomb", ["lagged", "implicit"])
@pytest.mark.parametrize("method", ["min", "fb"])
def test_reduced_run_equals_whole_run(problems, monkeypatch, method,
                                      coulomb):
    """The quarter block's run: every step's fields equal to 1e-10, and the
    same Jacobian and residual counts in every step, as with the whole
    system's LU."""
    kw = dict(RUN, method=method, coulomb=coulomb)
    ours = solve_friction(problems["quarter"], FC, **kw)
    monkeypatch.setattr(disc, "REDUCED", False)
    whole = solve_friction(problems["quarter"], FC, **kw)
    assert_same_run(ours, whole)
    assert [(r["njev"], r["nfev"]) for r in ours.records] == \
        [(r["njev"], r["nfev"]) for r in whole.records]


def test_no_flexibility_takes_the_primal(problems, monkeypatch):
    """Where C = T⁻¹ cannot be made (T not positive definite, LAPACK's
    potrf says so) the dual form is not taken: the primal one solves, and
    the run is the whole system's."""
    monkeypatch.setattr(disc, "FORM", "dual")
    tried = []

    def refused(self):
        tried.append(1)
        raise np.linalg.LinAlgError("T is not positive definite")

    kinds = []
    solve = ProjectionSystem._reduced_solve

    def counted(self, A, h, symmetric, kind):
        kinds.append(kind)
        return solve(self, A, h, symmetric, kind)

    monkeypatch.setattr(disc.DiscSystem, "flexibility", refused)
    monkeypatch.setattr(disc.DiscSystem, "shares_flexibility", False)
    monkeypatch.setattr(disc.DiscSystem, "_reduced_solve", counted,
                        raising=False)
    kw = dict(RUN, method="min", coulomb="lagged")
    ours = solve_friction(problems["quarter"], FC, **kw)
    monkeypatch.setattr(disc, "REDUCED", False)
    whole = solve_friction(problems["quarter"], FC, **kw)
    assert tried and kinds and set(kinds) == {"primal"}
    assert_same_run(ours, whole)
