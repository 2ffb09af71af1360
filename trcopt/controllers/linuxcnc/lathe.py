"""LinuxCNC lathe tools under cutter radius compensation.

A lathe tool of orientation 1–8 (tool table ``Q``, or ``G41.1/G42.1 … L``; only in G18) is
programmed by its imaginary tool tip, not by the centre of its nose radius. LinuxCNC compensates
the nose centre as for a mill tool and moves every compensated move by the radius from the centre
towards the tip when it leaves the queue of moves waiting for their corner (``latheorigin_x`` /
``latheorigin_z`` of its interpreter): X by −r for orientations 1, 2, 6 and +r for 3, 4, 8; Z by
−r for 2, 3, 7 and +r for 1, 4, 5. Orientations 0 and 9 (and a radius of 0) move nothing. The
entry move starts where the tool is (the tip), so only its end is moved; an entry arc is preceded
by a straight move from there to the moved start of the arc. The move after G40 starts at the
moved end of the last compensated move.
"""

from __future__ import annotations

from dataclasses import replace

from trcopt.geometry.plane import Plane
from trcopt.geometry.primitives import Arc, Line
from trcopt.geometry.vec import Vec3
from trcopt.modes import Side
from trcopt.nc.model import Move
from trcopt.path import Role, Segment

__all__ = ["tip_shift", "moved", "nose_centres"]


def tip_shift(orientation: int, radius: float, plane: Plane) -> Vec3 | None:
    """The move from the compensated nose centre to the tool tip, in ``plane``'s (u, v, w);
    None where there is none."""
    dx = -radius if orientation in (1, 2, 6) else radius if orientation in (3, 4, 8) else 0.0
    dz = -radius if orientation in (2, 3, 7) else radius if orientation in (1, 4, 5) else 0.0
    if dx == 0.0 and dz == 0.0:
        return None
    return plane.to_uvw((dx, 0.0, dz))


def moved(p: Vec3, d: Vec3) -> Vec3:
    return (p[0] + d[0], p[1] + d[1], p[2] + d[2])


def nose_centres(toolpath: list[Segment], moves: list[Move]) -> list[Segment]:
    """The path of the nose centre where the tool path is a lathe tool's tip (what the
    verification measures against the programmed contour: the centre is r from it): every
    compensated segment of a block with a lathe tool moved back by its shift — an entry line only
    at its end (it starts where the tool was), the straight move before an entry arc dropped (it
    only goes to the shifted start) — and the move after them from the centre. The tool path
    itself where no block has a lathe tool."""
    lathe = {(m.span.file, m.span.line): m.comp.orientation for m in moves if m.comp.orientation not in (0, 9)}
    if not lathe:
        return toolpath
    out: list[Segment] = []
    last: Vec3 | None = None  # the shift of the segment before
    for seg in toolpath:
        orientation = lathe.get((seg.span.file, seg.span.line), 0)
        d = tip_shift(orientation, seg.radius, seg.plane) if seg.side is not Side.OFF else None
        g = seg.geometry
        if d is None:
            if last is not None and isinstance(g, Line):
                seg = seg.with_geometry(Line(moved(g.start, _minus(last)), g.end))
            out.append(seg)
            last = None
            continue
        back = _minus(d)
        if isinstance(g, Arc):
            out.append(seg.with_geometry(replace(g, center=(g.center[0] + back[0], g.center[1] + back[1]))))
        elif isinstance(g, Line):
            start = g.start if seg.role is Role.APPROACH else moved(g.start, back)
            end = moved(g.end, back)
            if start != end:
                out.append(seg.with_geometry(Line(start, end)))
        else:
            out.append(seg)
        last = d
    return out


def _minus(d: Vec3) -> Vec3:
    return (-d[0], -d[1], -d[2])
