"""Property-based tests (hypothesis, derandomized: every run draws the same
examples, so CI is reproducible; no example database is written).

- NCP functions: φ(a, b) = 0 ⇔ a ≥ 0, b ≥ 0, ab = 0, over all finite
  doubles, and the Fischer-Burmeister function's bounds against min;
- Jacobian weights against central finite differences away from kinks,
  and the assembled Jacobian of Φ of a nonlinear NCP likewise;
- 1000+ random small problems (LCPs with SPD matrices, degenerate ones
  with a known solution, monotone nonlinear NCPs, mixed NCPs of contact
  type) solved by both methods: every reported success is checked
  independently (complementarity ≤ 1e-10), every failure must say so;
- the .npz loader on fuzzed bytes and fuzzed arrays raises nothing but
  ProblemError.
"""

import io
import zipfile
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from solver.errors import ProblemError
from solver.examples import two_dof_bar
from solver.ncp import derivative_weights, phi, solve_ncp
from solver.ncp.newton import Counted
from solver.problem import load_problem, save_problem, validate_arrays

METHODS = ("min", "fb")


def profile(n):
    return settings(derandomize=True, database=None, max_examples=n,
                    deadline=None, suppress_health_check=[
                        HealthCheck.too_slow,
                        HealthCheck.function_scoped_fixture])


finite = st.floats(allow_nan=False, allow_infinity=False)
moderate = st.floats(-1e3, 1e3, allow_nan=False)


# ----------------------------------------------------------------------------
# NCP functions

@profile(3000)
@given(a=finite, b=finite, kind=st.sampled_from(METHODS))
def test_phi_zero_iff_complementary(a, b, kind):
    complementary = a >= 0 and b >= 0 and (a == 0 or b == 0)
    value = phi(np.array([a]), np.array([b]), kind)[0]
    assert np.isfinite(value) or max(abs(a), abs(b)) > 1e307
    assert (value == 0) == complementary, (a, b, value)


@profile(2000)
@given(a=finite, b=finite)
def test_fb_sign_and_bounds(a, b):
    """Tseng (1996): (2 − √2)|min(a, b)| ≤ |φ_FB(a, b)| ≤ (2 + √2)|min(a, b)|,
    and φ_FB has the sign of −min(a, b)."""
    assume(max(abs(a), abs(b)) < 1e300)
    fb = phi(np.array([a]), np.array([b]), "fb")[0]
    mn = min(a, b)
    assert np.sign(fb) == -np.sign(mn)
    slack = 1e-12 * abs(mn) + 1e-320
    assert (2 - np.sqrt(2)) * abs(mn) - slack <= abs(fb)
    assert abs(fb) <= (2 + np.sqrt(2)) * abs(mn) + slack


@profile(1500)
@given(a=moderate, b=moderate, kind=st.sampled_from(METHODS))
def test_weights_match_finite_differences(a, b, kind):
    scale = max(1.0, abs(a), abs(b))
    if kind == "min":
        assume(abs(a - b) > 1e-6 * scale)  # the kink a = b
    else:
        assume(np.hypot(a, b) > 1e-6 * scale)  # the kink a = b = 0
    h = 1e-7 * (scale if kind == "min" else np.hypot(a, b))
    A, B = np.array([a]), np.array([b])
    wa, wb, _ = derivative_weights(A, B, kind)
    fd_a = (phi(A + h, B, kind) - phi(A - h, B, kind)) / (2 * h)
    fd_b = (phi(A, B + h, kind) - phi(A, B - h, kind)) / (2 * h)
    np.testing.assert_allclose(wa, fd_a, atol=1e-6)
    np.testing.assert_allclose(wb, fd_b, atol=1e-6)


def nonlinear_ncp(M, q, c):
    """x ≥ 0, F(x) = Mx + q + c x³ ≥ 0, xᵀF(x) = 0 (strongly monotone)."""
    M = sp.csr_matrix(M)
    n = M.shape[0]
    empty, eye = sp.csr_matrix((0, n)), sp.identity(n, format="csr")
    return (lambda x: (np.zeros(0), x, M @ x + q + c * x ** 3),
            lambda x: (empty, eye, M + sp.diags(3 * c * x ** 2)))


