"""Benchmark paths B1–B9 of spec timing.md §6 (tool-centre geometry built from Line/Arc)."""

from __future__ import annotations

import math

import numpy as np

from trcopt import Arc, AxisLimits, Line, Machine, Plane, Role, Segment, SourceSpan

ISO = Machine(
    name="isotropic", rapid_mm_min=12000.0,
    axes=(
        ("X", AxisLimits(200.0, 2000.0, 5e4)),
        ("Y", AxisLimits(200.0, 2000.0, 5e4)),
        ("Z", AxisLimits(200.0, 2000.0, 5e4)),
    ),
)
ANISO = Machine(
    name="anisotropic", rapid_mm_min=15000.0,
    axes=(
        ("X", AxisLimits(250.0, 3000.0, 5e4)),
        ("Y", AxisLimits(200.0, 2000.0, 5e4)),
        ("Z", AxisLimits(100.0, 1000.0, 5e4)),
    ),
)


def seg(g, feed, n=0):
    return Segment(g, Plane.G17, Role.CONTOUR, SourceSpan("bench", n + 1, 1, f"N{10 * (n + 1)}"), feed)


def polyline(pts, feed):
    return [
        seg(Line((a[0], a[1], 0.0), (b[0], b[1], 0.0)), feed, i)
        for i, (a, b) in enumerate(zip(pts, pts[1:], strict=False))
    ]


def line_arc_line(R, feed):
    return [
        seg(Line((-30.0, -R, 0.0), (0.0, -R, 0.0)), feed, 0),
        seg(Arc((0.0, 0.0), R, -math.pi / 2, math.pi), feed, 1),
        seg(Line((0.0, R, 0.0), (-30.0, R, 0.0)), feed, 2),
    ]


def rounded_rect(w, h, r, feed, lead_r=None):
    """Tool-centre path around a w×h rectangle offset by r (G41 outside, corner arcs), with a
    tangential quarter-circle lead-in and lead-out of radius ``lead_r`` in the middle of the bottom side."""
    out = []
    x0, y0 = 0.0, -r
    segs = []
    if lead_r:
        c = (x0, y0 + lead_r)  # lead-in arc ends at (x0, y0) heading +X, turning left (CCW)
        segs.append(Arc(c, lead_r, math.pi, math.pi / 2))
    segs += [
        Line((x0, y0, 0.0), (w / 2, y0, 0.0)),
        Arc((w / 2, 0.0), r, -math.pi / 2, math.pi / 2),
        Line((w / 2 + r, 0.0, 0.0), (w / 2 + r, h, 0.0)),
        Arc((w / 2, h), r, 0.0, math.pi / 2),
        Line((w / 2, h + r, 0.0), (-w / 2, h + r, 0.0)),
        Arc((-w / 2, h), r, math.pi / 2, math.pi / 2),
        Line((-w / 2 - r, h, 0.0), (-w / 2 - r, 0.0, 0.0)),
        Arc((-w / 2, 0.0), r, math.pi, math.pi / 2),
        Line((-w / 2, -r, 0.0), (x0, y0, 0.0)),
    ]
    if lead_r:
        c = (x0, y0 + lead_r)
        segs.append(Arc(c, lead_r, -math.pi / 2, math.pi / 2))
    for i, g in enumerate(segs):
        out.append(seg(g, feed, i))
    return out


def blended_square(side, delta, feed):
    phi = math.pi / 2
    r = delta * math.cos(phi / 2) / (1 - math.cos(phi / 2))
    t = r  # tangent distance r / tan(θ/2) with θ = 90°
    pts = [(0, 0), (side, 0), (side, side), (0, side)]
    out = []
    n = 0
    for k in range(4):
        a, b = np.array(pts[k], float), np.array(pts[(k + 1) % 4], float)
        d = (b - a) / side
        out.append(seg(Line((*(a + d * t), 0.0), (*(b - d * t), 0.0)), feed, n))
        n += 1
        nxt = np.array(pts[(k + 2) % 4], float)
        d2 = (nxt - b) / side
        centre = b - d * t + np.array([-d[1], d[0]]) * r
        a0 = math.atan2(-d[0], d[1])  # start point relative to centre: -left normal
        out.append(seg(Arc((float(centre[0]), float(centre[1])), r, a0, math.pi / 2), feed, n))
        n += 1
        del d2
    return out


