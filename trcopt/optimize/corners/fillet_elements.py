"""Circular blends at line–arc and arc–arc corners of one plane: the circle tangent to both
elements on the inside of the turn (:mod:`~trcopt.optimize.corners.tangent_circle`), as large as
the tolerance and the element lengths allow."""

from __future__ import annotations

import math
from collections.abc import Sequence

from trcopt.geometry import Arc, Line
from trcopt.modes import ToleranceKind, TransitionKind
from trcopt.optimize.corners.curves import joint_turn
from trcopt.optimize.corners.fillet_spec import (
    APPLICATE_TOL_MM,
    LINE_SHARE,
    MAX_TURN_RAD,
    MIN_TANGENT_MM,
    TANGENT_TOL_RAD,
    Cut,
    FilletSpec,
    inside_turn,
)
from trcopt.optimize.corners.records import CornerRecord
from trcopt.optimize.corners.tangent_circle import distance_back, foot, intersections, offset_locus
from trcopt.path import Segment

__all__ = ["element_blend", "element_joint"]


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
    flat = all(abs(g.start[2] - g.end[2]) <= APPLICATE_TOL_MM and g.plane_length > 1e-9 for g in (g1, g2))
    if not flat or abs(g1.end[2] - g2.start[2]) > APPLICATE_TOL_MM or math.dist(g1.end, g2.start) > 1e-9:
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


def element_blend(
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
    inside = segs[k].radius > 0.0 and inside_turn(segs[k], turn)
    record = CornerRecord(
        k, math.degrees(turn), inside, True, spec.tolerance_mm or 0.0, max_curvature=1.0 / r,
        span_mm=cut_a + cut_b, transition=TransitionKind.ARC, vertex_mm=vertex, contour_mm=contour, radius_mm=r,
    )  # fmt: skip
    return (cut_a, cut_b, arc, vertex, contour), record
