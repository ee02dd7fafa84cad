"""solver.linalg backends: each installed backend against SuperLU (the
reference, and SciPy's spsolve where named) to 1e-10 relative: solutions,
the Schur complement S and the condensed right-hand side, the back-
substitution, the positive-definiteness check, and a whole frictionless
solve. A backend whose pip extra is missing is skipped, saying which."""

from importlib import import_module

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from solver import load_problem, solve_friction, solve_frictionless
from solver.contact import contact_geometry
from solver.errors import ProblemError, SolverError
from solver.linalg import (AUTO_ORDER, BACKENDS, Condensation, factorize,
                           available_backends, dof_ordering, resolve)

OTHERS = ("pardiso", "cholmod")


def require(name):
    """Skip, saying which extra installs it, unless ``name`` is installed."""
    module = import_module(f"solver.linalg.{name}")
    if not module.available():
        pytest.skip(f"{name} backend not installed: pip install "
                    f"'.[{module.EXTRA}]'")


@pytest.fixture(scope="module", params=["454", "refined"])
def problem(request, exported, refined_block):
    if request.param == "454":
        return load_problem(exported(454)[0])
    return refined_block(1)


def close(a, b, rtol=1e-10):
    """max |a − b| ≤ rtol · max |b|."""
    scale = np.abs(b).max()
    assert np.abs(np.asarray(a) - b).max() <= rtol * scale


@pytest.mark.parametrize("name", BACKENDS)
def test_solve_matches_spsolve(problem, name):
    require(name)
    factor = factorize(problem.K, dof_ordering(problem), backend=name)
    assert factor.backend == name
    reference = sla.spsolve(problem.K.tocsc(), problem.f)  # SciPy's LU
    close(factor.solve(problem.f), reference)
    B = np.column_stack([problem.f, np.roll(problem.f, 5)])
    X = factor.solve(B)
    assert X.shape == B.shape
    close(X[:, 0], reference)
    close(X[:, 1], sla.spsolve(problem.K.tocsc(), B[:, 1]))


@pytest.mark.parametrize("name", OTHERS)
def test_schur_complement_matches_superlu(problem, name):
    """S, g̃ and the back-substitution of each backend equal SuperLU's
    (itself checked against spsolve in test_linalg)."""
    require(name)
    c = contact_geometry(problem).dofs.ravel()[::-1]  # any order of c
    reference = Condensation(problem, c, backend="superlu")
    ours = Condensation(problem, c, backend=name)
    assert ours.backend == name and ours.S.shape == (len(c), len(c))
    close(ours.S, reference.S)
    g, w = ours.load(problem.f)
    g_ref, w_ref = reference.load(problem.f)
    close(g, g_ref)
    close(w, w_ref)
    close(ours.factorization.condensed_rhs(problem.f), g_ref)
    rng = np.random.default_rng(1)
    U_c = 1e-3 * rng.standard_normal((len(c), 3))
    W = np.column_stack([w, 2 * w, -w])
    close(ours.displacement(U_c, W), reference.displacement(U_c, W))
    u = ours.factorization.back_substitute(problem.f, U_c[:, 0])
    r = problem.K @ u - problem.f  # equilibrium off c
    interior = np.setdiff1d(np.arange(problem.n_dofs), c)
    assert np.abs(r[interior]).max() <= 1e-9 * np.abs(problem.f).max()
    close(u[c], U_c[:, 0])


@pytest.mark.parametrize("name", BACKENDS)
@pytest.mark.parametrize("matrix, message", [
    # eigenvalues ≈ −1.16, 1.77, 3.39 (numpy.linalg.eigvalsh): one negative
    (np.array([[2.0, -1, 0], [-1, 1, 2], [0, 2, 1]]),
     "not positive definite: it has 1 negative eigenvalue"),
    # the path graph's Laplacian: L·1 = 0
    (np.array([[1.0, -1, 0], [-1, 2, -1], [0, -1, 1]]),
     r"not positive definite \(singular stiffness")])
@pytest.mark.parametrize("schur", [None, [2]])
def test_refuses_indefinite_and_singular(name, matrix, message, schur):
    """Every backend refuses with the same inertia message as SuperLU."""
    require(name)
    with pytest.raises(ProblemError, match="K_data: K is " + message):
        factorize(sp.csr_matrix(matrix), schur=schur, backend=name)


@pytest.mark.parametrize("name", BACKENDS)
def test_refuses_unsupported_block(problem, name):
    """The block without its clamp (K·1 = 0 per direction: rigid modes)."""
    require(name)
    K = problem.K.tolil()
    K.setdiag(K.diagonal() - np.asarray(K.sum(axis=1)).ravel())
    c = contact_geometry(problem).dofs.ravel()
    with pytest.raises(ProblemError, match="not positive definite"):
        factorize(K.tocsr(), dof_ordering(problem, last=c), schur=c,
                  backend=name)


