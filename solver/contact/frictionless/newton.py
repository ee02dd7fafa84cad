r"""The Newton system of the condensed frictionless system (67), solved on
its free components only.

Condensed onto Γc (K → S, dense), the Jacobian of (67) with the NCP
function's row weights (w_a, w_b) (:func:`solver.ncp.functions.
derivative_weights`) is, in the rotated displacement v = R d (R of
(58)-(60), orthogonal on the condensed DOFs) and with T = R S Rᵀ,

.. math::
    T_{x,:}\,v = −F_x \quad (\text{rows } X), \qquad
    −w_{a,i} T_{n_i,:}\,v − w_{b,i}\,c\,v_{n_i} = −F_i \quad
    (\text{rows } Y).

A normal row with w_a = 0 (φ_min's gap row) fixes v_{n_i} =
F_i/(c w_{b,i}); the others, divided by −w_a, leave the exact block
elimination

.. math:: (T + \mathrm{diag}(ρ))_{FF}\, v_F = h_F − T_{FK}\, v_K,
          \qquad ρ_i = c\,w_{b,i}/w_{a,i}

on the free components F (ρ = 0 on the rows X). ρ ≥ 0 for φ_min and φ_FB
(w_a, w_b ≤ 0, thesis (30)): a principal submatrix of the SPD T plus a
non-negative diagonal, one Cholesky factorisation, singular exactly when
J is; the direction is that of J d = −Φ up to round-off. This is the
primal-dual active set structure (Hintermüller, Ito & Kunisch 2002) of the
condensed system; :mod:`solver.contact.friction.newton` does the same with
friction. The rows X carry no NCP and never change, so they are
eliminated once per system: with C = T_XX⁻¹T_XY and the normal complement
N = T_YY − T_YX C (SPD), the free normal components solve

.. math:: (N + \mathrm{diag}(ρ))_{FF}\, v_F = ĥ_F − N_{FK}\, v_K, \qquad
          ĥ = h_Y − T_{YX} z, \quad z = T_{XX}^{-1} h_X,

and v_X = z − C v_Y: |F|³/3 flops instead of (|X| + |F|)³/3."""

import warnings

import numpy as np
import scipy.linalg as sla

from ...linalg.dense import factorize

__all__ = ["CondensedJacobian"]


class CondensedJacobian:
    """The structured Jacobian of (67) on a dense S that
    :func:`solver.ncp.solve_ncp` accepts from ``jac``: ``JA``, ``JB`` (for
    φ_FB's rule (31)) and :meth:`combine`. ``S`` is the condensed stiffness
    (SPD), ``R`` the orthogonal rotation, ``x_rows``, ``y_rows`` the rows X
    and Y of (66), ``JA``, ``JB`` the dense −YRS and −cYR, ``gap_scale`` c."""

    def __init__(self, S, R, x_rows, y_rows, JA, JB, gap_scale):
        RS = R @ S
        self.T = np.ascontiguousarray((R @ RS.T).T)  # R S Rᵀ
        self.R, self.x_rows, self.y_rows = R, x_rows, y_rows
        #: Rᵀ made once (SciPy builds a new transpose on every ``R.T``)
        self.RT = R.T
        self.JA, self.JB, self.c = JA, JB, float(gap_scale)
        self.n = S.shape[0]
        self._normal = None  # (cho(T_XX), C, N, T_YX), made when first used

    def normal_complement(self):
        """(cho(T_XX), C, N, T_YX) of the module docstring, made once; None
        if X is empty or T_XX is not numerically positive definite (then
        the directions take the unreduced path)."""
        if self._normal is None:
            x, y, T = self.x_rows, self.y_rows, self.T
            self._normal = False
            if len(x):
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", sla.LinAlgWarning)
                    try:
                        cho = sla.cho_factor(T[np.ix_(x, x)],
                                             check_finite=False)
                    except np.linalg.LinAlgError:
                        return None
                T_yx = np.ascontiguousarray(T[np.ix_(y, x)])
                C = sla.cho_solve(cho, T_yx.T, check_finite=False)
                N = T[np.ix_(y, y)] - T_yx @ C
                self._normal = (cho, C, 0.5 * (N + N.T), T_yx)
        return self._normal or None

    def combine(self, wa, wb):
        """The Newton system for the row weights (w_a, w_b)."""
        return _Combined(self, np.asarray(wa, float), np.asarray(wb, float))


