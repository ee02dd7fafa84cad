r"""Algebraic multigrid for K: the iterative path beside the factorisations.

Smoothed aggregation (Vaněk, Mandel & Brezina, Computing 56, 1996) by
pyamg (``pip install '.[amg]'``; MIT licence), built once on the reduced
stiffness K with the rigid-body modes as near-null space (Wiesner, Mayr,
Popp, Gee & Wall, IJNME 122, 2021, use the same for mortar contact): the
d translations and the d(d − 1)/2 infinitesimal rotations ω × (x − x̄),
evaluated at the node of every reduced DOF (3 modes in 2D, 6 in 3D). One
V-cycle is the preconditioner of conjugate gradients.

The contact systems it serves are K restricted to an affine set: on an
active set A of contact nodes the normal displacements are prescribed,
C_A u = s_A, with C_A the normal rows of the rotation R (one row per node,
disjoint supports, so C_A C_Aᵀ = D diagonal). :func:`projected_cg` solves

.. math::  P K u = P f, \quad C_A u = s_A, \qquad P = I − C_A^T D^{-1} C_A,

by CG on the range of the orthogonal projector P with the preconditioner
P M P (M the V-cycle): PKP is SPD on that range, so CG applies (the
projected CG of constrained quadratic programs; Dostál, *Optimal quadratic
programming algorithms*, Springer 2009, §5.9). P costs one sparse product
with C_A; nothing mesh-sized is factorised.

P M P with M ≈ K⁻¹ is not a uniform preconditioner of the constrained
operator: even with M = K⁻¹ exactly, the eigenvalues of P K⁻¹ P · P K P
on range(P) spread with the Schur complement C_A K⁻¹ C_Aᵀ of the active
set, a surface operator whose condition number grows like 1/h, so the CG
count grows like h^(−1/2) under refinement (measured on the Hertz sphere:
benchmarks/README.md). :meth:`Multigrid.eliminated` is the
uniform one: where R is orthogonal, C_A u = s_A fixes DOFs of y = R u, and
the system is the principal submatrix K̂_FF of K̂ = R K Rᵀ on the other
DOFs F, an elasticity operator with Dirichlet-like conditions on the
contact zone; its hierarchy keeps K's aggregates and smoothed prolongator
with the rows of the fixed DOFs dropped (the usual treatment of Dirichlet
rows in smoothed aggregation; Vaněk, Mandel & Brezina 1996, §4) and
recomputes only the Galerkin products and the smoothers: a fraction of a
setup per active set, nothing re-aggregated.

:func:`factor_memory` estimates, before anything is factorised, the bytes
a Cholesky factor of K would take from CHOLMOD's symbolic analysis (its
fill-reducing ordering and the supernodal column counts), so that
``backend="auto"`` can choose this path when a factorisation would not fit
the memory."""

import contextlib
import time

import numpy as np
import scipy.sparse as sp

__all__ = ["NAME", "EXTRA", "REQUIRES", "LICENCE", "available",
           "rigid_body_modes", "Multigrid", "projected_cg", "projected_gmres",
           "KrylovResult", "GMRES_RESTART",
           "factor_memory", "available_memory", "direct_fits",
           "FACTOR_OVERHEAD", "MEMORY_SHARE", "SMOOTHER", "SEED", "seeded"]

NAME, EXTRA, REQUIRES = "amg", "amg", "pyamg>=5.2"
LICENCE = "MIT (pyamg)"


def available():
    """Whether pyamg imports."""
    try:
        import pyamg  # noqa: F401
    except ImportError:
        return False
    return True


def rigid_body_modes(points, components):
    """The rigid-body modes at the reduced DOFs, shape (n, 3) in 2D or
    (n, 6) in 3D: ``points`` (n, d) the coordinates of each DOF's node,
    ``components`` (n,) its direction 0..d−1. Columns: the d translations
    e_k, then the rotations ω × (x − x̄) about the axes (2D: about z),
    x̄ the centroid (it keeps the columns well conditioned)."""
    points = np.asarray(points, float)
    comp = np.asarray(components, np.int64)
    n, d = points.shape
    x = points - points.mean(axis=0)
    modes = [(comp == k).astype(float) for k in range(d)]
    if d == 2:
        modes.append(np.where(comp == 0, -x[:, 1], x[:, 0]))
    else:
        # ω = e_x: (0, −z, y); ω = e_y: (z, 0, −x); ω = e_z: (−y, x, 0)
        for a in range(3):
            b, c = (a + 1) % 3, (a + 2) % 3
            modes.append(np.where(comp == b, -x[:, c],
                                  np.where(comp == c, x[:, b], 0.0)))
    return np.column_stack(modes)


