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
    an arc sweep further than programmed, the corner gouges — an error. The same check runs on
    the moves still queued when the tool leaves them where they are at an outside corner of a
    straight block, at G40 and at the program end (LinuxCNC's ``move_endpoint_and_flush`` to the
    current point): a line whose start an earlier inside corner moved past its end is that error
    too; the near-tangent case and arc blocks flush without it, as LinuxCNC does;
* an inside arc whose radius is not larger than r is an error;
* **exit** (first move after G40): a straight line from the last tool position to the programmed
  end point; an arc there is an error.

Errors stop the path with LinuxCNC's message text and the stable codes ``LCNC-*``. Segments carry
the roles approach (entry), contour, corner (inserted arcs and corner traverses), retract (exit)
and rapid.

This module owns the rules above and LinuxCNC's queue of tool-centre moves still waiting for their
corner; the formulas, the tolerances and the message texts are :mod:`trcopt.controllers.linuxcnc.corners`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import dataclass

from trcopt.codes import Code
from trcopt.config import TrcSettings
from trcopt.controllers.linuxcnc.corners import (
    ARC_SWEEP_SLACK,
    ARC_SWEEP_SLACK_MM,
    HALF_PI,
    TOLERANCE_CONCAVE_CORNER,
    TWO_PI,
    CompensationStop,
    angle_to,
    arc_arc_corner,
    arc_line_corner,
    check_moved_arc_end,
    entry_arc_center,
    find_turn,
    line_arc_corner,
    line_line_corner,
    plane_center,
    point_at,
    tool_inside_arc,
    turn_of,
)
from trcopt.controllers.linuxcnc.lathe import moved, tip_shift
from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.geometry.plane import Plane
from trcopt.geometry.primitives import Arc, Line
from trcopt.geometry.vec import Vec2, Vec3
from trcopt.modes import Side
from trcopt.nc.model import Move, MoveKind
from trcopt.path import Role, Segment, new_segment

__all__ = ["compensate_linuxcnc"]

_OFF, _G17 = Side.OFF, Plane.G17


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
    tip_start: bool = True  # a lathe tool's shift moves the start too (not the entry's: the tool is there)

    @property
    def is_arc(self) -> bool:
        return self.center is not None


