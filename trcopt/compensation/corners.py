"""Junction geometry between two compensated elements (spec R14–R24).

Pure functions of the two elements' programmed geometry and modal state: classification of the
junction (tangential, outside, inside), the G450 transition circle (with the DISC conic), the
G451 / near-tangent intersection, and the approach/retraction junctions of NORM, KONT, KONTT and
KONTC. Inside corners depend on how far the previous block has been trimmed and are resolved by
:mod:`trcopt.compensation.junctions`.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Callable
from dataclasses import dataclass, field

from trcopt.codes import Code
from trcopt.compensation.elements import Elem, ElemKind, Piece
from trcopt.config import TrcSettings
from trcopt.errors import AlarmError, Diagnostic, Severity
from trcopt.geometry import vec
from trcopt.geometry.intersect import intersections
from trcopt.geometry.poly import Poly, SamplingError, conic_curve, hermite_curve
from trcopt.geometry.primitives import Arc, Line
from trcopt.geometry.vec import Vec2
from trcopt.modes import CornerMode
from trcopt.path import Role

__all__ = ["JunctionKind", "Outside", "classify", "outside_corner", "transition_conic"]


class JunctionKind(enum.Enum):
    TANGENTIAL = "tangential"
    OUTSIDE = "outside"
    INSIDE = "inside"


def classify(a: Elem, b: Elem, settings: TrcSettings) -> tuple[JunctionKind, float]:
    """Kind of the junction a→b and the signed deflection δ (rad), spec §0.4."""
    t1, t2 = a.end_tangent(), b.start_tangent()
    delta = vec.deflection(t1, t2)
    pa, pb = a.off_end.end, b.off_start.start
    gap = math.hypot(pa[0] - pb[0], pa[1] - pb[1])
    if gap <= settings.tolerances.coincidence_mm and vec.dot(t1, t2) > 0.0:
        return JunctionKind.TANGENTIAL, delta
    if abs(delta) >= math.pi - 1e-12:
        return JunctionKind.OUTSIDE, -a.side * math.pi  # reversal: outside, turning away from the tool
    if a.side * delta < 0.0:
        return JunctionKind.OUTSIDE, delta
    if delta == 0.0:
        return JunctionKind.TANGENTIAL, delta
    return JunctionKind.INSIDE, delta


@dataclass(slots=True)
class Outside:
    """Result of an outside corner: where a ends and what b starts with.

    ``lam_a`` is the end parameter on a's offset (None = its natural end λ=1); ``trailing`` are
    pieces appended to a's chain (approach bypass circle), ``leading`` the pieces b's chain starts
    with, ``lam_b`` the start parameter of b's own offset.
    """

    lam_a: float | None = None
    trailing: list[Piece] = field(default_factory=list)
    leading: list[Piece] = field(default_factory=list)
    lam_b: float = 0.0


def transition_conic(k: Vec2, q0: Vec2, q2: Vec2, radius: float, delta: float, disc: int, w: float) -> Poly:
    """DISC transition (spec R22, [A]): rational quadratic Bézier whose mid-point lies at
    ``R + DISC/100 · (R/cos(|δ|/2) − R)`` from the corner K; DISC=100 reaches the intersection."""
    half = abs(delta) / 2.0
    x_dist = radius / math.cos(half)
    bis = vec.unit(vec.sub(vec.scale(vec.add(q0, q2), 0.5), k))
    q1 = vec.add(k, vec.scale(bis, x_dist))
    target = radius + disc / 100.0 * (x_dist - radius)
    # mid-point of a conic: M = (Q0 + Q2)/2·1/(1+w) + Q1·w/(1+w); solve |M − K| = target for w
    m0 = vec.scale(vec.add(q0, q2), 0.5)
    d0 = vec.dot(vec.sub(m0, k), bis)
    d1 = vec.dot(vec.sub(q1, k), bis)
    if target >= d1 - 1e-12:
        weight = 1e9
    else:
        weight = (target - d0) / (d1 - target)
    return conic_curve(q0, q1, q2, max(weight, 1e-9), w, label=f"DISC={disc}")


def outside_corner(
    a: Elem,
    b: Elem,
    delta: float,
    settings: TrcSettings,
    corner: CornerMode,
    disc: int,
    arc_owner_is_a: bool = False,
    arc_role: Role = Role.CORNER,
) -> Outside:
    """Outside corner a→b: transition circle (G450, DISC) or intersection (G451, R24)."""
    k = (a.prog.end[0], a.prog.end[1])
    absd = abs(delta)
    disc = min(disc, settings.cutcom_max_disc)
    use_intersection = (
        absd < settings.curve_insert_limit_rad
        or (corner is CornerMode.INTERSECTION and absd <= settings.corner_limit_rad)
        or disc >= 100  # DISC=100: the corner at the intersection of the equidistants (R22)
    )
    if use_intersection:
        hits = intersections(a.off_end, b.off_start)
        if hits:
            best = min(hits, key=lambda h: vec.dist(h.point, k))
            return Outside(lam_a=best.lam_a, lam_b=best.lam_b)
    q0 = a.off_end.point2(1.0)
    q2 = b.off_start.point2(0.0)
    radius = vec.dist(q0, k)
    w = a.prog.end[2]
    carrier: Arc | Poly
    if disc > 0:
        carrier = _curve(a, lambda: transition_conic(k, q0, q2, radius, delta, disc, w))
    else:
        carrier = Arc(k, radius, math.atan2(q0[1] - k[1], q0[0] - k[0]), delta, w, w)
    owner = a if arc_owner_is_a else b
    piece = Piece(owner, arc_role, 0.0, 1.0, main=False, carrier=carrier)
    if arc_owner_is_a:
        return Outside(trailing=[piece])
    return Outside(leading=[piece])


def behind(p_ref: Vec2, p_other: Vec2, tangent: Vec2, side: int) -> bool:
    """Spec R14: the start (end) point lies behind the contour."""
    return side * vec.cross(tangent, vec.sub(p_other, p_ref)) < 0.0


def _curve(owner: Elem, make: Callable[[], Poly]) -> Poly:
    """The KONTT/KONTC polynomial or DISC conic ``make`` builds; a curve the sampler cannot resolve
    within ``MAX_CURVE_SAMPLES`` (a degenerate or extreme one) is an alarm at ``owner``'s block."""
    try:
        return make()
    except SamplingError as exc:
        raise AlarmError(Diagnostic(Severity.ERROR, Code.TRC_CURVE, str(exc), owner.span)) from None


