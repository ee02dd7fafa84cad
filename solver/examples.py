"""Ready-made problems from the thesis that need no mesh.

:func:`two_dof_bar` is the "simple bar system" of thesis §6 (Fig. 17-21): one
point A with two DOFs (u_x, u_y) held by springs, loaded by
f = [1000, -1000]ᵀ, with a rigid obstacle at distance s = 0.005 below A.
"""

import numpy as np
import scipy.sparse as sp

from .problem import ContactProblem

__all__ = ["two_dof_bar"]


def two_dof_bar(stiffness=9e4, load=(1000.0, -1000.0), gap=0.005,
                normal=(0.0, -1.0)):
    r"""The thesis's 2-DOF bar system (§6): K = 10⁴·diag(9, 9).

    Parameters
    ----------
    stiffness : float
        Spring stiffness of both DOFs (thesis: 9·10⁴).
    load : (float, float)
        Full load f (thesis: [1000, -1000]ᵀ).
    gap : float
        Initial gap s along ``normal`` (thesis: 0.005).
    normal : (float, float)
        Unit normal from A towards the obstacle. The thesis's Fig. 17 is
        lost; the obstacle is taken below A, ν = (0, -1), so that the load
        closes the gap at load step κ = 45 of 100 (u_y = -κ/100 · 1000/9e4
        reaches -0.005 at κ = 45) and the tangential load 1000 loads the
        friction, as the thesis's Fig. 18-21 describe.

    Returns
    -------
    ContactProblem
        A ``"discrete"`` problem; M = [[1]], so the contact "stress" equals
        the nodal contact force.
    """
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
