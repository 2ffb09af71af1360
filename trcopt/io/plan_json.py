"""The plan JSON (design.md §3.1): a stable contract other tools read — extend it, never break it.

``plan_json`` builds the dictionary with the contract keys in their documented order, then the
keys of ``extra`` that do not collide with them; ``dumps_plan`` serialises it (indent 1, insertion
order, and an error instead of ``NaN``/``Infinity``, which JSON does not have).
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from trcopt.codes import Code
from trcopt.errors import Diagnostic, Severity, TrcoptError
from trcopt.io.atomic import write_text_atomic
from trcopt.path import Segment

__all__ = [
    "PLAN_SCHEMA",
    "CONTRACT_KEYS",
    "PlanJsonError",
    "plan_json",
    "dumps_plan",
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
    diags = list(diagnostics)
    out: dict[str, Any] = {
        "schema": PLAN_SCHEMA,
        "program": str(program),
        "dialect": str(dialect),
        "units": "mm",
        "ok": not any(_is_error(d) for d in diags),
        "diagnostics": [_diag_json(d) for d in diags],
        "programmed": [_seg_json(s) for s in programmed],
        "toolpath": [_seg_json(s) for s in toolpath],
        "timing": None if timing is None else dict(timing),
    }
    for key, value in (extra or {}).items():
        if key not in out:
            out[key] = value
    return out


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
