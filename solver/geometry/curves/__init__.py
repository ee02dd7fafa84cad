r"""Signed gaps between contact nodes and the rigid obstacle (thesis §2.1).

Small deformations and small displacements are assumed, so the gap *s* and
the contact normal ν are evaluated **once, on the undeformed body**. For a
contact node *B* the obstacle point is found on a normal line
:math:`B + k\,\nu = \Gamma_o(t)` ((1), (4)), with ν the obstacle's normal
at its nearest point (:func:`gap_from_obstacle`, "measured from the
obstacle", §2.1.1) or the body's outward normal at *B*
(:func:`gap_along_normals`, "measured from the body", §2.1.2). In both ν
is normalised (7) and oriented **from the body towards the obstacle**, and
:math:`s = (\Gamma_o(t) - B)\cdot\nu = k`: negative when *B* already lies
past the obstacle (allowed, but warned about by :func:`warn_penetration`).
This follows the errata of the thesis digest: the distance along
:math:`B + k\nu` is :math:`|k|\,|\nu|` (the thesis's (3) and (6) print
:math:`|k|/|\nu|`), and ν's orientation replaces §2.1.1's sign rule.
Both problems are one-dimensional in *t*, solved for all nodes at once by
the sampled bracketing search of :mod:`.search`."""

import numpy as np

from .rays import gap_along_normals
from ..checks import GapError, warn_penetration
from .closest import gap_from_obstacle
from .search import DEFAULT_SAMPLES, MIN_COSINE, parameter_window
from .several import SeveralCurves, several_gaps

__all__ = ["GapError", "parameter_window", "gap_from_obstacle",
           "gap_along_normals", "warn_penetration", "DEFAULT_SAMPLES",
           "MIN_COSINE", "SeveralCurves", "obstacle_gaps"]


def obstacle_gaps(points, obstacle, body_normals, gap="obstacle", *,
                  node_ids=None, warn=True):
    """(s, ν, foot) at the contact nodes ``points`` with outward
    ``body_normals``: :func:`gap_from_obstacle` (``gap`` "obstacle") or
    :func:`gap_along_normals` ("body") for one curve (foot: t), the
    nearest of several for :class:`SeveralCurves` (foot: the point Γo(t);
    +∞ where none reaches, :mod:`.several`)."""
    if isinstance(obstacle, SeveralCurves):
        s, normal, foot, _ = several_gaps(points, obstacle, body_normals,
                                          gap, node_ids=node_ids)
        if warn:
            reach = np.isfinite(s)
            warn_penetration(s[reach], np.asarray(points)[reach],
                             None if node_ids is None
                             else np.asarray(node_ids)[reach])
        return s, normal, foot
    if gap == "obstacle":
        return gap_from_obstacle(points, obstacle, body_normals,
                                 node_ids=node_ids, warn=warn)
    return gap_along_normals(points, body_normals, obstacle,
                             node_ids=node_ids, warn=warn)
