"""Circles tangent to two plane elements: the geometry of a circular blend at a line–arc or
arc–arc corner (:mod:`trcopt.optimize.corners.fillet`).

The centres of the circles of radius r tangent to an element on one side are an offset of it: a
parallel line, or a concentric circle of radius R ∓ r; the blend's centre is where the two offsets
meet (closed form: line–circle and circle–circle intersections), its tangent points are the feet
of the centre on the elements.
"""

from __future__ import annotations

import math

from trcopt.geometry import Arc, Line

__all__ = ["distance_back", "foot", "intersections", "offset_locus"]

Locus = tuple[str, tuple[float, ...]]  # ("line", (x0, y0, dx, dy)) or ("circle", (cx, cy, radius))


def offset_locus(g: Line | Arc, side: float, r: float) -> Locus:
    """The centres of circles of radius ``r`` tangent to ``g`` on ``side`` (+1 left of travel)."""
    if isinstance(g, Line):
        d = g.direction2()
        n = (-d[1] * side, d[0] * side)
        return "line", (g.start[0] + r * n[0], g.start[1] + r * n[1], d[0], d[1])
    left_is_inside = g.sweep > 0
    radius = g.radius - r if (side > 0) == left_is_inside else g.radius + r
    return "circle", (g.center[0], g.center[1], radius)


def intersections(p: Locus, q: Locus) -> list[tuple[float, float]]:
    if p[0] == "line" and q[0] == "line":
        return []
    if p[0] == "circle" and q[0] == "line":
        p, q = q, p
    if p[0] == "line":
        x0, y0, dx, dy = p[1]
        cx, cy, rad = q[1]
        if rad <= 0.0:
            return []
        fx, fy = x0 - cx, y0 - cy
        b = fx * dx + fy * dy
        c = fx * fx + fy * fy - rad * rad
        disc = b * b - c
        if disc < 0.0:
            return []
        root = math.sqrt(disc)
        return [(x0 + t * dx, y0 + t * dy) for t in (-b - root, -b + root)]
    ax, ay, ra = p[1]
    bx, by, rb = q[1]
    dist = math.hypot(bx - ax, by - ay)
    if ra <= 0.0 or rb <= 0.0 or dist == 0.0 or dist > ra + rb or dist < abs(ra - rb):
        return []
    along = (ra * ra - rb * rb + dist * dist) / (2.0 * dist)
    h = math.sqrt(max(ra * ra - along * along, 0.0))
    mx, my = ax + along * (bx - ax) / dist, ay + along * (by - ay) / dist
    ox, oy = -(by - ay) / dist * h, (bx - ax) / dist * h
    return [(mx + ox, my + oy), (mx - ox, my - oy)]


def foot(g: Line | Arc, c: tuple[float, float]) -> tuple[float, float]:
    if isinstance(g, Line):
        d = g.direction2()
        t = (c[0] - g.start[0]) * d[0] + (c[1] - g.start[1]) * d[1]
        return g.start[0] + t * d[0], g.start[1] + t * d[1]
    ux, uy = c[0] - g.center[0], c[1] - g.center[1]
    n = math.hypot(ux, uy)
    return g.center[0] + g.radius * ux / n, g.center[1] + g.radius * uy / n


def distance_back(g: Line | Arc, p: tuple[float, float], from_end: bool) -> float | None:
    """Plane length along ``g`` from its end (``from_end``) or start to ``p`` on it; None when ``p``
    is not on the element."""
    if isinstance(g, Line):
        d = g.direction2()
        t = (p[0] - g.start[0]) * d[0] + (p[1] - g.start[1]) * d[1]
        length = g.plane_length
        if not -1e-12 <= t <= length * (1 + 1e-12):
            return None
        return length - t if from_end else t
    lam = g.param_of(p)
    if not -1e-12 <= lam <= 1.0 + 1e-12:
        return None
    return (1.0 - lam) * g.plane_length if from_end else lam * g.plane_length
