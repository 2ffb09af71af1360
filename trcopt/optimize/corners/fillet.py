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
from dataclasses import dataclass, replace

import numpy as np

from trcopt.geometry import Arc, Line, Poly
from trcopt.geometry.poly import CHORD_TOL_MM
from trcopt.modes import ToleranceKind, TransitionKind
from trcopt.optimize.corners.bspline_corner import bspline_corner, bspline_distances, spacing_for
from trcopt.optimize.corners.records import CornerRecord, CornerResult
from trcopt.optimize.corners.tangent_circle import distance_back, foot, intersections, joint_turn, offset_locus
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
    "turn_between",
]

LINE_SHARE = 0.98  # the largest share of a line a blend may take when the line's other end is not blended
MAX_TURN_RAD = math.radians(170.0)  # sharper turns (near reversals) keep the exact path
TANGENT_TOL_RAD = 1e-6  # smaller turns are tangent-continuous joints, not corners
MIN_TANGENT_MM = 1e-7  # a blend shorter than this on each line is no blend
MIN_LINE_MM = 0.01  # the shortest piece of a line left between two blends (unless they meet exactly)
_W_TOL = 1e-12  # a line lies in its plane when its applicate changes by less, mm


@dataclass(frozen=True, slots=True)
class FilletSpec:
    """How large the blend at one joint may be.

    Attributes
    ----------
    tolerance_mm:
        Bound of the blend measured as ``kind`` says, mm; None for no bound (as large as the lines
        allow).
    kind:
        How ``tolerance_mm`` is measured.
    max_radius_mm:
        Largest blend radius, mm (the tool radius at an outside corner of a compensated path).
    length_share:
        The tolerance is at most this share of the shorter of the two lines (LinuxCNC's quarter);
        None for no such bound.
    """

    tolerance_mm: float | None
    kind: ToleranceKind = ToleranceKind.CONTOUR
    max_radius_mm: float = math.inf
    length_share: float | None = None

    def bounded(self, length_a: float, length_b: float) -> FilletSpec:
        """This spec with its tolerance bounded by ``length_share`` of the shorter line, mm."""
        if self.length_share is None:
            return self
        cap = self.length_share * min(length_a, length_b)
        tol = cap if self.tolerance_mm is None else min(self.tolerance_mm, cap)
        return FilletSpec(tol, self.kind, self.max_radius_mm)

    def radius(self, phi: float) -> float:
        """The largest radius within the tolerance at a turn of ``phi`` rad (before the line lengths)."""
        r = self.max_radius_mm
        tol = self.tolerance_mm
        if tol is None:
            return r
        half = 0.5 * phi
        one_minus_cos = 2.0 * math.sin(0.5 * half) ** 2  # 1 − cos(φ/2), without cancellation
        if one_minus_cos <= 0.0:
            return r
        if self.kind is ToleranceKind.VERTEX:
            return min(r, tol * math.cos(half) / one_minus_cos)
        if self.kind is ToleranceKind.CONTOUR:
            return min(r, tol / one_minus_cos)
        return min(r, tol / math.tan(half))  # DISTANCE: the tangent length


def blend_distances(radius: float, phi: float) -> tuple[float, float]:
    """(vertex distance, contour distance) of a circular blend of ``radius`` at a turn of ``phi``, mm."""
    c = math.cos(0.5 * phi)
    return radius * (1.0 - c) / c, radius * (1.0 - c)


def turn_between(a: Line, b: Line) -> float:
    """Signed turning angle from line ``a`` to line ``b``, rad (positive = left)."""
    ta, tb = a.direction2(), b.direction2()
    return math.atan2(ta[0] * tb[1] - ta[1] * tb[0], ta[0] * tb[0] + ta[1] * tb[1])


def _in_plane(g: Line) -> bool:
    return abs(g.start[2] - g.end[2]) <= _W_TOL and g.plane_length > 1e-9


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
        phi_signed = turn_between(a, b) if _flat(a, b) else phi
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
        inside = s1.radius > 0.0 and _flat(a, b) and _inside(s1, phi_signed)
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
        found = _element_blend(segs, k, specs[k], at)
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
    return _in_plane(a) and _in_plane(b) and abs(a.end[2] - b.start[2]) <= _W_TOL


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


def _inside(seg: Segment, turn: float) -> bool:
    from trcopt.optimize.corners.boundary import material_sign

    return turn * material_sign(seg) < 0


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


Cut = tuple[float, float, "Arc | Poly", float, float]  # (cut from a's end, from b's start, blend, vertex, contour)


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
def element_joint(segs: Sequence[Segment], k: int) -> bool:
    """A corner between a line and an arc or two arcs of one plane at one applicate (feeds, same
    compensation), turning by more than :data:`TANGENT_TOL_RAD` and at most :data:`MAX_TURN_RAD`."""
    s1, s2 = segs[k], segs[k + 1]
    g1, g2 = s1.geometry, s2.geometry
    if not (isinstance(g1, Line | Arc) and isinstance(g2, Line | Arc)):
        return False
    if isinstance(g1, Line) and isinstance(g2, Line):
        return False
    if s1.is_rapid or s2.is_rapid or s1.plane != s2.plane or s1.side != s2.side or s1.radius != s2.radius:
        return False
    flat = all(abs(g.start[2] - g.end[2]) <= _W_TOL and g.plane_length > 1e-9 for g in (g1, g2))
    if not flat or abs(g1.end[2] - g2.start[2]) > _W_TOL or math.dist(g1.end, g2.start) > 1e-9:
        return False
    turn = abs(joint_turn(g1, g2))
    return TANGENT_TOL_RAD < turn <= MAX_TURN_RAD


