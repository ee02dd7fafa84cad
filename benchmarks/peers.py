"""Independent solvers of the same frictionless problem, for the benchmark.

Both take the problem's K, f and the gaps and normals of
:func:`solver.contact_geometry` (gap from the obstacle), i.e. the
linear complementarity problem

    K u = f − Cᵀλ,   λ ≥ 0,   s − C u ≥ 0,   λᵀ(s − C u) = 0,

with C (Nca × Ñ) the unit normals at the free contact nodes' DOFs. It is the
thesis's (67) (λ the normal contact force, s the gap) and the KKT system of
the QP  min ½uᵀKu − fᵀu  subject to  C u ≤ s.

* :func:`clarabel_qp`: Clarabel (interior point conic solver; Goulart & Chen
  2024) on that QP, raw (no polishing; it has none).
* :func:`sfepy_semismooth_newton`: SfePy's ``nls.semismooth_newton`` (its
  φ_FB mode, with its own line search and ``ls.scipy_direct`` linear
  solver, which refactorises the (Ñ + Nca)² Jacobian every iteration) on the mixed system in
  x = (u, λ): smooth part K u − f + Cᵀλ, A(x) = λ, B(x) = k̄(s − C u).
  B is scaled by the mean stiffness k̄ at the contact DOFs so that A and B
  are both forces (unscaled it needs more iterations).

Neither is imported unless called: both are optional dependencies.
"""

import numpy as np
import scipy.sparse as sp


def normal_matrix(problem, geometry):
    """C: row i = ν_i at the DOFs of free contact node i."""
    m = len(geometry.gap)
    return sp.csr_matrix((geometry.normal.ravel(),
                          (np.repeat(np.arange(m), 2), geometry.dofs.ravel())),
                         shape=(m, problem.n_dofs))


def clarabel_qp(problem, geometry, tol=1e-12):
    """u from Clarabel on the QP (objective scaled by 1/k̄; tolerances
    ``tol``: its defaults, 1e-8, stop ~4e-6 from the solution here, and
    1e-10 still 3e-5 on the 7668-DOF block; 1e-12 reaches 8e-9 there at
    +15 % time)."""
    import clarabel

    C = normal_matrix(problem, geometry)
    k = problem.K.diagonal().mean()
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = settings.tol_gap_rel = settings.tol_feas = tol
    solution = clarabel.DefaultSolver(
        sp.triu(problem.K / k).tocsc(), -problem.f / k, C.tocsc(),
        geometry.gap, [clarabel.NonnegativeConeT(C.shape[0])],
        settings).solve()
    return np.asarray(solution.x), str(solution.status)


def sfepy_semismooth_newton(problem, geometry, tol=1e-10, max_iter=100,
                            semismooth=True, scale_gap=True,
                            start_force=1e-6, **options):
    """u from SfePy's nls.semismooth_newton; returns (u, Jacobians,
    converged). Stops when ‖[F; Φ(A, B)]‖ ≤ tol·‖f‖.

    Settings (measured on the 1878 block; the defaults here are those that
    converge):

    * ``semismooth=True``: its φ_FB mode. Its φ_min mode (False) does not
      converge: its Jacobian takes ∇A where A > B, i.e. where min(A, B) = B
      (SfePy 2026.3, ``compute_jacobian``).
    * ``start_force``: λ at the start (u = 0). Not 0: at a pair with
      A_i = B_i = 0 (λ = 0 at a node that touches, s = 0) SfePy 2026.3's
      degenerate-pair branch fails on NumPy 2 (``.todense()`` of a 1-D
      sparse-array row).
    * ``ls_on=2.0, ls_min=1e-10`` (its own test's line search settings;
      with its defaults it ends up in steepest descent and stalls).
    * ``scale_gap``: B = k̄(s − Cu) (21 Jacobians on the 1878 block; 36
      unscaled).
    """
    from sfepy.base.base import dict_to_struct, output
    from sfepy.solvers import Solver

    output.set_output(quiet=True)
    n = problem.n_dofs
    C = normal_matrix(problem, geometry)
    m = C.shape[0]
    K, f, s = sp.csr_matrix(problem.K), problem.f, geometry.gap
    k = float(K.diagonal()[geometry.dofs].mean()) if scale_gap else 1.0
    smooth_grad = sp.csr_array(sp.hstack([K, C.T]))  # arrays, as SfePy's
    a_grad = sp.csr_array(sp.hstack([sp.csr_matrix((m, n)),  # own test
                                     sp.identity(m)]))
    b_grad = sp.csr_array(sp.hstack([-k * C, sp.csr_matrix((m, m))]))
    calls = {"jacobian": 0}

    def fun_smooth_grad(x):
        calls["jacobian"] += 1
        return smooth_grad

    conf = {"name": "ssn", "kind": "nls.semismooth_newton",
            "semismooth": semismooth, "i_max": max_iter,
            "eps_a": tol * max(np.linalg.norm(f), 1.0), "eps_r": 1.0,
            # its "linear system not solved" test compares ‖J dx − r‖ with
            # eps_a·lin_red and falls back to steepest descent; a direct
            # solve is exact to round-off, which eps_a would call unsolved
            "lin_red": 1e300, "ls_on": 2.0, "ls_min": 1e-10, **options}
    status = {}
    solver = Solver.any_from_conf(
        dict_to_struct(conf),
        fun_smooth=lambda x: K @ x[:n] - f + C.T @ x[n:],
        fun_smooth_grad=fun_smooth_grad,
        fun_a=lambda x: x[n:], fun_a_grad=lambda x: a_grad,
        fun_b=lambda x: k * (s - C @ x[:n]), fun_b_grad=lambda x: b_grad,
        lin_solver=Solver.any_from_conf(dict_to_struct(
            {"name": "ls", "kind": "ls.scipy_direct"})),
        status=status)
    x0 = np.zeros(n + m)
    x0[n:] = start_force
    x = solver(x0)
    return x[:n], calls["jacobian"], status.get("condition") == 0
