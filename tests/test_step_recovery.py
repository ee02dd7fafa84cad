"""A friction run kept in memory recovers its steps' displacements in all
unknowns when first read (solver/contact/friction/stream.py): the same
numbers as the steps streamed through ``on_step``, each step in
equilibrium with its load, whatever way the result is read."""

import copy
import pickle

import numpy as np
import pytest

from solver import load_problem, solve
from solver.contact.result import ContactResult, Deferred

RUN = dict(friction=0.3, steps=8, method="min")


@pytest.fixture(scope="module")
def block(exported):
    return load_problem(exported(454)[0])


def test_recovered_when_read_equal_to_the_streamed_steps(block):
    streamed = []
    eager = solve(block, on_step=lambda f: streamed.append(
        (f["u"].copy(), f["displacement"].copy())), **RUN)
    lazy = solve(block, **RUN)
    assert lazy.success and lazy.condensed
    assert isinstance(dict.__getitem__(lazy, "u"), Deferred)  # not yet
    assert lazy.displacement.shape == (8,) + block.u_prescribed.shape
    assert not isinstance(dict.__getitem__(lazy, "u"), Deferred)  # both
    np.testing.assert_array_equal(lazy.u, [u for u, _ in streamed])
    np.testing.assert_array_equal(lazy.displacement,
                                  [d for _, d in streamed])
    np.testing.assert_array_equal(lazy.u, eager.u)


def test_every_step_in_equilibrium_with_its_load(block):
    """Independent of the recovery's algebra: K u_κ = f_κ on every free
    DOF that no contact force acts on (f_κ = load factor·f, the default
    path), to round-off of the load."""
    result = solve(block, **RUN)
    contact = block.contact_dofs[block.contact_dofs >= 0]
    other = np.setdiff1d(np.arange(block.n_dofs), contact)
    scale = np.linalg.norm(block.f)
    for factor, u in zip(result.load_factor, result.u):
        residual = block.K @ u - factor * block.f
        assert np.linalg.norm(residual[other]) <= 1e-10 * scale
    assert np.linalg.norm(result.u[-1] - result.u[-2]) > 0  # steps differ


@pytest.mark.parametrize("read", [
    lambda r: r.get("u"), lambda r: dict(r)["u"], lambda r: {**r}["u"],
    lambda r: dict(r.items())["u"], lambda r: r.values()[list(r).index("u")],
    lambda r: pickle.loads(pickle.dumps(r))["u"],
    lambda r: copy.deepcopy(r)["u"], lambda r: r.copy()["u"]])
def test_every_way_of_reading_gives_the_arrays(block, read):
    result = solve(block, **RUN)
    u = read(result)
    assert isinstance(u, np.ndarray) and u.shape == (8, block.n_dofs)
    assert "<computed" not in repr(result)


def test_not_kept_or_streamed_runs_hold_no_placeholder(block):
    kept = solve(block, keep_steps=False, **RUN)
    assert "u" not in kept and kept.success
    full = solve(block, system="full", **RUN)
    assert isinstance(dict.__getitem__(full, "u"), np.ndarray)


def test_a_placeholder_is_computed_once():
    calls = []

    def compute():
        calls.append(1)
        return dict(a=np.ones(2), b=np.zeros(2))

    result = ContactResult(x=1, a=Deferred(compute, "ab"),
                           b=Deferred(compute, "ab"))
    assert result.b.sum() == 0 and result.a.sum() == 2 and result["a"][0]
    assert len(calls) == 1 and result.get("missing", 5) == 5


def test_contact_nodes_closed_in_every_recovered_step(block):
    """The recovered fields against the contact solve's own: every node in
    contact at step κ has u·ν = g (its gap closed), every other free node
    u·ν ≤ g."""
    result = solve(block, **RUN)
    nodes = np.asarray(block.contact_nodes)
    length = 1e-8 * np.nanmax(np.abs(result.gap))
    for k in range(RUN["steps"]):
        u_n = np.einsum("ij,ij->i", result.displacement[k][nodes],
                        result.normal)
        closed = result.in_contact[k]
        np.testing.assert_allclose(u_n[closed], result.gap[closed], rtol=0,
                                   atol=length)
        free = ~np.isnan(result.gap)
        assert np.all(u_n[free] <= result.gap[free] + length)
    assert result.in_contact[-1].sum() >= 3  # the check has nodes to test
