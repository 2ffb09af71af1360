"""Small closed-form 2D vector helpers on tuples (fast, allocation-light)."""

from __future__ import annotations

import math

Vec2 = tuple[float, float]
Vec3 = tuple[float, float, float]
TWO_PI = 2.0 * math.pi


def sub(a: Vec2, b: Vec2) -> Vec2:
    return (a[0] - b[0], a[1] - b[1])


def add(a: Vec2, b: Vec2) -> Vec2:
    return (a[0] + b[0], a[1] + b[1])


def scale(a: Vec2, k: float) -> Vec2:
    return (a[0] * k, a[1] * k)


def dot(a: Vec2, b: Vec2) -> float:
    return a[0] * b[0] + a[1] * b[1]


def cross(a: Vec2, b: Vec2) -> float:
    return a[0] * b[1] - a[1] * b[0]


def norm(a: Vec2) -> float:
    return math.hypot(a[0], a[1])


def dist(a: Vec2, b: Vec2) -> float:
    return math.hypot(a[0] - b[0], a[1] - b[1])


def unit(a: Vec2) -> Vec2:
    n = math.hypot(a[0], a[1])
    if n == 0.0:
        raise ZeroDivisionError("unit vector of a zero vector")
    return (a[0] / n, a[1] / n)


def rot90(a: Vec2) -> Vec2:
    """Counter-clockwise rotation by 90° (the left normal of a tangent)."""
    return (-a[1], a[0])


def polar(center: Vec2, radius: float, angle: float) -> Vec2:
    return (center[0] + radius * math.cos(angle), center[1] + radius * math.sin(angle))


def angle_of(a: Vec2) -> float:
    return math.atan2(a[1], a[0])


def deflection(t1: Vec2, t2: Vec2) -> float:
    """Signed turning angle from tangent t1 to t2, in (−π, π]."""
    d = math.atan2(cross(t1, t2), dot(t1, t2))
    return math.pi if d == -math.pi else d


def wrap_positive(angle: float) -> float:
    """Angle in [0, 2π)."""
    a = math.fmod(angle, TWO_PI)
    if a < 0.0:
        a += TWO_PI
    if a >= TWO_PI:
        a -= TWO_PI
    return a


def bisector_foot(start: Vec2, end: Vec2, centre: Vec2) -> Vec2:
    """The point of the perpendicular bisector of the chord ``start``–``end`` nearest ``centre``
    (the centre of a circle through both points nearest a given one); ``centre`` for a zero chord."""
    chord = math.hypot(end[0] - start[0], end[1] - start[1])
    if chord == 0.0:
        return centre
    mu, mv = 0.5 * (start[0] + end[0]), 0.5 * (start[1] + end[1])
    nu, nv = -(end[1] - start[1]) / chord, (end[0] - start[0]) / chord
    h = (centre[0] - mu) * nu + (centre[1] - mv) * nv
    return (mu + h * nu, mv + h * nv)