@profile(300)
@given(seed=st.integers(0, 2 ** 32 - 1), n=st.integers(1, 8),
       kind=st.sampled_from(METHODS))
def test_jacobian_of_phi_matches_finite_differences(seed, n, kind):
    """The assembled J ∈ ∂_B Φ (rows w_a∇A + w_b∇B, solver.ncp.newton) is
    the derivative of Φ where no pair is at a kink."""
    rng = np.random.default_rng(seed)
    G = rng.normal(size=(n, n))
    fun, jac = nonlinear_ncp(G @ G.T + np.eye(n), rng.normal(size=n),
                             rng.uniform(0, 1, n))
    x = rng.normal(size=n)
    _, a, b = fun(x)
    kink = np.abs(a - b) if kind == "min" else np.hypot(a, b)
    assume(kink.min() > 1e-3)
    counted = Counted(fun, jac, kind)
    F, parts = counted.residual(x)
    J = counted.jacobian(x, parts)[0].toarray()
    h = 1e-7
    fd = np.column_stack([(counted.residual(x + h * e)[0]
                           - counted.residual(x - h * e)[0]) / (2 * h)
                          for e in np.eye(n)])
    np.testing.assert_allclose(J, fd, atol=1e-5 * max(1, np.abs(J).max()))


# ----------------------------------------------------------------------------
# random problems solved by both methods: success means solved

TOL = 1e-10


def spd(rng, n):
    G = rng.normal(size=(n, n))
    return G @ G.T / n + rng.uniform(0.05, 1.0) * np.eye(n)


def make_problem(rng, family, n):
    """(fun, jac, x0, check) of one random problem; ``check(x)`` returns the
    independent complementarity measure and the distance to the known
    solution (or 0)."""
    if family in ("lcp", "degenerate"):
        M = spd(rng, n)
        if family == "lcp":
            q, x_star = rng.normal(scale=rng.choice([0.1, 1, 10]), size=n), \
                None
        else:  # a known solution with degenerate pairs x_i = w_i = 0
            pattern = rng.integers(0, 3, n)  # 0: x > 0; 1: w > 0; 2: both 0
            x_star = np.where(pattern == 0, rng.uniform(0.1, 2, n), 0.0)
            w_star = np.where(pattern == 1, rng.uniform(0.1, 2, n), 0.0)
            q = w_star - M @ x_star
        fun, jac = nonlinear_ncp(M, q, np.zeros(n))

        def check(x):
            w = M @ x + q
            gap = 0.0 if x_star is None else np.abs(x - x_star).max()
            return np.abs(np.minimum(x, w)).max(), gap
        return fun, jac, np.zeros(n), check
    if family == "nonlinear":
        M, q, c = spd(rng, n), rng.normal(size=n), rng.uniform(0, 2, n)
        fun, jac = nonlinear_ncp(M, q, c)

        def check(x):
            return np.abs(np.minimum(x, M @ x + q + c * x ** 3)).max(), 0.0
        return fun, jac, rng.uniform(0, 1, n), check
    # "mixed": contact type, unknowns u (n), the last m of them constrained:
    # E = (Ku − f) on free rows = 0; λ = −(Ku − f)_c ≥ 0 ⊥ s − u_c ≥ 0
    m = int(rng.integers(1, n + 1))
    K, f = spd(rng, n), rng.normal(scale=3, size=n)
    s = rng.uniform(-0.5, 1.0, m)
    c = np.arange(n - m, n)
    K_sp = sp.csr_matrix(K)
    Ic = sp.identity(n, format="csr")[c]

    def fun(u):
        r = K @ u - f
        return r[:n - m], -r[c], s - u[c]

    def jac(u):
        return K_sp[:n - m], -K_sp[c], -Ic

    def check(u):
        E, lam, gap = fun(u)
        return max(np.abs(np.minimum(lam, gap)).max(),
                   np.abs(E).max(initial=0.0)), 0.0
    return fun, jac, np.zeros(n), check


