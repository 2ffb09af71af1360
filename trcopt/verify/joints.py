"""Where a controller's own construction brings the tool nearer than R to the part contour, and
how the verification measures there.

Three places, each identified from the geometry of the plan (never from a result):

* **near-tangent joints** (:func:`continuations`). A controller may leave a joint whose programmed
  turn is at most a limit of its own as it is (LinuxCNC: 0.05 rad, ``TOLERANCE_CONCAVE_CORNER``):
  no transition, no intersection, the next line starts where the tool is — at the offset of the
  joint on the *previous* element's side — and runs to its own offset end. Such a line is not on
  its offset carrier at its start: it is measured against that construction (start point, end on
  the carrier at R, running in the programmed sense). The tool then comes at most R·(1 − cos β)
  closer than R to the two programmed elements that meet at the joint, and the line (which is not
  parallel to its carrier) to the element at its other end (β the joint's turn): that much is the
  controller's rule, not a gouge; anything beyond it, or elsewhere, is.
* **activation and deselection transitions** (:func:`activation_corners`): a corner segment
  between an approach segment and the first contour segment (or between the last one and a
  retraction) is the controller's transition around the start (end) point of the contour, built
  from the direction of the approach (retraction) move — LinuxCNC's arc around the first
  programmed point, like SINUMERIK's KONT circle. Its clearance is lead clearance.
* **the closing joint of a closed contour** (:func:`clearance_limits`): the tool enters the loop at
  the end of its activation and leaves it at the start of its retraction, and no corner is
  compensated between the last block and the first. Where that point is closer than R to the
  block across the joint, the lead move ending (starting) there already comes that close — it is
  lead clearance (and shown as such); the first (last) block's tool path is a gouge only where it
  comes closer still.

These functions measure one segment (joint) at a time; :mod:`trcopt.verify.batch` gives the same
values for a whole path at once.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from trcopt.geometry import Arc, Line
from trcopt.geometry.vec import Vec2
from trcopt.path import Role, Segment
from trcopt.verify.contour import Closing, ContourBlocks
from trcopt.verify.model import points_distance

__all__ = [
    "NEAR_TANGENT_SLACK_RAD",
    "SAME_POINT_MM",
    "Continuation",
    "Limit",
    "continuations",
    "continuation_residuals",
    "activation_corners",
    "clearance_limits",
]

NEAR_TANGENT_SLACK_RAD = 1e-9  # a joint turning by the controller's limit within this is near-tangent
SAME_POINT_MM = 1e-9  # two programmed blocks join when the end of one is this close to the other's start

NEAR_TANGENT = "near_tangent"
CLOSING = "closing"


@dataclass(frozen=True, slots=True)
class Continuation:
    """A contour line that starts where the tool is at a near-tangent joint.

    Attributes
    ----------
    start:
        Where it must start: the offset of the joint point on the previous element's side, mm.
    turn:
        |turn| of the programmed joint, rad.
    programmed:
        Its block's programmed element (the first one).
    previous:
        The programmed element before the joint (the last one of the previous block).
    following:
        The programmed element after the block (the first one of the next block), if any.
    """

    start: Vec2
    turn: float
    programmed: Segment
    previous: Segment
    following: Segment | None = None


@dataclass(frozen=True, slots=True)
class Limit:
    """The distance (mm) below which a tool segment gouges one part element (R elsewhere), and why."""

    distance: float
    kind: str  # NEAR_TANGENT or CLOSING


def _turn(t1: Vec2, t2: Vec2) -> float:
    return abs(math.atan2(t1[0] * t2[1] - t1[1] * t2[0], t1[0] * t2[0] + t1[1] * t2[1]))


def continuations(
    toolpath: Sequence[Segment],
    programmed: Sequence[Segment],
    near_tangent_rad: float,
    closings: Sequence[Closing] = (),
) -> dict[int, Continuation]:
    """The contour lines (by toolpath index) that start where the tool is at a joint whose
    programmed turn is at most ``near_tangent_rad`` (rad; 0: the controller leaves no joint as it
    is, there are none); the element following the last block of a closed loop is its first."""
    if near_tangent_rad <= 0.0:
        return {}
    by_line: dict[int, list[Segment]] = {}
    for p in programmed:
        if p.geometry.plane_length > 0.0 and isinstance(p.geometry, Line | Arc):
            by_line.setdefault(p.span.line, []).append(p)
    lines = sorted(by_line)
    loop_start = {c.last_line: c.first_line for c in closings}
    out: dict[int, Continuation] = {}
    for k in range(1, len(toolpath)):
        seg, prev = toolpath[k], toolpath[k - 1]
        if seg.role is not Role.CONTOUR or not isinstance(seg.geometry, Line) or seg.radius <= 0.0:
            continue
        if prev.radius <= 0.0 or prev.side is not seg.side or prev.span.line == seg.span.line:
            continue
        pa, pb = by_line.get(prev.span.line), by_line.get(seg.span.line)
        if not pa or not pb or not isinstance(pb[0].geometry, Line):
            continue
        a, b = pa[-1].geometry, pb[0].geometry
        if math.dist(a.end[:2], b.start[:2]) > SAME_POINT_MM:
            continue
        ta = a.end_tangent()
        turn = _turn(ta, b.start_tangent())
        if turn > near_tangent_rad + NEAR_TANGENT_SLACK_RAD:
            continue
        off = seg.side.sign * seg.radius
        n = bisect.bisect_right(lines, seg.span.line)
        nxt = by_line[lines[n]][0] if n < len(lines) else None
        if seg.span.line in loop_start and loop_start[seg.span.line] in by_line:
            nxt = by_line[loop_start[seg.span.line]][0]
        following = nxt if nxt is not None and math.dist(nxt.geometry.start[:2], b.end[:2]) <= SAME_POINT_MM else None
        start = (b.start[0] - off * ta[1], b.start[1] + off * ta[0])
        out[k] = Continuation(start, turn, pb[0], pa[-1], following)
    return out


def continuation_residuals(seg: Segment, c: Continuation) -> tuple[float, float]:
    """(radius, tangency) residual of a continuation line: its start against :attr:`start`, its
    end against the offset carrier (signed: on the compensation side, at R); tangency only for a
    line running against its programmed element (≥ 1, as for every contour element)."""
    g = seg.geometry
    b = c.programmed.geometry
    assert isinstance(b, Line)
    e = g.point2(1.0)
    d = b.direction2()
    offset = (e[1] - b.start[1]) * d[0] - (e[0] - b.start[0]) * d[1]
    radius = max(math.dist(g.point2(0.0), c.start), abs(offset - seg.side.sign * seg.radius))
    t = g.start_tangent()
    cos = t[0] * d[0] + t[1] * d[1]
    return radius, (0.0 if cos > 0.0 else 1.0 + abs(cos))


def activation_corners(toolpath: Sequence[Segment]) -> set[int]:
    """Indices of the corner segments right after an approach segment and right before a
    retraction segment: the transitions around the contour's start and end point."""
    out: set[int] = set()
    for k, seg in enumerate(toolpath):
        if seg.role is Role.APPROACH:
            j = k + 1
            while j < len(toolpath) and toolpath[j].role is Role.CORNER:
                out.add(j)
                j += 1
        elif seg.role is Role.RETRACT:
            j = k - 1
            while j >= 0 and toolpath[j].role is Role.CORNER:
                out.add(j)
                j -= 1
    return out


