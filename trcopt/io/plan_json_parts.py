"""The plan JSON written in parts, for a plan computed window by window (:mod:`trcopt.streaming`).

The long arrays — ``programmed``, ``toolpath`` and ``timing.sections`` — are written as they are
produced, each to a temporary file (:class:`ArrayText`), and :func:`plan_json_parts_chunks` gives
the whole text at the end in pieces, with the diagnostics and ``ok`` known by then: the same text
:func:`trcopt.io.plan_json.plan_json_chunks` writes for the same values, never held whole in memory.
"""

from __future__ import annotations

import tempfile
from collections.abc import Iterable, Iterator, Mapping
from json.encoder import encode_basestring
from typing import IO, Any

from trcopt.errors import Diagnostic
from trcopt.io.json_text import Unsupported, encode, indent, segment_text
from trcopt.io.plan_json import PlanJsonError, _plan_items, _seg_dict

__all__ = ["ArrayText", "plan_json_parts_chunks"]

_COPY = 1 << 20  # bytes per piece when a part is copied out


class ArrayText:
    """A JSON array at nesting ``level`` written item by item to a temporary file.

    ``segments=True``: the items are ``<segment>`` values (:class:`~trcopt.path.Segment`), else
    any JSON value (:func:`~trcopt.io.json_text.encode`). A value the fast writer does not take
    raises :class:`~trcopt.io.plan_json.PlanJsonError` with its reason.
    """

    def __init__(self, level: int, segments: bool) -> None:
        self.level, self.segments = level, segments
        self.count = 0
        self._file: IO[str] = tempfile.TemporaryFile("w+", encoding="utf-8")  # noqa: SIM115 (closed by close())

    def add(self, items: Iterable[Any]) -> None:
        inner = indent(self.level + 1)
        parts: list[str] = []
        try:
            for item in items:
                text = segment_text(_seg_dict(item), self.level + 1) if self.segments else encode(item, self.level + 1)
                parts += ("," if self.count else "", inner, text)
                self.count += 1
        except Unsupported:
            raise PlanJsonError(f"a value of the plan cannot be written as JSON: {item!r:.200}") from None
        self._file.write("".join(parts))

    def chunks(self) -> Iterator[str]:
        """The array's text: ``[]``, or ``[`` + the items + the closing bracket at its level."""
        if not self.count:
            yield "[]"
            return
        yield "["
        self._file.flush()
        self._file.seek(0)
        while piece := self._file.read(_COPY):
            yield piece
        yield indent(self.level) + "]"

    def close(self) -> None:
        self._file.close()


_SECTIONS = "\x00sections\x00"  # stands for timing.sections while the timing object is encoded


def plan_json_parts_chunks(
    *,
    program: str,
    dialect: str,
    diagnostics: Iterable[Diagnostic | Mapping[str, Any]],
    programmed: ArrayText,
    toolpath: ArrayText,
    timing: Mapping[str, Any] | None,
    sections: ArrayText | None,
    extra: Mapping[str, Any] | None,
) -> Iterator[str]:
    """The plan JSON text with its arrays from their parts (``programmed`` and ``toolpath`` at
    level 1, ``sections`` — ``timing.sections`` — at level 2); ``timing`` without its sections."""
    if timing is not None:
        timing = {**timing, "sections": _SECTIONS}
    items = _plan_items(program, dialect, diagnostics, [], [], timing, extra)
    sep = "{" + indent(1)
    parts = {"programmed": programmed, "toolpath": toolpath}
    for key, value in items:
        head = f"{sep}{encode_basestring(key)}: "
        sep = "," + indent(1)
        if key in parts:
            yield head
            yield from parts[key].chunks()
            continue
        try:
            text = encode(value, 1)
        except Unsupported:
            raise PlanJsonError(f"the plan's {key!r} cannot be written as JSON") from None
        if key == "timing" and sections is not None and value is not None:
            before, _, after = text.partition(encode_basestring(_SECTIONS))
            yield head + before
            yield from sections.chunks()
            yield after
        else:
            yield head + text
    yield "\n}\n"
