"""Exact distances of many (tool element, part element) pairs with an arc, as whole arrays.

:func:`arc_pair_distances` is :func:`trcopt.verify.model.element_distance` of line–arc, arc–line
and arc–arc pairs, formula by formula: 0 where the bounded elements intersect
(:func:`trcopt.geometry.bounded_intersections`: the carriers' intersection points with their
parameters, tangent contacts within the same tolerances), else the smallest of the end points'
distances to the other element and of the interior critical points (common normals of two
circles, the foot of a circle's centre on a line). The float operations are those of the scalar
code (:mod:`trcopt.verify.table`: ``math`` functions mapped over the elements, ``np.vecdot``
for its ``@``), so every distance is the same to the last bit; a pair that gives NaN is left to
the scalar code.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from trcopt.verify.table import ARC, LINE, SegmentTable, fmap, hypot

__all__ = ["arc_pair_distances"]

TWO_PI = 2.0 * math.pi
FULL = TWO_PI - 1e-12  # a sweep this large is a full circle
TOL = 1e-9  # intersections: tangent contacts (mm) and parameter tolerance
_SWEEP_TOL = 1e-12


class _Arcs:
    """Arc parameters of the rows ``idx`` of a table."""

    def __init__(self, t: SegmentTable, idx: np.ndarray) -> None:
        self.cx, self.cy, self.r, self.a0, self.sweep = t.cx[idx], t.cy[idx], t.r[idx], t.a0[idx], t.sweep[idx]
        u0, v0, u1, v1 = t.ends2()
        self.p0, self.p1 = (u0[idx], v0[idx]), (u1[idx], v1[idx])


def _in_sweep(a: _Arcs, ang: np.ndarray) -> np.ndarray:
    """``model._in_sweep_scalar``."""
    span = np.abs(a.sweep)
    d = np.where(a.sweep >= 0.0, np.mod(ang - a.a0, TWO_PI), np.mod(a.a0 - ang, TWO_PI))
    return (span >= FULL) | (d <= span + _SWEEP_TOL) | (d >= TWO_PI - _SWEEP_TOL)


def _param_of(a: _Arcs, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``Arc.param_of``."""
    ang = fmap(math.atan2, v - a.cy, u - a.cx)
    span = np.abs(a.sweep)
    d = np.fmod(np.where(a.sweep > 0, ang - a.a0, a.a0 - ang), TWO_PI)
    d = np.where(d < 0.0, d + TWO_PI, d)
    d = np.where(d >= TWO_PI, d - TWO_PI, d)
    with np.errstate(divide="ignore", invalid="ignore"):
        inside = (span >= FULL) | (d <= span) | (d - span <= (TWO_PI - span) / 2.0)
        return np.where(inside, d / span, -(TWO_PI - d) / span)


def _on(lam: np.ndarray) -> np.ndarray:
    return (-TOL <= lam) & (lam <= 1.0 + TOL)


def _line_point(ax: Any, ay: Any, bx: Any, by: Any, u: Any, v: Any) -> np.ndarray:
    """``model.point_distance`` of a line."""
    dx, dy = bx - ax, by - ay
    dd = dx * dx + dy * dy
    with np.errstate(divide="ignore", invalid="ignore"):
        t = ((u - ax) * dx + (v - ay) * dy) / dd
    t = np.where(t > 0.0, t, 0.0)
    t = np.where(dd == 0.0, 0.0, np.where(t < 1.0, t, 1.0))
    return hypot(u - ax - t * dx, v - ay - t * dy)


