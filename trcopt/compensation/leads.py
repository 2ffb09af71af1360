"""Dialect-neutral lead specification and the exact geometry of its points P0…P4.

A lead (approach or retraction) runs P0 → P1 → P2 → P3 → P4 (retraction: the reverse), spec
``sinumerik_trc.md`` §A.8 (R37–R42). All points are in plane coordinates (u, v, w) of the working
plane: (u, v) the plane, w the applicate. The contour P3 → P4 is a line, a quarter circle or a
half circle; with spatial segmentation and P3 off the machining plane it is a slanted line or a
helix.

Conventions (stated once, used everywhere here): ``side`` +1 = left of travel (G41 / G141),
−1 = right; ``rot90(a) = (−a_v, a_u)``; the lead circle of side q turns with sense σ = q
(counter-clockwise for the left side). With compensation on side s and radius R the *programmed*
circle has radius ρp = DISR + s·σ·R so that its offset — the tool-centre circle — has radius DISR.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from trcopt.errors import AlarmError, SourceSpan, alarm
from trcopt.geometry import vec
from trcopt.geometry.vec import Vec2, Vec3
from trcopt.modes import LeadSegmentation, LeadShape, LeadSide, RetractEnd, SarContour
from trcopt.nc.model import SarSpec

__all__ = [
    "LeadSpec",
    "SarGeometry",
    "lead_spec",
    "sar_points",
    "side_from_start_point",
]


@dataclass(frozen=True, slots=True)
class LeadSpec:
    """One approach or retraction lead, independent of the NC dialect.

    Parameters
    ----------
    shape, approach:
        Contour shape and direction (``approach=False`` for a retraction).
    side:
        Side of the lead circle (ignored for lines).
    segmentation:
        Spatial (G340) or planar (G341).
    disr:
        Line: distance of the cutter edge from P4 (mm; the line is DISR + R long with
        compensation). Circle: radius of the tool-centre path (mm). ``None`` = not programmed.
    discl, discl_absolute:
        Level of P2: ``w4 + discl`` (mm along +applicate) or the absolute applicate ``discl``.
    disrp, disrp_absolute:
        Level of P1 (retraction plane) likewise; ``None`` = the level of P0.
    """

    shape: LeadShape
    approach: bool = True
    side: LeadSide = LeadSide.FROM_COMPENSATION
    segmentation: LeadSegmentation = LeadSegmentation.SPATIAL
    disr: float | None = None
    discl: float | None = None
    discl_absolute: bool = False
    disrp: float | None = None
    disrp_absolute: bool = False


_SHAPES = {
    SarContour.G147: LeadShape.LINE,
    SarContour.G148: LeadShape.LINE,
    SarContour.G247: LeadShape.QUADRANT,
    SarContour.G248: LeadShape.QUADRANT,
    SarContour.G347: LeadShape.SEMICIRCLE,
    SarContour.G348: LeadShape.SEMICIRCLE,
}


def lead_spec(spec: SarSpec | LeadSpec) -> LeadSpec:
    """The dialect-neutral lead of a SINUMERIK SAR block (a :class:`LeadSpec` passes through)."""
    if isinstance(spec, LeadSpec):
        return spec
    discl, discl_abs = spec.discl if spec.discl is not None else (None, False)
    disrp, disrp_abs = spec.disrp if spec.disrp is not None else (None, False)
    return LeadSpec(
        shape=_SHAPES[spec.contour],
        approach=spec.contour.is_approach,
        side=spec.side,
        segmentation=spec.segmentation,
        disr=spec.disr,
        discl=discl,
        discl_absolute=discl_abs,
        disrp=disrp,
        disrp_absolute=disrp_abs,
    )


@dataclass(frozen=True, slots=True)
class SarGeometry:
    """The exact points of one lead, in plane coordinates (u, v, w), mm.

    ``p0``…``p4`` are programmed (uncompensated) points in the order of the approach: P0 is the
    start point (approach) or the end point (retraction), P4 the contour point. ``center`` is the
    centre of the programmed lead circle (``None`` for a line), ``ccw`` its sense seen from
    +applicate in the direction of *travel* (approach P3→P4, retraction P4→P3), ``side`` the
    circle side q (+1 left, −1 right, 0 for a line). ``radius_programmed`` is ρp (the internal
    circle TRC offsets), ``radius_centre`` the tool-centre radius (= DISR). ``helix`` is True when
    the circle is traversed with applicate motion (spatial segmentation, P3 off the plane of P4).
    ``p3_centre``/``p4_centre`` are the tool-centre plane points at P3 and P4 (R39).
    """

    shape: LeadShape
    approach: bool
    p0: Vec3
    p1: Vec3
    p2: Vec3
    p3: Vec3
    p4: Vec3
    tangent: Vec2
    side: int
    center: Vec2 | None
    ccw: bool | None
    radius_programmed: float | None
    radius_centre: float | None
    line_length: float | None
    helix: bool
    p3_centre: Vec2
    p4_centre: Vec2
    snapped: bool = False

    @property
    def points(self) -> tuple[Vec3, Vec3, Vec3, Vec3, Vec3]:
        return (self.p0, self.p1, self.p2, self.p3, self.p4)


def side_from_start_point(tangent: Vec2, p4: Vec2, point: Vec2) -> int:
    """G143: +1 when ``point`` lies left of the tangent line through P4, else −1.

    A point exactly on the tangent line counts as left (assumption; the manuals are silent).
    """
    return 1 if vec.cross(tangent, vec.sub(point, p4)) >= 0.0 else -1


def _fail(number: int, message: str, span: SourceSpan) -> AlarmError:
    return AlarmError(alarm(number, message, span))


def sar_points(
    spec: SarSpec | LeadSpec,
    *,
    p0: Vec3,
    p4: Vec3,
    tangent: Vec2,
    comp_side: int = 0,
    radius: float = 0.0,
    retract_end: RetractEnd = RetractEnd.PROGRAMMED,
    clearance_tolerance: float = 0.01,
    span: SourceSpan | None = None,
) -> SarGeometry:
    """Exact geometry of a smooth approach/retraction (spec R37–R42).

    Parameters
    ----------
    spec:
        The SAR words of the block (:class:`~trcopt.nc.model.SarSpec`) or a :class:`LeadSpec`.
    p0:
        Start point of the approach / programmed end point of the retraction, (u, v, w) in mm.
        For ``retract_end`` APPLICATE_ONLY only its w counts; for NONE it is ignored.
    p4:
        Contour point (u, v, w) in mm.
    tangent:
        Plane tangent at P4 (approach: start tangent of the contour; retraction: its end
        tangent); normalised here.
    comp_side:
        Compensation side in force for the lead contour after the sign normalisation of spec
        §0.2: +1 G41, −1 G42, 0 off.
    radius:
        Effective compensation radius |R| in mm (DP6 + DP15 + OFFN).
    retract_end:
        Which coordinates the retraction block programs (R45).
    clearance_tolerance:
        MD20204 WAB_CLEARANCE_TOLERANCE, mm: P2 outside [P1, P3] by at most this much is snapped.
    span:
        Source span for the alarms.

    Raises
    ------
    AlarmError
        10742 (DISR missing/invalid, line length or circle radius ≤ 0), 10741 (direction
        reversal of the infeed), 10748 (illegal retraction plane DISRP), 10747 (automatic side on
        retraction without a programmed end point).
    """
    lead = lead_spec(spec)
    where = span or SourceSpan()
    t_raw = (float(tangent[0]), float(tangent[1]))
    if not all(math.isfinite(c) for c in t_raw) or vec.norm(t_raw) <= 1e-12:
        raise _fail(
            10744, "no valid SAR direction: the tangent at the contour point is undefined", where
        )
    t = vec.unit(t_raw)
    n_left = vec.rot90(t)
    p4_2 = (p4[0], p4[1])
    s = 0 if comp_side == 0 else (1 if comp_side > 0 else -1)
    r = abs(radius) if s else 0.0
    w4 = p4[2]

    # ---- side of the lead circle (R37)
    q = 0
    if lead.shape is not LeadShape.LINE:
        if lead.side is LeadSide.LEFT:
            q = 1
        elif lead.side is LeadSide.RIGHT:
            q = -1
        elif lead.side is LeadSide.FROM_COMPENSATION and s != 0:
            q = s
        else:
            if not lead.approach and retract_end is not RetractEnd.PROGRAMMED:
                raise _fail(
                    10747,
                    "retraction side undefined: automatic side (G143, or G140 without TRC) "
                    "needs a programmed end point in the SAR block",
                    where,
                )
            q = side_from_start_point(t, p4_2, (p0[0], p0[1]))

    # ---- line length / circle radius (R38)
    center: Vec2 | None = None
    rho_p: float | None = None
    rho_c: float | None = None
    length: float | None = None
    if lead.shape is LeadShape.LINE:
        disr = 0.0 if lead.disr is None else lead.disr  # assumption: missing DISR on a line = 0
        length = disr + (r if r > 0.0 else 0.0)
        if length <= 0.0:
            raise _fail(
                10742,
                f"SAR line length DISR + R = {length:g} mm is not positive "
                f"(DISR {disr:g}, R {r:g})",
                where,
            )
        sign = -1.0 if lead.approach else 1.0
        p3_2 = vec.add(p4_2, vec.scale(t, sign * length))
        p3c = vec.add(p3_2, vec.scale(n_left, s * r))
    else:
        if lead.disr is None:
            raise _fail(10742, "SAR circle without DISR (radius of the tool-centre path)", where)
        if lead.disr <= 0.0:
            raise _fail(10742, f"SAR circle radius DISR = {lead.disr:g} mm must be positive", where)
        rho_c = lead.disr
        rho_p = lead.disr + s * q * r
        if rho_p <= 0.0:
            raise _fail(
                10742,
                f"internal SAR circle radius DISR + s·σ·R = {rho_p:g} mm is not positive "
                "(the lead circle lies on the tool side and is smaller than the tool)",
                where,
            )
        center = vec.add(p4_2, vec.scale(n_left, q * rho_p))
        if lead.shape is LeadShape.QUADRANT:
            sign = -1.0 if lead.approach else 1.0
            p3_2 = vec.add(center, vec.scale(t, sign * rho_p))
        else:
            p3_2 = vec.add(p4_2, vec.scale(n_left, 2.0 * q * rho_p))
        p3c = vec.add(center, vec.scale(vec.sub(p3_2, center), rho_c / rho_p))
    p4c = vec.add(p4_2, vec.scale(n_left, s * r))

    # ---- applicate levels (R41)
    w0 = p0[2]
    if not lead.approach and retract_end is RetractEnd.NONE:
        w0 = math.nan  # decided below: the lead ends in P2
    if lead.disrp is None:
        w1 = w0
    else:
        w1 = lead.disrp if lead.disrp_absolute else w4 + lead.disrp
    if lead.discl is None:
        w2 = w4
    else:
        w2 = lead.discl if lead.discl_absolute else w4 + lead.discl
    if math.isnan(w1):  # retraction without geometry axes: P0 = P1 = P2
        w1 = w0 = w2
    discl_zero = abs(w2 - w4) <= 1e-12
    spatial = lead.segmentation is LeadSegmentation.SPATIAL
    if spatial and discl_zero:
        w2 = w1  # §D-3: P1, P2, P3 coincide; the contour runs from P1 to P4

    # ---- no direction reversal along the applicate (R42)
    snapped = False
    lo, hi = min(w1, w4), max(w1, w4)
    if w2 < lo or w2 > hi:
        excess = lo - w2 if w2 < lo else w2 - hi
        if excess <= clearance_tolerance:
            w2 = lo if w2 < lo else hi
            snapped = True
        else:
            beyond_p1 = (w2 - w4) * (w1 - w4) > 0.0  # P2 on P1's side, but farther than P1
            if lead.disrp is not None and beyond_p1:
                raise _fail(
                    10748,
                    f"illegal retraction plane DISRP: P1 at {w1:g} lies between the plane "
                    f"{w4:g} and the DISCL level {w2:g}",
                    where,
                )
            raise _fail(
                10741,
                f"SAR infeed reverses direction: DISCL level {w2:g} lies outside {lo:g}…{hi:g} "
                f"by {excess:g} mm (> WAB_CLEARANCE_TOLERANCE {clearance_tolerance:g})",
                where,
            )
    if lead.disrp is not None and lead.approach and not math.isnan(w0):
        # P0→P1 must not run against the infeed either
        if (w1 - w0) * (w4 - w1) < 0.0 and min(abs(w1 - w0), abs(w4 - w1)) > clearance_tolerance:
            raise _fail(
                10748, f"illegal retraction plane DISRP: P1 at {w1:g} reverses the infeed", where
            )
    w3 = w2 if spatial else w4

    if not lead.approach and retract_end is RetractEnd.NONE:
        p0 = (p3_2[0], p3_2[1], w2)
    elif not lead.approach and retract_end is RetractEnd.APPLICATE_ONLY:
        p0 = (p3_2[0], p3_2[1], w1)
    p1 = (p3_2[0], p3_2[1], w1)
    p2 = (p3_2[0], p3_2[1], w2)
    p3 = (p3_2[0], p3_2[1], w3)
    helix = lead.shape is not LeadShape.LINE and abs(w3 - w4) > 1e-12
    return SarGeometry(
        shape=lead.shape,
        approach=lead.approach,
        p0=(float(p0[0]), float(p0[1]), float(w0 if lead.approach else p0[2])),
        p1=p1,
        p2=p2,
        p3=p3,
        p4=(p4[0], p4[1], w4),
        tangent=t,
        side=q,
        center=center,
        ccw=None if center is None else q > 0,
        radius_programmed=rho_p,
        radius_centre=rho_c,
        line_length=length,
        helix=helix,
        p3_centre=p3c,
        p4_centre=p4c,
        snapped=snapped,
    )
