"""The ``obstacle_surface`` key: a JSON surface spec (3D, format version
3; its fields in docs/npz-format.md), parsed with the bounded JSON reader
of :mod:`.meta` and made a surface by
:func:`solver.geometry.surfaces.surface_from_spec`."""

import json

from ..errors import ProblemError
from ..geometry.surfaces import surface_from_spec
from .checks import fail
from .meta import parse_json

__all__ = ["SURFACE_KINDS", "obstacle_surface", "surface_spec_text"]

#: The kinds of obstacle surface a spec may name.
SURFACE_KINDS = ("plane", "sphere", "graph", "parametric", "rectangle",
                 "polygon", "several")

KEY = "obstacle_surface"


def obstacle_surface(text):
    """The obstacle :class:`~solver.geometry.surfaces.Surface` of a 3D
    problem from the text of its spec; ProblemError ``"obstacle_surface:
    ..."`` (one line) for text that is not a JSON object, no or an unknown
    ``kind``, or a field the surface module refuses."""
    spec = parse_json(text, KEY)
    kind = spec.get("kind")
    if kind not in SURFACE_KINDS:
        fail(KEY, f"'kind' must be one of {', '.join(SURFACE_KINDS)}, got "
                  f"{str(kind)[:40]!r}")
    try:
        return surface_from_spec(spec)
    except ProblemError as exc:
        fail(KEY, " ".join(str(exc).split()))


def surface_spec_text(obstacle):
    """The JSON text stored for ``obstacle`` (a surface object with a
    ``spec()`` method, or a spec dict)."""
    spec = obstacle.spec() if hasattr(obstacle, "spec") else obstacle
    return json.dumps(spec, sort_keys=True)