def min_measure(E, A, B):
    """Stopping measure: max(‖E‖∞, max|min(A, B)|), the complementarity the
    test checks (φ_FB's own ‖Φ‖ is up to 2 + √2 times larger or 2 − √2
    times smaller)."""
    return float(max(np.abs(E).max(initial=0.0),
                     np.abs(np.minimum(A, B)).max(initial=0.0)))


FAMILIES = ("lcp", "degenerate", "nonlinear", "mixed")


def solve_both(seed, family, n, failures):
    rng = np.random.default_rng(seed)
    fun, jac, x0, check = make_problem(rng, family, n)
    for method in METHODS:
        result = solve_ncp(fun, jac, x0, method=method, tol=TOL,
                           max_iter=100, error=min_measure)
        comp, distance = check(result.x)
        if result.success:  # never a wrong "success"
            assert result.status == 0
            assert comp <= TOL, (seed, family, n, method, comp)
            assert distance <= 1e-6, (seed, family, n, method, distance)
        else:
            assert result.status != 0 and "not converged" in result.message
            failures.append((seed, family, n, method, result.message))


def test_random_problems_hypothesis():
    """600 problems drawn by hypothesis, each solved by both methods;
    failures are allowed if reported, but must stay rare (≤ 1 %)."""
    failures = []

    @profile(600)
    @given(seed=st.integers(0, 2 ** 32 - 1), n=st.integers(1, 12),
           family=st.sampled_from(FAMILIES))
    def check(seed, n, family):
        solve_both(seed, family, n, failures)

    check()
    assert len(failures) <= 12, failures[:5]


@pytest.mark.parametrize("family", FAMILIES)
def test_random_problems_seeded(family):
    """100 more per family from a fixed seed (600 + 400 ≥ 1000 problems,
    each solved by both methods)."""
    failures = []
    rng = np.random.default_rng(20240607 + FAMILIES.index(family))
    for seed, n in zip(rng.integers(0, 2 ** 32, 100), rng.integers(1, 13,
                                                                     100)):
        solve_both(int(seed), family, int(n), failures)
    assert len(failures) <= 2, failures


# ----------------------------------------------------------------------------
# the loader on fuzzed input: ProblemError or a valid problem, nothing else

@pytest.fixture(scope="module")
def valid_files(exported, tmp_path_factory):
    """Bytes of valid problem files: the bar compressed (as save_problem
    writes) and uncompressed, and the 118 block uncompressed."""
    folder = tmp_path_factory.mktemp("fuzz")
    bar = two_dof_bar()
    compressed = Path(save_problem(folder / "bar.npz", bar)).read_bytes()
    buffer = io.BytesIO()
    np.savez(buffer, **bar.to_arrays())
    with np.load(exported(118)[0], allow_pickle=False) as archive:
        mesh = {k: archive[k] for k in archive.files}
    block = io.BytesIO()
    np.savez(block, **mesh)
    return Files({"bar compressed": compressed, "bar": buffer.getvalue(),
                  "block": block.getvalue()})


class Files(dict):
    """A dict of file contents that hypothesis reports briefly."""

    def __repr__(self):
        return f"<valid files {sorted(self)}>"


def load_bytes(data, tmp_path):
    path = tmp_path / "fuzzed.npz"
    path.write_bytes(data)
    try:
        load_problem(path)
    except ProblemError as exc:
        message = str(exc)
        assert message and "\n" not in message


@profile(400)
@given(which=st.sampled_from(["bar compressed", "bar", "block"]),
       edits=st.lists(st.tuples(st.floats(0, 1, exclude_max=True),
                                st.integers(0, 255)), min_size=1,
                      max_size=8),
       cut=st.one_of(st.none(), st.floats(0, 1)))
def test_loader_on_fuzzed_bytes(valid_files, tmp_path, which, edits, cut):
    data = bytearray(valid_files[which])
    for where, byte in edits:
        data[int(where * len(data))] = byte
    if cut is not None:
        data = data[:int(cut * len(data))]
    load_bytes(bytes(data), tmp_path)