#: The seed of the random start vector of pyamg's spectral radius
#: estimate (:func:`seeded`).
SEED = 0


@contextlib.contextmanager
def seeded(seed=SEED):
    """Run the body with NumPy's global generator seeded by ``seed`` and
    restore its state after: pyamg estimates ρ(D⁻¹A) for the Jacobi
    smoothing of the tentative prolongator (ω = 4/(3ρ); Vaněk, Mandel &
    Brezina 1996) by Lanczos/Arnoldi from ``np.random.rand``, so an
    unseeded build gives a hierarchy, hence CG iterates, that differ in
    the last bits from run to run; seeded, the same K gives the same
    hierarchy bit for bit, and the caller's random stream is left as it
    was."""
    state = np.random.get_state()
    np.random.seed(seed)
    try:
        yield
    finally:
        np.random.set_state(state)


#: The pre- and post-smoother of every level: one symmetric (block)
#: Gauss–Seidel sweep, pyamg's default for smoothed aggregation (more
#: sweeps, Chebyshev or energy-minimising prolongators did not change the
#: growth of the contact systems' CG counts: benchmarks/README.md).
SMOOTHER = ("block_gauss_seidel", {"sweep": "symmetric"})


class Multigrid:
    """One smoothed-aggregation hierarchy of the SPD K (module docstring)
    with the near-null space ``modes`` (:func:`rigid_body_modes`):
    ``levels``, ``operator_complexity``, ``setup_time``; calling it applies
    one V-cycle (the preconditioner M ≈ K⁻¹). ``singular``: K is only
    positive semidefinite (a body held by contact only, whose kernel is
    its rigid-body modes): the coarsest level, which inherits that kernel
    (the modes are in the span of the near-null space, hence of every
    prolongator), is solved by its pseudo-inverse instead of a sparse LU,
    here and in every :meth:`eliminated` hierarchy, whose K̂_FF keeps the
    modes that no active constraint fixes."""

    def __init__(self, K, modes, singular=False):
        import pyamg

        clock = time.perf_counter()
        K = sp.csr_matrix(K)
        self._coarse = "pinv" if singular else "splu"
        with seeded():  # the prolongator's ω: a Lanczos from a random start
            self._ml = pyamg.smoothed_aggregation_solver(
                K, B=np.ascontiguousarray(modes), symmetry="hermitian",
                max_coarse=300, coarse_solver=self._coarse,
                presmoother=SMOOTHER, postsmoother=SMOOTHER)
        self._finish(clock, K.shape[0])
        self._rotated = None  # (Q, Q P_0) of the last eliminated()

    def _finish(self, clock, n):
        self._cycle = self._ml.aspreconditioner(cycle="V")
        self.levels = len(self._ml.levels)
        self.operator_complexity = float(self._ml.operator_complexity())
        self.setup_time = time.perf_counter() - clock
        self.n = n

    def __call__(self, r):
        return self._cycle @ r

    def operators(self):
        """The operator of every level, finest first (sparse)."""
        return [level.A for level in self._ml.levels]

    def prolongators(self):
        """The prolongator of every level but the coarsest (sparse)."""
        return [level.P for level in self._ml.levels[:-1]]

    def eliminated(self, K_hat, rotation, keep, spring=None):
        """The hierarchy of A = K̂_FF = K̂[keep][:, keep], K̂ = Q K Qᵀ
        (``K_hat``; ``rotation`` Q orthogonal, ``keep`` a boolean mask of
        its rows: the DOFs not fixed), built from this one's (module
        docstring): the finest prolongator P̂ = Q P_0 with the fixed rows
        E dropped, the coarser ones this hierarchy's, the same smoothers
        and coarse solver. The first coarse operator P̂_Fᵀ K̂_FF P̂_F is
        K's own P_0ᵀ K P_0 = P̂ᵀ K̂ P̂ less the products through the rows E
        only (−P̂_Eᵀ Y − Yᵀ P̂_E + P̂_Eᵀ K̂_EE P̂_E, Y = K̂_E: P̂), so a new
        active set costs O(|E|) there, not a Galerkin product of the mesh;
        the coarser ones likewise through the change of the finer one
        (R_k Δ_k P_k added to this hierarchy's operator). ``spring``: a
        symmetric positive semidefinite sparse S (n, n), zero on the rows
        and columns not kept (friction's slip springs,
        :mod:`solver.contact.friction.active_set`): A = (K̂ + S)_FF, and
        the first coarse operator gains P̂_Sᵀ S_SS P̂_S through S's rows
        only. Returns a Multigrid of A
        (``matrix`` A itself, ``setup_time`` the time this took)."""
        from pyamg.multilevel import MultilevelSolver
        from pyamg.relaxation.smoothing import change_smoothers

        clock = time.perf_counter()
        K_hat = sp.csr_matrix(K_hat)
        keep = np.asarray(keep, bool)
        A = K_hat[keep][:, keep].tocsr()
        if spring is not None:
            spring = sp.csr_matrix(spring)
            A = (A + spring[keep][:, keep]).tocsr()
            touched = np.flatnonzero(np.diff(spring.indptr))
        fine = self._ml.levels
        levels = []
        for k, level in enumerate(fine[:-1]):
            new = MultilevelSolver.Level()
            if k == 0:
                if self._rotated is None or self._rotated[0] is not rotation:
                    self._rotated = (rotation,
                                     sp.csr_matrix(rotation @ level.P))
                P = self._rotated[1]
                new.A, new.P = A, P[keep]
                new.R = new.P.T  # CSC: its products need no CSR copy
                fixed = np.flatnonzero(~keep)
                P_E, Y = P[fixed], K_hat[fixed] @ P
                coarse = (fine[1].A - P_E.T @ Y - Y.T @ P_E
                          + P_E.T @ (K_hat[fixed][:, fixed] @ P_E))
                if spring is not None and len(touched):
                    P_S = P[touched]
                    coarse = coarse + P_S.T @ (
                        spring[touched][:, touched] @ P_S)
            else:  # R (A_k + Δ) P = A_{k+1} + R Δ P, Δ near E only
                new.A = coarse
                new.P, new.R = level.P, level.R
                change = sp.csr_matrix(coarse - level.A)
                change.eliminate_zeros()
                coarse = fine[k + 1].A + new.R @ change @ new.P
            if sp.isspmatrix_bsr(fine[k + 1].A):
                coarse = sp.bsr_matrix(coarse,
                                       blocksize=fine[k + 1].A.blocksize)
            levels.append(new)
        coarsest = MultilevelSolver.Level()
        coarsest.A = sp.csr_matrix(coarse) if levels else A
        levels.append(coarsest)
        out = Multigrid.__new__(Multigrid)
        out._ml = MultilevelSolver(levels, coarse_solver=self._coarse)
        change_smoothers(out._ml, SMOOTHER, SMOOTHER)
        out._rotated, out._coarse = None, self._coarse
        out.matrix = A
        out._finish(clock, A.shape[0])
        return out


