"""The canonical moves SAR reads and writes (spec R36–R48).

What the SAR expansion (:mod:`trcopt.controllers.siemens.sar`) reads from the blocks around a SAR
block — the F written in a block, the plane tangent at the start of the block that defines the
approach direction and at the end of the last contour block — and the moves it writes in their
place: the straight sub-movements P0→P1→P2(→P3) and the lead contour between P3 and P4 (line,
arc or helix). Points are plane coordinates (u, v, w) in mm unless named ``_xyz``; feeds mm/s.
"""

from __future__ import annotations

import math
import re

from trcopt.compensation.leads import SarGeometry
from trcopt.errors import SourceSpan
from trcopt.geometry import vec
from trcopt.geometry.plane import Plane
from trcopt.geometry.vec import Vec2, Vec3
from trcopt.nc.model import CompState, Move, MoveKind

__all__ = ["sub_move", "lead_move", "same_point", "programmed_feed", "start_tangent", "end_tangent"]

_F_WORD = re.compile(r"^F=?\(?([-+]?(?:\d+\.?\d*|\.\d+)(?:E[-+]?\d+)?)\)?$", re.IGNORECASE)


def sub_move(
    plane: Plane,
    start: Vec3,
    end: Vec3,
    *,
    kind: MoveKind,
    span: SourceSpan,
    comp: CompState,
    feed: float | None,
    actions: tuple[str, ...],
    origin: str,
    center: Vec2 | None = None,
    ccw: bool | None = None,
) -> Move:
    """A sub-movement of a lead from ``start`` to ``end`` (plane coordinates): straight, or an arc
    about the plane point ``center`` (at the start's applicate) with sense ``ccw``."""
    return Move(
        kind=kind,
        start=plane.to_xyz(start),
        end=plane.to_xyz(end),
        plane=plane,
        span=span,
        comp=comp,
        feed_mm_s=feed,
        center=None if center is None else plane.to_xyz((center[0], center[1], start[2])),
        ccw=ccw,
        actions=actions,
        plane_programmed=True,
        origin=origin,
    )


def lead_move(
    geo: SarGeometry,
    plane: Plane,
    *,
    start: Vec3,
    end: Vec3,
    span: SourceSpan,
    comp: CompState,
    feed: float | None,
    actions: tuple[str, ...],
    origin: str,
) -> Move:
    """The lead contour between P3 and P4: a (slanted) line, or an arc / helix."""
    if geo.center is None:
        kind, ccw = (MoveKind.LINE if feed is not None else MoveKind.RAPID), None
    else:
        kind, ccw = MoveKind.ARC, geo.ccw
    return sub_move(
        plane,
        start,
        end,
        kind=kind,
        span=span,
        comp=comp,
        feed=feed,
        actions=actions,
        origin=origin,
        center=geo.center,
        ccw=ccw,
    )


def same_point(a: Vec3, b: Vec3, tol: float) -> bool:
    """Whether two points are within ``tol`` (mm) of each other."""
    return math.dist(a, b) <= tol


def programmed_feed(m: Move) -> float | None:
    """The F written in this block, mm/s (G0 blocks keep it only in ``actions``, in mm/min)."""
    for a in m.actions:
        match = _F_WORD.match(a.replace(" ", ""))
        if match:
            if m.feed_mm_s is not None:
                return m.feed_mm_s
            return float(match.group(1)) / 60.0
    return None


def start_tangent(m: Move, plane: Plane) -> Vec2 | None:
    """Unit plane tangent at the start of a move (projected onto the plane); None without one."""
    if m.kind is MoveKind.ARC and m.center is not None:
        return _arc_tangent(m, m.start, plane)
    a, b = plane.to_uvw(m.start), plane.to_uvw(m.end)
    d = (b[0] - a[0], b[1] - a[1])
    return None if vec.norm(d) <= 1e-12 else vec.unit(d)


def end_tangent(m: Move, plane: Plane) -> Vec2 | None:
    """Unit plane tangent at the end of a move; None without one."""
    if m.kind is MoveKind.ARC and m.center is not None:
        return _arc_tangent(m, m.end, plane)
    return start_tangent(m, plane)


def _arc_tangent(m: Move, point: Vec3, plane: Plane) -> Vec2 | None:
    assert m.center is not None
    c = plane.to_uvw(m.center)
    p = plane.to_uvw(point)
    radial = (p[0] - c[0], p[1] - c[1])
    if vec.norm(radial) <= 1e-12:
        return None
    tangent = vec.rot90(vec.unit(radial))
    return tangent if m.ccw else vec.scale(tangent, -1.0)
