"""Heidenhain APPR/DEP geometry (spec ``heidenhain_trc.md`` §7) in working-plane coordinates (u, v).

Points as the spec names them: ``PS`` start point (reached with R0), ``PH`` auxiliary point, ``PA``
first contour point, ``PE`` last contour point, ``PN`` end point (reached with R0). ``t`` is the start
tangent of the first contour element at PA (the end tangent of the last one at PE), ``s`` the side
(+1 RL, −1 RR), ``n = s·nL(t)`` the unit normal toward the tool, ``r`` the compensation value (mm).

Each function returns a :class:`Lead`: the tool-centre path of the spec's table (``centre``, for
checks and pictures) and the pieces the front end hands to the compensation engine (``pieces``):
a piece with ``compensated=True`` is contour-level geometry that the engine offsets by ``r`` on side
``s`` (an approach's first compensated piece is the engine's selection line, whose end the engine
places perpendicular to the next element); ``compensated=False`` pieces are already tool-centre
(side R0). Both describe the same path.

APPR/DEP CT and LCT radius reading (spec R9) is a setting: ``radius_ref="contour"`` (recommended
default: R is the radius of the contour-level arc, the tool centre runs on ``R ∓ r``) or
``"centre"`` (R is the tool-centre radius).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from trcopt.codes import Code
from trcopt.geometry import vec
from trcopt.geometry.vec import Vec2
from trcopt.modes import ApprRadius, parse_enum

__all__ = [
    "LeadPiece",
    "Lead",
    "LeadError",
    "appr_lt",
    "appr_ln",
    "appr_ct",
    "appr_lct",
    "dep_lt",
    "dep_ln",
    "dep_ct",
    "dep_lct",
]



class LeadError(ValueError):
    """APPR/DEP geometry impossible; ``code`` is the spec's error code."""

    def __init__(self, code: Code, message: str) -> None:
        super().__init__(message)
        self.code = code
        self.message = message


@dataclass(frozen=True, slots=True)
class LeadPiece:
    """A line (``center is None``) or arc from ``start`` to ``end`` (plane mm)."""

    start: Vec2
    end: Vec2
    center: Vec2 | None = None
    ccw: bool | None = None
    compensated: bool = False


@dataclass(frozen=True, slots=True)
class Lead:
    """An approach or departure: tool-centre path, engine pieces and the named points."""

    centre: tuple[LeadPiece, ...]
    pieces: tuple[LeadPiece, ...]
    points: dict[str, Vec2]


def _normal(t: Vec2, side: int) -> Vec2:
    return vec.scale(vec.rot90(vec.unit(t)), float(side))


def _contour_radius(radius: float, r: float, radius_ref: ApprRadius | str) -> float:
    """Signed radius of the contour-level arc (centre at PA + Rc·n) for the programmed R."""
    ref = parse_enum(ApprRadius, radius_ref, "APPR/DEP radius reading")
    return radius if ref is ApprRadius.CONTOUR else radius + r


def _centre_radius(rc: float, r: float) -> float:
    """Tool-centre radius about M = P + Rc·n: Rc − r (tool side) or |Rc| + r (material side)."""
    rho = rc - r if rc > 0 else -rc + r
    if rc == 0.0 or (rc > 0 and rho <= 1e-9):
        raise LeadError(
            Code.HH_TOOL_RADIUS_TOO_LARGE,
            f"Tool radius too large: the tool-centre arc of the approach/departure has radius "
            f"{rho:.4f} mm (R {rc:+.4f}, compensation {r:.4f})",
        )
    return rho


def _check_cca(cca: float) -> None:
    if not 0.0 < cca <= 360.0:
        raise LeadError(Code.HH_APPR_CCA, f"centre angle CCA {cca:g} must lie in (0, 360]")


def _on(m: Vec2, rho: float, p: Vec2) -> Vec2:
    return vec.add(m, vec.scale(vec.unit(vec.sub(p, m)), rho))