class KrylovResult:
    """What :func:`projected_cg` (``method`` "CG") or
    :func:`projected_gmres` ("GMRES") did: ``x``, ``iterations``,
    ``converged``, ``residual`` ‖P(f − Kx)‖₂ at the end and ``initial``
    at the start (their ratio: the reduction this solve achieved);
    ``setup``: the seconds of a preconditioner built for this solve alone
    (0; set by whoever built one)."""

    def __init__(self, x, iterations, converged, residual, initial=None):
        self.x, self.iterations = x, iterations
        self.converged, self.residual = converged, residual
        self.initial = residual if initial is None else initial
        self.setup = 0.0
        self.method = "CG"


def projected_cg(K, f, precondition, x0, C=None, atol=0.0, maxiter=None):
    """Solve P K x = P f on {x : C x = C x0} by preconditioned CG (module
    docstring); ``x0`` must already satisfy the constraints (the warm
    start), ``C`` (m, n) sparse rows with disjoint supports (None: no
    constraint, plain PCG). Stops when ‖P(f − Kx)‖₂ ≤ ``atol`` or after
    ``maxiter`` iterations (default n)."""
    x = np.array(x0, float)
    if C is not None and C.shape[0]:
        C = sp.csr_matrix(C)
        d_inv = 1.0 / np.asarray(C.multiply(C).sum(axis=1)).ravel()

        def project(v):
            return v - C.T @ (d_inv * (C @ v))
    else:
        def project(v):
            return v
    maxiter = K.shape[0] if maxiter is None else int(maxiter)
    r = project(f - K @ x)
    norm = initial = float(np.linalg.norm(r))
    if norm <= atol:
        return KrylovResult(x, 0, True, norm, norm)
    z = project(precondition(r))
    p = z.copy()
    rz = float(r @ z)
    for k in range(1, maxiter + 1):
        q = project(K @ p)
        pq = float(p @ q)
        if not pq > 0:  # breakdown: p in the kernel (cannot happen on SPD)
            return KrylovResult(x, k, False, norm, initial)
        alpha = rz / pq
        x += alpha * p
        r -= alpha * q
        norm = float(np.linalg.norm(r))
        if norm <= atol:
            return KrylovResult(x, k, True, norm, initial)
        z = project(precondition(r))
        rz, rz_old = float(r @ z), rz
        p *= rz / rz_old
        p += z
    return KrylovResult(x, maxiter, False, norm, initial)


