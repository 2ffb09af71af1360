"""Circular blends between two lines in closed form: the controllers' rounding and the ``arc``
strategy, at thousands of corners per second.

A corner between two lines of one plane, turning by φ, gets the circle of radius ``r`` tangent
to both; it starts ``T = r·tan(φ/2)`` before the corner point and ends ``T`` after it. How far the
new path lies from the old one is exact:

* **vertex distance** (from the corner point to the arc's midpoint): ``r·(1/cos(φ/2) − 1)``;
* **contour distance** (the largest distance of the arc from the two lines — the Hausdorff
  distance of the blended path from the exact one): ``r·(1 − cos(φ/2))``;
* **rounding distance** (SINUMERIK ``ADIS``: the transition starts and ends this far from the
  corner): ``T``.

A :class:`FilletSpec` per joint says how large the blend may be: its tolerance and how that is
measured (:class:`~trcopt.modes.ToleranceKind`; no tolerance: as large as the lines allow), and a
largest radius. Each blend takes at most half of a line it shares with another blend and at most
:data:`LINE_SHARE` of a line it does not, so neighbouring blends never overlap.

Corners of lines on a compensated path need the cut part's view (:func:`cut_contour_spec`): at an
inside corner (pocket-like) the cut fillet of radius ``r + R`` lies ``r·(1/cos(φ/2) − 1)`` from the
exact cut's fillet of radius ``R`` — the vertex distance of the tool-centre blend; at an outside
corner (the tool-centre path meets at the intersection of its offset lines, G451) every blend with
``r ≤ R`` keeps the tool touching the programmed corner point: no material is left and nothing is
gouged, so ``r = R`` (the transition circle) is the largest.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from trcopt.geometry import Arc, Line, Poly
from trcopt.geometry.poly import CHORD_TOL_MM
from trcopt.modes import ToleranceKind, TransitionKind
from trcopt.optimize.corners.bspline_corner import bspline_corner, bspline_distances, spacing_for
from trcopt.optimize.corners.curves import joint_turn
from trcopt.optimize.corners.fillet_elements import element_blend, element_joint
from trcopt.optimize.corners.fillet_spec import (
    APPLICATE_TOL_MM,
    LINE_SHARE,
    MAX_TURN_RAD,
    MIN_LINE_MM,
    MIN_TANGENT_MM,
    TANGENT_TOL_RAD,
    Cut,
    FilletSpec,
    blend_distances,
    inside_turn,
)
from trcopt.optimize.corners.records import CornerRecord, CornerResult
from trcopt.path import Role, Segment

__all__ = [
    "LINE_SHARE",
    "MAX_TURN_RAD",
    "MIN_TANGENT_MM",
    "FilletSpec",
    "blend_distances",
    "cut_contour_spec",
    "fillet_path",
    "blend_joints",
    "element_joint",
    "line_joints",
    "rebuild_with_origin",
    "turn_angle3",
]


def _in_plane(g: Line) -> bool:
    return abs(g.start[2] - g.end[2]) <= APPLICATE_TOL_MM and g.plane_length > 1e-9


def _direction3(g: Line) -> tuple[float, float, float]:
    length = g.length
    return ((g.end[0] - g.start[0]) / length, (g.end[1] - g.start[1]) / length, (g.end[2] - g.start[2]) / length)


def turn_angle3(a: Line, b: Line) -> float:
    """Unsigned angle between the directions of two lines in space, rad."""
    ta, tb = _direction3(a), _direction3(b)
    cross = (ta[1] * tb[2] - ta[2] * tb[1], ta[2] * tb[0] - ta[0] * tb[2], ta[0] * tb[1] - ta[1] * tb[0])
    dot = ta[0] * tb[0] + ta[1] * tb[1] + ta[2] * tb[2]
    return math.atan2(math.sqrt(cross[0] ** 2 + cross[1] ** 2 + cross[2] ** 2), dot)


def line_joints(segments: Sequence[Segment]) -> list[int]:
    """The joints ``k`` (between ``segments[k]`` and ``[k + 1]``) that a circular blend can round:
    two feed lines of one working plane and the same compensation, meeting at a turn between
    :data:`TANGENT_TOL_RAD` and :data:`MAX_TURN_RAD` (measured in space: the blend lies in the
    plane of the two lines, which need not be the working plane)."""
    out = []
    for k in range(len(segments) - 1):
        s1, s2 = segments[k], segments[k + 1]
        g1, g2 = s1.geometry, s2.geometry
        if not (isinstance(g1, Line) and isinstance(g2, Line)):
            continue
        if s1.is_rapid or s2.is_rapid or s1.plane != s2.plane or s1.side != s2.side or s1.radius != s2.radius:
            continue
        if g1.length <= 1e-9 or g2.length <= 1e-9 or math.dist(g1.end, g2.start) > 1e-9:
            continue
        if TANGENT_TOL_RAD < turn_angle3(g1, g2) <= MAX_TURN_RAD:
            out.append(k)
    return out


def blend_joints(segments: Sequence[Segment]) -> list[int]:
    """The joints a circular blend can round: :func:`line_joints` and the line–arc and arc–arc
    corners of one plane (:func:`element_joint`)."""
    lines = set(line_joints(segments))
    return sorted(lines | {k for k in range(len(segments) - 1) if k not in lines and element_joint(segments, k)})


def cut_contour_spec(seg: Segment, turn: float, tolerance_mm: float) -> FilletSpec:
    """The blend that keeps the cut part within ``tolerance_mm`` at a corner of the compensated
    path ``seg`` ends in (turning by ``turn`` rad): see the module description; a corner of an
    uncompensated path bounds the path's own contour distance."""
    if seg.radius <= 0.0:
        return FilletSpec(tolerance_mm, ToleranceKind.CONTOUR)
    from trcopt.optimize.corners.boundary import material_sign

    inside = turn * material_sign(seg) < 0
    if inside:
        return FilletSpec(tolerance_mm, ToleranceKind.VERTEX)
    return FilletSpec(None, ToleranceKind.CONTOUR, seg.radius)


