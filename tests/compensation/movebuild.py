"""Build canonical moves by hand (independent of the NC front end) for engine tests."""

from __future__ import annotations

from dataclasses import replace

from trcopt.errors import SourceSpan
from trcopt.geometry.plane import Plane
from trcopt.modes import Side
from trcopt.nc.model import CompState, Move, MoveKind


def build(steps, start=(0.0, 0.0, 0.0), comp=None, feed=10.0):
    """steps: list of (kind, end, extra dict). extra may hold center, ccw, comp changes, block."""
    state = comp or CompState(tool_active=True)
    pos = start
    out = []
    for n, step in enumerate(steps, start=1):
        kind, end = step[0], step[1]
        extra = step[2] if len(step) > 2 else {}
        changes = {k: v for k, v in extra.items() if k in CompState.__slots__}
        if changes:
            state = replace(state, **changes)
        end3 = tuple(float(c) for c in (end + (pos[2],) if len(end) == 2 else end))
        mk = {
            "G0": MoveKind.RAPID, "G1": MoveKind.LINE, "G2": MoveKind.ARC, "G3": MoveKind.ARC, "NONE": MoveKind.NONE
        }[kind]
        center = extra.get("center")
        if center is not None:
            center = (float(center[0]), float(center[1]), pos[2])
        block = extra.get("block", f"N{n * 10}")
        out.append(
            Move(
                mk,
                pos,
                end3 if mk is not MoveKind.NONE else pos,
                Plane.G17,
                SourceSpan("t.mpf", n, 1, block),
                state,
                None if mk is MoveKind.RAPID else extra.get("feed", feed),
                center,
                True if kind == "G3" else (False if kind == "G2" else None),
            )
        )
        if mk is not MoveKind.NONE:
            pos = end3
    return out


LEFT, RIGHT, OFF = Side.LEFT, Side.RIGHT, Side.OFF
