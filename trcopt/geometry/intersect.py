"""Closed-form intersections of element carriers (infinite lines, full circles) and polylines.

``intersections(a, b)`` returns every intersection point of the carriers of ``a`` and ``b`` with
the parameters ``lam`` of the point on each element (see :mod:`.primitives`; values outside
[0, 1] lie on the extensions). Tangent contacts within ``tol`` are reported once.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from trcopt.geometry import vec
from trcopt.geometry.poly import Poly
from trcopt.geometry.primitives import Arc, Line
from trcopt.geometry.vec import Vec2

__all__ = ["Hit", "intersections", "bounded_intersections"]


class Hit(NamedTuple):
    point: Vec2
    lam_a: float
    lam_b: float


def _line_line(a: Line, b: Line) -> list[Hit]:
    (px, py, _), (ex, ey, _) = a.start, a.end
    (qx, qy, _), (fx, fy, _) = b.start, b.end
    rx, ry, sx, sy = ex - px, ey - py, fx - qx, fy - qy
    den = rx * sy - ry * sx
    scale = math.hypot(rx, ry) * math.hypot(sx, sy)
    if scale == 0.0 or abs(den) <= 1e-12 * scale:
        return []
    wx, wy = qx - px, qy - py
    t = (wx * sy - wy * sx) / den
    u = (wx * ry - wy * rx) / den
    return [Hit((px + t * rx, py + t * ry), t, u)]


def _line_circle(line: Line, center: Vec2, radius: float, tol: float) -> list[tuple[Vec2, float]]:
    (px, py, _), (ex, ey, _) = line.start, line.end
    dx, dy = ex - px, ey - py
    dd = dx * dx + dy * dy
    if dd == 0.0 or radius <= 0.0:
        return []
    # foot of the perpendicular from the centre
    t0 = ((center[0] - px) * dx + (center[1] - py) * dy) / dd
    fx, fy = px + t0 * dx, py + t0 * dy
    h = math.hypot(fx - center[0], fy - center[1])
    if h > radius + tol:
        return []
    if h >= radius - tol * 1e-3 and abs(h - radius) <= tol:
        return [((fx, fy), t0)]
    half = math.sqrt(max(radius * radius - h * h, 0.0)) / math.sqrt(dd)
    t1, t2 = t0 - half, t0 + half
    return [((px + t1 * dx, py + t1 * dy), t1), ((px + t2 * dx, py + t2 * dy), t2)]


def _circle_circle(c1: Vec2, r1: float, c2: Vec2, r2: float, tol: float) -> list[Vec2]:
    d = vec.dist(c1, c2)
    if r1 <= 0.0 or r2 <= 0.0 or d == 0.0:
        return []
    if d > r1 + r2 + tol or d < abs(r1 - r2) - tol:
        return []
    a = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d)
    h2 = r1 * r1 - a * a
    ex = vec.scale(vec.sub(c2, c1), 1.0 / d)
    base = vec.add(c1, vec.scale(ex, a))
    if h2 <= (tol * 1e-3) ** 2 or abs(d - (r1 + r2)) <= tol or abs(d - abs(r1 - r2)) <= tol:
        if h2 <= tol * tol:
            return [base]
    h = math.sqrt(max(h2, 0.0))
    ey = vec.rot90(ex)
    return [vec.add(base, vec.scale(ey, h)), vec.sub(base, vec.scale(ey, h))]


def _poly_segments(p: Poly) -> list[Line]:
    return [Line(a, b) for a, b in zip(p.points, p.points[1:], strict=False) if a[:2] != b[:2]]


def _poly_param(p: Poly, seg_index: int, t: float) -> float:
    """Parameter (fraction of 3D arc length) of a point on sample segment ``seg_index``."""
    c0, c1 = p.cum[seg_index], p.cum[seg_index + 1]
    return (c0 + t * (c1 - c0)) / p.cum[-1]


def intersections(a: object, b: object, tol: float = 1e-9) -> list[Hit]:
    """All intersections of the carriers of two elements (polys: bounded samples only)."""
    ta, tb = type(a), type(b)
    if ta is Line:
        if tb is Line:
            return _line_line(a, b)  # type: ignore[arg-type]
        if tb is Arc:
            return [Hit(p, t, b.param_of(p)) for p, t in _line_circle(a, b.center, b.radius, tol)]  # type: ignore[arg-type, attr-defined]
    elif ta is Arc:
        if tb is Line:
            return [Hit(p, a.param_of(p), t) for p, t in _line_circle(b, a.center, a.radius, tol)]  # type: ignore[arg-type, attr-defined]
        if tb is Arc:
            return [
                Hit(p, a.param_of(p), b.param_of(p))  # type: ignore[attr-defined]
                for p in _circle_circle(a.center, a.radius, b.center, b.radius, tol)  # type: ignore[attr-defined]
            ]
    if ta is Poly or tb is Poly:
        return _with_poly(a, b, tol)
    raise TypeError(f"cannot intersect {ta.__name__} with {tb.__name__}")


def _with_poly(a: object, b: object, tol: float) -> list[Hit]:
    if isinstance(b, Poly) and not isinstance(a, Poly):
        return [Hit(h.point, h.lam_b, h.lam_a) for h in _with_poly(b, a, tol)]
    assert isinstance(a, Poly)
    hits: list[Hit] = []
    segs_a = list(enumerate(zip(a.points, a.points[1:], strict=False)))
    for i, (p, q) in segs_a:
        if p[:2] == q[:2]:
            continue
        sa = Line(p, q)
        others: list[tuple[object, int | None]]
        if isinstance(b, Poly):
            others = [
                (Line(u, v), j)
                for j, (u, v) in enumerate(zip(b.points, b.points[1:], strict=False))
                if u[:2] != v[:2]
            ]
        else:
            others = [(b, None)]
        for other, j in others:
            for h in intersections(sa, other, tol):
                if -1e-12 <= h.lam_a <= 1.0 + 1e-12:
                    lb = h.lam_b
                    if j is not None:
                        if not (-1e-12 <= lb <= 1.0 + 1e-12):
                            continue
                        assert isinstance(b, Poly)
                        lb = _poly_param(b, j, lb)
                    hits.append(Hit(h.point, _poly_param(a, i, h.lam_a), lb))
    # merge duplicates at shared sample points
    out: list[Hit] = []
    for h in hits:
        if all(vec.dist(h.point, o.point) > 1e-9 for o in out):
            out.append(h)
    return out


def bounded_intersections(a: object, b: object, tol_lam_a: float = 1e-9, tol_lam_b: float = 1e-9) -> list[Hit]:
    """Intersections that lie on both bounded elements (parameters within [0, 1] ± tolerance)."""
    return [
        h
        for h in intersections(a, b)
        if -tol_lam_a <= h.lam_a <= 1.0 + tol_lam_a and -tol_lam_b <= h.lam_b <= 1.0 + tol_lam_b
    ]