def fillet_path(
    segments: Sequence[Segment], specs: dict[int, FilletSpec], mode: str = "arc", *, g2: bool = False
) -> CornerResult:
    """``segments`` with a circular blend at every joint of ``specs`` that :func:`line_joints`
    can round (other joints are kept and recorded with the reason); with ``g2`` the corners between
    two lines get the curvature-continuous B-spline transition of
    :mod:`~trcopt.optimize.corners.bspline_corner` instead (what a jerk-limited feed needs).

    Returns the new path with one :class:`~trcopt.optimize.corners.records.CornerRecord` per joint
    of ``specs``; ``max_deviation_mm`` is the largest distance measured as each spec says.
    """
    segs = list(segments)
    ok = set(line_joints(segs))
    wanted = sorted(specs)
    blended = [k for k in wanted if k in ok]
    # every joint that may get a blend: a line it shares with another one gives each half of it
    at = set(blended) | {k for k in wanted if k not in ok and element_joint(segs, k)}
    records: list[CornerRecord] = []
    cuts: dict[int, Cut] = {}  # joint → (cut from a, cut from b, blend, vertex, contour)
    # first the tangent length of every blend, then the slivers, then the geometry
    sizes: dict[int, tuple[float, float, float]] = {}  # joint → (turn, signed turn, tangent length)
    for k in blended:
        a, b = segs[k].geometry, segs[k + 1].geometry
        assert isinstance(a, Line) and isinstance(b, Line)
        phi = turn_angle3(a, b)
        phi_signed = joint_turn(a, b) if _flat(a, b) else phi
        tan_half = math.tan(0.5 * phi)
        share_a = 0.5 if (k - 1) in at else LINE_SHARE
        share_b = 0.5 if (k + 1) in at else LINE_SHARE
        t_len = min(a.length * share_a, b.length * share_b)
        spec = specs[k].bounded(a.length, b.length)
        if g2:  # the B-spline takes 2d of each line
            tol = spec.tolerance_mm
            d = math.inf if tol is None else (
                0.5 * tol if spec.kind is ToleranceKind.DISTANCE
                else spacing_for(tol, phi, spec.kind is ToleranceKind.VERTEX)
            )  # fmt: skip
            sizes[k] = (phi, phi_signed, min(2.0 * d, t_len))
            continue
        r = min(spec.radius(phi), t_len / tan_half)
        sizes[k] = (phi, phi_signed, r * tan_half)
    _no_slivers(segs, sizes)
    for k in wanted:
        spec = specs[k]
        if k not in sizes:
            records.append(CornerRecord(k, 0.0, False, False, spec.tolerance_mm or 0.0, reason=_why_not(segs, k)))
            continue
        s1 = segs[k]
        a, b = s1.geometry, segs[k + 1].geometry
        assert isinstance(a, Line) and isinstance(b, Line)
        phi, phi_signed, T = sizes[k]
        r = T / math.tan(0.5 * phi)
        inside = s1.radius > 0.0 and _flat(a, b) and inside_turn(s1, phi_signed)
        if not (T >= MIN_TANGENT_MM and math.isfinite(r)):
            records.append(CornerRecord(k, math.degrees(phi_signed), inside, False, spec.tolerance_mm or 0.0,
                                        reason="no room for a blend"))  # fmt: skip
            continue
        if g2:
            d = 0.5 * T
            vertex, contour = bspline_distances(d, phi)
            cuts[k] = (T, T, bspline_corner(a, b, d), vertex, contour)
            peak = 4.0 * math.sin(0.5 * phi) / (3.0 * d * math.cos(0.5 * phi) ** 2)
            records.append(
                CornerRecord(
                    k, math.degrees(phi_signed), inside, True, spec.tolerance_mm or 0.0, max_curvature=peak,
                    span_mm=2.0 * T, transition=TransitionKind.SPLINE, vertex_mm=vertex, contour_mm=contour,
                )
            )  # fmt: skip
            continue
        blend = _flat_arc(a, b, T, r, phi_signed) if _flat(a, b) else _space_arc(a, b, T, r, phi)
        vertex, contour = blend_distances(r, phi)
        cuts[k] = (T, T, blend, vertex, contour)
        records.append(
            CornerRecord(
                k, math.degrees(phi_signed), inside, True, spec.tolerance_mm or 0.0,
                max_curvature=1.0 / r, span_mm=2.0 * T, transition=TransitionKind.ARC,
                vertex_mm=vertex, contour_mm=contour, radius_mm=r,
            )
        )  # fmt: skip
    for k in sorted(set(wanted) - set(blended)):
        found = element_blend(segs, k, specs[k], at)
        if found is None:
            continue
        cuts[k] = found[0]
        records = [rec for rec in records if rec.index != k] + [found[1]]
    records.sort(key=lambda rec: rec.index)
    out, origin = rebuild_with_origin(segs, cuts)
    deviation = 0.0
    for rec in records:
        if rec.blended and rec.vertex_mm is not None and rec.contour_mm is not None:
            kind = specs[rec.index].kind
            deviation = max(deviation, rec.vertex_mm if kind is ToleranceKind.VERTEX else rec.contour_mm)
    result = CornerResult(out, records, deviation, mode)
    result.origin = origin
    return result


