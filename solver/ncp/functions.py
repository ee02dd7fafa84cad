r"""NCP functions φ(a, b) and their (generalised) partial derivatives.

An NCP function vanishes exactly on the complementarity set,

.. math::  φ(a, b) = 0 \iff a \ge 0,\ b \ge 0,\ a b = 0,

so the complementarity problem (15) of the thesis, A(x) ≥ 0, B(x) ≥ 0,
A(x)ᵀB(x) = 0, becomes the nonsmooth equation Φ(x) = 0 with
Φ_i = φ(A_i(x), B_i(x)). Two choices (thesis (19), (20)):

- ``"min"``: φ(a, b) = min(a, b);
- ``"fb"``: the Fischer–Burmeister function φ(a, b) = √(a² + b²) − (a + b)
  (Fischer 1992).

:func:`derivative_weights` returns (w_a, w_b) such that the Jacobian row of
Φ_i is w_a ∇A_i + w_b ∇B_i, an element of the B-subdifferential: for
``"min"`` the thesis's rule of §2.2.1 (∇B_i if A_i > B_i, else ∇A_i); for
``"fb"`` rule (30), and at the kink a = b = 0 rule (31) of De Luca,
Facchinei and Kanzow (1996) with the directional values ∇A_iᵀz, ∇B_iᵀz."""

import numpy as np

__all__ = ["NCP_FUNCTIONS", "phi", "derivative_weights"]

NCP_FUNCTIONS = ("min", "fb")


def phi(a, b, kind):
    """Φ_i = φ(a_i, b_i) componentwise, thesis (19) or (20)."""
    if kind == "min":
        return np.minimum(a, b)
    if kind == "fb":
        # √(a²+b²) − (a+b) cancels when a ≫ b > 0 (a contact force against a
        # gap of another unit): the gap would be resolved only to ε·a. Where
        # a + b > 0 use the equal form −2ab / (√(a²+b²) + a + b).
        a, b = np.broadcast_arrays(np.asarray(a, float), np.asarray(b, float))
        with np.errstate(all="ignore"):  # extreme values are redone below
            r = np.hypot(a, b)
            s = a + b
            positive = s > 0
            out = np.array(r - s)  # a sum of non-negative terms if s ≤ 0
            ab2 = -2.0 * a[positive] * b[positive]
            denominator = r[positive] + s[positive]
            out[positive] = ab2 / denominator
            # 2ab or a + b outside the double range (a = b = 1e308 gave
            # NaN, a = b = 1e-300 gave 0): the homogeneous form. With m the
            # entry of larger magnitude (m > 0 where a + b > 0) and
            # ρ = other/m ∈ (−1, 1], φ = −2·other / (√(1+ρ²) + 1 + ρ),
            # whose denominator lies in [√2, 2+√2].
            extreme = np.zeros_like(positive)
            extreme[positive] = ~np.isfinite(ab2 * denominator) | (
                np.abs(ab2) < np.finfo(float).tiny)
            ap, bp = a[extreme], b[extreme]
            a_larger = np.abs(ap) >= np.abs(bp)
            m = np.where(a_larger, ap, bp)
            other = np.where(a_larger, bp, ap)
            rho = other / m
            out[extreme] = -other * (2.0 / (np.hypot(1.0, rho) + 1.0 + rho))
        return out
    raise ValueError(f"unknown NCP function {kind!r}; use one of "
                     f"{NCP_FUNCTIONS}")


def derivative_weights(a, b, kind, za=None, zb=None):
    """Weights (w_a, w_b, degenerate) of the Jacobian rows
    w_a ∇A_i + w_b ∇B_i at a = A(x), b = B(x) for ``kind``; ``degenerate``
    marks γ = {a_i = b_i = 0} (``"fb"``) or the ties a = b (``"min"``).
    ``za``, ``zb`` (``"fb"``): ∇A_iᵀz, ∇B_iᵀz for the direction z of DFK's
    rule (31) on γ; without them w_a = w_b = 1/√2 − 1 there."""
    if kind == "min":
        take_b = a > b  # thesis §2.2.1 a): J_i = ∇B_i if A_i > B_i
        return (~take_b).astype(float), take_b.astype(float), a == b
    if kind == "fb":
        norm = np.hypot(a, b)
        degenerate = norm == 0.0
        safe = np.where(degenerate, 1.0, norm)
        wa, wb = a / safe - 1.0, b / safe - 1.0  # (30)
        if degenerate.any():
            if za is None:
                za = zb = np.ones_like(a)
            za, zb = np.broadcast_to(za, a.shape), np.broadcast_to(zb, a.shape)
            znorm = np.hypot(za, zb)
            znorm = np.where(znorm == 0.0, 1.0, znorm)
            wa = np.where(degenerate, za / znorm - 1.0, wa)  # (31)
            wb = np.where(degenerate, zb / znorm - 1.0, wb)
        return wa, wb, degenerate
    raise ValueError(f"unknown NCP function {kind!r}; use one of "
                     f"{NCP_FUNCTIONS}")
