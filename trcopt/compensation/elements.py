"""Compensated elements and the pieces of their tool-centre chains.

An :class:`Elem` is one plane-moving block inside a compensation region (the selection block,
the contour blocks and the deselection block) with its programmed geometry and the offset
geometries used for the junction with the previous (``off_start``, radius at the block start) and
the next block (``off_end``, radius at the block end) — spec R9. A :class:`Piece` is a part of the
tool-centre chain of a block: the block's own offset (``main``) or an element inserted before or
after it (transition circle, DISC conic, KONT bypass circle, approach polynomial).
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field

from trcopt.errors import SourceSpan
from trcopt.geometry import vec
from trcopt.geometry.intersect import Hit, intersections
from trcopt.geometry.plane import Plane
from trcopt.geometry.poly import Poly, spiral_curve
from trcopt.geometry.primitives import Arc, Line
from trcopt.geometry.vec import Vec2
from trcopt.nc.model import CompState, Move, MoveKind
from trcopt.path import Geometry, Role

__all__ = ["ElemKind", "Elem", "Piece", "make_programmed_geometry", "MIN_OFFSET_RADIUS_MM"]

LAM_TOL = 1e-9
# an offset circle at most this large (mm) is a point: the inside arc has the tool's radius (to
# rounding); treated as degenerate like a negative one, it never becomes a carrier of curvature 1/r
MIN_OFFSET_RADIUS_MM = 1e-9


class ElemKind(enum.Enum):
    APPROACH = "approach"
    CONTOUR = "contour"
    RETRACT = "retract"


def make_programmed_geometry(move: Move) -> Line | Arc:
    """The programmed element of a move in plane coordinates (u, v, w)."""
    plane = move.plane
    if plane is Plane.G17:
        start, end = move.start, move.end
    else:
        start, end = plane.to_uvw(move.start), plane.to_uvw(move.end)
    if move.kind is MoveKind.ARC and move.center is not None:
        c = plane.to_uvw(move.center)
        arc = Arc.from_points(start, end, (c[0], c[1]), bool(move.ccw))
        if move.turns:
            extra = 2.0 * math.pi * move.turns * (1 if arc.sweep > 0 else -1)
            arc = Arc(arc.center, arc.radius, arc.a0, arc.sweep + extra, arc.w0, arc.w1)
        return arc
    return Line(start, end)


@dataclass(slots=True)
class Elem:
    """A plane-moving block of a compensation region."""

    index: int
    kind: ElemKind
    move: Move
    prog: Line | Arc
    side: int  # +1 left (G41), −1 right (G42)
    r0: float  # compensation radius at the block start (mm, ≥ 0)
    r1: float  # ... at the block end
    dummies: list[Move] = field(default_factory=list)
    off_start: Line | Arc = field(init=False)  # offset with the radius at the block start
    off_end: Line | Arc = field(init=False)  # offset with the radius at the block end
    t_start: Vec2 = field(init=False)  # unit plane tangents of the programmed element
    t_end: Vec2 = field(init=False)

    def __post_init__(self) -> None:
        prog = self.prog
        self.off_start = prog.offset(self.side * self.r0)
        self.off_end = self.off_start if self.r1 == self.r0 else prog.offset(self.side * self.r1)
        if isinstance(prog, Line):
            self.t_start = self.t_end = prog.direction2()
        else:
            self.t_start, self.t_end = prog.start_tangent(), prog.end_tangent()

    @property
    def span(self) -> SourceSpan:
        return self.move.span

    @property
    def comp(self) -> CompState:
        return self.move.comp

    @property
    def plane(self) -> Plane:
        return self.move.plane

    @property
    def variable(self) -> bool:
        return self.r0 != self.r1

    @property
    def degenerate(self) -> bool:
        """Offset circle with radius ≤ 0 (inside arc smaller than the tool, R30), or so small
        (≤ :data:`MIN_OFFSET_RADIUS_MM`) that it is a point: an inside arc of the tool's radius."""
        off_start, off_end = self.off_start, self.off_end
        if not (isinstance(off_start, Arc) and isinstance(off_end, Arc)):  # the offsets of a line
            return False
        return min(off_start.radius, off_end.radius) <= MIN_OFFSET_RADIUS_MM

    @property
    def feed(self) -> float | None:
        return self.move.feed_mm_s

    @property
    def role(self) -> Role:
        if self.move.origin == "approach":
            return Role.APPROACH
        if self.move.origin == "retract":
            return Role.RETRACT
        if self.kind is ElemKind.APPROACH:
            return Role.APPROACH
        if self.kind is ElemKind.RETRACT:
            return Role.RETRACT
        return Role.CONTOUR

    def start_tangent(self) -> Vec2:
        return self.t_start

    def end_tangent(self) -> Vec2:
        return self.t_end