def _flat(a: Line, b: Line) -> bool:
    """Both lines in the working plane at one applicate (the blend is an Arc)."""
    return _in_plane(a) and _in_plane(b) and abs(a.end[2] - b.start[2]) <= APPLICATE_TOL_MM


def _no_slivers(segs: Sequence[Segment], sizes: dict[int, tuple[float, float, float]]) -> None:
    """Shorten the blends at both ends of a line that would leave less than :data:`MIN_LINE_MM`
    of it (but more than nothing) so that :data:`MIN_LINE_MM` stays: a line of a few micrometres
    between two blends carries no motion a controller can use, and its direction does not survive
    the digits of written G-code. Blends that meet exactly (two halves of one line) stay."""
    for k in sorted(sizes):
        if (k + 1) not in sizes:
            continue
        length = segs[k + 1].geometry.length
        t0, t1 = sizes[k][2], sizes[k + 1][2]
        rest = length - t0 - t1
        if rest <= 1e-12 * length or rest >= MIN_LINE_MM:
            continue
        scale = max(0.0, (length - MIN_LINE_MM) / (t0 + t1))
        sizes[k] = (*sizes[k][:2], t0 * scale)
        sizes[k + 1] = (*sizes[k + 1][:2], t1 * scale)


def _flat_arc(a: Line, b: Line, T: float, r: float, turn: float) -> Arc:
    """The blend of radius ``r`` between two lines of the working plane at one applicate."""
    ta, tb = a.direction2(), b.direction2()
    J = a.end
    A = (J[0] - T * ta[0], J[1] - T * ta[1], J[2])
    B = (J[0] + T * tb[0], J[1] + T * tb[1], J[2])
    sgn = 1.0 if turn > 0 else -1.0
    centre = (A[0] - sgn * r * ta[1], A[1] + sgn * r * ta[0])
    return Arc.from_points(A, B, centre, sgn > 0, False)


