"""The JSON Schema of the plan JSON (``trcopt.plan/1``) and a validator for plan documents.

The schema (draft 2020-12) ships beside this module as ``plan.schema.json``; it is the
machine-readable form of the contract described in ``docs/plan-json.md``. :func:`plan_schema`
loads it with :mod:`importlib.resources` (json only); :func:`validate_plan` checks a document
against it and imports ``jsonschema`` only when called, so ``import trcopt`` never needs it.

JSON has no NaN or Infinity, but :func:`json.loads` accepts them and a JSON Schema ``number``
does not exclude them, so :func:`validate_plan` also rejects non-finite numbers explicitly (the
writer, :func:`trcopt.io.plan_json.dumps_plan`, never produces them).
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterator, Mapping
from importlib import resources
from typing import Any

from trcopt.codes import Code

from ..errors import TrcoptError

__all__ = ["SCHEMA_RESOURCE", "plan_schema", "validate_plan"]

SCHEMA_RESOURCE = "plan.schema.json"
_MAX_REPORTED = 5  # schema errors listed in the message (the rest are counted)


def plan_schema() -> dict[str, Any]:
    """The plan JSON Schema as a fresh dictionary (``$id`` ``"trcopt.plan/1"``)."""
    text = resources.files(__package__).joinpath(SCHEMA_RESOURCE).read_text(encoding="utf-8")
    schema: dict[str, Any] = json.loads(text)
    return schema


def _non_finite(obj: Any, where: str) -> Iterator[str]:
    if isinstance(obj, float):
        if not math.isfinite(obj):
            yield where or "(document)"
    elif isinstance(obj, Mapping):
        for key, value in obj.items():
            yield from _non_finite(value, f"{where}.{key}" if where else str(key))
    elif isinstance(obj, (list, tuple)):
        for i, value in enumerate(obj):
            yield from _non_finite(value, f"{where}[{i}]")


def _path(parts: Any) -> str:
    out = ""
    for p in parts:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out or "(document)"


def _short(message: str, limit: int = 200) -> str:
    """A schema error message cut to ``limit`` characters (some quote whole sub-documents)."""
    return message if len(message) <= limit else message[: limit - 1] + "…"


def validate_plan(doc: Any) -> None:
    """Check a plan document (the parsed JSON, or ``PlanResult.to_json()``) against the schema.

    Parameters
    ----------
    doc:
        The document as Python objects (dicts, lists, str, int, float, bool, None).

    Raises
    ------
    TrcoptError
        Code ``"SCHEMA"``: the document does not conform. The message names the location and
        the reason of the first few violations (``toolpath[3].kind: 'spline' is not one of …``).
        Also raised (code ``"SCHEMA"``) when the optional ``jsonschema`` package is missing.
    """
    try:
        import jsonschema
    except ImportError:  # pragma: no cover - jsonschema is a test dependency
        raise TrcoptError(
            "validating a plan needs the 'jsonschema' package (pip install jsonschema)", code=Code.SCHEMA
        ) from None
    bad = list(_non_finite(doc, ""))
    if bad:
        raise TrcoptError(
            f"plan JSON is invalid: non-finite number at {', '.join(bad[:_MAX_REPORTED])}", code=Code.SCHEMA
        )
    schema = plan_schema()
    cls = jsonschema.validators.validator_for(schema)
    validator = cls(schema)
    # a oneOf (value or null) reports its failing branch best: descend into its context
    errors = [jsonschema.exceptions.best_match([e]) or e for e in validator.iter_errors(doc)]
    errors.sort(key=lambda e: (len(e.absolute_path), list(map(str, e.absolute_path))))
    if not errors:
        return
    lines = [f"{_path(e.absolute_path)}: {_short(e.message)}" for e in errors[:_MAX_REPORTED]]
    more = len(errors) - len(lines)
    if more > 0:
        lines.append(f"… and {more} more")
    raise TrcoptError("plan JSON does not conform to trcopt.plan/1: " + "; ".join(lines), code=Code.SCHEMA)