class _LinuxCncCompensator:
    def __init__(self, settings: TrcSettings, diagnostics: list[Diagnostic], complete: bool) -> None:
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
        self.inch = False  # the unit of the block being compensated (LinuxCNC's arc-sweep slack)
        self.tip: Vec3 | None = None  # a lathe tool's nose centre → tip shift (trcopt.controllers.linuxcnc.lathe)

    # -- output -----------------------------------------------------------------------------
    def _segment(self, q: _Queued) -> Segment | None:
        m = q.move
        start, end, c = q.start, q.end, q.center
        if q.compensated:
            side, radius = (Side.LEFT if self.side > 0 else Side.RIGHT), self.r
            if self.tip is not None:
                d = self.tip
                start, end = moved(start, d) if q.tip_start else start, moved(end, d)
                c = None if c is None else (c[0] + d[0], c[1] + d[1])
        else:
            side, radius = _OFF, 0.0
        if c is not None:
            rad = math.hypot(end[0] - c[0], end[1] - c[1])
            sweep = find_turn(start[:2], c, q.turn, end[:2])
            if rad <= 0.0:
                geom: Line | Arc = Line(start, end)
                if geom.length <= 1e-12:
                    return None
            else:
                geom = Arc(c, rad, angle_to(c, start[:2]), sweep, start[2], end[2])
            return new_segment(geom, self.plane, q.role, m.span, m.feed_mm_s, side, radius)
        if math.dist(start, end) <= 1e-12:  # Line.length
            return None
        line = Line(start, end)
        role = q.role
        if m.feed_mm_s is None and role is Role.CONTOUR:
            role = Role.RAPID
        return new_segment(line, self.plane, role, m.span, m.feed_mm_s, side, radius)

    def _flush(self, out: list[Segment]) -> None:
        """Emit the queued moves (append their segments to ``out``)."""
        queue = self.queue
        if not queue:
            return
        for q in queue:
            seg = self._segment(q)
            if seg is not None:
                out.append(seg)
        queue.clear()

    def _move_endpoint_and_flush(self, p: Vec2, span: SourceSpan, out: list[Segment]) -> None:
        """Move the end of every queued move to ``p`` (an inside corner), then emit them."""
        for k, q in enumerate(self.queue):
            if q.is_arc:
                assert q.center is not None
                check_moved_arc_end(q.center, q.end, p, self.inch, span)
                if q.prog_sweep:
                    sweep = find_turn(self.endpoint, q.center, q.turn, p)
                    slack = ARC_SWEEP_SLACK if self.inch else ARC_SWEEP_SLACK_MM
                    if abs(sweep) > abs(q.prog_sweep) + slack:
                        raise CompensationStop(Code.LCNC_CONCAVE_GOUGE_ARC, span)
            else:
                new = (p[0] - self.endpoint[0], p[1] - self.endpoint[1])
                if q.prog_dir[0] * new[0] + q.prog_dir[1] * new[1] < 0.0:
                    code = Code.LCNC_CONCAVE_GOUGE_TRAVERSE if q.move.feed_mm_s is None else Code.LCNC_CONCAVE_GOUGE
                    raise CompensationStop(code, span)
            q.end = (p[0], p[1], q.end[2])
            if k > 0:
                q.start = (p[0], p[1], q.start[2])
        self._flush(out)
        self.endpoint = p

    def _flush_where_the_tool_is(self, span: SourceSpan, out: list[Segment]) -> None:
        """LinuxCNC's ``move_endpoint_and_flush`` to the current tool position (outside corner
        of a straight block, G40, program end): the queued moves keep their ends, but a line that
        now runs against its programmed direction (its start was moved past its end by an inside
        corner) is the gouge error."""
        if not self.queue or self.cur is None or self.r <= 0.0:
            self._flush(out)
            return
        self._move_endpoint_and_flush(self.cur[:2], span, out)

    def _front(self) -> _Queued | None:
        return self.queue[0] if self.queue else None

    # -- driver -----------------------------------------------------------------------------
    def run(self, moves: Iterable[Move]) -> Iterator[Segment]:
        out: list[Segment] = []  # the segments a block makes final, given before the next block is read
        try:
            span = None
            for m in moves:
                span = m.span
                self._block(m, out)
                if out:
                    yield from out
                    out.clear()
            if self.on and span is not None:  # program end (M2/M30): LinuxCNC's convert_stop
                self._flush_where_the_tool_is(span, out)
            self._flush(out)
        except CompensationStop as stop:
            self.queue.clear()
            yield from out  # those final before the error
            self.diags.append(Diagnostic(Severity.ERROR, stop.code, str(stop), stop.span))
            return
        yield from out

    def _block(self, m: Move, out: list[Segment]) -> None:
        """One move: the common contour move (a straight move in G17 with compensation on and
        running, its side not programmed in the block) straight to :meth:`_straight`, which
        is where :meth:`_any_block` takes it; every other move through :meth:`_any_block`."""
        comp = m.comp
        if (
            self.on and not self.first and comp.side is not _OFF and not comp.side_programmed
            and m.plane is _G17 and self.plane is _G17 and self.r > 0.0
            and (m.kind is MoveKind.LINE or m.kind is MoveKind.RAPID)
        ):  # fmt: skip
            self.inch = comp.inch
            self._straight(m, m.end, out)
            return
        self._any_block(m, out)

    def _any_block(self, m: Move, out: list[Segment]) -> None:
        comp = m.comp
        self.inch = comp.inch
        want = comp.effective_side
        if want is not Side.OFF and (not self.on or comp.side_programmed):
            if self.on:
                raise CompensationStop(Code.LCNC_COMP_ALREADY_ON, m.span)
            if m.plane is Plane.G19:
                raise CompensationStop(Code.LCNC_YZ_PLANE, m.span)
            self.on, self.first = True, True
            self.side = 1 if want is Side.LEFT else -1
            self.r = comp.effective_radius
            self._set_plane(m.plane)
            self.tip = tip_shift(comp.orientation, self.r, self.plane)
            self.exit_pending = False
        elif want is Side.OFF and self.on:
            self._flush_where_the_tool_is(m.span, out)
            if self.tip is not None and self.cur is not None and not self.first:
                self.cur = moved(self.cur, self.tip)  # the next move starts at the tip
            self.on = False
            self.exit_pending = not self.first and self.r > 0.0
            self.first = False
        if self.on and m.plane is not self.plane:
            if m.plane is Plane.G19:
                raise CompensationStop(Code.LCNC_YZ_PLANE, m.span)
            self._set_plane(m.plane)
        if m.kind is MoveKind.NONE:
            return
        plane = m.plane
        if plane is Plane.G17:  # (u, v, w) = (x, y, z)
            start, end = m.start, m.end
        else:
            start, end = plane.to_uvw(m.start), plane.to_uvw(m.end)
        if self.cur is None or not self.on:
            self._set_plane(plane)
        if self.cur is None:
            self.cur = self.prog = start
        if not self.on or self.r <= 0.0:
            # a zero radius (G41.1 D0) leaves every move as programmed: LinuxCNC compensates only
            # with cutter_comp_radius > 0 (convert_straight, convert_arc)
            self._uncompensated(m, start, end, out)
        elif self.first:
            if m.kind is not MoveKind.ARC and math.hypot(end[0] - start[0], end[1] - start[1]) == 0.0:
                self._uncompensated(m, start, end, out, keep_exit=True)
            elif m.kind is MoveKind.ARC:
                self._entry_arc(m, end)
            else:
                self._entry_line(m, end)
        elif m.kind is MoveKind.ARC:
            self._arc(m, end, out)
        else:
            self._straight(m, end, out)

    # -- compensation off -------------------------------------------------------------------
    def _set_plane(self, plane: Plane) -> None:
        """Work in ``plane`` from now on: the tool position, kept in the plane's (u, v, w), is
        carried over to the new plane's coordinates."""
        if plane is self.plane:
            return
        if self.cur is not None:
            self.cur = plane.to_uvw(self.plane.to_xyz(self.cur))
        if self.prog is not None:
            self.prog = plane.to_uvw(self.plane.to_xyz(self.prog))
        self.plane = plane

    def _uncompensated(self, m: Move, start: Vec3, end: Vec3, out: list[Segment], keep_exit: bool = False) -> None:
        assert self.cur is not None
        role = Role.RAPID if m.kind is MoveKind.RAPID else Role.CONTOUR
        if self.exit_pending and not keep_exit:
            if m.kind is MoveKind.ARC:
                raise CompensationStop(Code.LCNC_ARC_AFTER_G40, m.span)
            role = Role.RETRACT
            self.exit_pending = False
        if m.kind is MoveKind.ARC:
            assert m.center is not None
            c = plane_center(m)
            q = _Queued(self.cur, end, m, role, center=c, turn=turn_of(m), compensated=False)
        else:
            q = _Queued(self.cur, end, m, role, compensated=False)
        seg = self._segment(q)
        if seg is not None:
            out.append(seg)
        self.cur = self.prog = end

    # -- entry ------------------------------------------------------------------------------
    def _entry_line(self, m: Move, end: Vec3) -> None:
        assert self.cur is not None
        c = self.cur[:2]
        p = end[:2]
        if math.hypot(p[0] - c[0], p[1] - c[1]) <= self.r:
            raise CompensationStop(Code.LCNC_ENTRY_TOO_SHORT, m.span)
        alpha = angle_to(c, p) + self.side * HALF_PI
        e = point_at(p, self.r, alpha)
        self.endpoint = c
        self.queue.append(_Queued(self.cur, (e[0], e[1], end[2]), m, Role.APPROACH, tip_start=False))
        self.first = False
        self.cur, self.prog = (e[0], e[1], end[2]), end

    def _entry_arc(self, m: Move, end: Vec3) -> None:
        assert self.cur is not None
        c = self.cur[:2]
        p = end[:2]
        if math.hypot(p[0] - c[0], p[1] - c[1]) <= self.r:
            raise CompensationStop(Code.LCNC_ENTRY_ARC_TOO_SHORT, m.span)
        center = plane_center(m)
        turn = turn_of(m)
        if tool_inside_arc(self.side, turn):
            gamma = angle_to(p, center)
        else:
            gamma = angle_to(center, p)
        e = point_at(p, self.r, gamma)
        # the compensated arc runs from the current point to e
        new_center = entry_arc_center(c, e, center, m.span)
        sweep = find_turn(c, new_center, turn, e)
        self.endpoint = c
        if self.tip is not None:  # a lathe tool first moves from its tip to the shifted arc start
            self.queue.append(_Queued(self.cur, self.cur, m, Role.APPROACH, tip_start=False))
        end_e = (e[0], e[1], end[2])
        self.queue.append(_Queued(self.cur, end_e, m, Role.APPROACH, center=new_center, turn=turn, prog_sweep=sweep))
        self.first = False
        self.cur, self.prog = (e[0], e[1], end[2]), end

    # -- contour: straight ------------------------------------------------------------------
    def _straight(self, m: Move, end: Vec3, out: list[Segment]) -> None:
        cur, prog = self.cur, self.prog
        assert cur is not None and prog is not None
        small = TOLERANCE_CONCAVE_CORNER
        r, side = self.r, self.side
        opx, opy, px, py = prog[0], prog[1], end[0], end[1]
        cx, cy, cz = cur
        if px == opx and py == opy:  # no plane motion: the tool stays where it is
            self.queue.append(_Queued(cur, (cx, cy, end[2]), m, Role.CONTOUR))
            self.cur, self.prog = (cx, cy, end[2]), end
            return
        theta = math.atan2(cy - opy, cx - opx)  # angle_to(op, c)
        alpha = math.atan2(py - opy, px - opx)  # angle_to(op, p)
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
        # point_at(p, r, alpha + gamma) is (px + cos, py + sin), point_at(op, …) (opx + cos, opy + sin)
        cos, sin = r * math.cos(alpha + gamma), r * math.sin(alpha + gamma)
        queue = self.queue
        front = queue[0] if queue else None
        concave = beta < -small or beta > math.pi + small
        if not concave and beta > math.pi - small and front is not None and front.center is not None:
            # "h" shape: over a round top into a line on the side the tool is on
            concave = (side < 0 and front.turn > 0) or (side > 0 and front.turn < 0)
        if not concave and beta > small:  # outside corner
            mid = (opx + cos, opy + sin)
            self._flush_where_the_tool_is(m.span, out)
            if m.kind is MoveKind.RAPID:
                corner = _Queued(cur, (mid[0], mid[1], cz), m, Role.CORNER)
            else:
                corner = _Queued(cur, (mid[0], mid[1], cz), m, Role.CORNER, center=(opx, opy), turn=-side)
            seg = self._segment(corner)
            if seg is not None:
                out.append(seg)
            start = (mid[0], mid[1], cz)
            self.endpoint = mid
        elif concave:
            if front is None or front.center is None:
                mid = line_line_corner((cx, cy), theta, beta, gamma, r)
            else:
                assert front.center is not None
                radius = math.hypot(front.end[0] - front.center[0], front.end[1] - front.center[1])
                mid = arc_line_corner(front.center, radius, front.turn, (opx, opy), (px, py), r, side, m.span)
            self._move_endpoint_and_flush(mid, m.span, out)
            start = (mid[0], mid[1], cz)
        else:  # near-tangent: continue from where the tool is
            if queue:
                self._flush(out)
            self.endpoint = (cx, cy)
            start = cur
        new = (px + cos, py + sin, end[2])
        queue.append(_Queued(start, new, m, Role.CONTOUR, None, 0, (px - opx, py - opy)))  # center, turn, prog_dir
        self.cur, self.prog = new, end

    # -- contour: arc -----------------------------------------------------------------------
    def _arc(self, m: Move, end: Vec3, out: list[Segment]) -> None:
        assert self.cur is not None and self.prog is not None
        small = TOLERANCE_CONCAVE_CORNER
        r, side = self.r, self.side
        op, c, p = self.prog[:2], self.cur[:2], end[:2]
        cz = self.cur[2]
        center = plane_center(m)
        turn = turn_of(m)
        arc_radius = math.hypot(center[0] - p[0], center[1] - p[1])
        theta = angle_to(op, c) + (-HALF_PI if side > 0 else HALF_PI)
        delta = angle_to(op, center)
        alpha = delta - HALF_PI if turn > 0 else delta + HALF_PI
        beta = theta - alpha if side > 0 else alpha - theta
        if beta > 1.5 * math.pi:
            beta -= TWO_PI
        elif beta < -HALF_PI:
            beta += TWO_PI
        inside = tool_inside_arc(side, turn)
        if inside:
            gamma = angle_to(p, center)
            if arc_radius <= r:
                raise CompensationStop(Code.LCNC_ARC_TOO_SMALL, m.span)
        else:
            gamma = angle_to(center, p)
            delta += math.pi
        e = point_at(p, r, gamma)
        prog_sweep = find_turn(op, center, turn, p)
        front = self._front()
        if beta < -small or beta > math.pi + small or (abs(beta - math.pi) < small and not inside):
            if front is None or not front.is_arc:  # line -> arc
                mid = line_arc_corner(center, arc_radius, turn, inside, theta, beta, r, m.span)
            else:  # arc -> arc
                assert front.center is not None
                radius = math.hypot(front.end[0] - front.center[0], front.end[1] - front.center[1])
                mid = arc_arc_corner(
                    front.center, radius, front.turn, center, arc_radius, turn, inside, r, side, m.span
                )
            self._move_endpoint_and_flush(mid, m.span, out)
            start = (mid[0], mid[1], cz)
        elif beta > small:  # outside corner: an arc around the programmed corner first
            mid = point_at(op, r, delta)
            self._flush(out)
            corner = _Queued(self.cur, (mid[0], mid[1], cz), m, Role.CORNER, center=op, turn=-side)
            seg = self._segment(corner)
            if seg is not None:
                out.append(seg)
            self.endpoint = mid
            start = (mid[0], mid[1], cz)
        else:
            self._flush(out)
            self.endpoint = c
            start = self.cur
        end_e = (e[0], e[1], end[2])
        self.queue.append(_Queued(start, end_e, m, Role.CONTOUR, center=center, turn=turn, prog_sweep=prog_sweep))
        self.cur, self.prog = (e[0], e[1], end[2]), end


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
    comp = _LinuxCncCompensator(settings or TrcSettings(), diagnostics if diagnostics is not None else [], complete)
    return comp.run(moves)
