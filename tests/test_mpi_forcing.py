"""Inexact Newton under ``mpiexec`` (issue 33, point 1; solver/mpi/full.py
``ForcingTerm``): the Krylov Newton systems of the partitioned folder's
full system, frictionless and with friction, are solved to Eisenstat &
Walker's forcing term (choice 2, η_0 = 10⁻³, the in-process AMG path's
rule) and the last one to the relative 1e-12 as before, with warm
starts, and the answer is unchanged.

The rule itself is checked here by hand (Eisenstat & Walker, SISC 17,
1996, choice 2 and its safeguards); that the mpiexec runs use it
(:func:`assert_forcing`, read from summary.json) is checked in the runs
that already compare each path with the serial engine to 1e-8, so that
no launch is added: tests/test_mpi_partitioned_full.py (1, 2 and 4
ranks), tests/test_mpi_krylov_friction.py,
tests/test_mpi_krylov_friction3d.py and
tests/test_mpi_krylov_friction_implicit.py. No PETSc in this
process."""

import numpy as np
import pytest

from solver.contact.frictionless.active_set import ETA_MAX, forcing_term

#: PETSc's relative tolerance of every Newton system before the forcing
#: term (solver/mpi/full.py CG_RTOL).
FIXED_RTOL = 1e-12


def test_forcing_term_choice_2():
    """Eisenstat–Walker choice 2 with its safeguards, by hand: γ(r)² in
    [η_min, η_max], γη² where that exceeds 0.1, uncapped below without
    the safeguard."""
    assert forcing_term(ETA_MAX, 1e-3, 1.0) == pytest.approx(1e-4)  # floor
    assert forcing_term(ETA_MAX, 0.02, 1.0) == pytest.approx(3.6e-4)
    assert forcing_term(ETA_MAX, 1.0, 1.0) == ETA_MAX  # capped
    assert forcing_term(ETA_MAX, 1e-3, 1.0, False) == pytest.approx(9e-7)


def assert_forcing(engine):
    """The first system solved to η_0 (orders looser than the fixed
    rule's relative 1e-12), the last one tighter than the first, one
    entry per Newton system."""
    forcing = engine["ksp_forcing"]
    assert len(forcing) == engine["newton_solves"] > 1
    assert forcing[0] == pytest.approx(ETA_MAX)
    assert forcing[-1] < forcing[0]
    assert all(f >= FIXED_RTOL for f in forcing)


def assert_forcing_steps(summary):
    """A friction run (test_mpi_krylov_friction*): :func:`assert_forcing`,
    and the last system of every load step solved to the relative 1e-12
    (its sets repeated), at least half of them to η."""
    engine = summary["engine"]
    assert_forcing(engine)
    forcing = np.array(engine["ksp_forcing"])
    assert len(forcing) == sum(r["njev"] for r in summary["records"])
    last = np.cumsum([r["njev"] for r in summary["records"]]) - 1
    assert np.all(forcing[last] == FIXED_RTOL)
    assert np.count_nonzero(forcing > FIXED_RTOL) >= len(forcing) // 2