def _point_distance(el: Segment, p: Vec2) -> float:
    return float(points_distance(el.geometry, np.array([p], float))[0])


def clearance_limits(
    toolpath: Sequence[Segment],
    blocks: ContourBlocks,
    conts: dict[int, Continuation],
    leads: set[int],
) -> dict[int, dict[int, Limit]]:
    """Per tool segment: part element (index into ``blocks.part``) → its :class:`Limit`, where it
    is not R (see the module docstring); ``leads`` are the segments measured as lead clearance."""
    index = {id(p): i for i, p in enumerate(blocks.part)}
    out: dict[int, dict[int, Limit]] = {}
    n = len(toolpath)

    def put(k: int, i: int | None, distance: float, kind: str) -> None:
        if i is None or not 0 <= k < n or distance >= toolpath[k].radius:
            return
        old = out.setdefault(k, {}).get(i)
        if old is None or distance < old.distance:
            out[k][i] = Limit(distance, kind)

    get = index.get
    for k, c in conts.items():
        # both tool segments at the joint, against the programmed elements that meet there, and
        # the line against the element at its other end (which its tilt approaches); put() inlined
        limit = toolpath[k].radius * math.cos(c.turn)
        lim = Limit(limit, NEAR_TANGENT)
        puts = [(k, get(id(c.previous))), (k - 1, get(id(c.previous))), (k, get(id(c.programmed))),
                (k - 1, get(id(c.programmed)))]  # fmt: skip
        if c.following is not None:
            puts.append((k, get(id(c.following))))
        for kk, i in puts:
            if i is None or not 0 <= kk < n or limit >= toolpath[kk].radius:
                continue
            own = out.get(kk)
            if own is None:
                out[kk] = {i: lim}
                continue
            old = own.get(i)
            if old is None or limit < old.distance:
                own[i] = lim
    part_by_line: dict[int, list[int]] = {}
    for i, p in enumerate(blocks.part):
        part_by_line.setdefault(p.span.line, []).append(i)
    for closing in blocks.closings:
        first, last = (
            [
                k
                for k, s in enumerate(toolpath)
                if s.span.line == line and s.radius > 0.0 and s.role in (Role.CONTOUR, Role.CORNER) and k not in leads
            ]
            for line in (closing.first_line, closing.last_line)
        )
        if not first or not last:
            continue
        # only where a lead move ends (starts) at that point: its own lead clearance shows the overlap
        if first[0] > 0 and first[0] - 1 not in leads or last[-1] + 1 < len(toolpath) and last[-1] + 1 not in leads:
            continue
        entry, exit_ = toolpath[first[0]].geometry.point2(0.0), toolpath[last[-1]].geometry.point2(1.0)
        for ks, point, across in ((first, entry, closing.last_line), (last, exit_, closing.first_line)):
            for i in part_by_line.get(across, []):
                limit = _point_distance(blocks.part[i], point)
                for k in ks:
                    put(k, i, limit, CLOSING)
    return out