def _tangent_point(m: Vec2, rho: float, p: Vec2, ccw: bool, leaving: bool) -> Vec2:
    """Tangent point on circle (m, rho) of the line through p, consistent with travel sense ``ccw``
    (``leaving``: the tool leaves the circle toward p; else it arrives from p)."""
    d = vec.dist(p, m)
    if d <= rho + 1e-9:
        raise LeadError(
            Code.HH_APPR_NO_TANGENT,
            f"point ({p[0]:.4f}, {p[1]:.4f}) lies within the tool-centre circle of radius {rho:.4f}",
        )
    phi = vec.angle_of(vec.sub(p, m))
    beta = math.acos(rho / d)
    k = 1.0 if ccw else -1.0
    for a in (phi + beta, phi - beta):
        q = vec.polar(m, rho, a)
        tan = (-math.sin(a) * k, math.cos(a) * k)
        towards = vec.sub(p, q) if leaving else vec.sub(q, p)
        if vec.dot(tan, towards) > 0.0:
            return q
    raise LeadError(Code.HH_APPR_NO_TANGENT, "no tangent from the point to the approach circle")


def _rot(m: Vec2, p: Vec2, angle: float) -> Vec2:
    a = vec.angle_of(vec.sub(p, m)) + angle
    return vec.polar(m, vec.dist(p, m), a)


def appr_lt(ps: Vec2, pa: Vec2, t: Vec2, side: int, r: float, length: float) -> Lead:
    """APPR LT: PH = PA − LEN·t; tool centre PS → PH + r·n → PA + r·n."""
    if length <= 0.0:
        raise LeadError(Code.HH_SYNTAX, f"APPR LT needs LEN > 0 (got {length:g})")
    n, tu = _normal(t, side), vec.unit(t)
    ph = vec.sub(pa, vec.scale(tu, length))
    ph_c, pa_c = vec.add(ph, vec.scale(n, r)), vec.add(pa, vec.scale(n, r))
    centre = (LeadPiece(ps, ph_c), LeadPiece(ph_c, pa_c))
    pieces = (LeadPiece(ps, ph_c), LeadPiece(ph_c, pa, compensated=True))
    return Lead(centre, pieces, {"PS": ps, "PH": ph, "PA": pa})


def appr_ln(ps: Vec2, pa: Vec2, t: Vec2, side: int, r: float, length: float) -> Lead:
    """APPR LN: PH_c = PA + (r + LEN)·n (spec R8); tool centre PS → PH_c → PA + r·n."""
    if length <= 0.0:
        raise LeadError(Code.HH_SYNTAX, f"APPR LN needs LEN > 0 (got {length:g})")
    n = _normal(t, side)
    ph_c, pa_c = vec.add(pa, vec.scale(n, r + length)), vec.add(pa, vec.scale(n, r))
    centre = (LeadPiece(ps, ph_c), LeadPiece(ph_c, pa_c))
    pieces = (LeadPiece(ps, ph_c), LeadPiece(ph_c, pa, compensated=True))
    return Lead(centre, pieces, {"PS": ps, "PH": vec.add(pa, vec.scale(n, length)), "PA": pa})


def appr_ct(
    ps: Vec2,
    pa: Vec2,
    t: Vec2,
    side: int,
    r: float,
    cca: float,
    radius: float,
    radius_ref: ApprRadius | str = ApprRadius.CONTOUR,
) -> Lead:
    """APPR CT: arc tangent to the first element at PA, centre M = PA + Rc·n, through CCA (deg);
    R > 0: centre on the tool side (RL CCW, RR CW), R < 0: on the material side (RL CW, RR CCW)."""
    _check_cca(cca)
    n = _normal(t, side)
    rc = _contour_radius(radius, r, radius_ref)
    rho = _centre_radius(rc, r)
    m = vec.add(pa, vec.scale(n, rc))
    ccw = side * rc > 0
    back = -math.radians(cca) if ccw else math.radians(cca)
    ph = _rot(m, pa, back)
    pa_c = vec.add(pa, vec.scale(n, r))
    ph_c = _on(m, rho, ph)
    centre = (LeadPiece(ps, ph_c), LeadPiece(ph_c, pa_c, m, ccw))
    pieces = (LeadPiece(ps, ph, compensated=True), LeadPiece(ph, pa, m, ccw, compensated=True))
    return Lead(centre, pieces, {"PS": ps, "PH": ph, "PA": pa, "M": m})