#: The Krylov basis of :func:`projected_gmres` before it restarts.
GMRES_RESTART = 60


def _projector(C):
    """v ↦ P v, P = I − Cᵀ(CCᵀ)⁻¹C for sparse rows C with disjoint
    supports (CCᵀ diagonal); the identity for None or no rows."""
    if C is None or not C.shape[0]:
        return lambda v: v
    C = sp.csr_matrix(C)
    d_inv = 1.0 / np.asarray(C.multiply(C).sum(axis=1)).ravel()
    return lambda v: v - C.T @ (d_inv * (C @ v))


def projected_gmres(A, f, precondition, x0, C=None, atol=0.0, maxiter=None,
                    restart=GMRES_RESTART):
    r"""Solve P A x = P f on {x : C x = C x0} for a nonsymmetric A (an
    operator with ``@``) by right-preconditioned restarted GMRES (Saad &
    Schultz, SISSC 7, 1986; Saad, *Iterative methods for sparse linear
    systems*, 2nd ed., SIAM 2003, Alg. 9.5): the iterate is x0 + Z y with
    the columns of Z = P M P V (M ``precondition``, the V-cycle of A's
    symmetric part), so every iterate keeps the constraints and the
    residual GMRES minimises is the true one, ‖P(f − Ax)‖₂; that is the
    norm of ``atol``, as :func:`projected_cg`'s. ``C`` as there (None: no
    constraint). Stops when the residual is ≤ ``atol`` or after
    ``maxiter`` iterations (default n), restarting every ``restart``."""
    project = _projector(C)
    x = np.array(x0, float)
    n = len(x)
    maxiter = n if maxiter is None else int(maxiter)
    r = project(f - A @ x)
    norm = initial = float(np.linalg.norm(r))
    iterations = 0
    while norm > atol and iterations < maxiter:
        size = min(restart, maxiter - iterations)
        V = np.zeros((size + 1, n))
        Z = np.zeros((size, n))
        H = np.zeros((size + 1, size))
        cs, sn = np.zeros(size), np.zeros(size)
        e = np.zeros(size + 1)
        e[0] = norm
        V[0] = r / norm
        j = 0
        for j in range(size):
            Z[j] = project(precondition(V[j]))
            w = project(A @ Z[j])
            for i in range(j + 1):  # modified Gram–Schmidt
                H[i, j] = w @ V[i]
                w -= H[i, j] * V[i]
            H[j + 1, j] = np.linalg.norm(w)
            if H[j + 1, j] > 0:
                V[j + 1] = w / H[j + 1, j]
            for i in range(j):  # the earlier Givens rotations
                H[i, j], H[i + 1, j] = (cs[i] * H[i, j] + sn[i] * H[i + 1, j],
                                        -sn[i] * H[i, j] + cs[i] * H[i + 1, j])
            rho = np.hypot(H[j, j], H[j + 1, j])
            cs[j], sn[j] = (H[j, j] / rho, H[j + 1, j] / rho) if rho > 0 \
                else (1.0, 0.0)
            H[j, j], H[j + 1, j] = rho, 0.0
            e[j + 1], e[j] = -sn[j] * e[j], cs[j] * e[j]
            iterations += 1
            if abs(e[j + 1]) <= atol or rho == 0:
                break
        j += 1
        y = np.linalg.solve(np.triu(H[:j, :j]), e[:j]) if H[j - 1, j - 1] \
            else np.linalg.lstsq(np.triu(H[:j, :j]), e[:j], rcond=None)[0]
        x += y @ Z[:j]
        r = project(f - A @ x)
        last, norm = norm, float(np.linalg.norm(r))
        if not norm < last:  # no progress (breakdown): give up
            break
    out = KrylovResult(x, iterations, norm <= atol, norm, initial)
    out.method = "GMRES"
    return out


