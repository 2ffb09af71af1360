"""An independent re-reader of the tool-centre G-code :mod:`trcopt.io.gcode` writes: every arc
block checked the way a controller checks it (start and end radius about the written centre)."""

from __future__ import annotations

import math
import re

__all__ = ["check_gcode_arcs"]

_CENTRE_WORDS = ("I", "J", "K")  # centre word of x, y, z


_WORD = re.compile(r"([A-Z])\s*([-+]?(?:\d+\.?\d*|\.\d+))")
_PLANE_AXES = {"G17": (0, 1), "G18": (2, 0), "G19": (1, 2)}


def _strip_comment(line: str) -> str:
    line = re.sub(r"\([^)]*\)", " ", line)
    return line.split(";", 1)[0]


def check_gcode_arcs(text: str, tolerance_mm: float = 0.002) -> list[str]:
    """Re-read G-code and report arcs whose start and end radius differ by more than a tolerance.

    Reads the subset this module writes: absolute coordinates, G0/G1/G2/G3, G17/G18/G19, centre
    words I/J/K incremental from the start, ``;`` and ``( )`` comments, N numbers. Returns one
    message per bad arc (``line 12: G2 radius 10.0021 at start, 10.0000 at end (diff 0.0021 mm)``);
    an arc whose start equals its end, or whose centre equals its start, is reported too.
    """
    pos: list[float | None] = [None, None, None]
    plane = "G17"
    motion: str | None = None
    problems: list[str] = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        body = _strip_comment(raw).upper()
        words = _WORD.findall(body)
        if not words:
            continue
        gs = [float(v) for k, v in words if k == "G"]
        for gv in gs:
            name = f"G{gv:g}"
            if name in _PLANE_AXES:
                plane = name
            elif name in ("G0", "G1", "G2", "G3"):
                motion = name
        values = {k: float(v) for k, v in words if k in "XYZIJK"}
        has_axes = any(k in values for k in "XYZ")
        if not has_axes:
            continue
        start = list(pos)
        end = [values.get(n, pos[i]) for i, n in enumerate("XYZ")]
        if motion in ("G2", "G3"):
            a, b = _PLANE_AXES[plane]
            if start[a] is None or start[b] is None:
                problems.append(f"line {lineno}: {motion} from an unknown position")
            else:
                sa, sb = float(start[a]), float(start[b])  # type: ignore[arg-type]
                ea, eb = float(end[a]), float(end[b])  # type: ignore[arg-type]
                ca = sa + values.get(_CENTRE_WORDS[a], 0.0)
                cb = sb + values.get(_CENTRE_WORDS[b], 0.0)
                r0 = math.hypot(sa - ca, sb - cb)
                r1 = math.hypot(ea - ca, eb - cb)
                if abs(r0 - r1) > tolerance_mm:
                    problems.append(
                        f"line {lineno}: {motion} radius {r0:.6f} at start, {r1:.6f} at end "
                        f"(diff {abs(r0 - r1):.6f} mm)"
                    )
                elif r0 == 0.0:
                    problems.append(f"line {lineno}: {motion} with zero radius")
                elif sa == ea and sb == eb:
                    problems.append(f"line {lineno}: {motion} start equals end (full circle)")
        pos = end
    return problems
