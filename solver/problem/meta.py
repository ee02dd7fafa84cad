"""The ``meta`` key: the problem's metadata (material E, ν, plane; load;
mesh name) as JSON text, parsed safely. Unbounded recursion, integers of
thousands of digits, the non-standard ``NaN`` and ``Infinity`` and strings
with lone surrogates are each refused with a one-line ProblemError."""

import json
import math
import re

import numpy as np

from ..errors import ProblemError
from .format import MAX_INT_DIGITS, MAX_META_DEPTH

__all__ = ["parse_meta", "parse_json", "check_material", "check_bodies"]

# A JSON string literal (with escapes); removed before counting brackets.
_STRING = re.compile(r'"(?:[^"\\]|\\.)*"', re.DOTALL)


def _fail(message):
    raise ProblemError(f"meta: {message}")


def _depth(text):
    """Deepest nesting of [ and { outside strings, without recursion."""
    bare = _STRING.sub('""', text).encode("utf-8", "surrogatepass")
    codes = np.frombuffer(bare, dtype=np.uint8)
    step = (np.isin(codes, (ord("["), ord("{"))).astype(np.int64)
            - np.isin(codes, (ord("]"), ord("}"))))
    return int(np.cumsum(step).max(initial=0))


def _constant(name):
    _fail(f"{name} is not a number in JSON (NaN and Infinity are refused)")


def _integer(text):
    digits = text.lstrip("-")
    if len(digits) > MAX_INT_DIGITS:
        _fail(f"an integer of {len(digits)} digits (at most "
              f"{MAX_INT_DIGITS} are accepted)")
    return int(text)


def _float(text):
    value = float(text)
    if not math.isfinite(value):
        _fail(f"the number {text[:40]} overflows double precision")
    return value


def parse_meta(text):
    """The ``meta`` text as a dict; ProblemError ``"meta: ..."`` for each
    of the module docstring's hostile inputs (limits
    :data:`~solver.problem.format.MAX_META_DEPTH`,
    :data:`~solver.problem.format.MAX_INT_DIGITS`)."""
    depth = _depth(text)
    if depth > MAX_META_DEPTH:
        _fail(f"nests {depth} levels deep (at most {MAX_META_DEPTH})")
    try:
        meta = json.loads(text, parse_constant=_constant,
                          parse_int=_integer, parse_float=_float)
    except json.JSONDecodeError as exc:
        _fail(f"not valid JSON ({exc.msg})")
    except RecursionError:
        _fail(f"nests too deeply (at most {MAX_META_DEPTH} levels)")
    if not isinstance(meta, dict):
        _fail("must be a JSON object")
    stack = [meta]
    while stack:  # every string, key or value, must be valid Unicode
        item = stack.pop()
        if isinstance(item, dict):
            stack.extend(item.keys())
            stack.extend(item.values())
        elif isinstance(item, list):
            stack.extend(item)
        elif isinstance(item, str):
            try:
                item.encode("utf-8")
            except UnicodeEncodeError:
                _fail(f"the string {item[:30]!r} is not valid Unicode (lone "
                      "surrogate)")
    return meta


def parse_json(text, key):
    """:func:`parse_meta` for another JSON key: the same limits, the
    message starts with ``key``."""
    try:
        return parse_meta(text)
    except ProblemError as exc:
        message = str(exc).removeprefix("meta: ")
        raise ProblemError(f"{key}: {message}") from None


def _number(value):
    """A finite real number: JSON true/false are not numbers."""
    return isinstance(value, (int, float)) and not isinstance(value, bool) \
        and math.isfinite(value)


def check_material(meta, dim=2):
    """E > 0 and -1 < ν < 0.5 finite numbers; in 2D plane strain or stress
    (the plane elasticity of thesis §3.1). A 3D problem needs no ``plane``;
    if it carries one it is not read."""
    E, nu = meta["E"], meta["nu"]
    if not _number(E) or not E > 0:
        _fail(f"E must be a positive finite number, got {_short(E)}")
    if not _number(nu) or not -1 < nu < 0.5:
        _fail(f"nu must be a number in (-1, 0.5), got {_short(nu)}")
    if dim == 2 and meta["plane"] not in ("strain", "stress"):
        _fail(f"plane must be 'strain' or 'stress', got "
              f"{_short(meta['plane'])}")


def _body_id(meta, name, n_bodies, n_pairs):
    """``meta[name]``: a body id, or a list of one per pair."""
    value = meta[name]
    ids = value if isinstance(value, list) else [value]
    if not all(_number(v) and isinstance(v, int) and 0 <= v < n_bodies
               for v in ids) or isinstance(value, list) \
            and len(value) != n_pairs:
        _fail(f"{name} must be a body id 0 … {n_bodies - 1} (or a list of "
              f"one per pair, {n_pairs}), got {_short(value)}")
    return ids * n_pairs if not isinstance(value, list) else ids


def check_bodies(meta, n_bodies, slave_body=None, master_body=None):
    """The two-body fields of ``meta`` (format version 4): ``bodies``, one
    {name, E, nu} per body id, and ``slave_body``, ``master_body`` naming the
    bodies of the pairs' segments (found by the loader); ``E`` and ``nu`` of
    ``meta`` must be the slave body's."""
    bodies = meta.get("bodies")
    if not isinstance(bodies, list) or len(bodies) != n_bodies:
        _fail(f"bodies must be a list of {n_bodies} objects "
              f"{{name, E, nu}} (one per body), got {_short(bodies)}")
    for i, entry in enumerate(bodies):
        if not isinstance(entry, dict) or not isinstance(
                entry.get("name"), str) or "E" not in entry \
                or "nu" not in entry:
            _fail(f"bodies[{i}] must be an object with name, E and nu, got "
                  f"{_short(entry)}")
        try:
            check_material(entry, dim=3)
        except ProblemError as exc:
            _fail(f"bodies[{i}]: {str(exc).removeprefix('meta: ')}")
    if slave_body is None:
        return
    n_pairs = len(slave_body)
    for name, found in (("slave_body", slave_body),
                        ("master_body", master_body)):
        if name not in meta:
            _fail(f"field {name!r} missing (a two-body file needs "
                  "slave_body and master_body)")
        ids = _body_id(meta, name, n_bodies, n_pairs)
        for pair, (want, got) in enumerate(zip(ids, found)):
            if want != got:
                _fail(f"{name} is {want} for pair {pair}, but its segments "
                      f"lie in body {int(got)}")
    if len(set(int(b) for b in slave_body)) == 1:
        entry = bodies[int(slave_body[0])]
        if (meta["E"], meta["nu"]) != (entry["E"], entry["nu"]):
            _fail(f"E, nu ({_short(meta['E'])}, {_short(meta['nu'])}) must "
                  f"be those of the slave body {int(slave_body[0])} "
                  f"({_short(entry['E'])}, {_short(entry['nu'])})")


def _short(value):
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
