r"""Signed gaps between contact nodes and the rigid obstacle (thesis §2.1).

Small deformations and small displacements are assumed, so the gap *s* and
the contact normal ν are evaluated **once, on the undeformed body**. For a
contact node *B* the obstacle point is found on a normal line

.. math::  B + k\,\nu = \Gamma_o(t), \qquad (1), (4)

two equations for the unknowns *k* and *t*, with two choices of ν:

* :func:`gap_from_obstacle` -- "measured from the obstacle" (§2.1.1, (1)-(3)):
  ν is the obstacle's normal at *t*, so :math:`\Gamma_o(t)` is a foot point of
  *B*, :math:`(\Gamma_o(t) - B)\cdot\Gamma_o'(t) = 0`; of all foot points the
  nearest one is taken.
* :func:`gap_along_normals` -- "measured from the body" (§2.1.2, (4)-(6)):
  ν is the body's outward normal at *B* (from :mod:`.normals`), and
  *t* is a root of :math:`h(t) = (\Gamma_o(t) - B) \times \nu`; of all roots
  the one with the smallest :math:`|k|` is taken.

In both cases ν is normalised (7) and oriented **from the body towards the
obstacle**, and the gap is the signed distance along it,

.. math::  s = (\Gamma_o(t) - B)\cdot\nu = k \qquad (|\nu| = 1),

positive when the obstacle lies ahead of *B*, negative when *B* already lies
past the obstacle (initial penetration; allowed, the contact conditions then
push the node back, but warned about by :func:`warn_penetration`: it is
rarely what a problem meant). This follows the errata of the thesis digest:
along :math:`B + k\nu` the distance is :math:`|k|\,|\nu|` (the thesis's (3)
and (6) print :math:`|k|/|\nu|`), and the sign rule of §2.1.1 for choosing the
normal from the sign of *k* is replaced by "ν points from the body towards
the obstacle", which makes :math:`s \ge 0` for a node outside the obstacle.

Both problems are one-dimensional in *t*, solved for all nodes at once by
the sampled bracketing search of :mod:`.search`; the checks and messages
are in :mod:`solver.geometry.checks`, the two gaps in :mod:`.closest` and
:mod:`.rays`.
"""

from .rays import gap_along_normals
from ..checks import GapError, warn_penetration
from .closest import gap_from_obstacle
from .search import DEFAULT_SAMPLES, MIN_COSINE, parameter_window

__all__ = ["GapError", "parameter_window", "gap_from_obstacle",
           "gap_along_normals", "warn_penetration", "DEFAULT_SAMPLES",
           "MIN_COSINE"]
