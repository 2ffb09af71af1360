"""LinuxCNC's cutter-compensation arithmetic, as its RS274NGC interpreter computes it.

The rules that decide *when* each formula applies are :mod:`trcopt.controllers.linuxcnc.compensation`;
this module holds the formulas and LinuxCNC's vocabulary:

* the corner tolerances (:data:`TOLERANCE_CONCAVE_CORNER`, :data:`ARC_SWEEP_SLACK`, rad);
* the error codes ``LCNC-*`` with LinuxCNC's message texts (:data:`MESSAGES`) and the exception
  that stops the path (:class:`CompensationStop`);
* angles and points around a centre, the sweep of an arc from LinuxCNC's ``turn`` count
  (:func:`find_turn`), which side of an arc the tool is on, the plane centre of an arc move;
* where the tool stops at an inside corner — line→line, arc→line, line→arc, arc→arc — and the
  centre of a compensated entry arc.

Points are plane coordinates (u, v) in mm, angles in rad; ``side`` is +1 left (G41), −1 right
(G42); ``turn`` is +1 CCW, −1 CW, |turn| > 1 adds full turns.
"""

from __future__ import annotations

import math

from trcopt.codes import Code
from trcopt.errors import SourceSpan
from trcopt.geometry.vec import Vec2
from trcopt.nc.model import Move

__all__ = [
    "TOLERANCE_CONCAVE_CORNER",
    "ARC_SWEEP_SLACK",
    "ARC_SWEEP_SLACK_MM",
    "HALF_PI",
    "TWO_PI",
    "MESSAGES",
    "CompensationStop",
    "point_at",
    "angle_to",
    "find_turn",
    "tool_inside_arc",
    "turn_of",
    "plane_center",
    "line_line_corner",
    "arc_line_corner",
    "line_arc_corner",
    "arc_arc_corner",
    "entry_arc_center",
    "check_moved_arc_end",
]

TOLERANCE_CONCAVE_CORNER = 0.05  # rad: joins flatter than this are left untouched
ARC_SWEEP_SLACK = 0.001  # rad: a trimmed arc may sweep this much more than programmed (inch program)
ARC_SWEEP_SLACK_MM = 0.0254  # the same in a metric program (LinuxCNC compares with .001 in as mm)
HALF_PI = 0.5 * math.pi
TWO_PI = 2.0 * math.pi

#: LinuxCNC's error text for each of our codes.
MESSAGES: dict[str, str] = {
    Code.LCNC_ENTRY_TOO_SHORT: "Length of cutter compensation entry move is not greater than the tool radius",
    Code.LCNC_ENTRY_ARC_TOO_SHORT: "Radius of cutter compensation entry arc is not greater than the tool radius",
    Code.LCNC_CONCAVE_GOUGE: "Straight feed in concave corner cannot be reached by the tool without gouging",
    Code.LCNC_CONCAVE_GOUGE_TRAVERSE: (
        "Straight traverse in concave corner cannot be reached by the tool without gouging"
    ),
    Code.LCNC_CONCAVE_GOUGE_ARC: "Arc move in concave corner cannot be reached by the tool without gouging",
    Code.LCNC_ARC_LINE_GOUGE: "Arc to straight motion makes a corner the compensated tool can't fit in without gouging",
    Code.LCNC_ARC_ARC_GOUGE: "Arc to arc motion makes a corner the compensated tool can't fit in without gouging",
    Code.LCNC_ARC_SAME_CENTER: "Arc to arc motion is invalid because the arcs have the same center",
    Code.LCNC_ARC_TOO_SMALL: "Tool radius not less than arc radius with comp",
    Code.LCNC_COMP_ALREADY_ON: "Cannot turn cutter radius comp on when already on",
    Code.LCNC_YZ_PLANE: "Cannot use YZ plane with cutter radius comp",
    Code.LCNC_ARC_AFTER_G40: "The move just after exiting cutter compensation mode must be straight, not an arc",
    Code.LCNC_ARC_MISMATCH: "BUG: cutter compensation has generated an invalid arc with mismatched radii",
}
ARC_MISMATCH = 0.01  # program units: a queued arc's end may move off its circle by this much