def _arc_point(a: _Arcs, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``model.point_distance`` of an arc."""
    ru, rv = u - a.cx, v - a.cy
    inside = _in_sweep(a, fmap(math.atan2, rv, ru))
    out = np.empty(len(u))
    i, o = np.nonzero(inside)[0], np.nonzero(~inside)[0]
    out[i] = np.abs(hypot(ru[i], rv[i]) - a.r[i])
    d0, d1 = hypot(u[o] - a.p0[0][o], v[o] - a.p0[1][o]), hypot(u[o] - a.p1[0][o], v[o] - a.p1[1][o])
    out[o] = np.where(d1 < d0, d1, d0)
    return out


def _circle_point(a: _Arcs, du: np.ndarray, dv: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``model._circle_point``: (found, u, v)."""
    n = hypot(du, dv)
    found = (n != 0.0) & _in_sweep(a, fmap(math.atan2, dv, du))
    with np.errstate(divide="ignore", invalid="ignore"):
        return found, a.cx + a.r * du / n, a.cy + a.r * dv / n


def _line_circle(px: Any, py: Any, ex: Any, ey: Any, a: _Arcs) -> np.ndarray:
    """Whether ``geometry.intersect._line_circle`` gives a point on both bounded elements."""
    dx, dy = ex - px, ey - py
    dd = dx * dx + dy * dy
    cx, cy, r = a.cx, a.cy, a.r
    with np.errstate(divide="ignore", invalid="ignore"):
        t0 = ((cx - px) * dx + (cy - py) * dy) / dd
        fx, fy = px + t0 * dx, py + t0 * dy
        h = hypot(fx - cx, fy - cy)
        ok = ~((dd == 0.0) | (r <= 0.0)) & ~(h > r + TOL)
        single = (h >= r - TOL * 1e-3) & (np.abs(h - r) <= TOL)
        x = r * r - h * h
        half = np.sqrt(np.where(0.0 > x, 0.0, x)) / np.sqrt(dd)
    hit = np.zeros(len(px), bool)
    for t, sel in ((t0, single), (t0 - half, ~single), (t0 + half, ~single)):
        u, v = (fx, fy) if t is t0 else (px + t * dx, py + t * dy)
        m = np.nonzero(ok & sel)[0]
        if m.size:
            hit[m] |= _on(t[m]) & _on(_param_of(_take(a, m), u[m], v[m]))
    return hit


def _take(a: _Arcs, m: np.ndarray) -> _Arcs:
    out = _Arcs.__new__(_Arcs)
    out.cx, out.cy, out.r, out.a0, out.sweep = a.cx[m], a.cy[m], a.r[m], a.a0[m], a.sweep[m]
    out.p0, out.p1 = (a.p0[0][m], a.p0[1][m]), (a.p1[0][m], a.p1[1][m])
    return out


def _circle_circle(a: _Arcs, b: _Arcs) -> np.ndarray:
    """Whether ``geometry.intersect._circle_circle`` gives a point on both bounded arcs."""
    r1, r2 = a.r, b.r
    d = hypot(a.cx - b.cx, a.cy - b.cy)
    ok = ~((r1 <= 0.0) | (r2 <= 0.0) | (d == 0.0))
    ok &= ~((d > r1 + r2 + TOL) | (d < np.abs(r1 - r2) - TOL))
    with np.errstate(divide="ignore", invalid="ignore"):
        along = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d)
        h2 = r1 * r1 - along * along
        exu, exv = (b.cx - a.cx) * (1.0 / d), (b.cy - a.cy) * (1.0 / d)
    bu, bv = a.cx + exu * along, a.cy + exv * along
    touch = (h2 <= (TOL * 1e-3) ** 2) | (np.abs(d - (r1 + r2)) <= TOL) | (np.abs(d - np.abs(r1 - r2)) <= TOL)
    single = touch & (h2 <= TOL * TOL)
    h = np.sqrt(np.where(0.0 > h2, 0.0, h2))
    eyu, eyv = -exv, exu
    hit = np.zeros(len(d), bool)
    for u, v, sel in ((bu, bv, single), (bu + eyu * h, bv + eyv * h, ~single), (bu - eyu * h, bv - eyv * h, ~single)):
        m = np.nonzero(ok & sel)[0]
        if m.size:
            hit[m] |= _on(_param_of(_take(a, m), u[m], v[m])) & _on(_param_of(_take(b, m), u[m], v[m]))
    return hit


