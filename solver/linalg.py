r"""Sparse direct linear algebra for the contact solvers.

One factorisation of the stiffness matrix K serves a whole contact solve:

* :func:`nested_dissection` orders the nodes of a mesh by geometric nested
  dissection (George 1973; recursive coordinate bisection with vertex
  separators), a fill-reducing ordering that SciPy's SuperLU does not offer.
  On the refined thesis block it gives 30-40 % fewer factor nonzeros than
  SuperLU's COLAMD (SciPy's default) and, ordering included, a 1.3-3.9×
  faster solve from 3·10⁴ to 9·10⁵ DOFs (``benchmarks/README.md``).
* :class:`Factorization` factorises PKPᵀ = LDLᵀ with SuperLU in symmetric
  mode (diagonal pivots only) and checks, from the pivots, that K is
  positive definite (Sylvester's law of inertia).
* :class:`Condensation` orders the DOFs of the free contact nodes last, so
  that the trailing block of the factors is the Schur complement

  .. math:: S = K_{cc} − K_{ci} K_{ii}^{-1} K_{ic} = L_{cc} U_{cc},

  the stiffness of the body seen from Γc (its inverse is the Neumann-to-
  Dirichlet map, the "influence coefficients" of the contact literature).
  Contact acts only on these DOFs, so the thesis's systems (67) and
  (110)/(111) are *exactly* the same systems with K replaced by the dense
  2Nc×2Nc matrix S and f by g̃ = f_c − K_ci K_ii⁻¹ f_i: the Newton iterations
  then cost dense algebra of the size of Γc, and the whole solve costs about
  one factorisation of K and two solves (Wriggers, *Computational Contact
  Mechanics*, 2006, §6.2.2; Dostál, *Optimal Quadratic Programming
  Algorithms*, 2009, for the dual/condensed view).

Nothing here forms a dense Ñ×Ñ array; the only dense arrays are 2Nc×2Nc.
"""

import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
import scipy.sparse.linalg as sla

from .errors import ProblemError

__all__ = ["PIVOT_RTOL", "nested_dissection", "dof_ordering",
           "Factorization", "Condensation"]

#: A pivot of the LDLᵀ factorisation below this fraction of the largest
#: pivot counts as zero (see :class:`Factorization`).
PIVOT_RTOL = 1e-10

#: Subdomains of at most this many nodes are not bisected further; 16 was
#: the fastest of 16/64/256 on the refined thesis block (480k DOFs).
LEAF_SIZE = 16


def nested_dissection(points, edges, leaf=LEAF_SIZE):
    """Fill-reducing node ordering by geometric nested dissection.

    Every subdomain (all nodes at first) with more than ``leaf`` nodes is
    split at the median of the coordinate in which it is most spread out;
    the nodes of the upper half that share an edge with the lower half form
    the separator, which is ordered after both halves (recursively). All
    subdomains of one level are split at once (vectorised; no loop over
    nodes or subdomains).

    Parameters
    ----------
    points : (n, d) array
        Node coordinates.
    edges : (m, 2) int array
        Graph edges (e.g. the edges of the mesh cells; repeats allowed).
    leaf : int
        Size below which a subdomain is not split.

    Returns
    -------
    (n,) int array
        The nodes in elimination order.
    """
    points = np.asarray(points, float)
    n = len(points)
    i, j = np.asarray(edges, np.int64).T
    domain = np.zeros(n, np.int64)         # subdomain id within its level
    path = np.zeros(n, np.int64)           # subdomain id when it was ordered
    depth = np.zeros(n, np.int64)          # level at which it was ordered
    active = np.ones(n, bool)
    level = 0
    while active.any():
        idx = np.flatnonzero(active)
        ids, inv, size = np.unique(domain[idx], return_inverse=True,
                                   return_counts=True)
        done = (size <= leaf)[inv]
        path[idx[done]], depth[idx[done]] = domain[idx[done]], level
        active[idx[done]] = False
        keep = ~done
        idx, inv = idx[keep], inv[keep]
        if not len(idx):
            break
        counts = np.maximum(np.bincount(inv, minlength=len(ids)), 1)
        spread = np.column_stack([  # variance of each coordinate
            np.bincount(inv, x * x, len(ids)) / counts
            - (np.bincount(inv, x, len(ids)) / counts) ** 2
            for x in points[idx].T])
        axis = np.argmax(spread, axis=1)[inv]
        order = np.lexsort((idx, points[idx, axis], inv))
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        rank = np.empty(len(idx), np.int64)
        rank[order] = np.arange(len(idx)) - starts[inv[order]]
        upper = np.full(n, -1, np.int64)
        upper[idx] = rank >= counts[inv] // 2
        cut = (active[i] & active[j] & (domain[i] == domain[j])
               & (upper[i] != upper[j]))
        separator = np.unique(np.where(upper[i[cut]] == 1, i[cut], j[cut]))
        path[separator], depth[separator] = domain[separator], level
        active[separator] = False
        domain[idx] = 2 * domain[idx] + upper[idx]
        level += 1
    # Post-order of the bisection tree: a subdomain (or separator) ordered
    # at depth d with id q comes after every subdomain below it.
    shift = level + 1 - depth
    key = (path << shift) + (np.int64(1) << shift) - 1
    return np.lexsort((np.arange(n), -depth, key))