def approach_polynomial(a: Elem, b: Elem, curvature_continuous: bool) -> Piece:
    """KONTT/KONTC approach (spec R20, [A]): Hermite polynomial from P0 to S = P1 + R·n1."""
    p0 = a.prog.start
    off = b.off_start
    s_pt = off.point2(0.0)
    s3 = (s_pt[0], s_pt[1], a.prog.end[2])
    chord = math.dist(p0, s3)
    t_end = _tangent3(off, at_start=True)
    d1 = (chord * t_end[0], chord * t_end[1], chord * t_end[2])
    u = vec.unit(vec.sub((s3[0], s3[1]), (p0[0], p0[1]))) if chord > 0 else (1.0, 0.0)
    d0 = (chord * u[0], chord * u[1], s3[2] - p0[2])
    if curvature_continuous:
        kappa = off.curvature2(0.0) if isinstance(off, Arc) else 0.0
        n = vec.rot90(off.start_tangent())
        a1 = (chord * chord * kappa * n[0], chord * chord * kappa * n[1], 0.0)
        poly = _curve(b, lambda: hermite_curve(p0, d0, s3, d1, (0.0, 0.0, 0.0), a1, label="KONTC"))
    else:
        poly = _curve(b, lambda: hermite_curve(p0, d0, s3, d1, label="KONTT"))
    return Piece(a, Role.APPROACH, 0.0, 1.0, main=False, carrier=poly)


def retract_polynomial(a: Elem, b: Elem, curvature_continuous: bool) -> Piece:
    """KONTT/KONTC retraction: mirror of :func:`approach_polynomial` from a's offset end to T."""
    off = a.off_end
    e_pt = off.point2(1.0)
    e3 = (e_pt[0], e_pt[1], b.prog.start[2])
    t3 = b.prog.end
    chord = math.dist(e3, t3)
    t_start = _tangent3(off, at_start=False)
    d0 = (chord * t_start[0], chord * t_start[1], chord * t_start[2])
    u = vec.unit(vec.sub((t3[0], t3[1]), e_pt)) if chord > 0 else (1.0, 0.0)
    d1 = (chord * u[0], chord * u[1], t3[2] - e3[2])
    if curvature_continuous:
        kappa = off.curvature2(1.0) if isinstance(off, Arc) else 0.0
        n = vec.rot90(off.end_tangent())
        a0 = (chord * chord * kappa * n[0], chord * chord * kappa * n[1], 0.0)
        poly = _curve(b, lambda: hermite_curve(e3, d0, t3, d1, a0, (0.0, 0.0, 0.0), label="KONTC"))
    else:
        poly = _curve(b, lambda: hermite_curve(e3, d0, t3, d1, label="KONTT"))
    return Piece(b, Role.RETRACT, 0.0, 1.0, main=False, carrier=poly)


def _tangent3(g: Line | Arc, at_start: bool) -> tuple[float, float, float]:
    t = g.start_tangent() if at_start else g.end_tangent()
    plane_len = g.plane_length
    slope = (g.end[2] - g.start[2]) / plane_len if plane_len > 0 else 0.0
    n = math.sqrt(1.0 + slope * slope)
    return (t[0] / n, t[1] / n, slope / n)


def corner_mode_for(a: Elem, b: Elem) -> tuple[CornerMode, int]:
    """G450/G451 and DISC in force at the junction a→b (the following block's state; the
    selection block's state for the approach, R19)."""
    owner = a if a.kind is ElemKind.APPROACH else b
    return owner.comp.corner, owner.comp.disc

