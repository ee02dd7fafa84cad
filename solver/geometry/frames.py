r"""Orthonormal contact frames: the tangents that go with a unit normal.

In 2D the tangent is the thesis's γ = (−ν_y, ν_x) (§3.2, (58)-(60)), the
normal turned by +90°. In 3D the two tangents are the branch-free
orthonormal basis of Duff et al. (2017), a corrected form of Frisvad's
(2012): with σ = sign(ν_z) (+1 at ν_z = 0), a = −1/(σ + ν_z),
b = ν_x ν_y a,

.. math::
    τ_1 = (1 + σ ν_x^2 a,\ σ b,\ −σ ν_x), \qquad
    τ_2 = (b,\ σ + ν_y^2 a,\ −ν_y),

which is continuous except across ν_z = 0 and accurate to round-off for
every unit ν (no division by a small number: |σ + ν_z| ≥ 1). (τ_1, τ_2, ν)
is right-handed. Vectorised over nodes; any frame in the tangent plane
gives the same frictionless answer, and friction sees only the plane.

References
----------
T. Duff, J. Burgess, P. Christensen, C. Hery, A. Kensler, M. Liani,
R. Villemin: Building an orthonormal basis, revisited. JCGT 6(1) (2017).
J. R. Frisvad: Building an orthonormal basis from a 3D unit vector without
normalization. J. Graphics Tools 16(3) (2012) 151-159.
"""

import numpy as np

from ..errors import SolverError

__all__ = ["tangent_basis", "frames"]


def tangent_basis(normal):
    """Unit tangents of the unit normals ``normal``.

    Parameters
    ----------
    normal : (m, d) array, d = 2 or 3
        Unit normals (rows).

    Returns
    -------
    (m, d − 1, d) array
        Orthonormal tangents, orthogonal to the normal: in 2D exactly
        γ = (−ν_y, ν_x); in 3D (τ_1, τ_2) of the module docstring.
    """
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