def factor_memory(K):
    """The bytes of the values of a supernodal Cholesky factor of K, from
    CHOLMOD's symbolic analysis (its ordering: AMD or METIS, whichever it
    picks), or None if kvxopt is not installed or the analysis cannot be
    read. Costs about one copy of K's lower triangle; nothing numeric."""
    try:
        from kvxopt import cholmod, matrix, spmatrix
    except ImportError:
        return None
    from .cholmod_struct import supernodal_size

    L = sp.tril(sp.csr_matrix(K), format="coo")
    n = L.shape[0]
    lower = spmatrix(matrix(np.ones(L.nnz)), matrix(L.row.astype(np.int64)),
                     matrix(L.col.astype(np.int64)), (n, n))
    del L
    saved = dict(cholmod.options)
    cholmod.options.update(supernodal=2)
    try:
        F = cholmod.symbolic(lower, uplo="L")
    finally:
        cholmod.options.clear()
        cholmod.options.update(saved)
    size = supernodal_size(F)
    return None if size is None else 8 * size


def available_memory():
    """The bytes this machine can still give (``MemAvailable`` of
    /proc/meminfo), or None where that file does not exist."""
    try:
        with open("/proc/meminfo") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return 1024 * int(line.split()[1])
    except OSError:
        return None
    return None


#: A factorisation is taken to need this many times the bytes of its
#: factor's values (index arrays, workspace, the solve's own arrays).
FACTOR_OVERHEAD = 1.25

#: The share of the available memory a factorisation may take.
MEMORY_SHARE = 0.8


def direct_fits(K):
    """Whether a factorisation of K fits this machine's memory, and why
    (a sentence, or None when no estimate was needed): the bound of a dense
    triangle, n²/2 values, is tried first, then :func:`factor_memory`
    (times :data:`FACTOR_OVERHEAD`, plus K), against
    :data:`MEMORY_SHARE` of :func:`available_memory`."""
    n = K.shape[0]
    free = available_memory()
    if free is None:
        return True, "auto: the available memory is unknown, so factorise"
    budget = MEMORY_SHARE * free
    if 8 * FACTOR_OVERHEAD * n * (n + 1) / 2 <= budget:
        return True, None
    values = factor_memory(K)
    if values is None:
        return True, ("auto: no symbolic analysis (kvxopt) to estimate the "
                      "factor's size, so factorise")
    K = sp.csr_matrix(K)
    need = FACTOR_OVERHEAD * values + K.data.nbytes + K.indices.nbytes
    text = (f"a Cholesky factor of K needs ≈ {need / 1e9:.3g} GB "
            f"(CHOLMOD's symbolic analysis), {free / 1e9:.3g} GB available")
    if need <= budget:
        return True, f"auto: {text}: factorise"
    return False, (f"auto: {text}, more than {MEMORY_SHARE:.0%} of it: "
                   "AMG-preconditioned CG instead")
