r"""The Newton system of a condensed friction step, solved on the free
components only (the projection formulation, :mod:`.projection`).

On the system condensed onto Γc (S dense 2m×2m) the Jacobian of the
projection formulation, in the rotated displacement v = RΔu and the
scaled traction ĝ = g_t/c_t, has the rows

.. math::
    T_{t,:}\,dv − D c_t\,dĝ = −E_2, \qquad
    \text{stick: } c_t\,dv_{t,i} = −E_{3,i}, \quad
    \text{slip: } c_t\,dĝ_i ∓ f_c a_i/D_i\,T_{n_i,:}dv = −E_{3,i}, \\
    −w_{a,i} T_{n_i,:}dv − w_{b,i}\,c\,dv_{n,i} = −Φ_i,

with T = R S Rᵀ, (w_a, w_b) the NCP function's row weights and
a_i = [λ_i > 0] (implicit bound only). A sticking node fixes its dv_t, a
normal row with w_a = 0 fixes dv_n, and ĝ follows from one row per node.
What is left is the exact block elimination

.. math:: M_{FF}\, dv_F = h_F − M_{FK}\, dv_K

on the free components F = {dv_t of sliding nodes} ∪ {dv_n with
w_a ≠ 0}, M's rows T_{t_i,:} ± f_c a_i T_{n_i,:} (slip) and
T_{n_i,:} + (w_b/w_a) c e_{n_i}. With the lagged bound M_FF is a principal
submatrix of T plus a non-negative diagonal (w_a, w_b ≤ 0 for φ_FB, (30)):
SPD, so Cholesky; otherwise LU.

Usually few nodes touch and F is most of Γc. The same system is then
solved in the forces q = T dv (:meth:`_Combined._dual`): dv = C q with the
flexibility C = T⁻¹ (once per run), and what is left is a system on the
contact constraints, usually much smaller than F. Whichever is smaller
is solved (with the implicit bound only for f_c ≤ :data:`DUAL_MAX_FRICTION`);
an unchanged reduced matrix reuses its factorisation. The direction is that
of J d = −Φ up to round-off; J is singular exactly when the reduced matrix
is. This is the primal-dual active set structure of Hüeber, Stadler &
Wohlmuth (2008), applied to the condensed system."""

import numpy as np

__all__ = ["ReducedJacobian", "DUAL", "DUAL_MAX_FRICTION"]

#: Solve through the flexibility (:meth:`_Combined._dual`) when its system
#: is the smaller one (and, with the implicit bound, f_c ≤
#: :data:`DUAL_MAX_FRICTION`); False: always the primal M_FF (tests).
DUAL = True

#: The implicit bound's slip rows q_t,i + k_i q_n,i = h_t,i (|k_i| = f_c)
#: pass the error of q_n,i (through C = T⁻¹, ~cond(T)·eps) to q_t,i times
#: f_c: above this f_c the primal M_FF is solved (benchmarks/README.md).
DUAL_MAX_FRICTION = 1.0


class ReducedJacobian:
    """The structured Jacobian that :func:`solver.ncp.solve_ncp` accepts
    from ``jac`` (``JA``, ``JB``, :meth:`combine`), made by
    :meth:`~solver.contact.friction.projection.ProjectionSystem.jacobian` at
    the iterate ``x``: ``stick`` and ``upper`` masks of the projection,
    ``active`` (a_i, None if lagged)."""

    def __init__(self, system, x, stick, upper, active):
        self.system, self.x, self.stick, self.upper = system, x, stick, upper
        self.active = active
        self.JA, self.JB = system._JA, system._JB

    def combine(self, wa, wb):
        """The Newton system for the row weights (w_a, w_b)."""
        return _Combined(self, np.asarray(wa, float), np.asarray(wb, float))