class _Combined:
    """J = [JE; diag(w_a)JA + diag(w_b)JB]: :meth:`direction` solves
    J d = −F, :meth:`rmatvec` gives JᵀF."""

    def __init__(self, jac, wa, wb):
        self.jac, self.wa, self.wb = jac, wa, wb

    def _natural(self, F):
        """F (rows [X; Y]) in the natural row order of v."""
        jac = self.jac
        g = np.empty(jac.n)
        g[jac.x_rows] = F[:len(jac.x_rows)]
        g[jac.y_rows] = F[len(jac.x_rows):]
        return g

    def rmatvec(self, F):
        """JᵀF = Rᵀ(T(W₁g) + W₂g), g = F in v's row order, W₁ = 1 on X and
        −w_a on Y, W₂ = −c w_b on Y (∇ψ of φ_FB, (28))."""
        jac = self.jac
        g = self._natural(F)
        w1, w2 = g.copy(), np.zeros(jac.n)
        y, Fy = jac.y_rows, F[len(jac.x_rows):]
        w1[y] = -self.wa * Fy
        w2[y] = -jac.c * self.wb * Fy
        return jac.RT @ (w1 @ jac.T + w2)

    def direction(self, F):
        """d with J d = −F, or None if J is (numerically) singular: on the
        free normal components after the elimination of X (module
        docstring), else on all free components (:meth:`_unreduced`)."""
        jac = self.jac
        y, c = jac.y_rows, jac.c
        h = -self._natural(F)
        wa, wb = self.wa, self.wb
        fixed_n = wa == 0.0
        if np.any(wb[fixed_n] == 0.0):
            return None  # a zero row
        free_n = ~fixed_n
        v_K = h[y[fixed_n]] / (-c * wb[fixed_n])
        h[y[free_n]] /= -wa[free_n]
        normal = jac.normal_complement()
        if normal is None:
            return self._unreduced(h, fixed_n, v_K)
        cho, C, N, T_yx = normal
        z = sla.cho_solve(cho, h[jac.x_rows], check_finite=False)
        v_y = np.empty(len(y))
        v_y[fixed_n] = v_K
        if np.any(free_n):
            F_, K_ = np.flatnonzero(free_n), np.flatnonzero(fixed_n)
            rhs = (h[y] - T_yx @ z)[F_] - N[np.ix_(F_, K_)] @ v_K
            A = N[np.ix_(F_, F_)]
            A.flat[::len(F_) + 1] += c * wb[F_] / wa[F_]
            solve = factorize(A, True)
            if solve is None:
                return None
            v_y[F_] = solve(rhs)
        v = np.empty(jac.n)
        v[y] = v_y
        v[jac.x_rows] = z - C @ v_y
        d = jac.RT @ v
        return d if np.all(np.isfinite(d)) else None

    def _unreduced(self, h, fixed_n, v_K):
        """The direction on all free components, X included: the fixed
        components K stay in the matrix as unit rows and columns (T copied
        whole and masked). ``h`` has its free normal rows divided by −w_a."""
        jac = self.jac
        T, y, c, n = jac.T, jac.y_rows, jac.c, jac.n
        wa, wb = self.wa, self.wb
        fixed, free_n = y[fixed_n], y[~fixed_n]
        A = T.copy()
        A.flat[free_n * (n + 1)] += c * wb[~fixed_n] / wa[~fixed_n]
        if fixed.size:
            h -= T[:, fixed] @ v_K
            A[fixed, :] = 0.0
            A[:, fixed] = 0.0
            A[fixed, fixed] = 1.0
            h[fixed] = v_K
        solve = factorize(A, True)
        if solve is None:
            return None
        v = solve(h)
        v[fixed] = v_K
        d = jac.RT @ v
        return d if np.all(np.isfinite(d)) else None
