"""Tool-path segments: geometry + role + source span + feed + the compensation in force.

The geometry is stored in plane coordinates (u, v, w) of ``plane``; the ``*_xyz`` accessors and
:meth:`Segment.to_json` give absolute workpiece coordinates (design.md §3.1).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, replace
from typing import Any

from trcopt.errors import SourceSpan
from trcopt.geometry.plane import Plane
from trcopt.geometry.poly import Poly
from trcopt.geometry.primitives import Arc, Line
from trcopt.geometry.vec import Vec3
from trcopt.modes import Side
from trcopt.units import mm_s_to_mm_min

Geometry = Line | Arc | Poly

__all__ = ["Role", "Segment", "Geometry", "new_segment", "segments_length"]


class Role(enum.Enum):
    CONTOUR = "contour"
    CORNER = "corner"
    APPROACH = "approach"
    RETRACT = "retract"
    RAPID = "rapid"
    POSITIONING = "positioning"


@dataclass(frozen=True, slots=True)
class Segment:
    """One element of a path (programmed or tool-centre)."""

    geometry: Geometry
    plane: Plane
    role: Role
    span: SourceSpan
    feed_mm_s: float | None  # None = rapid traverse
    side: Side = Side.OFF
    radius: float = 0.0
    t_start_s: float | None = None
    t_end_s: float | None = None
    stop: bool = False  # exact stop at the end (the program's G60, G9, G61.1), also where tangent
    smooth_end: bool = False  # the kink at the end is rounded by the path-control mode: no stop there

    @property
    def kind(self) -> str:
        if self.feed_mm_s is None and isinstance(self.geometry, Line):
            return "rapid"
        if isinstance(self.geometry, Line):
            return "line"
        if isinstance(self.geometry, Arc):
            return "arc"
        return "poly"

    @property
    def is_rapid(self) -> bool:
        return self.feed_mm_s is None

    @property
    def start_xyz(self) -> Vec3:
        return self.plane.to_xyz(self.geometry.start)

    @property
    def end_xyz(self) -> Vec3:
        return self.plane.to_xyz(self.geometry.end)

    @property
    def center_xyz(self) -> Vec3 | None:
        g = self.geometry
        if isinstance(g, Arc):
            return self.plane.to_xyz((g.center[0], g.center[1], g.w0))
        return None

    @property
    def length(self) -> float:
        return self.geometry.length

    def with_times(self, t_start: float, t_end: float) -> Segment:
        return replace(self, t_start_s=t_start, t_end_s=t_end)

    def with_geometry(self, geometry: Geometry) -> Segment:
        return replace(self, geometry=geometry)

    def to_json(self, digits: int = 9) -> dict[str, object]:
        """The ``<segment>`` object of the plan JSON (design.md §3.1)."""

        def r(p: Vec3 | None) -> list[float] | None:
            return None if p is None else [round(c, digits) + 0.0 for c in p]

        g = self.geometry
        points = None
        if isinstance(g, Poly):
            points = [r(self.plane.to_xyz(p)) for p in g.points]
        return {
            "kind": self.kind,
            "start": r(self.start_xyz),
            "end": r(self.end_xyz),
            "center": r(self.center_xyz),
            "ccw": g.ccw if isinstance(g, Arc) else None,
            "plane": self.plane.value,
            "role": self.role.value,
            "line": self.span.line,
            "block": self.span.block,
            "side": None if self.side is Side.OFF else self.side.value,
            "radius": self.radius,
            "feed_mm_min": None if self.feed_mm_s is None else round(mm_s_to_mm_min(self.feed_mm_s), 9),
            "points": points,
            "t_start_s": self.t_start_s,
            "t_end_s": self.t_end_s,
        }


class _SegmentSlots:
    """The slots of :class:`Segment` (the same layout) without its frozen ``__setattr__``."""

    __slots__ = Segment.__slots__


def new_segment(
    geometry: Geometry,
    plane: Plane,
    role: Role,
    span: SourceSpan,
    feed_mm_s: float | None,
    side: Side = Side.OFF,
    radius: float = 0.0,
) -> Segment:
    """``Segment(...)`` (the same arguments, an equal segment, no times) at a third of the cost,
    for the loops that make a segment per block: the fields are set on a :class:`_SegmentSlots`,
    which then becomes a :class:`Segment` (the dataclass constructor sets each field through
    ``object.__setattr__``)."""
    s: Any = _SegmentSlots()
    s.geometry, s.plane, s.role, s.span, s.feed_mm_s = geometry, plane, role, span, feed_mm_s
    s.side, s.radius = side, radius
    s.t_start_s = s.t_end_s = None
    s.stop = s.smooth_end = False
    s.__class__ = Segment
    return s


def segments_length(segments: list[Segment] | tuple[Segment, ...]) -> float:
    """Total 3D path length, mm."""
    return sum([s.geometry.length for s in segments])  # a list: quicker than a generator, the same sum
