"""The constraint model of design.md §4: contact radius, tangency, no reversal, clearance.

Every constraint family exists twice, with the same meaning:

* as an **exact float evaluation** (closed forms, NumPy) used to *verify* a tool-centre path —
  :func:`carrier_residual`, :func:`tangency_residual`, :func:`reversal_residual`,
  :func:`element_distance`;
* as a **CasADi expression** used as a constraint of the optimisation problems —
  :func:`ca_point_segment_distance`, :func:`ca_point_arc_distance`, :func:`ca_cross`,
  :func:`ca_monotonic`.

Conventions: plane coordinates (u, v), applicate w, mm; a positive offset is to the left of travel;
arcs carry a signed sweep (CCW positive). CasADi is imported only by the ``ca_*`` functions'
callers (they receive CasADi symbols), so importing this module stays cheap.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from trcopt.geometry import Arc, Line, Poly, bounded_intersections
from trcopt.geometry.vec import Vec2

Element = Line | Arc | Poly

__all__ = [
    "carrier_residual",
    "tangency_residual",
    "reversal_residual",
    "element_distance",
    "line_pair_distances",
    "line_pair_distances_uv",
    "point_distance",
    "points_distance",
    "points_foot",
    "bbox",
    "ca_cross",
    "ca_point_segment_distance",
    "ca_point_arc_distance",
    "ca_monotonic",
]


# --------------------------------------------------------------------------------------------
# exact float evaluations (verification)
# --------------------------------------------------------------------------------------------


def carrier_residual(tool: Element, programmed: Element, radius: float) -> float:
    """Contact residual |distance(tool-centre point, carrier of programmed) − radius|, mm.

    The carrier is the infinite line or full circle of the programmed element (a tool-centre
    element may be extended or shortened to an intersection, it stays on the offset carrier).
    Evaluated at the start, middle and end of ``tool`` (for an arc on the same circle family the
    residual is constant, for a line it is linear, so three points bound it exactly).
    """
    pts = np.array([tool.point2(0.0), tool.point2(0.5), tool.point2(1.0)], float)
    if isinstance(programmed, Line):
        a = np.array(programmed.start2, float)
        d = np.array(programmed.end2, float) - a
        n = math.hypot(d[0], d[1])
        if n == 0.0:
            return 0.0
        rel = pts - a
        dist = np.abs(rel[:, 0] * d[1] - rel[:, 1] * d[0]) / n
    elif isinstance(programmed, Arc):
        dist = np.abs(np.hypot(pts[:, 0] - programmed.center[0], pts[:, 1] - programmed.center[1]) - programmed.radius)
    else:
        dist = points_distance(programmed, pts)
    return float(np.max(np.abs(dist - radius)))


def tangency_residual(t1: Vec2, t2: Vec2) -> float:
    """Tangency residual of two unit tangents: |sin| of the angle between them, or 1 + |cos| when
    they point against each other (a reversal is never tangent)."""
    c = t1[0] * t2[0] + t1[1] * t2[1]
    s = abs(t1[0] * t2[1] - t1[1] * t2[0])
    return s if c > 0.0 else 1.0 + abs(c)


def reversal_residual(ws: list[float] | np.ndarray) -> float:
    """Largest step (mm) by which a sequence of applicates moves against its overall direction.

    Zero for a monotonic sequence (spec R42: all sub-movements along the applicate keep one sign).
    """
    w = np.asarray(ws, float)
    if w.size < 3:
        return 0.0
    sign = 1.0 if w[-1] >= w[0] else -1.0
    sw = sign * w
    # largest retreat below the running maximum
    return float(np.max(np.maximum.accumulate(sw) - sw))


def bbox(el: Element) -> tuple[float, float, float, float]:
    """Plane bounding box (umin, vmin, umax, vmax), exact for lines and arcs."""
    if isinstance(el, Line):
        return (
            min(el.start[0], el.end[0]),
            min(el.start[1], el.end[1]),
            max(el.start[0], el.end[0]),
            max(el.start[1], el.end[1]),
        )
    if isinstance(el, Arc):
        pts = [el.point2(0.0), el.point2(1.0)]
        for k in range(-8, 9):  # axis extremes inside the sweep
            a = k * math.pi / 2.0
            lam = (a - el.a0) / el.sweep if el.sweep != 0.0 else 2.0
            if 0.0 <= lam <= 1.0:
                pts.append((el.center[0] + el.radius * math.cos(a), el.center[1] + el.radius * math.sin(a)))
        us, vs = [p[0] for p in pts], [p[1] for p in pts]
        return (min(us), min(vs), max(us), max(vs))
    arr = np.array([p[:2] for p in el.points], float)
    return (
        float(arr[:, 0].min()),
        float(arr[:, 1].min()),
        float(arr[:, 0].max()),
        float(arr[:, 1].max()),
    )


def _segment_points_distance(a: np.ndarray, b: np.ndarray, pts: np.ndarray) -> np.ndarray:
    d = b - a
    dd = float(d @ d)
    if dd == 0.0:
        return np.hypot(pts[:, 0] - a[0], pts[:, 1] - a[1])
    t = np.clip((pts - a) @ d / dd, 0.0, 1.0)
    q = a + t[:, None] * d
    return np.hypot(pts[:, 0] - q[:, 0], pts[:, 1] - q[:, 1])


def _in_sweep(el: Arc, ang: np.ndarray, tol: float = 1e-12) -> np.ndarray:
    if abs(el.sweep) >= 2.0 * math.pi - 1e-12:
        return np.ones_like(ang, dtype=bool)
    if el.sweep >= 0.0:
        d = np.mod(ang - el.a0, 2.0 * math.pi)
    else:
        d = np.mod(el.a0 - ang, 2.0 * math.pi)
    return (d <= abs(el.sweep) + tol) | (d >= 2.0 * math.pi - tol)


def points_foot(el: Line | Arc, pts: np.ndarray) -> np.ndarray:
    """Nearest point (n×2) of the bounded plane line or arc to each point of ``pts`` (n×2)."""
    pts = np.asarray(pts, float).reshape(-1, 2)
    if isinstance(el, Line):
        a, b = np.array(el.start2, float), np.array(el.end2, float)
        d = b - a
        dd = float(d @ d)
        t = np.zeros(len(pts)) if dd == 0.0 else np.clip((pts - a) @ d / dd, 0.0, 1.0)
        return a + t[:, None] * d
    c = np.array(el.center, float)
    rel = pts - c
    ang = np.arctan2(rel[:, 1], rel[:, 0])
    radial = c + el.radius * np.stack((np.cos(ang), np.sin(ang)), axis=1)
    p0, p1 = np.array(el.point2(0.0)), np.array(el.point2(1.0))
    end = np.where((np.hypot(*(pts - p0).T) <= np.hypot(*(pts - p1).T))[:, None], p0, p1)
    return np.where(_in_sweep(el, ang)[:, None], radial, end)


def points_distance(el: Element, pts: np.ndarray) -> np.ndarray:
    """Plane distance (mm) from each point of ``pts`` (n×2) to the bounded element."""
    pts = np.asarray(pts, float).reshape(-1, 2)
    if isinstance(el, Line):
        return _segment_points_distance(np.array(el.start2, float), np.array(el.end2, float), pts)
    if isinstance(el, Arc):
        foot = points_foot(el, pts)
        return np.hypot(pts[:, 0] - foot[:, 0], pts[:, 1] - foot[:, 1])
    poly = np.array([p[:2] for p in el.points], float)
    best = np.full(len(pts), np.inf)
    for a, b in zip(poly[:-1], poly[1:], strict=True):
        best = np.minimum(best, _segment_points_distance(a, b, pts))
    return best


def point_distance(el: Line | Arc, p: Vec2) -> float:
    """Scalar fast path of :func:`points_distance` for one point and a line or arc."""
    if isinstance(el, Line):
        ax, ay = el.start[0], el.start[1]
        dx, dy = el.end[0] - ax, el.end[1] - ay
        dd = dx * dx + dy * dy
        t = 0.0 if dd == 0.0 else min(1.0, max(0.0, ((p[0] - ax) * dx + (p[1] - ay) * dy) / dd))
        return math.hypot(p[0] - ax - t * dx, p[1] - ay - t * dy)
    ru, rv = p[0] - el.center[0], p[1] - el.center[1]
    if _in_sweep_scalar(el, math.atan2(rv, ru)):
        return abs(math.hypot(ru, rv) - el.radius)
    return min(math.dist(p, el.point2(0.0)), math.dist(p, el.point2(1.0)))


def _in_sweep_scalar(el: Arc, ang: float, tol: float = 1e-12) -> bool:
    span = abs(el.sweep)
    if span >= 2.0 * math.pi - 1e-12:
        return True
    d = (ang - el.a0) % (2.0 * math.pi) if el.sweep >= 0.0 else (el.a0 - ang) % (2.0 * math.pi)
    return d <= span + tol or d >= 2.0 * math.pi - tol


def _pieces(el: Element) -> list[Line | Arc]:
    if isinstance(el, Poly):
        return [Line(a, b) for a, b in zip(el.points, el.points[1:], strict=False) if a[:2] != b[:2]]
    return [el]


def _circle_point(el: Arc, direction: np.ndarray) -> tuple[float, float] | None:
    """Point of the bounded arc along ``direction`` from its centre (None if outside the sweep)."""
    n = math.hypot(direction[0], direction[1])
    if n == 0.0:
        return None
    if not _in_sweep_scalar(el, math.atan2(direction[1], direction[0])):
        return None
    return (
        el.center[0] + el.radius * direction[0] / n,
        el.center[1] + el.radius * direction[1] / n,
    )


def _pair_distance(a: Line | Arc, b: Line | Arc) -> tuple[float, Vec2]:
    """Exact minimum plane distance between two bounded elements and the point of ``a`` attaining it."""
    if a.plane_length == 0.0 and b.plane_length == 0.0:
        return math.dist(a.start[:2], b.start[:2]), (a.start[0], a.start[1])
    hits = bounded_intersections(a, b) if a.plane_length > 0 and b.plane_length > 0 else []
    if hits:
        return 0.0, hits[0].point
    cands: list[tuple[float, Vec2]] = []
    for p in (a.point2(0.0), a.point2(1.0)):
        cands.append((point_distance(b, p), p))
    for q in (b.point2(0.0), b.point2(1.0)):
        cands.append((point_distance(a, q), q))  # the point of a is within d of q; keep q as a locator
    # interior-interior critical points (common normals)
    if isinstance(a, Arc) and isinstance(b, Arc):
        u = np.array(b.center) - np.array(a.center)
        if float(np.hypot(*u)) > 0.0:
            for sa in (1.0, -1.0):
                pa = _circle_point(a, sa * u)
                for sb in (1.0, -1.0):
                    pb = _circle_point(b, sb * u)
                    if pa is not None and pb is not None:
                        cands.append((math.dist(pa, pb), pa))
    elif isinstance(a, Arc) or isinstance(b, Arc):
        arc, line = (a, b) if isinstance(a, Arc) else (b, a)
        assert isinstance(arc, Arc) and isinstance(line, Line)
        s0, s1 = np.array(line.start2), np.array(line.end2)
        d = s1 - s0
        dd = float(d @ d)
        if dd > 0.0:
            t = float((np.array(arc.center) - s0) @ d / dd)
            if 0.0 <= t <= 1.0:
                foot = s0 + t * d
                pc = _circle_point(arc, foot - np.array(arc.center))
                if pc is not None:
                    cands.append(
                        (
                            math.dist(pc, tuple(foot)),
                            pc if arc is a else (float(foot[0]), float(foot[1])),
                        )
                    )
    return min(cands, key=lambda c: c[0])


def line_pair_distances(p0: np.ndarray, p1: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """Exact minimum plane distances (mm) between the segments ``p0p1`` and ``q0q1`` (each n×2):
    :func:`element_distance` of many pairs of lines at once — 0 where they cross, else the
    smallest distance of an end point to the other segment."""
    return line_pair_distances_uv(p0[:, 0], p0[:, 1], p1[:, 0], p1[:, 1], q0[:, 0], q0[:, 1], q1[:, 0], q1[:, 1])


def line_pair_distances_uv(*coords: np.ndarray) -> np.ndarray:
    """:func:`line_pair_distances` of the coordinate arrays p0u, p0v, p1u, p1v, q0u, q0v, q1u, q1v."""
    p0u, p0v, p1u, p1v, q0u, q0v, q1u, q1v = coords

    def point_segment(pu: Any, pv: Any, au: Any, av: Any, bu: Any, bv: Any) -> np.ndarray:
        du, dv = bu - au, bv - av
        dd = du * du + dv * dv
        t = np.where(dd > 0.0, ((pu - au) * du + (pv - av) * dv) / np.where(dd > 0.0, dd, 1.0), 0.0)
        t = np.clip(t, 0.0, 1.0)
        return np.hypot(pu - au - t * du, pv - av - t * dv)

    def orient(au: Any, av: Any, bu: Any, bv: Any, cu: Any, cv: Any) -> np.ndarray:
        return (bu - au) * (cv - av) - (bv - av) * (cu - au)

    ends = np.minimum(
        np.minimum(point_segment(p0u, p0v, q0u, q0v, q1u, q1v), point_segment(p1u, p1v, q0u, q0v, q1u, q1v)),
        np.minimum(point_segment(q0u, q0v, p0u, p0v, p1u, p1v), point_segment(q1u, q1v, p0u, p0v, p1u, p1v)),
    )
    crossing = (orient(p0u, p0v, p1u, p1v, q0u, q0v) * orient(p0u, p0v, p1u, p1v, q1u, q1v) < 0.0) & (
        orient(q0u, q0v, q1u, q1v, p0u, p0v) * orient(q0u, q0v, q1u, q1v, p1u, p1v) < 0.0
    )
    return np.where(crossing, 0.0, ends)


def element_distance(a: Element, b: Element) -> tuple[float, Vec2]:
    """Exact minimum plane distance (mm) between two bounded elements (polys: their samples),
    with a point near where it is attained."""
    best: tuple[float, Vec2] = (math.inf, (math.nan, math.nan))
    for pa in _pieces(a):
        for pb in _pieces(b):
            c = _pair_distance(pa, pb)
            if c[0] < best[0]:
                best = c
    return best


# --------------------------------------------------------------------------------------------
# CasADi expressions (optimisation); arguments are CasADi SX/MX column vectors or floats
# --------------------------------------------------------------------------------------------


def ca_cross(a: Any, b: Any) -> Any:
    """Plane cross product a × b (tangency: zero when parallel)."""
    return a[0] * b[1] - a[1] * b[0]


def ca_point_segment_distance(p: Any, a: Vec2, b: Vec2) -> Any:
    """Distance from a symbolic point to a fixed bounded segment (clamped projection)."""
    import casadi as ca

    dx, dy = b[0] - a[0], b[1] - a[1]
    dd = dx * dx + dy * dy
    if dd == 0.0:
        return ca.sqrt((p[0] - a[0]) ** 2 + (p[1] - a[1]) ** 2 + 1e-18)
    t = ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / dd
    t = ca.fmin(1.0, ca.fmax(0.0, t))
    return ca.sqrt((p[0] - a[0] - t * dx) ** 2 + (p[1] - a[1] - t * dy) ** 2 + 1e-18)


def ca_point_arc_distance(p: Any, arc: Arc) -> Any:
    """Distance from a symbolic point to a fixed bounded arc (radial inside the sweep, else the
    nearer end point)."""
    import casadi as ca

    cx, cy = arc.center
    rel_u, rel_v = p[0] - cx, p[1] - cy
    radial = ca.fabs(ca.sqrt(rel_u**2 + rel_v**2 + 1e-18) - arc.radius)
    p0, p1 = arc.point2(0.0), arc.point2(1.0)
    ends = ca.fmin(
        ca.sqrt((p[0] - p0[0]) ** 2 + (p[1] - p0[1]) ** 2 + 1e-18),
        ca.sqrt((p[0] - p1[0]) ** 2 + (p[1] - p1[1]) ** 2 + 1e-18),
    )
    if abs(arc.sweep) >= 2.0 * math.pi - 1e-12:
        return radial
    # angle from the arc's start, measured in its sense, in [0, 2π)
    mid = arc.a0 + 0.5 * arc.sweep
    # rotate so the middle of the sweep is at angle 0; inside iff |angle| ≤ |sweep|/2
    cm, sm = math.cos(mid), math.sin(mid)
    x = rel_u * cm + rel_v * sm
    y = -rel_u * sm + rel_v * cm
    ang = ca.fabs(ca.atan2(y, x))
    return ca.if_else(ang <= 0.5 * abs(arc.sweep), radial, ends)


def ca_point_element_distance(p: Any, el: Element) -> Any:
    """Distance from a symbolic point to a fixed element (polys: their sample polyline)."""
    import casadi as ca

    if isinstance(el, Line):
        return ca_point_segment_distance(p, el.start2, el.end2)
    if isinstance(el, Arc):
        return ca_point_arc_distance(p, el)
    ds = [ca_point_segment_distance(p, a[:2], b[:2]) for a, b in zip(el.points, el.points[1:], strict=False)]
    out = ds[0]
    for d in ds[1:]:
        out = ca.fmin(out, d)
    return out


def ca_monotonic(ws: list[Any], sign: float) -> list[Any]:
    """No-reversal constraints ``sign·(w[i+1] − w[i]) ≥ 0`` (return the left-hand sides)."""
    return [sign * (ws[i + 1] - ws[i]) for i in range(len(ws) - 1)]
