"""Klartext contour elements at contour level (spec ``heidenhain_trc.md`` §5, §6.4) in plane (u, v, w).

* :class:`Elem` — one traversed element (line or arc) before compensation, with its modal data;
* arc constructions: ``C`` about the pole, ``CR`` by radius, ``CT`` tangential;
* corner modifiers ``RND`` (fillet) and ``CHF`` (chamfer), resolved when the element after the
  corner is known;
* :func:`radius_too_large` — the control's "tool radius too large" check of a compensated region
  (arc offsets ≤ 0, offsets reversed between their inside-corner intersections, a small step after
  an outside corner without M97).

Errors are :class:`ContourError` with the spec's code; the reader turns them into diagnostics.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from trcopt.codes import Code
from trcopt.errors import SourceSpan
from trcopt.geometry import vec
from trcopt.geometry.intersect import intersections
from trcopt.geometry.primitives import Arc, Line
from trcopt.geometry.vec import Vec2, Vec3
from trcopt.modes import Side
from trcopt.nc.model import MoveKind

__all__ = [
    "ContourError",
    "Elem",
    "circle_about",
    "circle_by_radius",
    "circle_tangential",
    "apply_rnd",
    "apply_chf",
    "radius_too_large",
    "RegionCheck",
    "TOOL_RADIUS_TOO_LARGE",
]

TOOL_RADIUS_TOO_LARGE = "Tool radius too large"  # the Heidenhain message text [M H7]
_EPS = 1e-9


class ContourError(ValueError):
    def __init__(self, code: Code, message: str) -> None:
        super().__init__(message)
        self.code = code
        self.message = message


@dataclass(slots=True)
class Elem:
    """A traversed element in plane coordinates (mutable while RND/CHF trim it)."""

    kind: MoveKind
    start: Vec3
    end: Vec3
    span: SourceSpan
    side: Side = Side.OFF
    radius: float = 0.0  # compensation value in force
    feed: float | None = None
    center: Vec2 | None = None
    ccw: bool | None = None
    turns: int = 0
    actions: tuple[str, ...] = ()
    origin: str = ""
    m97: bool = False
    side_programmed: bool = False
    tool_active: bool = True
    extra: dict[str, object] = field(default_factory=dict)

    def geometry(self) -> Line | Arc:
        if self.kind is MoveKind.ARC:
            assert self.center is not None
            arc = Arc.from_points(self.start, self.end, self.center, bool(self.ccw))
            if self.turns:
                arc = Arc(
                    arc.center,
                    arc.radius,
                    arc.a0,
                    arc.sweep + math.copysign(2 * math.pi * self.turns, arc.sweep),
                    arc.w0,
                    arc.w1,
                )
            return arc
        return Line(self.start, self.end)

    def plane_length(self) -> float:
        return self.geometry().plane_length

    def end_tangent(self) -> Vec2:
        return self._direction(end=True)

    def start_tangent(self) -> Vec2:
        return self._direction(end=False)

    def _direction(self, end: bool) -> Vec2:
        """The unit tangent in the working plane at the end (start); an element that does not move
        in the plane has none (:class:`ContourError` ``HH-NO-DIRECTION``)."""
        g = self.geometry()
        if isinstance(g, Line) and g.plane_length <= 1e-12:
            where = f"block {self.span.block}" if self.span.block else f"line {self.span.line}"
            raise ContourError(
                Code.HH_NO_DIRECTION,
                f"the contour element of {where} does not move in the working plane: "
                "it has no direction to continue from (RND, CT, APPR and DEP need one)",
            )
        return g.end_tangent() if end else g.start_tangent()


def _uv(p: Vec3) -> Vec2:
    return (p[0], p[1])


def circle_about(s: Vec3, e: Vec3, m: Vec2, tol: float) -> float:
    """Check a ``C`` end point against the circle about the pole M through S; the radius (mm)."""
    rho = vec.dist(_uv(s), m)
    d = abs(vec.dist(_uv(e), m) - rho)
    if rho <= _EPS or d > tol:
        raise ContourError(
            Code.HH_CIRCLE_END,
            f"circle end position incorrect: end point is {vec.dist(_uv(e), m):.4f} mm from the centre, "
            f"start {rho:.4f} mm",
        )
    return rho


def circle_by_radius(s: Vec3, e: Vec3, radius: float, ccw: bool) -> Vec2:
    """Centre of a ``CR`` arc: R > 0 ⇒ sweep ≤ 180°, R < 0 ⇒ sweep > 180°; centre on the left of S→E
    when (DR+ and R > 0) or (DR− and R < 0)."""
    a, b = _uv(s), _uv(e)
    c = vec.dist(a, b)
    if c <= _EPS:
        raise ContourError(
            Code.HH_CR_CHORD, "CR: start and end point coincide (a full circle needs two CR blocks)"
        )
    if c > 2.0 * abs(radius) + 1e-9:
        raise ContourError(
            Code.HH_CR_CHORD, f"CR: chord {c:.4f} mm longer than the diameter {2 * abs(radius):.4f} mm"
        )
    h = math.sqrt(max(radius * radius - c * c / 4.0, 0.0))
    mid = vec.scale(vec.add(a, b), 0.5)
    left = vec.rot90(vec.unit(vec.sub(b, a)))
    on_left = ccw == (radius > 0)
    return vec.add(mid, vec.scale(left, h if on_left else -h))


def circle_tangential(s: Vec3, e: Vec3, t0: Vec2) -> tuple[Vec2, bool]:
    """Centre and sense of a ``CT`` arc tangent to ``t0`` at S through E."""
    a, b = _uv(s), _uv(e)
    n = vec.rot90(vec.unit(t0))
    d = vec.sub(b, a)
    h = vec.dot(d, n)
    if abs(h) <= 1e-9 * max(1.0, vec.norm(d)):
        raise ContourError(
            Code.HH_CT_NO_TANGENT, "CT: the end point lies on the tangent of the previous element"
        )
    rho = vec.dot(d, d) / (2.0 * h)
    return vec.add(a, vec.scale(n, rho)), rho > 0


def apply_rnd(a: Elem, b: Elem, radius: float, span: SourceSpan) -> Elem:
    """Fillet of radius R between a (ending at the corner) and b (starting there); trims both and
    returns the fillet arc (lines and arcs; the tangent points are found on offset carriers)."""
    if radius <= 0:
        raise ContourError(Code.HH_RND_TOO_LARGE, f"RND radius must be > 0 (got {radius:g})")
    ta, tb = a.end_tangent(), b.start_tangent()
    ga, gb = a.geometry(), b.geometry()
    k = vec.cross(ta, tb)
    if abs(k) <= 1e-12 and vec.dot(ta, tb) > 0:
        raise ContourError(Code.HH_RND_TOO_LARGE, "RND at a tangential transition (no corner to round)")
    sgn = 1.0 if k > 0 else -1.0  # fillet centre on the inner (turning) side
    corner = _uv(a.end)
    hits = [
        h
        for h in intersections(ga.offset(sgn * radius), gb.offset(sgn * radius))
        if -_EPS <= h.lam_a <= 1 + _EPS and -_EPS <= h.lam_b <= 1 + _EPS
    ]
    if not hits:
        raise ContourError(
            Code.HH_RND_TOO_LARGE, f"RND R{radius:g} does not fit between the adjacent elements"
        )
    m = min(hits, key=lambda h: vec.dist(h.point, corner)).point
    p1 = _foot(ga, m)
    p2 = _foot(gb, m)
    w = a.end[2]
    a.end = (p1[0], p1[1], w)
    b.start = (p2[0], p2[1], b.start[2])
    return Elem(MoveKind.ARC, a.end, (p2[0], p2[1], w), span, a.side, a.radius, a.feed, m, sgn > 0)


def _foot(g: Line | Arc, m: Vec2) -> Vec2:
    if isinstance(g, Line):
        return g.point2(g.param_of(m))
    return vec.add(g.center, vec.scale(vec.unit(vec.sub(m, g.center)), g.radius))


def apply_chf(a: Elem, b: Elem, length: float, span: SourceSpan) -> Elem:
    """Chamfer with side length c on both lines: from P − c·t1 to P + c·t2; trims a and b."""
    if a.kind is MoveKind.ARC or b.kind is MoveKind.ARC:
        raise ContourError(Code.HH_CHF_NOT_LINES, "CHF only between two straight lines")
    if length <= 0:
        raise ContourError(Code.HH_CHF_TOO_LARGE, f"CHF length must be > 0 (got {length:g})")
    la, lb = a.plane_length(), b.plane_length()
    if length > la + 1e-9 or length > lb + 1e-9:
        raise ContourError(
            Code.HH_CHF_TOO_LARGE, f"CHF {length:g} longer than an adjacent line ({min(la, lb):.4f} mm)"
        )
    ta, tb = a.end_tangent(), b.start_tangent()
    p = _uv(a.end)
    p1, p2 = vec.sub(p, vec.scale(ta, length)), vec.add(p, vec.scale(tb, length))
    w = a.end[2]
    a.end = (p1[0], p1[1], w)
    b.start = (p2[0], p2[1], b.start[2])
    return Elem(MoveKind.LINE, a.end, b.start, span, a.side, a.radius, a.feed)


def radius_too_large(region: list[Elem]) -> tuple[int, str] | None:
    """First element of a compensated region whose tool-centre path cannot exist.

    ``region`` are the compensated elements after the selection line (contour and lead arcs), in
    order; returns (index, detail) or None. Outside corners get the transition arc (λ unchanged),
    M97 in the block ending at an outside corner and every inside corner use the intersection of
    the two offsets nearest the corner (spec §6.4). :class:`RegionCheck` one element at a time.
    """
    check = RegionCheck()
    for k, e in enumerate(region):
        check.add(e, k)
        if check.arc is not None:
            break
    check.end()
    return check.found


class RegionCheck:
    """:func:`radius_too_large` with the region's elements given one at a time (:meth:`add`, in
    order, each with its place ``at``; then :meth:`end`): the same answer as ``(at, detail)``.

    The problems are looked for in the function's order — a compensated arc whose tool-centre
    radius is not positive anywhere in the region (``arc``: the answer as soon as it is found),
    else the first joint whose offsets do not intersect (``gap``), else the first element whose
    tool-centre path runs backwards (``back``) — so that a region read block by block gives the
    answer of the whole region; :attr:`open_from` is the first place the answer can still be.
    """

    __slots__ = ("arc", "gap", "back", "_prev", "_last")

    def __init__(self) -> None:
        self.arc: tuple[int, str] | None = None
        self.gap: tuple[int, str] | None = None
        self.back: tuple[int, str] | None = None
        # the last element: it, its geometry and offset, its λ at the start (lo) and its place
        self._prev: tuple[Elem, Line | Arc, Line | Arc, float, int] | None = None
        self._last: int | None = None  # the place of the last element added

    @property
    def found(self) -> tuple[int, str] | None:
        """The answer so far: final once :meth:`end` ran, or once ``arc`` is found."""
        return self.arc or self.gap or self.back

    @property
    def open_from(self) -> int | None:
        """The first place a problem can still be found at (the last element's: the joint after
        it is not known yet; an earlier problem's, which a later one may outrank); None before
        the first element."""
        if self.arc is not None:
            return self.arc[0]
        first = self._last
        for problem in (self.gap, self.back):
            if problem is not None and (first is None or problem[0] < first):
                first = problem[0]
        return first

    def add(self, e: Elem, at: int) -> None:
        """The next element of the region, at place ``at``."""
        self._last = at
        if self.arc is not None:
            return
        g = e.geometry()
        off = g.offset(e.side.sign * e.radius)
        if isinstance(off, Arc) and off.radius <= 1e-9:
            self.arc = (at, f"tool-centre radius {off.radius:.4f} mm of the compensated arc is not positive")
            return
        lo = 0.0
        prev = self._prev
        if prev is not None and self.gap is None:
            a, ga, oa, lo_a, at_a = prev
            hi_a = 1.0
            ta, tb = ga.end_tangent(), g.start_tangent()
            gap = vec.dist(oa.point2(1.0), off.point2(0.0))
            if not (gap <= 1e-6 and vec.dot(ta, tb) > 0):
                delta = vec.deflection(ta, tb)
                outside = abs(delta) >= math.pi - 1e-12 or a.side.sign * delta < 0
                if not outside or a.m97:
                    corner = _uv(a.end)
                    hits = intersections(oa, off, 1e-9)
                    if not hits:
                        self.gap = (at, "the offsets of the adjacent elements do not intersect")
                    else:
                        h = min(hits, key=lambda h: vec.dist(h.point, corner))
                        hi_a, lo = h.lam_a, h.lam_b
            if self.gap is None and self.back is None and hi_a < lo_a - _EPS:
                self.back = (at_a, _BACKWARDS)
        self._prev = (e, g, off, lo, at)

    def end(self) -> None:
        """The region has no more elements: the last one's path ends at λ = 1."""
        prev = self._prev
        if self.found is None and prev is not None and 1.0 < prev[3] - _EPS:
            self.back = (prev[4], _BACKWARDS)
        self._prev = None


_BACKWARDS = "the tool-centre path of this element would run backwards"