class CompensationStop(Exception):
    """A LinuxCNC error: ``code`` (a key of :data:`MESSAGES`) at the block ``span``; ``detail``
    follows the text where LinuxCNC's message carries numbers."""

    def __init__(self, code: Code, span: SourceSpan, detail: str = "") -> None:
        super().__init__(MESSAGES[code] + (" " + detail if detail else ""))
        self.code, self.span = code, span


def check_moved_arc_end(center: Vec2, end: Vec2, p: Vec2, inch: bool, span: SourceSpan) -> None:
    """LinuxCNC's check when an inside corner moves the end of a queued arc to ``p``: the new end
    must lie on the arc's circle within :data:`ARC_MISMATCH` (it need not after an entry arc, whose
    centre is not the programmed one, and the moves LinuxCNC queues before it)."""
    r1 = math.hypot(end[0] - center[0], end[1] - center[1])
    r2 = math.hypot(p[0] - center[0], p[1] - center[1])
    unit = 25.4 if inch else 1.0
    if abs(r1 - r2) > ARC_MISMATCH * unit:
        raise CompensationStop(Code.LCNC_ARC_MISMATCH, span, f"r1 {r1 / unit:f} r2 {r2 / unit:f}")


def point_at(p: Vec2, r: float, angle: float) -> Vec2:
    """The point ``r`` (mm) from ``p`` in direction ``angle``."""
    return (p[0] + r * math.cos(angle), p[1] + r * math.sin(angle))


def angle_to(frm: Vec2, to: Vec2) -> float:
    """Direction (rad) from ``frm`` to ``to``."""
    return math.atan2(to[1] - frm[1], to[0] - frm[0])


def find_turn(start: Vec2, center: Vec2, turn: int, end: Vec2) -> float:
    """Signed sweep (rad) from ``start`` to ``end`` around ``center`` with LinuxCNC's ``turn``
    (equal start and end angles make a full circle)."""
    if turn == 0:
        return 0.0
    a = angle_to(center, start)
    b = angle_to(center, end)
    if turn > 0:
        if b <= a:
            b += TWO_PI
        return b - a + (turn - 1) * TWO_PI
    if a <= b:
        a += TWO_PI
    return b - a + (turn + 1) * TWO_PI


def tool_inside_arc(side: int, turn: int) -> bool:
    """Whether the tool runs on the centre side of an arc."""
    return (side > 0 and turn > 0) or (side < 0 and turn < 0)


def turn_of(m: Move) -> int:
    """LinuxCNC's ``turn`` of an arc move: its sense and full turns."""
    sign = 1 if m.ccw else -1
    return sign * (1 + int(m.turns))


def plane_center(m: Move) -> Vec2:
    """The arc centre of a move in its plane coordinates (u, v)."""
    assert m.center is not None
    c = m.plane.to_uvw(m.center)
    return (c[0], c[1])


def line_line_corner(current: Vec2, theta: float, beta: float, gamma: float, r: float) -> Vec2:
    """Inside corner between two lines: the tool retreats along the previous line from its
    current point ``current`` (direction ``theta + gamma``) by ``r / tan((β + π) / 2)``."""
    halfcorner = (beta + math.pi) / 2.0
    retreat = r / math.tan(halfcorner) if math.tan(halfcorner) != 0.0 else 0.0
    return point_at(current, retreat, theta + gamma)