@dataclass(slots=True)
class Piece:
    """A part of a block's tool-centre chain, addressed by the parameter range [lam0, lam1].

    ``main`` pieces use the block's offsets as carriers; inserted pieces carry their own.
    ``p0``/``p1`` override the end points (a fixed uncompensated start, the NORM point S).
    """

    elem: Elem
    role: Role
    lam0: float
    lam1: float
    main: bool = True
    carrier: Geometry | None = None  # inserted pieces only
    p0: Vec2 | None = None
    p1: Vec2 | None = None

    def end_carrier(self) -> Geometry:
        if self.main:
            return self.elem.off_end
        assert self.carrier is not None  # an inserted piece always carries its own element
        return self.carrier

    def start_carrier(self) -> Geometry:
        if self.main:
            return self.elem.off_start
        assert self.carrier is not None
        return self.carrier

    def start_point(self) -> Vec2:
        if self.p0 is not None:
            return self.p0
        carrier = self.start_carrier()
        if self.lam0 == 0.0 and not isinstance(carrier, Poly):
            p = carrier.start
            return (p[0], p[1])
        return _point2(carrier, self.lam0)

    def end_point(self) -> Vec2:
        if self.p1 is not None:
            return self.p1
        carrier = self.end_carrier()
        if self.lam1 == 1.0 and isinstance(carrier, Line):
            p = carrier.end
            return (p[0], p[1])
        return _point2(carrier, self.lam1)

    def hits(self, other: Geometry, use_end: bool = True, lo: float | None = None) -> list[Hit]:
        """Intersections with ``other`` that lie on this piece (λ within its range)."""
        carrier = self.end_carrier() if use_end else self.start_carrier()
        a, b = (self.lam0 if lo is None else lo), self.lam1
        lo_, hi_ = min(a, b), max(a, b)
        return [h for h in intersections(carrier, other, 1e-9) if lo_ - LAM_TOL <= h.lam_a <= hi_ + LAM_TOL]

    def plane_length(self) -> float:
        g = self.geometry(0.0, 0.0)
        return g.plane_length

    def geometry(self, w0: float, w1: float) -> Geometry:
        """The traversed element with the applicate running from w0 to w1."""
        if not self.main:
            assert self.carrier is not None
            c = self.carrier
            if isinstance(c, Poly):
                total = c.length
                if self.lam0 <= 0.0 and self.lam1 >= 1.0:
                    sub = c
                else:
                    sub = c.sub_s(self.lam0 * total, self.lam1 * total)
                last = max(1, len(sub.points) - 1)
                pts = tuple((p[0], p[1], w0 + (w1 - w0) * (k / last)) for k, p in enumerate(sub.points))
                return Poly(pts, sub.tangents, sub.cum, sub.label)
            return c.sub(self.lam0, self.lam1, w0, w1)
        prog = self.elem.prog
        p0, p1 = self.start_point(), self.end_point()
        if isinstance(prog, Line):
            return Line((p0[0], p0[1], w0), (p1[0], p1[1], w1))
        if not self.elem.variable and self.p0 is None and self.p1 is None:
            return self.elem.off_end.sub(self.lam0, self.lam1, w0, w1)
        center = prog.center
        r_a, r_b = vec.dist(p0, center), vec.dist(p1, center)
        a0 = math.atan2(p0[1] - center[1], p0[0] - center[0])
        sweep = (self.lam1 - self.lam0) * prog.sweep
        if abs(r_a - r_b) <= 1e-12:
            return Arc(center, r_a, a0, sweep, w0, w1)
        return spiral_curve(center, r_a, r_b, a0, sweep, w0, w1)


def _point2(g: Geometry, lam: float) -> Vec2:
    if isinstance(g, Poly):
        return g.point2(min(max(lam, 0.0), 1.0))
    return g.point2(lam)