def appr_lct(
    ps: Vec2, pa: Vec2, t: Vec2, side: int, r: float, radius: float, radius_ref: ApprRadius | str = ApprRadius.CONTOUR
) -> Lead:
    """APPR LCT: line from PS tangent to an arc of radius R (> 0) that is tangent to the first
    element at PA (centre M = PA + Rc·n, RL CCW, RR CW)."""
    if radius <= 0.0:
        raise LeadError(Code.HH_SYNTAX, f"APPR LCT needs R > 0 (got {radius:g})")
    n = _normal(t, side)
    rc = _contour_radius(radius, r, radius_ref)
    rho = _centre_radius(rc, r)
    m = vec.add(pa, vec.scale(n, rc))
    ccw = side > 0
    ph_c = _tangent_point(m, rho, ps, ccw, leaving=False)
    ph = _on(m, rc, ph_c)
    pa_c = vec.add(pa, vec.scale(n, r))
    centre = (LeadPiece(ps, ph_c), LeadPiece(ph_c, pa_c, m, ccw))
    pieces = (LeadPiece(ps, ph, compensated=True), LeadPiece(ph, pa, m, ccw, compensated=True))
    return Lead(centre, pieces, {"PS": ps, "PH": ph, "PA": pa, "M": m})


def dep_lt(pe: Vec2, t: Vec2, side: int, r: float, length: float) -> Lead:
    """DEP LT: PN = PE + r·n + LEN·t (spec R10); R0 from PN on."""
    if length <= 0.0:
        raise LeadError(Code.HH_SYNTAX, f"DEP LT needs LEN > 0 (got {length:g})")
    n, tu = _normal(t, side), vec.unit(t)
    pe_c = vec.add(pe, vec.scale(n, r))
    pn = vec.add(pe_c, vec.scale(tu, length))
    return Lead((LeadPiece(pe_c, pn),), (LeadPiece(pe, pn),), {"PE": pe, "PN": pn})


def dep_ln(pe: Vec2, t: Vec2, side: int, r: float, length: float) -> Lead:
    """DEP LN: PN = PE + (r + LEN)·n (spec R8)."""
    if length <= 0.0:
        raise LeadError(Code.HH_SYNTAX, f"DEP LN needs LEN > 0 (got {length:g})")
    n = _normal(t, side)
    pe_c = vec.add(pe, vec.scale(n, r))
    pn = vec.add(pe, vec.scale(n, r + length))
    return Lead((LeadPiece(pe_c, pn),), (LeadPiece(pe, pn),), {"PE": pe, "PN": pn})


def dep_ct(
    pe: Vec2, t: Vec2, side: int, r: float, cca: float, radius: float, radius_ref: ApprRadius | str = ApprRadius.CONTOUR
) -> Lead:
    """DEP CT: tangential arc about M = PE + Rc·n through CCA (same sign rules as APPR CT)."""
    _check_cca(cca)
    n = _normal(t, side)
    rc = _contour_radius(radius, r, radius_ref)
    rho = _centre_radius(rc, r)
    m = vec.add(pe, vec.scale(n, rc))
    ccw = side * rc > 0
    sweep = math.radians(cca) if ccw else -math.radians(cca)
    pn_contour = _rot(m, pe, sweep)
    pe_c = vec.add(pe, vec.scale(n, r))
    pn = _on(m, rho, pn_contour)
    centre = (LeadPiece(pe_c, pn, m, ccw),)
    pieces = (LeadPiece(pe, pn_contour, m, ccw, compensated=True), LeadPiece(pn_contour, pn))
    return Lead(centre, pieces, {"PE": pe, "PN": pn, "M": m})


def dep_lct(
    pe: Vec2, t: Vec2, side: int, r: float, pn: Vec2, radius: float, radius_ref: ApprRadius | str = ApprRadius.CONTOUR
) -> Lead:
    """DEP LCT: arc from PE about M = PE + Rc·n (RL CCW, RR CW) to the tangent point PH, then the
    tangent line PH → PN (R0)."""
    if radius <= 0.0:
        raise LeadError(Code.HH_SYNTAX, f"DEP LCT needs R > 0 (got {radius:g})")
    n = _normal(t, side)
    rc = _contour_radius(radius, r, radius_ref)
    rho = _centre_radius(rc, r)
    m = vec.add(pe, vec.scale(n, rc))
    ccw = side > 0
    ph_c = _tangent_point(m, rho, pn, ccw, leaving=True)
    ph = _on(m, rc, ph_c)
    pe_c = vec.add(pe, vec.scale(n, r))
    centre = (LeadPiece(pe_c, ph_c, m, ccw), LeadPiece(ph_c, pn))
    pieces = (LeadPiece(pe, ph, m, ccw, compensated=True), LeadPiece(ph, pn))
    return Lead(centre, pieces, {"PE": pe, "PH": ph, "PN": pn, "M": m})