@pytest.mark.parametrize("name", OTHERS)
def test_frictionless_and_friction_equal_superlu(exported, name):
    require(name)
    problem = load_problem(exported(454)[0])
    ref = solve_frictionless(problem, backend="superlu")
    ours = solve_frictionless(problem, backend=name)
    assert ours.success and ours.linear_solver == name
    assert ref.linear_solver == "superlu"
    close(ours.u, ref.u)
    close(ours.contact_force, ref.contact_force, 1e-9)
    kwargs = dict(steps=5, formulation="projection")
    ref = solve_friction(problem, 0.3, backend="superlu", **kwargs)
    ours = solve_friction(problem, 0.3, backend=name, **kwargs)
    assert ours.success and ours.linear_solver == name
    close(ours.u, ref.u, 1e-9)


def test_auto_rule_and_missing_backend(monkeypatch):
    installed = available_backends()
    assert installed[-1] == "superlu"  # always there
    assert resolve("auto") == [n for n in AUTO_ORDER if n in installed][0]
    with pytest.raises(SolverError, match="must be one of"):
        resolve("umfpack")
    from solver.linalg import cholmod
    monkeypatch.setattr(cholmod, "available", lambda: False)
    with pytest.raises(SolverError, match=r"pip install 'contact-ssn\["
                                          r"cholmod\]'"):
        resolve("cholmod")


@pytest.mark.parametrize("friction", [None, "0.3"])
def test_cli_option_recorded_in_summary(exported, tmp_path, capsys,
                                        friction):
    import json

    from solver.cli import main

    extra = [] if friction is None else ["--friction", friction, "--steps",
                                         "3", "--formulation", "projection"]
    path = str(exported(118)[0])
    for name in available_backends():
        out = tmp_path / name
        assert main([path, "--linear-solver", name, "-o", str(out)]
                    + extra) == 0
        summary = json.loads((out / "summary.json").read_text())
        assert summary["linear_solver"] == name
    out = tmp_path / "auto"
    assert main([path, "-o", str(out)] + extra) == 0
    assert json.loads((out / "summary.json").read_text())[
        "linear_solver"] == resolve("auto")
    capsys.readouterr()


def test_cli_missing_backend_exit_2(exported, tmp_path, capsys,
                                    monkeypatch):
    from solver.cli import main
    from solver.linalg import pardiso

    monkeypatch.setattr(pardiso, "available", lambda: False)
    out = tmp_path / "never"
    assert main([str(exported(118)[0]), "--linear-solver", "pardiso", "-o",
                 str(out)]) == 2
    assert "pip install 'contact-ssn[mkl]'" in capsys.readouterr().err
    assert not out.exists()


def test_factorisation_reused_across_solves(exported):
    """One factorisation and S per K: solves with other methods, gap
    modes and starts reuse it; a new K is factorised anew."""
    problem = load_problem(exported(118)[0])
    c = contact_geometry(problem).dofs.ravel()
    first = Condensation.of(problem, c)
    for kwargs in (dict(method="fb"), dict(gap="body"),
                   dict(start="free")):
        assert solve_frictionless(problem, **kwargs).success
    assert solve_friction(problem, 0.2, steps=3,
                          formulation="projection").success
    assert Condensation.of(problem, c) is first
    assert first.n_solves <= 1 + 5  # K⁻¹f once, one back-substitution each
    problem.K = problem.K.copy()
    assert Condensation.of(problem, c) is not first


@pytest.mark.parametrize("read_in_place", [True, False])
def test_cholmod_schur_both_ways(exported, monkeypatch, read_in_place):
    """CHOLMOD's S read in place from the factor (the fast path, which must
    not silently fall back) and by forward sweeps equal SuperLU's."""
    require("cholmod")
    from solver.linalg import cholmod, cholmod_struct

    problem = load_problem(exported(454)[0])
    c = contact_geometry(problem).dofs.ravel()
    order = dof_ordering(problem, last=c)
    reference = factorize(problem.K, order, schur=c, backend="superlu")
    if not read_in_place:
        monkeypatch.setattr(cholmod, "trailing_block", lambda *a: None)
    ours = factorize(problem.K, order, schur=c, backend="cholmod")
    L22 = cholmod_struct.trailing_block(ours._F, order, len(c))
    assert L22 is not None  # and it passes the check of the fast path:
    assert np.array_equal(np.diagonal(L22), ours._diagonal[-len(c):])
    close(ours.S, reference.S)


@pytest.mark.parametrize("name", BACKENDS)
def test_schur_on_every_dof_is_the_matrix(name):
    """An empty interior (every DOF condensed, as in the 2-DOF bar): S is A
    itself in c's order, g̃ = b_c and the back-substitution puts u_c back
    (no interior left). PARDISO is not asked for its Schur mode there."""
    require(name)
    A = sp.csr_matrix(np.array([[4.0, 1, 0], [1, 3, 1], [0, 1, 2]]))
    c, b, u_c = np.array([2, 0, 1]), np.array([1.0, 2, 3]), \
        np.array([1.0, 2, 3])
    factor = import_module(f"solver.linalg.{name}").factorize(
        A, np.arange(3), c, "K", True)
    np.testing.assert_allclose(factor.S, A.toarray()[np.ix_(c, c)],
                               rtol=0, atol=1e-15)
    np.testing.assert_allclose(factor.condensed_rhs(b), b[c], atol=1e-15)
    u = factor.back_substitute(b, u_c)
    np.testing.assert_allclose(u[c], u_c, atol=1e-15)
    np.testing.assert_allclose(factor.solve(b), sla.spsolve(A.tocsc(), b),
                               rtol=1e-12)
