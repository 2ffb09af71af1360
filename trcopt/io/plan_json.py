"""The plan JSON (design.md §3.1): a stable contract other tools read — extend it, never break it.

``plan_json`` builds the dictionary with the contract keys in their documented order, then the
keys of ``extra`` that do not collide with them; ``dumps_plan`` serialises it (indent 1, insertion
order, and an error instead of ``NaN``/``Infinity``, which JSON does not have).
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

from trcopt.codes import Code
from trcopt.errors import Diagnostic, Severity, TrcoptError
from trcopt.io.atomic import write_text_atomic
from trcopt.io.json_text import Unsupported, encode, encode_basestring, indent, segment_text
from trcopt.path import Segment

__all__ = [
    "PLAN_SCHEMA",
    "CONTRACT_KEYS",
    "PlanJsonError",
    "plan_json",
    "dumps_plan",
    "plan_json_chunks",
    "TimedSegments",
    "write_plan_json",
]

PLAN_SCHEMA = "trcopt.plan/1"
CONTRACT_KEYS = (
    "schema",
    "program",
    "dialect",
    "units",
    "ok",
    "diagnostics",
    "programmed",
    "toolpath",
    "timing",
)


class PlanJsonError(TrcoptError, ValueError):
    """The plan cannot be written as JSON (non-finite number, unserialisable value); names where."""

    def __init__(self, message: str, code: str = Code.PLAN_JSON) -> None:
        super().__init__(message, None, code)


def _diag_json(d: Diagnostic | Mapping[str, Any]) -> dict[str, Any]:
    if isinstance(d, Diagnostic):
        return d.to_json()
    return dict(d)


def _is_error(d: Diagnostic | Mapping[str, Any]) -> bool:
    if isinstance(d, Diagnostic):
        return d.severity is Severity.ERROR
    return str(d.get("severity", "")).lower() == Severity.ERROR.value


def _seg_json(s: Segment | Mapping[str, Any]) -> dict[str, Any]:
    if isinstance(s, Segment):
        return s.to_json()
    return dict(s)


def _seg_dict(s: Any) -> Any:
    """A ``<segment>`` dict of a segment; anything else as it is (it is written as any value)."""
    return s.to_json() if isinstance(s, Segment) else s


def plan_json(
    *,
    program: str,
    dialect: str,
    diagnostics: Iterable[Diagnostic | Mapping[str, Any]],
    programmed: Iterable[Segment | Mapping[str, Any]],
    toolpath: Iterable[Segment | Mapping[str, Any]],
    timing: Mapping[str, Any] | None = None,
    extra: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """The plan dictionary of design.md §3.1.

    Parameters
    ----------
    program:
        Path of the part program as given by the user.
    dialect:
        ``"siemens"``, ``"heidenhain"`` or ``"rs274"``.
    diagnostics:
        :class:`~trcopt.errors.Diagnostic` values (or their JSON dicts); ``ok`` is False iff one
        of them has error severity.
    programmed, toolpath:
        :class:`~trcopt.path.Segment` values (or their ``<segment>`` dicts), mm.
    timing:
        The timing object (``duration_s`` in s, ``machine``, ``samples``, …) or None.
    extra:
        Additional top-level keys; a key that collides with a contract key is ignored (the
        contract always wins).
    """
    return {
        key: [_seg_json(s) for s in value] if key in _SEGMENT_LISTS else value
        for key, value in _plan_items(program, dialect, diagnostics, programmed, toolpath, timing, extra)
    }


_SEGMENT_LISTS = ("programmed", "toolpath")


def _plan_items(
    program: str,
    dialect: str,
    diagnostics: Iterable[Diagnostic | Mapping[str, Any]],
    programmed: Iterable[Segment | Mapping[str, Any]],
    toolpath: Iterable[Segment | Mapping[str, Any]],
    timing: Mapping[str, Any] | None,
    extra: Mapping[str, Any] | None,
) -> list[tuple[str, Any]]:
    """The keys of the plan dictionary in order with their values; the segment lists
    (``programmed``, ``toolpath``) as given, not yet turned into ``<segment>`` dicts."""
    diags = list(diagnostics)
    out: list[tuple[str, Any]] = [
        ("schema", PLAN_SCHEMA),
        ("program", str(program)),
        ("dialect", str(dialect)),
        ("units", "mm"),
        ("ok", not any(_is_error(d) for d in diags)),
        ("diagnostics", [_diag_json(d) for d in diags]),
        ("programmed", programmed),
        ("toolpath", toolpath),
        ("timing", None if timing is None else dict(timing)),
    ]
    keys = set(CONTRACT_KEYS)
    for key, value in (extra or {}).items():
        if key not in keys:
            keys.add(key)
            out.append((key, value))
    return out


class TimedSegments(Sequence[Segment]):
    """The tool path with ``t_start_s``/``t_end_s`` set (``segments_with_times``), each segment
    made when it is read."""

    def __init__(self, segments: Sequence[Segment], t0: Any, t1: Any) -> None:
        self.segments, self.t0, self.t1 = segments, t0.tolist(), t1.tolist()

    def __len__(self) -> int:
        return len(self.segments)

    def __getitem__(self, k: Any) -> Any:
        if isinstance(k, slice):
            return [self[i] for i in range(*k.indices(len(self)))]
        return self.segments[k].with_times(self.t0[k], self.t1[k])

    def __iter__(self) -> Iterator[Segment]:
        for seg, a, b in zip(self.segments, self.t0, self.t1, strict=True):
            yield seg.with_times(a, b)


def plan_json_chunks(
    *,
    program: str,
    dialect: str,
    diagnostics: Iterable[Diagnostic | Mapping[str, Any]],
    programmed: Iterable[Segment | Mapping[str, Any]],
    toolpath: Iterable[Segment | Mapping[str, Any]],
    timing: Mapping[str, Any] | None = None,
    extra: Mapping[str, Any] | None = None,
) -> Iterator[str]:
    """:func:`dumps_plan` of :func:`plan_json` (same arguments) in pieces: the same text, with one
    ``<segment>`` dict at a time (``programmed`` and ``toolpath`` may be generators).

    Raises
    ------
    PlanJsonError
        As :func:`dumps_plan` (possibly after some pieces were given: write them to a temporary
        file, :func:`trcopt.io.atomic.write_chunks_atomic`).
    """
    items = _plan_items(program, dialect, diagnostics, programmed, toolpath, timing, extra)
    try:
        yield from _items_text(items)
    except Unsupported:
        # a value the fast writer does not take: the standard library's text, or its error
        whole = plan_json(
            program=program, dialect=dialect, diagnostics=diagnostics, programmed=programmed, toolpath=toolpath,
            timing=timing, extra=extra,
        )
        raise PlanJsonError(_error_of(whole)) from None


def _items_text(items: list[tuple[str, Any]], lazy: bool = True) -> Iterator[str]:
    """The text of a plan dictionary given as its items (plus the trailing newline), in pieces;
    the segment lists may be any iterable when ``lazy`` (else only lists and tuples are)."""
    if not items:
        yield "{}\n"
        return
    sep = "{" + indent(1)
    for key, value in items:
        head = f"{sep}{encode_basestring(key)}: "
        sep = "," + indent(1)
        if key in _SEGMENT_LISTS and (
            isinstance(value, (list, tuple))
            or lazy and isinstance(value, Iterable) and not isinstance(value, (str, bytes, Mapping))
        ):
            it = iter(value)
            first = next(it, _END)
            if first is _END:
                yield head + "[]"
                continue
            inner = indent(2)
            batch = [head, "[", inner, segment_text(_seg_dict(first), 2)]
            for s in it:
                batch += (",", inner, segment_text(_seg_dict(s), 2))
                if len(batch) >= 3 * _BATCH:
                    yield "".join(batch)
                    batch = []
            batch.append(indent(1) + "]")
            yield "".join(batch)
        else:
            yield head + encode(value, 1)
    yield "\n}\n"


_END = object()
_BATCH = 512  # segments per piece of text


def _error_of(d: Mapping[str, Any]) -> str:
    """The message of the error :func:`dumps_plan` raises for ``d`` (it must raise)."""
    try:
        _dumps_std(d)
    except PlanJsonError as exc:
        return exc.message
    raise AssertionError("the fast plan JSON writer refused a plan the standard library writes")  # pragma: no cover


def _find_non_finite(obj: Any, where: str) -> str | None:
    if isinstance(obj, float) or type(obj).__name__.startswith("float"):
        try:
            if not math.isfinite(float(obj)):
                return where
        except (TypeError, ValueError):
            return None
        return None
    if isinstance(obj, Mapping):
        for k, v in obj.items():
            found = _find_non_finite(v, f"{where}.{k}" if where else str(k))
            if found:
                return found
        return None
    if isinstance(obj, (list, tuple)):
        for i, v in enumerate(obj):
            found = _find_non_finite(v, f"{where}[{i}]")
            if found:
                return found
        return None
    if hasattr(obj, "tolist"):  # numpy arrays/scalars
        return _find_non_finite(obj.tolist(), where)
    return None


def _default(obj: Any) -> Any:
    if hasattr(obj, "tolist"):  # numpy scalar or array
        return obj.tolist()
    if isinstance(obj, os.PathLike):
        return os.fspath(obj)
    if hasattr(obj, "value") and hasattr(type(obj), "__members__"):  # Enum
        return obj.value
    raise TypeError(f"{type(obj).__name__} is not JSON serialisable")


def dumps_plan(d: Mapping[str, Any]) -> str:
    """Serialise a plan dict: indent 1, keys in insertion (contract) order, trailing newline.

    Raises
    ------
    PlanJsonError
        A number is NaN or infinite (the message names its location, e.g.
        ``toolpath[3].t_end_s``), or a value is not serialisable.
    """
    if isinstance(d, dict):
        try:
            return "".join(_items_text(list(d.items()), lazy=False))
        except Unsupported:
            pass
    return _dumps_std(d)


def _dumps_std(d: Mapping[str, Any]) -> str:
    """:func:`dumps_plan` by the standard library (the reference the fast writer reproduces)."""
    where = _find_non_finite(d, "")
    if where is not None:
        raise PlanJsonError(f"non-finite number in plan JSON at {where}")
    try:
        return json.dumps(d, indent=1, allow_nan=False, ensure_ascii=False, default=_default) + "\n"
    except (TypeError, ValueError) as exc:
        raise PlanJsonError(f"plan JSON cannot be written: {exc}") from exc


def write_plan_json(path: str | os.PathLike[str], d: Mapping[str, Any]) -> Path:
    """Serialise with :func:`dumps_plan` and write atomically (OutputError on I/O failure)."""
    return write_text_atomic(path, dumps_plan(d))