def random_program(n, seed, feed=None):
    """Seeded random tool-centre program: lines and arcs, lengths log-uniform 0.05–50 mm,
    half of the joints tangent, the others corners of 20°–150°."""
    rng = np.random.default_rng(seed)
    p = np.zeros(2)
    heading = 0.0
    out = []
    for i in range(n):
        f = float(rng.choice([83.33, 150.0, 250.0])) if feed is None else feed
        if i and rng.random() < 0.5:
            heading += float(rng.uniform(20, 150)) * math.pi / 180 * rng.choice([-1, 1])
        length = float(np.exp(rng.uniform(math.log(0.05), math.log(50.0))))
        if rng.random() < 0.5:
            q = p + length * np.array([math.cos(heading), math.sin(heading)])
            out.append(seg(Line((p[0], p[1], 0.0), (q[0], q[1], 0.0)), f, i))
            p = q
        else:
            sweep = float(rng.uniform(0.2, 3.0)) * rng.choice([-1, 1])
            r = length / abs(sweep)
            side = 1.0 if sweep > 0 else -1.0
            c = p + r * side * np.array([-math.sin(heading), math.cos(heading)])
            a0 = math.atan2(p[1] - c[1], p[0] - c[0])
            arc = Arc((float(c[0]), float(c[1])), r, a0, sweep)
            out.append(seg(arc, f, i))
            p = np.array(arc.end[:2])
            heading += sweep
    return out


def families(big=False):
    """(family, case, segments, closed_form(machine) or None)."""
    cases = []
    for ang in (0, 30, 45):
        for L in (0.2, 2.0, 50.0):
            t = np.array([math.cos(math.radians(ang)), math.sin(math.radians(ang)), 0.0])
            path = [seg(Line((0.0, 0.0, 0.0), tuple(L * t)), 250.0)]

            def cf(m, t=t, L=L):
                v, a = _line_va(m, t, 250.0)
                return L / v + v / a if L >= v * v / a else 2 * math.sqrt(L / a)

            cases.append(("B1", f"line {ang}deg L={L}", path, cf))
    for R in (1.0, 5.0, 50.0):
        F = min(0.8 * math.sqrt(2000.0 * R), 150.0)
        cases.append(("B2", f"R={R} F={F:.1f}", line_arc_line(R, F),
                      lambda m, R=R, F=F: (60 + math.pi * R) / F + F / m.axis("X").amax_mm_s2))
        cases.append(("B3", f"R={R} F=250", line_arc_line(R, 250.0), None))
    circle = Arc((0.0, 0.0), 10.0, 0.0, 2 * math.pi)
    cases.append(("B4", "circle R=10 F=50", [seg(circle, 50.0)],
                  lambda m: 2 * math.pi * 10 / 50 + 50 / m.axis("Y").amax_mm_s2))
    cases.append(("B4", "circle R=10 F=250", [seg(circle, 250.0)], None))
    helix = Arc((0.0, 0.0), 10.0, 0.0, 6 * math.pi, 0.0, -6.0)
    cases.append(("B5", "helix R=10 pitch 2 x3", [seg(helix, 250.0)], None))
    for F in (83.33, 250.0):
        cases.append(("B6", f"G41 outside contour F={F}", rounded_rect(40.0, 30.0, 3.0, F, lead_r=5.0), None))
    sq = [(0, 0), (40, 0), (40, 40), (0, 40), (0, 0)]

    def cf7(m):
        tot = 0.0
        for a, b in zip(sq, sq[1:], strict=False):
            d = np.array([b[0] - a[0], b[1] - a[1], 0.0]) / 40.0
            v, acc = _line_va(m, d, 200.0)
            tot += 40 / v + v / acc
        return tot

    cases.append(("B7", "square 40 sharp", polyline(sq, 200.0), cf7))
    for d in (0.01, 0.05):
        cases.append(("B8", f"square blend d={d}", blended_square(40.0, d, 200.0), None))
    cases.append(("B9", "random 50 (LP subsample)", random_program(50, 7), None))
    cases.append(("B9", "random 1000", random_program(1000, 1), "throughput"))
    if big:
        cases.append(("B9", "random 10000", random_program(10000, 2), "throughput"))
    return cases


def _line_va(m, t, feed):
    vmax = np.array([m.axis(k).vmax_mm_s for k in "XYZ"])
    amax = np.array([m.axis(k).amax_mm_s2 for k in "XYZ"])
    with np.errstate(divide="ignore"):
        return min(feed, float((vmax / np.abs(t)).min())), float((amax / np.abs(t)).min())
