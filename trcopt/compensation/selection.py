"""How a compensation region starts and ends: the junctions of the selection (approach) block and
the deselection (retraction) block (spec R13–R21, R31–R35).

* :func:`approach_join` — NORM (straight to S = P1 + R·n1), KONT (bypass circle when the start
  point lies behind the contour, R14), KONTT/KONTC (Hermite polynomial, R20);
* :func:`retract_join` — the mirror image for the deselection block;
* :func:`retract_behind` — the KONT retraction whose end point lies behind the contour;
* :func:`auxiliary` — the auxiliary element of G461 (circle of the tool radius around the
  programmed point) or G462 (straight extension) that the search of an unresolved first or last
  corner walks along.

Which junction rules apply between two contour blocks is :mod:`trcopt.compensation.junctions`.
"""

from __future__ import annotations

import math

from trcopt.codes import Code
from trcopt.compensation import corners as cn
from trcopt.compensation.elements import Elem, Piece
from trcopt.compensation.lookahead import Join
from trcopt.config import TrcSettings
from trcopt.errors import AlarmError, Diagnostic, Severity, alarm
from trcopt.geometry import vec
from trcopt.geometry.primitives import Arc, Line
from trcopt.geometry.vec import Vec2
from trcopt.modes import ApproachMode, ApproachStrategy
from trcopt.nc.model import MoveKind
from trcopt.path import Role

__all__ = ["approach_join", "retract_join", "retract_behind", "auxiliary", "AUX_LINE_MM"]

AUX_LINE_MM = 1.0e5  # length of the G462 tangent extension searched for an intersection


def approach_join(a: Elem, b: Elem, settings: TrcSettings) -> Join:
    """The junction of the selection block ``a`` with the first contour block ``b``."""
    p0, p1 = (a.prog.start[0], a.prog.start[1]), (a.prog.end[0], a.prog.end[1])
    mode = a.comp.approach
    t1 = b.start_tangent()
    s_point = b.off_start.point2(0.0)
    if mode in (ApproachMode.KONTT, ApproachMode.KONTC):
        if a.move.kind is not MoveKind.LINE:
            raise AlarmError(
                Diagnostic(
                    Severity.ERROR,
                    Code.TRC_KONTT_BLOCK,
                    f"{mode.value} needs a G1 approach block",
                    a.span,
                )
            )
        piece = cn.approach_polynomial(a, b, mode is ApproachMode.KONTC)
        return Join(b.index, [Piece(b, b.role, 0.0, 1.0)], replace=[piece])
    if mode is ApproachMode.KONT and cn.behind(p1, p0, t1, a.side):
        if vec.dist(p0, p1) <= a.r1:
            raise AlarmError(alarm(10755, "KONT approach not possible: start point within the tool radius", a.span))
        delta = vec.deflection(vec.unit(vec.sub(p1, p0)), t1)
        corner, disc = cn.corner_mode_for(a, b)
        out = cn.outside_corner(a, b, delta, settings, corner, disc, arc_owner_is_a=True, arc_role=Role.APPROACH)
        end = None if out.lam_a is None else (0, out.lam_a)
        return Join(b.index, [Piece(b, b.role, out.lam_b, 1.0)], end=end, trailing=out.trailing)
    # NORM (and KONT in front): straight to S = P1 + R·n1
    return Join(b.index, [Piece(b, b.role, 0.0, 1.0)], replace=[Piece(a, Role.APPROACH, 0.0, 1.0, p1=s_point)])


def retract_join(a: Elem, b: Elem, i: int, settings: TrcSettings) -> Join:
    """The junction of the last contour block ``a`` (block ``i``) with the deselection block ``b``."""
    e_pt, t_pt = (b.prog.start[0], b.prog.start[1]), (b.prog.end[0], b.prog.end[1])
    mode = b.comp.approach
    t_e = a.end_tangent()
    if mode in (ApproachMode.KONTT, ApproachMode.KONTC):
        if b.move.kind is not MoveKind.LINE:
            raise AlarmError(
                Diagnostic(Severity.ERROR, Code.TRC_KONTT_BLOCK, f"{mode.value} needs a G1 retraction block", b.span)
            )
        return Join(i + 1, [cn.retract_polynomial(a, b, mode is ApproachMode.KONTC)])
    if mode is ApproachMode.KONT and cn.behind(e_pt, t_pt, t_e, a.side):
        if vec.dist(t_pt, e_pt) <= b.r0:
            raise AlarmError(alarm(10756, "KONT retraction not possible: end point within the tool radius", b.span))
        delta = vec.deflection(t_e, vec.unit(vec.sub(t_pt, e_pt)))
        corner, disc = cn.corner_mode_for(a, b)
        out = cn.outside_corner(a, b, delta, settings, corner, disc, arc_role=Role.RETRACT)
        end = None if out.lam_a is None else (-1, out.lam_a)
        return Join(i + 1, out.leading + [Piece(b, b.role, out.lam_b, 1.0)], end=end)
    return Join(i + 1, [Piece(b, Role.RETRACT, 0.0, 1.0, p0=a.off_end.point2(1.0))])


def retract_behind(last: Elem, r: Elem) -> bool:
    """KONT retraction with the end point behind the contour (R14, R18)."""
    e_pt, t_pt = (r.prog.start[0], r.prog.start[1]), (r.prog.end[0], r.prog.end[1])
    return r.comp.approach is ApproachMode.KONT and cn.behind(e_pt, t_pt, last.end_tangent(), last.side)


def auxiliary(strategy: ApproachStrategy, center: Vec2, start: Vec2, direction: Vec2, radius: float) -> Line | Arc:
    """G461: the circle of the tool radius (mm) around the programmed point, walked from ``start``
    in ``direction``; G462: the straight extension from ``start`` along ``direction``."""
    if strategy is ApproachStrategy.G462 or radius <= 0.0:
        end = (start[0] + AUX_LINE_MM * direction[0], start[1] + AUX_LINE_MM * direction[1], 0.0)
        return Line((start[0], start[1], 0.0), end)
    radial = vec.sub(start, center)
    ccw = vec.dot(vec.rot90(radial), direction) > 0.0
    sweep = (2.0 * math.pi - 1e-9) * (1.0 if ccw else -1.0)
    return Arc(center, vec.norm(radial), math.atan2(radial[1], radial[0]), sweep)