def _contour_distance(arc: Arc, a: Line | Arc, b: Line | Arc, samples: int = 17) -> float:
    """The largest distance of ``arc`` from the union of ``a`` and ``b``: the larger of the sampled
    maximum and the points where the distances to ``a`` and to ``b`` are equal (the maximum of a
    minimum of two distances lies there unless one of them peaks on its own), found by bisection."""
    def gap(t: float) -> tuple[float, float]:
        p = arc.point2(t)
        return a.distance2(p), b.distance2(p)

    ts = [i / (samples - 1) for i in range(samples)]
    values = [gap(t) for t in ts]
    best = max(min(da, db) for da, db in values)
    pairs = list(zip(ts, values, strict=True))
    for (t0, (a0, b0)), (t1, (a1, b1)) in zip(pairs, pairs[1:], strict=False):
        if (a0 - b0) * (a1 - b1) > 0.0:
            continue
        lo, hi, sign = t0, t1, a0 - b0
        for _ in range(50):
            mid = 0.5 * (lo + hi)
            da, db = gap(mid)
            if (da - db) * sign > 0.0:
                lo = mid
            else:
                hi = mid
        da, db = gap(0.5 * (lo + hi))
        best = max(best, min(da, db))
    return best


def _element_blend(
    segs: Sequence[Segment], k: int, spec: FilletSpec, shared: set[int]
) -> tuple[Cut, CornerRecord] | None:
    """The largest circular blend within ``spec`` at a line–arc or arc–arc corner ``k``: the circle
    tangent to both elements on the inside of the turn, its radius found by bisection (the
    distances grow with it); None when the joint is not such a corner or no blend fits."""
    if not element_joint(segs, k):
        return None
    a, b = segs[k].geometry, segs[k + 1].geometry
    assert isinstance(a, Line | Arc) and isinstance(b, Line | Arc)
    turn = joint_turn(a, b)
    side = 1.0 if turn > 0 else -1.0
    avail_a = a.plane_length * (0.5 if (k - 1) in shared else LINE_SHARE)
    avail_b = b.plane_length * (0.5 if (k + 1) in shared else LINE_SHARE)
    spec = spec.bounded(a.plane_length, b.plane_length)
    J = (a.end[0], a.end[1])
    w = a.end[2]

    def build(r: float) -> tuple[float, float, Arc, float, float] | None:
        found = intersections(offset_locus(a, side, r), offset_locus(b, side, r))
        if not found:
            return None
        c = min(found, key=lambda p: math.dist(p, J))
        pa, pb = foot(a, c), foot(b, c)
        cut_a, cut_b = distance_back(a, pa, True), distance_back(b, pb, False)
        if cut_a is None or cut_b is None or cut_a > avail_a or cut_b > avail_b:
            return None
        arc = Arc.from_points((pa[0], pa[1], w), (pb[0], pb[1], w), c, side > 0, False)
        if abs(arc.sweep) > abs(turn) + 1e-6:
            return None  # the circle on the wrong branch
        vertex = math.dist(c, J) - r
        return cut_a, cut_b, arc, vertex, _contour_distance(arc, a, b)

    def fits(r: float) -> tuple[float, float, Arc, float, float] | None:
        got = build(r)
        if got is None or spec.tolerance_mm is None:
            return got
        measure = {ToleranceKind.VERTEX: got[3], ToleranceKind.CONTOUR: got[4]}.get(spec.kind, max(got[0], got[1]))
        return got if measure <= spec.tolerance_mm else None

    hi = min(spec.max_radius_mm, 4.0 * max(avail_a, avail_b) / max(math.tan(0.5 * abs(turn)), 1e-12))
    lo, best = 0.0, None
    for _ in range(48):
        mid = 0.5 * (lo + hi)
        got = fits(mid)
        if got is not None:
            lo, best = mid, (mid, got)
        else:
            hi = mid
    if best is None or min(best[1][0], best[1][1]) < MIN_TANGENT_MM:
        return None
    r, (cut_a, cut_b, arc, vertex, contour) = best
    inside = segs[k].radius > 0.0 and _inside(segs[k], turn)
    record = CornerRecord(
        k, math.degrees(turn), inside, True, spec.tolerance_mm or 0.0, max_curvature=1.0 / r,
        span_mm=cut_a + cut_b, transition=TransitionKind.ARC, vertex_mm=vertex, contour_mm=contour, radius_mm=r,
    )  # fmt: skip
    return (cut_a, cut_b, arc, vertex, contour), record