def _line_arc(line: tuple[np.ndarray, ...], a: _Arcs, line_is_tool: bool) -> np.ndarray:
    """``model._pair_distance`` of lines and arcs (either the tool's); ``line``: start, end and
    the points ``point2(0)``, ``point2(1)`` (u and v each) of the lines."""
    lx0, ly0, lx1, ly1, q0u, q0v, q1u, q1v = line
    hit = _line_circle(lx0, ly0, lx1, ly1, a)
    ends = [_arc_point(a, q0u, q0v), _arc_point(a, q1u, q1v), _line_point(lx0, ly0, lx1, ly1, *a.p0),
            _line_point(lx0, ly0, lx1, ly1, *a.p1)]  # fmt: skip
    if not line_is_tool:
        ends = ends[2:] + ends[:2]
    best = np.minimum(np.minimum(ends[0], ends[1]), np.minimum(ends[2], ends[3]))
    s0 = np.column_stack((lx0, ly0))
    d = np.column_stack((lx1, ly1)) - s0
    dd = np.vecdot(d, d)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.vecdot(np.column_stack((a.cx, a.cy)) - s0, d) / dd
    m = np.nonzero((dd > 0.0) & (0.0 <= t) & (t <= 1.0))[0]
    if m.size:
        fu, fv = s0[m, 0] + t[m] * d[m, 0], s0[m, 1] + t[m] * d[m, 1]
        arc = _take(a, m)
        found, pu, pv = _circle_point(arc, fu - arc.cx, fv - arc.cy)
        normal = np.where(found, hypot(pu - fu, pv - fv), np.inf)
        best[m] = np.minimum(best[m], normal)
    return np.where(hit, 0.0, best)


def _arc_arc(a: _Arcs, b: _Arcs) -> np.ndarray:
    """``model._pair_distance`` of two arcs."""
    hit = _circle_circle(a, b)
    ends = [_arc_point(b, *a.p0), _arc_point(b, *a.p1), _arc_point(a, *b.p0), _arc_point(a, *b.p1)]
    best = np.minimum(np.minimum(ends[0], ends[1]), np.minimum(ends[2], ends[3]))
    uu, uv = b.cx - a.cx, b.cy - a.cy
    apart = np.hypot(uu, uv) > 0.0
    for sa in (1.0, -1.0):
        fa, pau, pav = _circle_point(a, sa * uu, sa * uv)
        for sb in (1.0, -1.0):
            fb, pbu, pbv = _circle_point(b, sb * uu, sb * uv)
            best = np.where(apart & fa & fb, np.minimum(best, hypot(pau - pbu, pav - pbv)), best)
    return np.where(hit, 0.0, best)


def _lines(t: SegmentTable, idx: np.ndarray) -> tuple[np.ndarray, ...]:
    u0, v0, u1, v1 = t.ends2()
    return (t.sx[idx], t.sy[idx], t.ex[idx], t.ey[idx], u0[idx], v0[idx], u1[idx], v1[idx])


def arc_pair_distances(
    tool: SegmentTable, part: SegmentTable, pk: np.ndarray, pi: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Distances of the pairs (tool row ``pk``, part row ``pi``) — lines and arcs of non-zero
    plane length, at least one an arc — and which of them are final (the others, NaN, are for
    :func:`~trcopt.verify.model.element_distance`)."""
    dist = np.full(len(pk), np.nan)
    ka, kb = tool.kind[pk], part.kind[pi]
    groups = (((ka == LINE) & (kb == ARC), "la"), ((ka == ARC) & (kb == LINE), "al"), ((ka == ARC) & (kb == ARC), "aa"))
    for sel, fn in groups:
        m = np.nonzero(sel)[0]
        if m.size == 0:
            continue
        k, i = pk[m], pi[m]
        if fn == "la":
            dist[m] = _line_arc(_lines(tool, k), _Arcs(part, i), True)
        elif fn == "al":
            dist[m] = _line_arc(_lines(part, i), _Arcs(tool, k), False)
        else:
            dist[m] = _arc_arc(_Arcs(tool, k), _Arcs(part, i))
    return dist, ~np.isnan(dist)