class _Combined:
    """J = [JE; diag(w_a)JA + diag(w_b)JB] of a :class:`ReducedJacobian`:
    :meth:`direction` solves J d = −Φ, :meth:`rmatvec` gives JᵀΦ."""

    def __init__(self, jac, wa, wb):
        self.jac, self.wa, self.wb = jac, wa, wb

    def _coefficients(self):
        """Per node: the slip rows' T_n factor (∓f_c a_i, 0 if lagged)."""
        jac, s = self.jac, self.jac.system
        if jac.active is None:
            return None
        sign = np.where(jac.upper, -1.0, 1.0) * (~jac.stick)
        return sign * (-s.friction) * jac.active  # row: sign·db, db/D·D

    def rmatvec(self, F):
        """JᵀF in the unknowns x = [Δu; ĝ] (∇ψ of φ_FB, (28))."""
        jac, s = self.jac, self.jac.system
        m, c_t = s.m, s.c_t
        F2, F3, Fc = F[:m], F[m:2 * m], F[2 * m:]
        stick = jac.stick
        T_t, T_n = _row_blocks(s)
        gv = F2 @ T_t - (self.wa * Fc) @ T_n
        gv[s.t_rows] += c_t * np.where(stick, F3, 0.0)
        gv[s.n_rows] -= s.gap_scale * self.wb * Fc
        k = self._coefficients()
        if k is not None:  # slip rows' db term: k_i/D_i · T_{n_i,:}
            gv += (k / s.lumped * F3) @ T_n
        gg = -s.lumped * c_t * F2 + c_t * np.where(stick, 0.0, F3)
        return np.concatenate([s.RT @ gv, gg])

    def direction(self, F):
        """d with J d = −F, or None if J is (numerically) singular."""
        jac, s = self.jac, self.jac.system
        m, c_t, c, T, D = s.m, s.c_t, s.gap_scale, s.T, s.lumped
        t, nr = s.t_rows, s.n_rows
        F2, F3, Fc = F[:m], F[m:2 * m], F[2 * m:]
        stick, wa, wb = jac.stick, self.wa, self.wb
        slip, free_n = ~stick, wa != 0.0
        k = self._coefficients()
        v = np.zeros(2 * m)  # dv: the fixed components first
        v[t[stick]] = -F3[stick] / c_t
        v[nr[~free_n]] = -Fc[~free_n] / (-wb[~free_n] * c)
        rows_t, rows_n = t[slip], nr[free_n]
        free = np.concatenate([rows_t, rows_n])
        if free.size:
            ht = -F2[slip] - D[slip] * F3[slip]
            ratio = wb[free_n] / wa[free_n]
            hn = Fc[free_n] / wa[free_n]
            fixed = np.ones(2 * m, bool)
            fixed[free] = False
            # the implicit bound's slip rows carry f_c: through the
            # explicit flexibility C their round-off grows with f_c
            # (:data:`DUAL_MAX_FRICTION`)
            if DUAL and (k is None or s.friction <= DUAL_MAX_FRICTION) \
                    and np.count_nonzero(fixed) \
                    + np.count_nonzero(ratio) < free.size:
                solved = self._dual(v, free, fixed, ht, hn, c * ratio, k,
                                    slip, free_n)
            else:
                solved = self._primal(v, free, ht, hn, ratio, k, slip)
            if solved is None:
                return None
            v[free] = solved
        dg = np.empty(m)
        Tv = T @ v if (k is not None and slip.any()) or stick.any() \
            else None
        dg[slip] = -F3[slip] / c_t
        if k is not None and slip.any():
            dg[slip] -= k[slip] / D[slip] * Tv[nr[slip]] / c_t
        dg[stick] = (Tv[t[stick]] + F2[stick]) / (D[stick] * c_t) \
            if stick.any() else 0.0
        d = np.concatenate([s.RT @ v, dg])
        return d if np.all(np.isfinite(d)) else None

    def _primal(self, v, free, ht, hn, ratio, k, slip):
        """dv_F from M_FF dv_F = h_F − M_FK dv_K (module docstring)."""
        s = self.jac.system
        T, nr, c = s.T, s.n_rows, s.gap_scale
        Mt = T[free[:len(ht)]]
        if k is not None:
            Mt = Mt + k[slip][:, None] * T[nr[slip]]
        M = np.vstack([Mt, T[free[len(ht):]]])
        h = np.concatenate([ht, hn]) - M @ v
        A = M[:, free]
        diagonal = len(ht) + np.arange(len(hn))
        A[diagonal, diagonal] += c * ratio
        return s._reduced_solve(A, h, k is None, "primal")

    def _dual(self, v, free, fixed, ht, hn, rho, k, slip, free_n):
        r"""dv_F through the forces q = T dv and the flexibility C = T⁻¹
        (module docstring), dv = C q. A free row gives q_j = h_j (a slip row
        with the implicit bound: q_{t_i} + k_i q_{n_i} = h_{t_i}) or, a normal
        row with ρ_j = c w_b/w_a > 0 (φ_FB), q_j + ρ_j dv_j = h_j. The unknowns
        are the forces q_U on U = K ∪ {j : ρ_j > 0}, K the fixed components:

        .. math:: (C_{UU} + \mathrm{diag}(0_K, 1/ρ))\, q_U
                  = [dv_K; h/ρ] − C_{UQ}\, h_Q

        (Q: the other free rows), SPD; the implicit bound's slip rows add
        −C_{U t_i} k_i to the column of an unknown q_{n_i} (then unsymmetric).
        """
        s = self.jac.system
        m, nr = s.m, s.n_rows
        n_t = len(ht)
        mixed = np.zeros(free.size, bool)
        mixed[n_t:] = rho != 0.0
        U = np.concatenate([np.flatnonzero(fixed), free[mixed]])
        h = np.concatenate([ht, hn])
        q = np.zeros(2 * m)
        q[free[~mixed]] = h[~mixed]  # q_Q; q_U follows
        kc = coupled = None
        if k is not None:  # q_t,i + k_i q_n,i = ht_i at sliding nodes
            known_n = np.zeros(m, bool)
            known_n[free_n] = ~mixed[n_t:]
            slip_nodes = np.flatnonzero(slip)
            q_n = np.zeros(m)
            q_n[free_n] = hn
            ks = k[slip]
            q[free[:n_t]] -= np.where(known_n[slip], ks * q_n[slip], 0.0)
            coupled = np.flatnonzero(~known_n[slip] & (ks != 0.0))
            if coupled.size:
                columns = np.searchsorted(np.sort(U),
                                          nr[slip_nodes[coupled]])
                kc = ks[coupled]
        order = np.argsort(U)
        U = U[order]  # sorted: coupled columns found by searchsorted
        C = s.flexibility()
        CU = C[U]
        A = CU[:, U]
        rhs = -(CU @ q)
        on_fixed = fixed[U]
        rhs[on_fixed] += v[U[on_fixed]]
        # mixed rows ρ_j C_j q + q_j = h_j, scaled symmetrically by
        # √ρ_j (unknowns q_j/√ρ_j): unit diagonal terms, no 1/ρ
        root = np.ones(len(U))
        rho_full = np.zeros(2 * m)
        rho_full[free[mixed]] = rho[mixed[n_t:]]
        h_full = np.zeros(2 * m)
        h_full[free] = h
        rows = ~on_fixed
        root[rows] = np.sqrt(rho_full[U[rows]])
        if kc is not None:
            A[:, columns] -= CU[:, free[coupled]] * kc
        A *= root[:, None]
        A *= root
        rhs *= root
        rhs[rows] += h_full[U[rows]] / root[rows]
        diagonal = np.flatnonzero(rows)
        A[diagonal, diagonal] += 1.0
        qU = s._reduced_solve(A, rhs, kc is None, "dual")
        if qU is None:
            return None
        qU = qU * root
        q[U] = qU
        if kc is not None:
            q[free[coupled]] -= kc * qU[columns]
        return (C @ q)[free]


def _row_blocks(system):
    """(T_t, T_n): T's tangential and normal rows, copied once per system
    (T is fixed)."""
    blocks = getattr(system, "_row_blocks", None)
    if blocks is None or blocks[0] is not system.T:
        blocks = (system.T, np.ascontiguousarray(system.T[system.t_rows]),
                  np.ascontiguousarray(system.T[system.n_rows]))
        system._row_blocks = blocks
    return blocks[1], blocks[2]