def dof_ordering(problem, last=None):
    """A fill-reducing permutation of the reduced DOFs, ``last`` at the end.

    Mesh problems: nested dissection of the mesh nodes (both DOFs of a node
    stay together). Discrete problems (no mesh): reverse Cuthill-McKee of K.
    ``last`` (DOF indices, in the order wanted) are taken out of the graph
    and appended.
    """
    n = problem.n_dofs
    last = np.zeros(0, np.int64) if last is None else \
        np.asarray(last, np.int64).ravel()
    is_last = np.zeros(n, bool)
    is_last[last] = True
    if problem.kind == "mesh":
        cells = np.asarray(problem.cells, np.int64)
        k = cells.shape[1]
        edges = np.concatenate([cells[:, [a, b]] for a in range(k)
                                for b in range(a + 1, k)])
        node = problem.dof_map[:, 0]
        excluded = np.zeros(len(problem.nodes), bool)
        excluded[node[last]] = True
        edges = edges[~excluded[edges].any(axis=1)]
        nodes = nested_dissection(problem.nodes, edges)
        rank = np.empty(len(problem.nodes), np.int64)
        rank[nodes] = np.arange(len(nodes))
        order = np.lexsort((problem.dof_map[:, 1], rank[node]))
    else:
        order = csgraph.reverse_cuthill_mckee(sp.csr_matrix(problem.K),
                                              symmetric_mode=True)
    order = order[~is_last[order]]
    return np.concatenate([order, last])


class Factorization:
    r"""PKPᵀ = LDLᵀ of a symmetric positive definite matrix (SuperLU).

    SuperLU runs in symmetric mode with diagonal pivots only
    (``diag_pivot_thresh=0``) and the given ordering P (``NATURAL`` on the
    permuted matrix), so that U = DLᵀ. By Sylvester's law of inertia A is
    positive definite iff every pivot D_kk > 0; this is checked on
    construction. The factorisation is that of Cholesky up to the first
    non-positive pivot, hence backward stable where it matters: a pivot's
    sign is trustworthy unless it is at round-off level, which is then
    reported as singular. For a positive definite A every pivot is at least
    λ_min(A), and for a finite element stiffness the pivots stay far above
    ‖A‖/cond(A); a body without supports gives pivots of round-off size,
    ~1e-14 of the largest (three, one per rigid body mode, on the thesis's
    block without its clamp). :data:`PIVOT_RTOL` = 1e-10 separates the two.

    Parameters
    ----------
    A : sparse (n, n)
        Symmetric.
    order : (n,) int array, optional
        Elimination order (e.g. :func:`dof_ordering`); default: SuperLU's
        minimum degree on A + Aᵀ.
    name : str
        Key prefix of A for error messages (``"K"`` or ``"M"``).
    check : bool
        Check the pivots (default). The check reads the factors out of
        SuperLU (SciPy copies L and U, about half the factorisation's time
        and its memory again); False skips it (a bare linear solver).

    Raises
    ------
    ProblemError
        ``"{name}_data: {name} is not positive definite (...)"``.
    """

    def __init__(self, A, order=None, name="K", check=True):
        A = sp.csc_matrix(A, dtype=np.float64)
        self.n = A.shape[0]
        self.order = order = None if order is None else np.asarray(order)
        key = f"{name}_data"
        singular = (f"{name} is not positive definite (singular "
                    + ("stiffness: is the body supported?)" if name == "K"
                       else "matrix)"))
        if order is not None:
            A = A[order][:, order].tocsc()
            spec = "NATURAL"
        else:
            spec = "MMD_AT_PLUS_A"
        try:
            self.lu = sla.splu(A, permc_spec=spec, diag_pivot_thresh=0.0,
                               options={"SymmetricMode": True})
        except RuntimeError:  # "Factor is exactly singular"
            raise ProblemError(f"{key}: {singular}: its factorisation has "
                               "an exactly zero pivot") from None
        if not np.array_equal(self.lu.perm_r, self.lu.perm_c):
            raise ProblemError(f"{key}: {name} is not positive definite: a "
                               "diagonal pivot of its LDLᵀ factorisation "
                               "is exactly zero")
        self.nnz = int(self.lu.nnz)
        if check:
            self._check_pivots(self.lu.U.diagonal(), key, name, singular)

    @staticmethod
    def _check_pivots(pivots, key, name, singular):
        if not np.isfinite(pivots).all() or pivots.max() <= 0:
            raise ProblemError(f"{key}: {name} is not positive definite "
                               "(its LDLᵀ factorisation has no positive "
                               "pivot)")
        ratio = pivots.min() / pivots.max()
        if ratio < -PIVOT_RTOL:
            negative = int(np.count_nonzero(
                pivots < -PIVOT_RTOL * pivots.max()))
            raise ProblemError(f"{key}: {name} is not positive definite: it "
                               f"has {negative} negative eigenvalue(s) "
                               f"(LDLᵀ pivot ratio {ratio:.2g})")
        if ratio <= PIVOT_RTOL:
            small = int(np.count_nonzero(pivots <= PIVOT_RTOL * pivots.max()))
            raise ProblemError(f"{key}: {singular}: {small} pivot(s) of its "
                               "LDLᵀ factorisation at round-off level "
                               f"({ratio:.2g} of the largest)")

    def solve(self, b):
        """A⁻¹b for b of shape (n,) or (n, k)."""
        b = np.asarray(b, dtype=np.float64)
        if self.order is None:
            return self.lu.solve(b)
        x = np.empty_like(b)
        x[self.order] = self.lu.solve(np.ascontiguousarray(b[self.order]))
        return x

    def trailing_schur(self, m):
        """The Schur complement of the last m eliminated DOFs (dense m×m):
        L₂₂U₂₂ of the trailing blocks of the factors."""
        n = self.n
        U = self.lu.U[n - m:, n - m:].toarray()
        L = self.lu.L[n - m:, n - m:].toarray()
        return L @ U


