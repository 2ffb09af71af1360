"""Whether a plan made window by window (``--stream on``) agrees with the whole plan's JSON.

The JSON must be the same apart from what a window changes by construction: segment and section
times and summed lengths to rounding (1e-9 relative; 2e-9 absolute: a length or place the JSON
rounds to 9 decimals is computed from sums that start at the window, not at the program start,
and may round the other way), the sampled maxima (``max_ratios``,
``max_jerk_mm_s3``, ``max_jerk_ratio``) to the sampling (2e-3, each window sampled from its own
start), the verification's elapsed time, and the binding constraint of a section whose time splits
evenly between two constraints (at most one section, or 2 % of them).
"""

from __future__ import annotations

import math
from typing import Any

__all__ = ["disagreement"]

BINDING_TIES = 0.02


def _first(a: Any, b: Any, path: str) -> str | None:
    if isinstance(a, dict):
        if not isinstance(b, dict) or list(a) != list(b):
            return f"{path}: keys {list(a)} vs {b if not isinstance(b, dict) else list(b)}"
        for k in a:
            found = _first(a[k], b[k], f"{path}/{k}")
            if found:
                return found
        return None
    if isinstance(a, list):
        if not isinstance(b, list) or len(a) != len(b):
            return f"{path}: {len(a)} items vs {len(b) if isinstance(b, list) else b!r}"
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            found = _first(x, y, f"{path}[{i}]")
            if found:
                return found
        return None
    if isinstance(a, float) and isinstance(b, (int, float)) and not isinstance(b, bool):
        if "max_ratios" in path or "max_jerk" in path:
            close = math.isclose(a, b, rel_tol=2e-3, abs_tol=2e-3)
        else:  # sums to rounding; a value rounded to 9 decimals may round the other way (2e-9)
            close = math.isclose(a, b, rel_tol=1e-9, abs_tol=2e-9)
        return None if close else f"{path}: {a!r} vs {b!r}"
    return None if a == b else f"{path}: {a!r} vs {b!r}"


def disagreement(whole: dict[str, Any], streamed: dict[str, Any]) -> str | None:
    """Where the streamed plan JSON differs from the whole plan's beyond the above, or None.
    (Both dictionaries are changed: the elapsed time and tied bindings are aligned.)"""
    for d in (whole, streamed):
        (d.get("verification") or {}).pop("elapsed_s", None)
    ws = (whole.get("timing") or {}).get("sections") or []
    ss = (streamed.get("timing") or {}).get("sections") or []
    if len(ws) == len(ss):
        ties = sum(a.get("binding") != b.get("binding") for a, b in zip(ws, ss, strict=True))
        if ties > max(1.0, BINDING_TIES * len(ws)):
            return f"{ties} of {len(ws)} sections name another binding constraint"
        for a, b in zip(ws, ss, strict=True):
            b["binding"] = a.get("binding")
    return _first(whole, streamed, "")