def _space_arc(a: Line, b: Line, T: float, r: float, phi: float) -> Poly:
    """The blend of radius ``r`` between two lines in space: a circle in the plane of the two lines,
    sampled at a chord error of at most :data:`~trcopt.geometry.poly.CHORD_TOL_MM` / 2 with its
    exact tangents, curvature vectors and arc length (a curvature-continuous Poly)."""
    ta, tb = np.array(_direction3(a)), np.array(_direction3(b))
    J = np.array(a.end)
    n = tb - float(ta @ tb) * ta
    n /= np.linalg.norm(n)
    centre = J - T * ta + r * n
    step = 2.0 * math.acos(max(-1.0, 1.0 - 0.5 * CHORD_TOL_MM / r)) if r > 0.5 * CHORD_TOL_MM else phi
    count = max(3, math.ceil(phi / max(step, 1e-9)) + 1)
    theta = np.linspace(0.0, phi, count)
    c, s_ = np.cos(theta)[:, None], np.sin(theta)[:, None]
    points = centre - r * c * n + r * s_ * ta
    tangents = s_ * n + c * ta
    curvatures = (c * n - s_ * ta) / r
    points[0], points[-1] = J - T * ta, J + T * tb  # the joints exactly
    return Poly(
        tuple(map(tuple, points)),
        tuple(map(tuple, tangents)),
        tuple((r * theta).tolist()),
        "blend",
        tuple(map(tuple, curvatures)),
    )


def _why_not(segs: Sequence[Segment], k: int) -> str:
    if k + 1 >= len(segs):
        return "end of the path"
    a, b = segs[k].geometry, segs[k + 1].geometry
    if not (isinstance(a, Line | Arc) and isinstance(b, Line | Arc)):
        return "circular blends round corners between lines and arcs only"
    if not (isinstance(a, Line) and isinstance(b, Line)):
        return "no circle tangent to both elements fits within the tolerance and their lengths"
    if segs[k].is_rapid or segs[k + 1].is_rapid:
        return "a rapid move is not blended"
    if segs[k].plane != segs[k + 1].plane:
        return "the working plane changes"
    turn = turn_angle3(a, b)
    if turn > MAX_TURN_RAD:
        return f"turn of {math.degrees(turn):.1f}° (near reversal): exact stop"
    if turn <= TANGENT_TOL_RAD:
        return "tangent joint"
    return "not joined"


def _rebuild(segs: list[Segment], cuts: dict[int, Cut]) -> list[Segment]:
    """The path with each element shortened by its blends' cuts and the blends inserted (role
    ``corner``, source span and feed of the following block)."""
    return rebuild_with_origin(segs, cuts)[0]


def _cut_fraction(g: Line | Arc, length: float) -> float:
    """The parameter share of ``length`` mm along ``g`` (3D length on a line, plane length on an arc)."""
    total = g.length if isinstance(g, Line) else g.plane_length
    return length / total


def rebuild_with_origin(segs: list[Segment], cuts: dict[int, Cut]) -> tuple[list[Segment], list[int]]:
    """:func:`_rebuild`, and for every new segment the index of the old segment it comes from (a
    blend: the segment before its joint)."""
    if not cuts:
        return list(segs), list(range(len(segs)))
    out: list[Segment] = []
    origin: list[int] = []
    for i, seg in enumerate(segs):
        g = seg.geometry
        before = cuts.get(i - 1)
        after = cuts.get(i)
        if before is None and after is None:
            out.append(seg)
            origin.append(i)
            continue
        assert isinstance(g, Line | Arc)
        t0 = _cut_fraction(g, before[1]) if before is not None else 0.0
        t1 = 1.0 - _cut_fraction(g, after[0]) if after is not None else 1.0
        if t1 - t0 > 1e-12:
            piece = g.sub(t0, t1)
            if isinstance(piece, Line):  # the blends' end points exactly
                start = before[2].end if before is not None else g.start
                piece = Line(start, after[2].start if after is not None else g.end)
            out.append(seg.with_geometry(piece))
            origin.append(i)
        if after is not None:
            nxt = segs[i + 1]
            out.append(replace(nxt, geometry=after[2], role=Role.CORNER))
            origin.append(i)
    return out, origin


# ------------------------------------------------------------------------------ line–arc, arc–arc