class Condensation:
    r"""K condensed onto the DOFs ``dofs`` (those of the free contact nodes).

    With c = ``dofs`` and i the other DOFs, K u = f + Pᵀr (r: forces acting
    on the c DOFs only) is equivalent to

    .. math:: S u_c = g̃ + r, \qquad S = K_{cc} − K_{ci}K_{ii}^{-1}K_{ic},
              \quad g̃ = f_c − K_{ci}K_{ii}^{-1}f_i,

    and u is recovered from u_c by one solve with K. S comes free from one
    factorisation of K with c ordered last (:meth:`Factorization.
    trailing_schur`), which also checks that K is positive definite.

    Parameters
    ----------
    problem : ContactProblem
    dofs : (m,) int array
        Reduced DOFs to condense onto, in the order wanted.
    """

    def __init__(self, problem, dofs):
        self.dofs = np.asarray(dofs, np.int64).ravel()
        m = len(self.dofs)
        self.factorization = Factorization(
            problem.K, dof_ordering(problem, last=self.dofs), name="K")
        S = self.factorization.trailing_schur(m)
        self.S = 0.5 * (S + S.T)  # symmetric up to round-off already
        self._solved = []  # up to two recent (f, K⁻¹f)
        self.n_solves = 0

    def load(self, f):
        """(g̃, w): the condensed load g̃ = S (K⁻¹f)_c and w = K⁻¹f.

        A load that is a combination a f₁ + b f₂ of the last two loads (to
        1e-13 relative) reuses their solutions: the load steps of a
        proportional load or of a piecewise linear load path cost no solve.
        """
        f = np.asarray(f, dtype=np.float64)
        w = self._combination(f)
        if w is None:
            w = self.factorization.solve(f)
            self.n_solves += 1
            self._solved = (self._solved + [(f.copy(), w)])[-2:]
        return self.S @ w[self.dofs], w

    def _combination(self, f):
        """K⁻¹f from the stored solutions if f is in their span, else None
        (least squares by the 2×2 normal equations; the residual is then
        checked directly)."""
        loads = [g for g, _ in self._solved]
        if not loads:
            return None
        G = np.array([[a @ b for b in loads] for a in loads])
        try:
            coef = np.linalg.solve(G, [a @ f for a in loads])
        except np.linalg.LinAlgError:  # two parallel loads
            coef = np.linalg.lstsq(G, [a @ f for a in loads], rcond=None)[0]
        residual = f.copy()
        for c, g in zip(coef, loads):
            residual -= c * g
        if np.linalg.norm(residual) > 1e-13 * np.linalg.norm(f):
            return None
        w = np.zeros_like(f)
        for c, (_, v) in zip(coef, self._solved):
            w += c * v
        return w

    def displacement(self, u_c, w):
        """The full u with contact DOFs u_c, given w = K⁻¹f from
        :meth:`load`: u = w + K⁻¹Pᵀ S(u_c − w_c), one solve. Several at
        once: u_c and w of shape (m, k) and (n, k), one solve with k
        right-hand sides (cheaper per column)."""
        r = np.zeros(np.shape(w))
        r[self.dofs] = self.S @ (u_c - w[self.dofs])
        self.n_solves += 1
        return w + self.factorization.solve(r)