def arc_line_corner(
    prev_center: Vec2, prev_radius: float, prev_turn: int, op: Vec2, p: Vec2, r: float, side: int, span: SourceSpan
) -> Vec2:
    """Inside corner from a compensated arc (centre, tool-centre radius, turn) into the line
    ``op`` → ``p``: the point of the arc that is ``r`` from the programmed line."""
    base = angle_to(op, p)
    th = base + HALF_PI if prev_turn > 0 else base - HALF_PI
    phi = angle_to(op, prev_center)
    inside = tool_inside_arc(side, prev_turn)
    oldrad_prog = prev_radius + r if inside else prev_radius - r
    d = oldrad_prog * math.cos(th - phi)
    if prev_radius == 0.0:  # the previous offset arc shrank to its centre
        raise CompensationStop(Code.LCNC_ARC_LINE_GOUGE, span)
    cos_ang = (d - r) / prev_radius if inside else (d + r) / prev_radius
    if cos_ang > 1.0 or cos_ang < -1.0:
        raise CompensationStop(Code.LCNC_ARC_LINE_GOUGE, span)
    if inside:
        ang = (-math.acos(cos_ang) if prev_turn > 0 else math.acos(cos_ang)) + th + math.pi
    else:
        ang = (math.acos(cos_ang) if prev_turn > 0 else -math.acos(cos_ang)) + th + math.pi
    return point_at(prev_center, prev_radius, ang)


def line_arc_corner(
    center: Vec2, arc_radius: float, turn: int, inside: bool, theta: float, beta: float, r: float, span: SourceSpan
) -> Vec2:
    """Inside corner from a line into the arc about ``center`` (programmed radius
    ``arc_radius``): the point of the arc's offset that is ``r`` from the line."""
    cyv = arc_radius * math.sin(beta - HALF_PI)
    if inside:
        dist = arc_radius - r
        sin_ang = (cyv + r) / dist
        if sin_ang > 1.0 or sin_ang < -1.0:
            raise CompensationStop(Code.LCNC_CONCAVE_GOUGE_ARC, span)
        ang = theta + math.asin(sin_ang) if turn > 0 else theta - math.asin(sin_ang)
    else:
        dist = arc_radius + r
        sin_ang = (cyv - r) / dist
        if sin_ang > 1.0 or sin_ang < -1.0:
            raise CompensationStop(Code.LCNC_CONCAVE_GOUGE_ARC, span)
        ang = theta + math.pi - math.asin(sin_ang) if turn > 0 else theta + math.pi + math.asin(sin_ang)
    return point_at(center, dist, ang)


def arc_arc_corner(
    prev_center: Vec2,
    prev_radius: float,
    prev_turn: int,
    center: Vec2,
    arc_radius: float,
    turn: int,
    inside: bool,
    r: float,
    side: int,
    span: SourceSpan,
) -> Vec2:
    """Inside corner between two arcs: where the previous offset arc (centre, tool-centre radius,
    turn) meets the offset of the arc about ``center`` (programmed radius ``arc_radius``)."""
    newrad = arc_radius - r if inside else arc_radius + r
    arc_cc = math.hypot(prev_center[0] - center[0], prev_center[1] - center[1])
    if prev_radius == 0.0 or arc_cc == 0.0:
        raise CompensationStop(Code.LCNC_ARC_SAME_CENTER, span)
    a = (prev_radius * prev_radius + arc_cc * arc_cc - newrad * newrad) / (2.0 * prev_radius * arc_cc)
    if a > 1.0 or a < -1.0:
        raise CompensationStop(Code.LCNC_ARC_ARC_GOUGE, span)
    pullback = math.acos(a)
    cc_dir = angle_to(prev_center, center)
    if tool_inside_arc(side, prev_turn):
        direction = cc_dir + pullback if turn > 0 else cc_dir - pullback
    else:
        direction = cc_dir - pullback if turn > 0 else cc_dir + pullback
    return point_at(prev_center, prev_radius, direction)


def entry_arc_center(current: Vec2, e: Vec2, center: Vec2, span: SourceSpan) -> Vec2:
    """Centre of the compensated entry arc from the (uncompensated) ``current`` point to ``e``:
    on the line from ``e`` through the programmed ``center``, equidistant from both ends."""
    ab = angle_to(e, center)
    b_len = math.hypot(current[0] - e[0], current[1] - e[1]) / 2.0
    a_ang = angle_to(e, current) - ab
    if abs(math.cos(a_ang)) < 1e-9:
        raise CompensationStop(Code.LCNC_ARC_TOO_SMALL, span)
    c_len = b_len / math.cos(a_ang)
    return point_at(e, c_len, ab)