@profile(100)
@given(which=st.sampled_from(["bar", "block"]),
       member=st.integers(0, 30), offset=st.integers(0, 200),
       byte=st.integers(0, 255))
def test_loader_on_fuzzed_headers(valid_files, tmp_path, which, member,
                                  offset, byte):
    """Edits inside the .npy headers of the members (shape, dtype, order),
    with the zip's CRC recomputed so that the damage reaches NumPy."""
    source = zipfile.ZipFile(io.BytesIO(valid_files[which]))
    names = source.namelist()
    target = names[member % len(names)]
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as archive:
        for name in names:
            raw = bytearray(source.read(name))
            if name == target:
                raw[min(offset, len(raw) - 1)] = byte
            archive.writestr(name, bytes(raw))
    load_bytes(out.getvalue(), tmp_path)


DTYPES = [np.float32, np.float64, np.int8, np.int32, np.int64, np.uint64,
          np.bool_, np.complex128, "U3", "S3", "datetime64[s]", "V8"]


def mutate_array(value, rng, how):
    """One mutation of an array: dtype, shape or values."""
    a = np.array(value)
    if how == "dtype":
        dtype = DTYPES[rng.integers(len(DTYPES))]
        try:
            with np.errstate(all="ignore"):
                return a.astype(dtype)
        except (TypeError, ValueError, OverflowError):
            return np.zeros(a.shape, dtype=dtype)
    if how == "shape":
        choice = rng.integers(5)
        if choice == 0:
            return a.reshape(-1)
        if choice == 1:
            return a[None]
        if choice == 2:
            return a.ravel()[:max(0, a.size - int(rng.integers(1, 3)))]
        if choice == 3:
            return np.concatenate([a.ravel(), a.ravel()[:2]])
        return np.zeros((0,) + a.shape[1:], dtype=a.dtype)
    # values
    if a.dtype.kind in "US" or a.size == 0:
        return np.array(["", "nan", "t**", "{}", "5 + t"][rng.integers(5)])
    flat = a.ravel().copy()
    i = rng.integers(flat.size)
    specials = [-1, 0, 2 ** 31, -(2 ** 62), 10 ** 9]
    if flat.dtype.kind == "f":
        specials += [np.nan, np.inf, -np.inf, -1e300, 1e-320]
    special = np.array(specials[rng.integers(len(specials))])
    try:
        with np.errstate(all="ignore"):
            flat[i] = special.astype(flat.dtype)  # ints wrap around
    except (TypeError, ValueError, OverflowError):
        pass  # no such value in this dtype (void, datetime)
    return flat.reshape(a.shape)


@profile(400)
@given(which=st.sampled_from(["bar", "block"]),
       seed=st.integers(0, 2 ** 32 - 1), count=st.integers(1, 3))
def test_loader_on_fuzzed_arrays(valid_files, tmp_path, which, seed, count):
    """Mutate 1-3 arrays (dtype, shape or values; or drop/duplicate a key)
    and validate: ProblemError or a problem that passes validation."""
    rng = np.random.default_rng(seed)
    with np.load(io.BytesIO(valid_files[which])) as archive:
        arrays = {k: archive[k] for k in archive.files}
    for _ in range(count):
        key = sorted(arrays)[rng.integers(len(arrays))]
        how = ["dtype", "shape", "values", "values", "drop"][
            rng.integers(5)]
        if how == "drop":
            del arrays[key]
        else:
            arrays[key] = mutate_array(arrays[key], rng, how)
    try:
        validate_arrays(arrays)
    except ProblemError as exc:
        assert "\n" not in str(exc)
    if rng.integers(4) == 0:  # and through a file, as written by np.savez
        buffer = io.BytesIO()
        try:
            np.savez(buffer, **arrays)
        except ValueError:  # e.g. object arrays (no pickling allowed)
            return
        load_bytes(buffer.getvalue(), tmp_path)
