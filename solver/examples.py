"""Ready-made problems from the thesis that need no mesh.

:func:`two_dof_bar` is the "simple bar system" of thesis §6 (Fig. 17-21): one
point A with two DOFs (u_x, u_y) held by springs, loaded by
f = [1000, -1000]ᵀ, with a rigid obstacle at distance s = 0.005 below A."""

import numpy as np
import scipy.sparse as sp

from .problem import ContactProblem

__all__ = ["two_dof_bar", "two_dof_bar_closed_form"]


def two_dof_bar(stiffness=9e4, load=(1000.0, -1000.0), gap=0.005,
                normal=(0.0, -1.0)):
    r"""The thesis's 2-DOF bar system (§6) as a ``"discrete"`` problem:
    springs of ``stiffness`` (thesis 9·10⁴) on both DOFs, the full ``load``
    (thesis [1000, -1000]ᵀ), the initial ``gap`` s (thesis 0.005) along the
    unit ``normal`` from A towards the obstacle, M = [[1]]. The thesis's
    Fig. 17 is lost: the obstacle is taken below A, ν = (0, -1), so that the
    load closes the gap at load step κ = 45 of 100 and the tangential load
    1000 loads the friction, as its Fig. 18-21 describe."""
    normal = np.asarray(normal, dtype=float)
    normal = normal / np.linalg.norm(normal)
    return ContactProblem(
        K=sp.csr_matrix(stiffness * np.eye(2)),
        f=np.asarray(load, dtype=float),
        M=sp.csr_matrix(np.eye(1)),
        contact_dofs=np.array([[0, 1]]),
        gap=np.array([float(gap)]),
        normal=normal[None, :],
        meta={"description": "thesis §6 two-DOF bar system (Fig. 17)",
              "load": {"f": list(map(float, load))}},
    ).validate()


def two_dof_bar_closed_form(step, friction, coulomb="lagged", steps=100):
    r"""Exact load path of the thesis's bar with Coulomb friction (§6).

    Derivation (K = k I with k = 9·10⁴, f = (F, −F) with F = 1000, gap
    s = 0.005 below A, tangent +x, M = [1]; step κ of ``steps`` loads
    (Fκ/steps, −Fκ/steps), i.e. 10κ per step for 100 steps):

    - While u_n = Fκ/(k·steps) < s the bar is free: u = (1, −1)·Fκ/(k·steps),
      λ = 0, g_t = 0. The gap closes at κ₀ = s·k·steps/F (= 45).
    - After that u_y = −s and λ_κ = Fκ/steps − k s (= 10κ − 450). Holding
      u_x needs a friction force growing by F/steps per step, while λ grows
      by F/steps per step too: f_c > 1 sticks, f_c < 1 slips in every step
      (the trial stick force exceeds the bound by induction).
    - Slip with bound f_c p, p = λ_{κ−1} (lagged) or λ_κ (implicit):
      g_t = −f_c p, u_x = (Fκ/steps − f_c p)/k.
    - Stick, implicit: frozen from the first step after κ₀ at u_x = F κ₀ /
      (k steps); g_t = k u_x − Fκ/steps.
    - Stick, lagged: the first step after κ₀ has p = λ_{κ₀} = 0 and slides
      freely to u_x = F(κ₀+1)/(k steps); frozen there afterwards.

    Returns (u_x, u_y, λ, g_t) at load step ``step``; valid for the
    thesis's numbers with an integer κ₀ and f_c ≠ 1."""
    k, F, s = 9e4, 1000.0, 0.005
    per_step = F / steps
    k0 = s * k / per_step
    if step <= k0:
        u = per_step * step / k
        return u, -u, 0.0, 0.0
    lam = per_step * step - k * s
    if friction < 1:
        p = (max(per_step * (step - 1) - k * s, 0.0) if coulomb == "lagged"
             else lam)
        return (per_step * step - friction * p) / k, -s, lam, -friction * p
    frozen = k0 + 1 if coulomb == "lagged" else k0
    if coulomb == "lagged" and step == k0 + 1:
        return per_step * step / k, -s, lam, 0.0
    ux = per_step * frozen / k
    return ux, -s, lam, k * ux - per_step * step
