"""The ``linuxcnc`` compensation profile: LinuxCNC's neighbour-only cutter radius compensation.

LinuxCNC (RS274NGC interpreter) compensates one block at a time against its predecessor only;
there is no look-ahead beyond the next block and no bottleneck detection. The rules reproduced
here (LinuxCNC user manual "Cutter Compensation", and its regression suite in
``shared/peer_cases/linuxcnc``):

* **entry** (first plane move after G41/G42/G41.1/G42.1): a line ends at the programmed end point
  plus r along the normal of the entry line (an entry line not longer than r is an error); an arc
  entry ends at its programmed end point plus r along the radius, on a circle through the current
  (uncompensated) point whose centre lies on that radius;
* then the normal corner logic between each block and the previous one. The previous block's
  end tangent is read from the tool position (the tool centre lies r to the side of the programmed
  point), the turn ``beta`` is measured towards the compensation side:

  - ``beta > 0.05 rad`` (outside corner): an arc of radius r around the programmed corner (a G0
    block gets a straight traverse to the arc's end instead — there is no rapid arc);
  - ``|beta| <= 0.05 rad``: nothing is inserted, the next element starts where the tool is;
  - a 180° reversal is an outside corner;
  - ``beta < -0.05 rad`` (inside corner): the previous element is trimmed to the intersection
    with the next offset element; if that makes a line run against its programmed direction, or
    an arc sweep further than programmed, the corner gouges — an error;
* an inside arc whose radius is not larger than r is an error;
* **exit** (first move after G40): a straight line from the last tool position to the programmed
  end point; an arc there is an error.

Errors stop the path with LinuxCNC's message text and the stable codes ``LCNC-*``. Segments carry
the roles approach (entry), contour, corner (inserted arcs and corner traverses), retract (exit)
and rapid.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import dataclass

from trcopt.config import TrcSettings
from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.geometry.plane import Plane
from trcopt.geometry.primitives import Arc, Line
from trcopt.geometry.vec import Vec2, Vec3
from trcopt.modes import Side
from trcopt.nc.model import Move, MoveKind
from trcopt.path import Role, Segment

__all__ = [
    "compensate_linuxcnc",
    "TOLERANCE_CONCAVE_CORNER",
    "MESSAGES",
]

TOLERANCE_CONCAVE_CORNER = 0.05  # rad: joins flatter than this are left untouched
ARC_SWEEP_SLACK = 0.001  # rad: a trimmed arc may sweep this much more than programmed
HALF_PI = 0.5 * math.pi
TWO_PI = 2.0 * math.pi


#: LinuxCNC's error text for each of our codes.
MESSAGES: dict[str, str] = {
    "LCNC-ENTRY-TOO-SHORT": "Length of cutter compensation entry move is not greater than the tool radius",
    "LCNC-ENTRY-ARC-TOO-SHORT": "Radius of cutter compensation entry arc is not greater than the tool radius",
    "LCNC-CONCAVE-GOUGE": "Straight feed in concave corner cannot be reached by the tool without gouging",
    "LCNC-CONCAVE-GOUGE-TRAVERSE": "Straight traverse in concave corner cannot be reached by the tool without gouging",
    "LCNC-CONCAVE-GOUGE-ARC": "Arc move in concave corner cannot be reached by the tool without gouging",
    "LCNC-ARC-LINE-GOUGE": "Arc to straight motion makes a corner the compensated tool can't fit in without gouging",
    "LCNC-ARC-ARC-GOUGE": "Arc to arc motion makes a corner the compensated tool can't fit in without gouging",
    "LCNC-ARC-SAME-CENTER": "Arc to arc motion is invalid because the arcs have the same center",
    "LCNC-ARC-TOO-SMALL": "Tool radius not less than arc radius with comp",
    "LCNC-COMP-ALREADY-ON": "Cannot turn cutter radius comp on when already on",
    "LCNC-YZ-PLANE": "Cannot use YZ plane with cutter radius comp",
    "LCNC-ARC-AFTER-G40": "The move just after exiting cutter compensation mode must be straight, not an arc",
}


class _Stop(Exception):
    def __init__(self, code: str, span: SourceSpan) -> None:
        super().__init__(MESSAGES[code])
        self.code, self.span = code, span


@dataclass(slots=True)
class _Queued:
    """A tool-centre move whose end point may still be moved by the next block (LinuxCNC's
    canon queue)."""

    start: Vec3
    end: Vec3
    move: Move
    role: Role
    center: Vec2 | None = None  # arcs
    turn: int = 0  # arcs: +1 CCW, -1 CW, |turn| > 1 adds full turns
    prog_dir: Vec2 = (0.0, 0.0)  # lines: programmed plane direction (0, 0: never reversed)
    prog_sweep: float = 0.0  # arcs: programmed sweep, rad (0: not checked)
    compensated: bool = True  # False: the exit move and moves with compensation off

    @property
    def is_arc(self) -> bool:
        return self.center is not None


def _dir(angle: float) -> Vec2:
    return (math.cos(angle), math.sin(angle))


def _at(p: Vec2, r: float, angle: float) -> Vec2:
    return (p[0] + r * math.cos(angle), p[1] + r * math.sin(angle))


def _angle(frm: Vec2, to: Vec2) -> float:
    return math.atan2(to[1] - frm[1], to[0] - frm[0])


def find_turn(start: Vec2, center: Vec2, turn: int, end: Vec2) -> float:
    """Signed sweep (rad) from ``start`` to ``end`` around ``center`` with LinuxCNC's ``turn``
    (equal start and end angles make a full circle)."""
    if turn == 0:
        return 0.0
    a = _angle(center, start)
    b = _angle(center, end)
    if turn > 0:
        if b <= a:
            b += TWO_PI
        return b - a + (turn - 1) * TWO_PI
    if a <= b:
        a += TWO_PI
    return b - a + (turn + 1) * TWO_PI


def _tool_inside_arc(side: int, turn: int) -> bool:
    return (side > 0 and turn > 0) or (side < 0 and turn < 0)


def _turn_of(m: Move) -> int:
    sign = 1 if m.ccw else -1
    return sign * (1 + int(m.turns))


class _LinuxCncCompensator:
    def __init__(
        self, settings: TrcSettings, diagnostics: list[Diagnostic], complete: bool
    ) -> None:
        self.settings = settings
        self.diags = diagnostics
        self.complete = complete
        self.on = False
        self.first = False
        self.side = 0  # +1 left, -1 right (effective)
        self.r = 0.0
        self.exit_pending = False
        self.plane = Plane.G17
        self.cur: Vec3 | None = None  # tool-centre position (plane u, v, w)
        self.prog: Vec3 | None = None  # programmed position
        self.queue: list[_Queued] = []
        self.endpoint: Vec2 = (0.0, 0.0)  # start of the first queued move

    # -- output -----------------------------------------------------------------------------
    def _segment(self, q: _Queued) -> Segment | None:
        m = q.move
        side = Side.OFF if not q.compensated else (Side.LEFT if self.side > 0 else Side.RIGHT)
        radius = self.r if side is not Side.OFF else 0.0
        if q.is_arc:
            assert q.center is not None
            c = q.center
            rad = math.hypot(q.end[0] - c[0], q.end[1] - c[1])
            sweep = find_turn(q.start[:2], c, q.turn, q.end[:2])
            if rad <= 0.0:
                geom: Line | Arc = Line(q.start, q.end)
                if geom.length <= 1e-12:
                    return None
            else:
                geom = Arc(c, rad, _angle(c, q.start[:2]), sweep, q.start[2], q.end[2])
            return Segment(geom, self.plane, q.role, m.span, m.feed_mm_s, side, radius)
        line = Line(q.start, q.end)
        if line.length <= 1e-12:
            return None
        role = q.role
        if m.feed_mm_s is None and role is Role.CONTOUR:
            role = Role.RAPID
        return Segment(line, self.plane, role, m.span, m.feed_mm_s, side, radius)

    def _flush(self) -> Iterator[Segment]:
        for q in self.queue:
            seg = self._segment(q)
            if seg is not None:
                yield seg
        self.queue.clear()

    def _move_endpoint_and_flush(self, p: Vec2, span: SourceSpan) -> Iterator[Segment]:
        """Move the end of every queued move to ``p`` (an inside corner), then emit them."""
        for k, q in enumerate(self.queue):
            if q.is_arc:
                assert q.center is not None
                if q.prog_sweep:
                    sweep = find_turn(self.endpoint, q.center, q.turn, p)
                    if abs(sweep) > abs(q.prog_sweep) + ARC_SWEEP_SLACK:
                        raise _Stop("LCNC-CONCAVE-GOUGE-ARC", span)
            else:
                new = (p[0] - self.endpoint[0], p[1] - self.endpoint[1])
                if q.prog_dir[0] * new[0] + q.prog_dir[1] * new[1] < 0.0:
                    code = (
                        "LCNC-CONCAVE-GOUGE-TRAVERSE"
                        if q.move.feed_mm_s is None
                        else "LCNC-CONCAVE-GOUGE"
                    )
                    raise _Stop(code, span)
            q.end = (p[0], p[1], q.end[2])
            if k > 0:
                q.start = (p[0], p[1], q.start[2])
        yield from self._flush()
        self.endpoint = p

    def _front(self) -> _Queued | None:
        return self.queue[0] if self.queue else None

    # -- driver -----------------------------------------------------------------------------
    def run(self, moves: Iterable[Move]) -> Iterator[Segment]:
        try:
            for m in moves:
                yield from self._block(m)
            yield from self._flush()
        except _Stop as stop:
            self.queue.clear()
            self.diags.append(Diagnostic(Severity.ERROR, stop.code, MESSAGES[stop.code], stop.span))

    def _block(self, m: Move) -> Iterator[Segment]:
        comp = m.comp
        want = comp.effective_side
        if want is not Side.OFF and (not self.on or comp.side_programmed):
            if self.on:
                raise _Stop("LCNC-COMP-ALREADY-ON", m.span)
            if m.plane is Plane.G19:
                raise _Stop("LCNC-YZ-PLANE", m.span)
            self.on, self.first = True, True
            self.side = 1 if want is Side.LEFT else -1
            self.r = comp.effective_radius
            self.plane = m.plane
            self.exit_pending = False
        elif want is Side.OFF and self.on:
            yield from self._flush()
            self.on = False
            self.exit_pending = not self.first
            self.first = False
        if self.on and m.plane is not self.plane:
            if m.plane is Plane.G19:
                raise _Stop("LCNC-YZ-PLANE", m.span)
            self.plane = m.plane
        if m.kind is MoveKind.NONE:
            return
        plane = m.plane
        start, end = plane.to_uvw(m.start), plane.to_uvw(m.end)
        if self.cur is None or not self.on:
            self.plane = plane
        if self.cur is None:
            self.cur = self.prog = start
        if not self.on:
            yield from self._uncompensated(m, start, end)
        elif self.first:
            if (
                m.kind is not MoveKind.ARC
                and math.hypot(end[0] - start[0], end[1] - start[1]) == 0.0
            ):
                yield from self._uncompensated(m, start, end, keep_exit=True)
            elif m.kind is MoveKind.ARC:
                self._entry_arc(m, end)
            else:
                self._entry_line(m, end)
        elif m.kind is MoveKind.ARC:
            yield from self._arc(m, end)
        else:
            yield from self._straight(m, end)

    # -- compensation off -------------------------------------------------------------------
    def _uncompensated(
        self, m: Move, start: Vec3, end: Vec3, keep_exit: bool = False
    ) -> Iterator[Segment]:
        assert self.cur is not None
        role = Role.RAPID if m.kind is MoveKind.RAPID else Role.CONTOUR
        if self.exit_pending and not keep_exit:
            if m.kind is MoveKind.ARC:
                raise _Stop("LCNC-ARC-AFTER-G40", m.span)
            role = Role.RETRACT
            self.exit_pending = False
        if m.kind is MoveKind.ARC:
            assert m.center is not None
            c = plane_center(m)
            q = _Queued(self.cur, end, m, role, center=c, turn=_turn_of(m), compensated=False)
        else:
            q = _Queued(self.cur, end, m, role, compensated=False)
        seg = self._segment(q)
        if seg is not None:
            yield seg
        self.cur = self.prog = end

    # -- entry ------------------------------------------------------------------------------
    def _entry_line(self, m: Move, end: Vec3) -> None:
        assert self.cur is not None
        c = self.cur[:2]
        p = end[:2]
        if math.hypot(p[0] - c[0], p[1] - c[1]) <= self.r:
            raise _Stop("LCNC-ENTRY-TOO-SHORT", m.span)
        alpha = _angle(c, p) + self.side * HALF_PI
        e = _at(p, self.r, alpha)
        self.endpoint = c
        self.queue.append(_Queued(self.cur, (e[0], e[1], end[2]), m, Role.APPROACH))
        self.first = False
        self.cur, self.prog = (e[0], e[1], end[2]), end

    def _entry_arc(self, m: Move, end: Vec3) -> None:
        assert self.cur is not None
        c = self.cur[:2]
        p = end[:2]
        if math.hypot(p[0] - c[0], p[1] - c[1]) <= self.r:
            raise _Stop("LCNC-ENTRY-ARC-TOO-SHORT", m.span)
        center = plane_center(m)
        turn = _turn_of(m)
        if _tool_inside_arc(self.side, turn):
            gamma = _angle(p, center)
        else:
            gamma = _angle(center, p)
        e = _at(p, self.r, gamma)
        # the compensated arc runs from the current point to e; its centre lies on the line from
        # e through the programmed centre, equidistant from both ends
        ab = _angle(e, center)
        b_len = math.hypot(c[0] - e[0], c[1] - e[1]) / 2.0
        a_ang = _angle(e, c) - ab
        if abs(math.cos(a_ang)) < 1e-9:
            raise _Stop("LCNC-ARC-TOO-SMALL", m.span)
        c_len = b_len / math.cos(a_ang)
        new_center = _at(e, c_len, ab)
        sweep = find_turn(c, new_center, turn, e)
        self.endpoint = c
        self.queue.append(
            _Queued(
                self.cur,
                (e[0], e[1], end[2]),
                m,
                Role.APPROACH,
                center=new_center,
                turn=turn,
                prog_sweep=sweep,
            )
        )
        self.first = False
        self.cur, self.prog = (e[0], e[1], end[2]), end

    # -- contour: straight ------------------------------------------------------------------
    def _straight(self, m: Move, end: Vec3) -> Iterator[Segment]:
        assert self.cur is not None and self.prog is not None
        small = TOLERANCE_CONCAVE_CORNER
        r, side = self.r, self.side
        op, c, p = self.prog[:2], self.cur[:2], end[:2]
        cz = self.cur[2]
        rapid = m.kind is MoveKind.RAPID
        if p[0] == op[0] and p[1] == op[1]:  # no plane motion: the tool stays where it is
            self.queue.append(_Queued(self.cur, (c[0], c[1], end[2]), m, Role.CONTOUR))
            self.cur, self.prog = (c[0], c[1], end[2]), end
            return
        theta = _angle(op, c)
        alpha = _angle(op, p)
        if side > 0:
            if theta < alpha:
                theta += TWO_PI
            beta = theta - alpha - HALF_PI
            gamma = HALF_PI
        else:
            if alpha < theta:
                alpha += TWO_PI
            beta = alpha - theta - HALF_PI
            gamma = -HALF_PI
        e = _at(p, r, alpha + gamma)
        mid = _at(op, r, alpha + gamma)
        front = self._front()
        concave = beta < -small or beta > math.pi + small
        if not concave and beta > math.pi - small and front is not None and front.is_arc:
            # "h" shape: over a round top into a line on the side the tool is on
            concave = (side < 0 and front.turn > 0) or (side > 0 and front.turn < 0)
        if not concave and beta > small:  # outside corner
            yield from self._flush()
            if rapid:
                corner = _Queued(self.cur, (mid[0], mid[1], cz), m, Role.CORNER)
            else:
                corner = _Queued(
                    self.cur, (mid[0], mid[1], cz), m, Role.CORNER, center=op, turn=-side
                )
            seg = self._segment(corner)
            if seg is not None:
                yield seg
            start = (mid[0], mid[1], cz)
            self.endpoint = mid
        elif concave:
            if front is None or not front.is_arc:
                halfcorner = (beta + math.pi) / 2.0
                retreat = r / math.tan(halfcorner) if math.tan(halfcorner) != 0.0 else 0.0
                mid = _at(c, retreat, theta + gamma)
            else:
                mid = self._arc_line_corner(front, op, p, m.span)
            yield from self._move_endpoint_and_flush(mid, m.span)
            start = (mid[0], mid[1], cz)
        else:  # near-tangent: continue from where the tool is
            yield from self._flush()
            self.endpoint = c
            start = self.cur
        self.queue.append(
            _Queued(
                start, (e[0], e[1], end[2]), m, Role.CONTOUR, prog_dir=(p[0] - op[0], p[1] - op[1])
            )
        )
        self.cur, self.prog = (e[0], e[1], end[2]), end

    def _arc_line_corner(self, prev: _Queued, op: Vec2, p: Vec2, span: SourceSpan) -> Vec2:
        """Inside corner from a (compensated) arc into a line: the point of the arc that is r
        from the programmed line."""
        assert prev.center is not None
        r, side = self.r, self.side
        pc = prev.center
        oldrad = math.hypot(prev.end[0] - pc[0], prev.end[1] - pc[1])
        base = _angle(op, p)
        th = base + HALF_PI if prev.turn > 0 else base - HALF_PI
        phi = _angle(op, pc)
        inside = _tool_inside_arc(side, prev.turn)
        oldrad_prog = oldrad + r if inside else oldrad - r
        d = oldrad_prog * math.cos(th - phi)
        if oldrad == 0.0:  # the previous offset arc shrank to its centre
            raise _Stop("LCNC-ARC-LINE-GOUGE", span)
        cos_ang = (d - r) / oldrad if inside else (d + r) / oldrad
        if cos_ang > 1.0 or cos_ang < -1.0:
            raise _Stop("LCNC-ARC-LINE-GOUGE", span)
        if inside:
            ang = (-math.acos(cos_ang) if prev.turn > 0 else math.acos(cos_ang)) + th + math.pi
        else:
            ang = (math.acos(cos_ang) if prev.turn > 0 else -math.acos(cos_ang)) + th + math.pi
        return _at(pc, oldrad, ang)

    # -- contour: arc -----------------------------------------------------------------------
    def _arc(self, m: Move, end: Vec3) -> Iterator[Segment]:
        assert self.cur is not None and self.prog is not None
        small = TOLERANCE_CONCAVE_CORNER
        r, side = self.r, self.side
        op, c, p = self.prog[:2], self.cur[:2], end[:2]
        cz = self.cur[2]
        center = plane_center(m)
        turn = _turn_of(m)
        arc_radius = math.hypot(center[0] - p[0], center[1] - p[1])
        theta = _angle(op, c) + (-HALF_PI if side > 0 else HALF_PI)
        delta = _angle(op, center)
        alpha = delta - HALF_PI if turn > 0 else delta + HALF_PI
        beta = theta - alpha if side > 0 else alpha - theta
        if beta > 1.5 * math.pi:
            beta -= TWO_PI
        elif beta < -HALF_PI:
            beta += TWO_PI
        inside = _tool_inside_arc(side, turn)
        if inside:
            gamma = _angle(p, center)
            if arc_radius <= r:
                raise _Stop("LCNC-ARC-TOO-SMALL", m.span)
        else:
            gamma = _angle(center, p)
            delta += math.pi
        e = _at(p, r, gamma)
        prog_sweep = find_turn(op, center, turn, p)
        front = self._front()
        if beta < -small or beta > math.pi + small or (abs(beta - math.pi) < small and not inside):
            if front is None or not front.is_arc:  # line -> arc
                cyv = arc_radius * math.sin(beta - HALF_PI)
                if inside:
                    dist = arc_radius - r
                    sin_ang = (cyv + r) / dist
                    if sin_ang > 1.0 or sin_ang < -1.0:
                        raise _Stop("LCNC-CONCAVE-GOUGE-ARC", m.span)
                    ang = theta + math.asin(sin_ang) if turn > 0 else theta - math.asin(sin_ang)
                else:
                    dist = arc_radius + r
                    sin_ang = (cyv - r) / dist
                    if sin_ang > 1.0 or sin_ang < -1.0:
                        raise _Stop("LCNC-CONCAVE-GOUGE-ARC", m.span)
                    ang = (
                        theta + math.pi - math.asin(sin_ang)
                        if turn > 0
                        else theta + math.pi + math.asin(sin_ang)
                    )
                mid = _at(center, dist, ang)
            else:  # arc -> arc
                assert front.center is not None
                pc = front.center
                oldrad = math.hypot(front.end[0] - pc[0], front.end[1] - pc[1])
                newrad = arc_radius - r if inside else arc_radius + r
                arc_cc = math.hypot(pc[0] - center[0], pc[1] - center[1])
                if oldrad == 0.0 or arc_cc == 0.0:
                    raise _Stop("LCNC-ARC-SAME-CENTER", m.span)
                a = (oldrad * oldrad + arc_cc * arc_cc - newrad * newrad) / (2.0 * oldrad * arc_cc)
                if a > 1.0 or a < -1.0:
                    raise _Stop("LCNC-ARC-ARC-GOUGE", m.span)
                pullback = math.acos(a)
                cc_dir = _angle(pc, center)
                if _tool_inside_arc(side, front.turn):
                    direction = cc_dir + pullback if turn > 0 else cc_dir - pullback
                else:
                    direction = cc_dir - pullback if turn > 0 else cc_dir + pullback
                mid = _at(pc, oldrad, direction)
            yield from self._move_endpoint_and_flush(mid, m.span)
            start = (mid[0], mid[1], cz)
        elif beta > small:  # outside corner: an arc around the programmed corner first
            mid = _at(op, r, delta)
            yield from self._flush()
            corner = _Queued(self.cur, (mid[0], mid[1], cz), m, Role.CORNER, center=op, turn=-side)
            seg = self._segment(corner)
            if seg is not None:
                yield seg
            self.endpoint = mid
            start = (mid[0], mid[1], cz)
        else:
            yield from self._flush()
            self.endpoint = c
            start = self.cur
        self.queue.append(
            _Queued(
                start,
                (e[0], e[1], end[2]),
                m,
                Role.CONTOUR,
                center=center,
                turn=turn,
                prog_sweep=prog_sweep,
            )
        )
        self.cur, self.prog = (e[0], e[1], end[2]), end


def plane_center(m: Move) -> Vec2:
    """The arc centre of a move in its plane coordinates (u, v)."""
    assert m.center is not None
    c = m.plane.to_uvw(m.center)
    return (c[0], c[1])


def compensate_linuxcnc(
    moves: Iterable[Move],
    settings: TrcSettings | None = None,
    diagnostics: list[Diagnostic] | None = None,
    complete: bool = True,
) -> Iterator[Segment]:
    """Tool-centre segments for canonical moves under LinuxCNC's compensation rules.

    Same contract as :func:`trcopt.compensation.compensate`: segments in plane coordinates with
    roles approach/contour/corner/retract/rapid; diagnostics (codes ``LCNC-*`` with LinuxCNC's
    message text) are appended to ``diagnostics``; an error stops the stream after the segments
    that were already final (LinuxCNC discards the moves still waiting for their corner).

    Parameters
    ----------
    moves:
        Canonical moves (absolute mm); ``comp.effective_side``/``effective_radius`` give the side
        and the tool radius (mm) — a negative radius swaps the side.
    settings:
        Unused by this profile (accepted for the common signature).
    diagnostics:
        List the alarms are appended to.
    complete:
        False when the moves stop early (the front end raised an error).
    """
    comp = _LinuxCncCompensator(
        settings or TrcSettings(), diagnostics if diagnostics is not None else [], complete
    )
    return comp.run(moves)
