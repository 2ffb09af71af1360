"""Immutable path elements in plane coordinates (u, v, w): Line, Arc (helix when w changes), Poly.

Conventions (stated once, used everywhere): a positive offset distance moves an element to the
**left** of its direction of travel (G41/RL); an arc carries a signed sweep, counter-clockwise
positive seen from +w; the applicate w varies linearly along an element (a helix is an arc whose w
changes). Every element is parameterised by ``lam`` in [0, 1] from start to end; ``lam`` outside
[0, 1] addresses the element's extension (lines along their tangent, arcs along their circle).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

from trcopt.geometry import vec
from trcopt.geometry.vec import TWO_PI, Vec2, Vec3

__all__ = ["Element", "Line", "Arc", "Vec2", "Vec3"]


@runtime_checkable
class Element(Protocol):
    """What every path element offers (lines, arcs/helices and polynomial curves)."""

    @property
    def start(self) -> Vec3: ...
    @property
    def end(self) -> Vec3: ...
    @property
    def length(self) -> float: ...
    @property
    def plane_length(self) -> float: ...
    def start_tangent(self) -> Vec2: ...
    def end_tangent(self) -> Vec2: ...
    def point2(self, lam: float) -> Vec2: ...
    def point(self, s: float) -> Vec3: ...
    def derivatives(self, s: float) -> tuple[Vec3, Vec3, Vec3]: ...
    def reversed(self) -> Element: ...


def _lerp(a: float, b: float, t: float) -> float:
    return a + (b - a) * t


@dataclass(frozen=True, slots=True, init=False)
class Line:
    """Straight segment from ``start`` to ``end`` (u, v, w), mm.

    A frozen dataclass made by ``__new__`` (see :class:`_LineSlots`): a line is made for nearly
    every block of a program, and the dataclass constructor, which sets each field through
    ``object.__setattr__``, costs three times as much.
    """

    start: Vec3
    end: Vec3

    def __new__(cls, start: Vec3 = (0.0, 0.0, 0.0), end: Vec3 = (0.0, 0.0, 0.0)) -> Line:
        # the defaults serve unpickling and copying, which make the object before setting its state
        line = _LineSlots()
        line.start, line.end = start, end
        line.__class__ = cls  # type: ignore[assignment]
        return line  # type: ignore[return-value]

    @property
    def plane_length(self) -> float:
        return math.hypot(self.end[0] - self.start[0], self.end[1] - self.start[1])

    @property
    def length(self) -> float:
        return math.dist(self.start, self.end)

    @property
    def start2(self) -> Vec2:
        return (self.start[0], self.start[1])

    @property
    def end2(self) -> Vec2:
        return (self.end[0], self.end[1])

    def direction2(self) -> Vec2:
        # vec.unit(vec.sub(end2, start2)), inlined (the same floats)
        du, dv = self.end[0] - self.start[0], self.end[1] - self.start[1]
        n = math.hypot(du, dv)
        if n == 0.0:
            raise ZeroDivisionError("unit vector of a zero vector")
        return (du / n, dv / n)

    def start_tangent(self) -> Vec2:
        return self.direction2()

    def end_tangent(self) -> Vec2:
        return self.direction2()

    def point2(self, lam: float) -> Vec2:
        return (
            _lerp(self.start[0], self.end[0], lam),
            _lerp(self.start[1], self.end[1], lam),
        )

    def param_of(self, p: Vec2) -> float:
        """Parameter of the projection of ``p`` on the carrier line."""
        d = vec.sub(self.end2, self.start2)
        return vec.dot(vec.sub(p, self.start2), d) / vec.dot(d, d)

    def point(self, s: float) -> Vec3:
        """Point at 3D arc length ``s`` (mm) from the start."""
        length = self.length
        t = s / length if length > 0 else 0.0
        return (
            _lerp(self.start[0], self.end[0], t),
            _lerp(self.start[1], self.end[1], t),
            _lerp(self.start[2], self.end[2], t),
        )

    def derivatives(self, s: float) -> tuple[Vec3, Vec3, Vec3]:
        """Point, first and second derivative with respect to 3D arc length."""
        length = self.length
        d = tuple((e - b) / length for b, e in zip(self.start, self.end, strict=True))
        return self.point(s), (d[0], d[1], d[2]), (0.0, 0.0, 0.0)

    def offset(self, distance: float) -> Line:
        """Parallel line at ``distance`` to the left (negative: right)."""
        n = vec.scale(vec.rot90(self.direction2()), distance)
        return Line(
            (self.start[0] + n[0], self.start[1] + n[1], self.start[2]),
            (self.end[0] + n[0], self.end[1] + n[1], self.end[2]),
        )

    def sub(self, lam0: float, lam1: float, w0: float | None = None, w1: float | None = None) -> Line:
        """The piece between two parameters (extensions allowed); w interpolated unless given."""
        p0, p1 = self.point2(lam0), self.point2(lam1)
        w_start = _lerp(self.start[2], self.end[2], lam0) if w0 is None else w0
        w_end = _lerp(self.start[2], self.end[2], lam1) if w1 is None else w1
        return Line((p0[0], p0[1], w_start), (p1[0], p1[1], w_end))

    def with_w(self, w0: float, w1: float) -> Line:
        return Line((self.start[0], self.start[1], w0), (self.end[0], self.end[1], w1))

    def reversed(self) -> Line:
        return Line(self.end, self.start)

    def distance2(self, p: Vec2) -> float:
        """Plane distance from ``p`` to the bounded segment."""
        d = vec.sub(self.end2, self.start2)
        dd = vec.dot(d, d)
        t = 0.0 if dd == 0.0 else max(0.0, min(1.0, vec.dot(vec.sub(p, self.start2), d) / dd))
        return vec.dist(p, self.point2(t))

    def curvature2(self, lam: float) -> float:
        return 0.0


class _LineSlots:
    """The slots of :class:`Line` (the same layout) without its frozen ``__setattr__``: a line
    is filled in as one of these, then becomes a :class:`Line`."""

    __slots__ = Line.__slots__
    start: Vec3
    end: Vec3


@dataclass(frozen=True, slots=True)
class Arc:
    """Circular arc (helix when ``w0 != w1``) in the (u, v) plane.

    Parameters
    ----------
    center:
        Centre (u, v), mm.
    radius:
        Radius, mm (> 0).
    a0:
        Start angle, rad.
    sweep:
        Signed sweep, rad; positive = counter-clockwise (G3), negative = clockwise (G2).
    w0, w1:
        Applicate at start and end, mm.
    """

    center: Vec2
    radius: float
    a0: float
    sweep: float
    w0: float = 0.0
    w1: float = 0.0

    @classmethod
    def from_points(
        cls, start: Vec3, end: Vec3, center: Vec2, ccw: bool, full_if_closed: bool = True
    ) -> Arc:
        """Arc from start to end around ``center``; radius from the start point.

        A closed arc (start == end) is a full circle when ``full_if_closed``.
        """
        a0 = math.atan2(start[1] - center[1], start[0] - center[0])
        a1 = math.atan2(end[1] - center[1], end[0] - center[0])
        radius = math.hypot(start[0] - center[0], start[1] - center[1])
        if ccw:
            sweep = vec.wrap_positive(a1 - a0)
            if full_if_closed and sweep * radius < 1e-9:
                sweep = TWO_PI
        else:
            sweep = -vec.wrap_positive(a0 - a1)
            if full_if_closed and -sweep * radius < 1e-9:
                sweep = -TWO_PI
        return cls(center, radius, a0, sweep, start[2], end[2])

    @property
    def ccw(self) -> bool:
        return self.sweep > 0.0

    @property
    def sense(self) -> int:
        """+1 for counter-clockwise (G3), −1 for clockwise (G2)."""
        return 1 if self.sweep > 0.0 else -1

    @property
    def a1(self) -> float:
        return self.a0 + self.sweep

    @property
    def start(self) -> Vec3:
        p = vec.polar(self.center, self.radius, self.a0)
        return (p[0], p[1], self.w0)

    @property
    def end(self) -> Vec3:
        p = vec.polar(self.center, self.radius, self.a0 + self.sweep)
        return (p[0], p[1], self.w1)

    @property
    def plane_length(self) -> float:
        return abs(self.sweep) * self.radius

    @property
    def length(self) -> float:
        return math.hypot(self.plane_length, self.w1 - self.w0)

    def point2(self, lam: float) -> Vec2:
        return vec.polar(self.center, self.radius, self.a0 + lam * self.sweep)

    def tangent2(self, lam: float) -> Vec2:
        a = self.a0 + lam * self.sweep
        k = 1.0 if self.sweep > 0 else -1.0
        return (-math.sin(a) * k, math.cos(a) * k)

    def start_tangent(self) -> Vec2:
        return self.tangent2(0.0)

    def end_tangent(self) -> Vec2:
        return self.tangent2(1.0)

    def param_of(self, p: Vec2) -> float:
        """Parameter of the point of the circle at the angle of ``p``.

        Angles inside the sweep give [0, 1]; the rest of the circle is split at its middle into
        the extension after the end (> 1) and before the start (< 0).
        """
        a = math.atan2(p[1] - self.center[1], p[0] - self.center[0])
        span = abs(self.sweep)
        d = vec.wrap_positive((a - self.a0) if self.sweep > 0 else (self.a0 - a))
        if span >= TWO_PI - 1e-12:
            # full circle: a point at the start is lam 0 (or 1 at the very end)
            return d / span
        if d <= span:
            return d / span
        gap = TWO_PI - span
        if d - span <= gap / 2.0:
            return d / span
        return -(TWO_PI - d) / span

    def point(self, s: float) -> Vec3:
        length = self.length
        lam = s / length if length > 0 else 0.0
        p = self.point2(lam)
        return (p[0], p[1], _lerp(self.w0, self.w1, lam))

    def derivatives(self, s: float) -> tuple[Vec3, Vec3, Vec3]:
        """Point, first and second derivative with respect to 3D arc length (closed form)."""
        length = self.length
        lam = s / length if length > 0 else 0.0
        a = self.a0 + lam * self.sweep
        da = self.sweep / length  # dangle/ds
        r = self.radius
        ca, sa = math.cos(a), math.sin(a)
        p = (self.center[0] + r * ca, self.center[1] + r * sa, _lerp(self.w0, self.w1, lam))
        d1 = (-r * sa * da, r * ca * da, (self.w1 - self.w0) / length)
        d2 = (-r * ca * da * da, -r * sa * da * da, 0.0)
        return p, d1, d2

    def offset(self, distance: float) -> Arc:
        """Concentric arc at ``distance`` to the left of travel (radius may become ≤ 0)."""
        return Arc(self.center, self.radius - self.sense * distance, self.a0, self.sweep, self.w0, self.w1)

    def sub(self, lam0: float, lam1: float, w0: float | None = None, w1: float | None = None) -> Arc:
        return Arc(
            self.center,
            self.radius,
            self.a0 + lam0 * self.sweep,
            (lam1 - lam0) * self.sweep,
            _lerp(self.w0, self.w1, lam0) if w0 is None else w0,
            _lerp(self.w0, self.w1, lam1) if w1 is None else w1,
        )

    def with_w(self, w0: float, w1: float) -> Arc:
        return Arc(self.center, self.radius, self.a0, self.sweep, w0, w1)

    def reversed(self) -> Arc:
        return Arc(self.center, self.radius, self.a0 + self.sweep, -self.sweep, self.w1, self.w0)

    def contains_angle(self, p: Vec2, tol: float = 1e-12) -> bool:
        lam = self.param_of(p)
        return -tol <= lam <= 1.0 + tol

    def distance2(self, p: Vec2) -> float:
        """Plane distance from ``p`` to the bounded arc."""
        if self.contains_angle(p):
            return abs(vec.dist(p, self.center) - self.radius)
        return min(vec.dist(p, self.point2(0.0)), vec.dist(p, self.point2(1.0)))

    def curvature2(self, lam: float) -> float:
        """Signed plane curvature (positive = turning left)."""
        return self.sense / self.radius
