r"""Orthonormal contact frames: the tangents that go with a unit normal.

In 2D the tangent is the thesis's γ = (−ν_y, ν_x) (§3.2, (58)-(60)). In 3D
the two tangents are the branch-free orthonormal basis of Duff et al.
(2017), a corrected form of Frisvad's (2012): with σ = sign(ν_z) (+1 at
ν_z = 0), a = −1/(σ + ν_z), b = ν_x ν_y a,

.. math::
    τ_1 = (1 + σ ν_x^2 a,\ σ b,\ −σ ν_x), \qquad
    τ_2 = (b,\ σ + ν_y^2 a,\ −ν_y),

continuous except across ν_z = 0, accurate to round-off for every unit
ν, (τ_1, τ_2, ν) right-handed. Any frame in the tangent plane gives the
same frictionless answer, and friction sees only the plane. A roller's
frame (:func:`roller_frames`) has its constrained directions e_c first:
(e_c, ν × e_c, ν) with one in 3D, (e_c1, ±e_c2, ν) with two,
right-handed; in 2D γ, then ±e_c.

References
----------
T. Duff, J. Burgess, P. Christensen, C. Hery, A. Kensler, M. Liani,
R. Villemin: Building an orthonormal basis, revisited. JCGT 6(1) (2017).
J. R. Frisvad: Building an orthonormal basis from a 3D unit vector without
normalization. J. Graphics Tools 16(3) (2012) 151-159."""

import numpy as np

from ..errors import SolverError

__all__ = ["ROLLER_TOLERANCE", "tangent_basis", "frames", "roller_frames"]

#: A node with Dirichlet components c is a roller when |ν_c| ≤ this.
ROLLER_TOLERANCE = 1e-8


def tangent_basis(normal):
    """Orthonormal tangents (m, d − 1, d) of the unit normals ``normal``
    (m, d), d = 2 or 3: in 2D exactly γ = (−ν_y, ν_x); in 3D (τ_1, τ_2) of
    the module docstring."""
    nu = np.asarray(normal, dtype=float)
    if nu.ndim != 2 or nu.shape[1] not in (2, 3):
        raise SolverError(f"normals must have shape (m, 2) or (m, 3), got "
                          f"{nu.shape}")
    if nu.shape[1] == 2:
        return np.stack([-nu[:, 1], nu[:, 0]], axis=1)[:, None, :]
    x, y, z = nu.T
    sign = np.where(z >= 0.0, 1.0, -1.0)
    a = -1.0 / (sign + z)
    b = x * y * a
    t1 = np.stack([1.0 + sign * x * x * a, sign * b, -sign * x], axis=1)
    t2 = np.stack([b, sign + y * y * a, -y], axis=1)
    return np.stack([t1, t2], axis=1)


def frames(normal, tangents=None):
    """Per-node rotations Q (m, d, d): rows the d − 1 tangents, then the
    normal, so that Q v = (tangential components, normal component)."""
    nu = np.asarray(normal, dtype=float)
    tangents = tangent_basis(nu) if tangents is None else tangents
    return np.concatenate([tangents, nu[:, None, :]], axis=1)


def roller_frames(normal, fixed):
    """Frames of roller nodes (module docstring): (normal, tangents) with
    ν's constrained components (``fixed`` (m, d): at least one, at most
    d − 1 per row) set to 0 and renormalised, and the constrained directions
    first among the tangents; vectorised per pattern of ``fixed``."""
    nu = np.array(normal, dtype=float)
    nu[fixed] = 0.0
    nu /= np.linalg.norm(nu, axis=1)[:, None]
    tangents = tangent_basis(nu)
    d = nu.shape[1]
    if d == 2 or not len(nu):
        return nu, tangents
    axes = np.eye(d)
    for pattern in np.unique(fixed, axis=0):
        rows = np.flatnonzero((fixed == pattern).all(axis=1))
        c = np.flatnonzero(pattern)
        t = np.empty((len(rows), 2, 3))
        t[:, :len(c)] = axes[c]
        if len(c) == 1:  # (e_c, ν × e_c, ν) right-handed
            t[:, 1] = np.cross(nu[rows], axes[c[0]])
        else:  # ν = ±e_f: orient e_c2 so that e_c1 × t_2 = ν
            t[:, 1] *= np.sign(nu[rows] @ np.cross(axes[c[0]], axes[c[1]]))[
                :, None]
        tangents[rows] = t
    return nu, tangents
