"""Fast JSON text of the plan: byte for byte what ``json.dumps(obj, indent=1, allow_nan=False,
ensure_ascii=False, default=…)`` writes, in pieces.

The standard library encodes indented JSON in pure Python, one generator step per value; a plan of
10⁵ segments has millions of values. :func:`encode` writes one value at a given indentation with
plain recursion, and :func:`segment_text` one ``<segment>`` object of the plan JSON with its keys
known in advance. Both give up (:class:`Unsupported`) on anything they do not write exactly as the
standard library does — a non-finite number, a key that is not a string, a value only ``default``
can turn into JSON — and the caller then falls back to the standard library, which gives the
same text or the error it always gave.
"""

from __future__ import annotations

import math
import os
from json.encoder import encode_basestring  # the C implementation where available
from math import isfinite
from typing import Any

__all__ = ["Unsupported", "encode", "segment_text", "SEGMENT_KEYS", "indent"]

# the keys of a plan-JSON <segment> object, in order (trcopt.path.Segment.to_json)
SEGMENT_KEYS = (
    "kind", "start", "end", "center", "ccw", "plane", "role", "line", "block", "side", "radius",
    "feed_mm_min", "points", "t_start_s", "t_end_s",
)  # fmt: skip

_INDENTS = ["\n" + " " * k for k in range(64)]


class Unsupported(Exception):
    """The value is not one this module writes exactly as ``json.dumps`` does (the caller falls back)."""


def indent(level: int) -> str:
    """``"\\n"`` and ``level`` blanks."""
    return _INDENTS[level] if level < len(_INDENTS) else "\n" + " " * level


def _float(v: float) -> str:
    if not math.isfinite(v):  # NaN or ±inf (JSON has neither)
        raise Unsupported
    return float.__repr__(v)


def encode(o: Any, level: int) -> str:
    """``o`` as indented JSON whose nested lines are indented by ``level`` + 1, … blanks."""
    if isinstance(o, str):
        return encode_basestring(o)
    if o is None:
        return "null"
    if o is True:
        return "true"
    if o is False:
        return "false"
    if isinstance(o, int):
        return int.__repr__(o)
    if isinstance(o, float):
        return _float(o)
    if isinstance(o, (list, tuple)):
        if not o:
            return "[]"
        inner = indent(level + 1)
        return "[" + inner + ("," + inner).join([_scalar(v, level + 1) for v in o]) + indent(level) + "]"
    if isinstance(o, dict):
        if not o:
            return "{}"
        inner = indent(level + 1)
        parts = []
        for k, v in o.items():
            if type(k) is not str:
                raise Unsupported
            parts.append(f"{encode_basestring(k)}: {_scalar(v, level + 1)}")
        return "{" + inner + ("," + inner).join(parts) + indent(level) + "}"
    if hasattr(o, "tolist"):  # numpy scalar or array (the plan JSON's default)
        return encode(o.tolist(), level)
    if isinstance(o, os.PathLike):
        return encode(os.fspath(o), level)
    if hasattr(o, "value") and hasattr(type(o), "__members__"):  # Enum
        return encode(o.value, level)
    raise Unsupported


def _scalar(v: Any, level: int) -> str:
    """:func:`encode` with the common scalar types first."""
    t = type(v)
    if t is float:
        if not isfinite(v):
            raise Unsupported
        return float.__repr__(v)
    if v is None:
        return "null"
    if t is str:
        return encode_basestring(v)
    if t is int:
        return int.__repr__(v)
    return encode(v, level)


def _point(p: Any, level: int) -> str:
    if p is None:
        return "null"
    if type(p) is list and len(p) == 3:
        a, b, c = p
        if type(a) is float and type(b) is float and type(c) is float and math.isfinite(a + b + c):
            inner = indent(level + 1)
            return f"[{inner}{a!r},{inner}{b!r},{inner}{c!r}{indent(level)}]"
    return encode(p, level)


def segment_text(d: dict[str, Any], level: int) -> str:
    """A ``<segment>`` object (the dict of :meth:`trcopt.path.Segment.to_json`) as :func:`encode`
    writes it, faster; any other dict goes through :func:`encode`."""
    if tuple(d) != SEGMENT_KEYS:
        return encode(d, level)
    i = indent(level + 1)
    n = level + 1
    return (
        f'{{{i}"kind": {_scalar(d["kind"], n)},{i}"start": {_point(d["start"], n)},'
        f'{i}"end": {_point(d["end"], n)},{i}"center": {_point(d["center"], n)},'
        f'{i}"ccw": {_scalar(d["ccw"], n)},{i}"plane": {_scalar(d["plane"], n)},'
        f'{i}"role": {_scalar(d["role"], n)},{i}"line": {_scalar(d["line"], n)},'
        f'{i}"block": {_scalar(d["block"], n)},{i}"side": {_scalar(d["side"], n)},'
        f'{i}"radius": {_scalar(d["radius"], n)},{i}"feed_mm_min": {_scalar(d["feed_mm_min"], n)},'
        f'{i}"points": {_scalar(d["points"], n)},{i}"t_start_s": {_scalar(d["t_start_s"], n)},'
        f'{i}"t_end_s": {_scalar(d["t_end_s"], n)}{indent(level)}}}'
    )
