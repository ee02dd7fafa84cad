r"""Rigid obstacle surfaces in 3D, built from a spec: the 3D counterpart of
the obstacle curve :math:`\Gamma_o(t)` of thesis §4, described by the JSON
``obstacle_surface`` of a problem file (docs/npz-format.md, "3D"): a
plane, a sphere (closed form, :mod:`.shapes`), a graph
:math:`z \le h(x, y)` or a parametric surface c(s, t) (Newton's method
vectorised over the nodes, :mod:`.parametric`, :mod:`.search`), a
rectangle or a polygon (bounded planes), or several of them
(:mod:`.several`). Each
answers the two gap questions of thesis §2.1:
:meth:`~.base.Surface.gap_along_obstacle_normal` (§2.1.1) and
:meth:`~.base.Surface.gap_along_rays` (§2.1.2).

Example
-------
>>> ball = surface_from_spec({"kind": "sphere", "center": [0, 0, 0],
...                           "radius": 1.0})
>>> gap, nu, foot = ball.gap_along_obstacle_normal([[0.0, 0.0, 3.0]])
>>> float(gap[0]), nu[0].tolist()
(2.0, [-0.0, -0.0, -1.0])"""

import json

from ...errors import ProblemError
from .base import GapError, Surface
from .parametric import GraphSurface, ParametricSurface
from .shapes import PlaneSurface, SphereSurface
from .several import PolygonSurface, RectangleSurface, SeveralSurfaces

__all__ = ["surface_from_spec", "Surface", "PlaneSurface", "SphereSurface",
           "GraphSurface", "ParametricSurface", "RectangleSurface",
           "PolygonSurface", "SeveralSurfaces", "GapError", "KINDS"]

#: The surface kinds by their spec name.
KINDS = {cls.kind: cls for cls in (PlaneSurface, SphereSurface,
                                   GraphSurface, ParametricSurface,
                                   RectangleSurface, PolygonSurface,
                                   SeveralSurfaces)}


def surface_from_spec(spec):
    """The :class:`Surface` described by ``spec`` (a dict, or its JSON
    text). ProblemError, one line naming the bad field: not a dict (or not
    JSON), an unknown kind, a missing or unknown field, non-finite numbers, a
    zero normal, a radius ≤ 0, a bad expression, an empty range."""
    if isinstance(spec, (str, bytes)):
        try:
            spec = json.loads(spec)
        except ValueError as exc:
            raise ProblemError(f"surface spec: not valid JSON ({exc})") \
                from None
    if not isinstance(spec, dict):
        raise ProblemError(f"surface spec: need a dict, got "
                           f"{type(spec).__name__}")
    kind = spec.get("kind")
    if not isinstance(kind, str) or kind not in KINDS:
        raise ProblemError(f"surface kind: unknown {kind!r} (known: "
                           f"{', '.join(sorted(KINDS))})"[:200])
    return KINDS[kind].from_spec(spec)
