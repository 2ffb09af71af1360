"""Closed-form ground truth of spec timing.md §4 (B1, B2, B4 feed-limited, B7) to 1e-3 relative."""

from __future__ import annotations

import math

import numpy as np
import pytest

from trcopt import Arc, AxisLimits, Line, Machine, Plane, Role, Segment, SourceSpan
from trcopt.timing import time_parameterize

ISO = Machine(
    name="iso", rapid_mm_min=12000.0,
    axes=(("X", AxisLimits(200.0, 2000.0)), ("Y", AxisLimits(200.0, 2000.0)), ("Z", AxisLimits(200.0, 2000.0))),
)
ANISO = Machine(
    name="aniso", rapid_mm_min=15000.0,
    axes=(("X", AxisLimits(250.0, 3000.0)), ("Y", AxisLimits(200.0, 2000.0)), ("Z", AxisLimits(100.0, 1000.0))),
)


def seg(g, feed=250.0, block="N10"):
    return Segment(g, Plane.G17, Role.CONTOUR, SourceSpan("t.mpf", 1, 1, block), feed)


def line_limits(machine, t, feed):
    vmax = np.array([machine.axis(k).vmax_mm_s for k in "XYZ"])
    amax = np.array([machine.axis(k).amax_mm_s2 for k in "XYZ"])
    with np.errstate(divide="ignore"):
        v = min(feed, float((vmax / np.abs(t)).min()))
        a = float((amax / np.abs(t)).min())
    return v, a


def rest_to_rest(length, v, a):
    return length / v + v / a if length >= v * v / a else 2.0 * math.sqrt(length / a)


@pytest.mark.parametrize("machine", [ISO, ANISO], ids=["iso", "aniso"])
@pytest.mark.parametrize("angle", [0.0, 30.0, 45.0])
@pytest.mark.parametrize("length", [0.2, 2.0, 50.0])
def test_b1_single_line(machine, angle, length):
    t = np.array([math.cos(math.radians(angle)), math.sin(math.radians(angle)), 0.0])
    line = Line((1.0, 2.0, 0.0), tuple(np.array([1.0, 2.0, 0.0]) + length * t))
    traj = time_parameterize([seg(line, 250.0)], machine)
    v, a = line_limits(machine, t, 250.0)
    assert traj.duration == pytest.approx(rest_to_rest(length, v, a), rel=1e-3)
    assert traj.check_limits().ok


@pytest.mark.parametrize("engine", ["own", "toppra"])
@pytest.mark.parametrize("radius", [1.0, 5.0, 50.0])
def test_b2_line_arc_line_feed_limited(engine, radius):
    feed = 0.8 * math.sqrt(2000.0 * radius) if radius < 20 else 150.0
    l1 = Line((-30.0, -radius, 0.0), (0.0, -radius, 0.0))
    arc = Arc((0.0, 0.0), radius, -math.pi / 2, math.pi)
    l2 = Line((0.0, radius, 0.0), (-30.0, radius, 0.0))
    traj = time_parameterize([seg(l1, feed), seg(arc, feed), seg(l2, feed)], ISO, engine=engine)
    total = 60.0 + math.pi * radius
    expected = total / feed + feed / 4000.0 + feed / 4000.0
    assert len(traj.sections) == 1
    assert traj.duration == pytest.approx(expected, rel=1e-3)
    assert traj.check_limits().ok


@pytest.mark.parametrize("machine", [ISO, ANISO], ids=["iso", "aniso"])
def test_b4_full_circle_feed_limited(machine):
    circle = Arc((0.0, 0.0), 10.0, 0.0, 2 * math.pi)
    traj = time_parameterize([seg(circle, 50.0)], machine)
    # the ramp starts along +Y (tangent at angle 0): a = amax_Y
    expected = 2 * math.pi * 10.0 / 50.0 + 50.0 / machine.axis("Y").amax_mm_s2
    assert traj.duration == pytest.approx(expected, rel=1e-3)
    assert traj.check_limits().ok


def test_b4_acceleration_limited_circle_lp_value():
    circle = Arc((0.0, 0.0), 10.0, 0.0, 2 * math.pi)
    traj = time_parameterize([seg(circle, 250.0)], ISO)
    assert traj.engines == ["own"]  # no silent fallback to toppra
    assert traj.duration == pytest.approx(0.505096, rel=2e-3)  # spec §4.3 LP at N=80 000; target CTR ≤ 1.005


@pytest.mark.parametrize("machine", [ISO, ANISO], ids=["iso", "aniso"])
def test_b7_square_exact_stop(machine):
    pts = [(0, 0), (40, 0), (40, 40), (0, 40), (0, 0)]
    path = [
        seg(Line((a[0], a[1], 0.0), (b[0], b[1], 0.0)), 200.0, f"N{10 * i}")
        for i, (a, b) in enumerate(zip(pts, pts[1:], strict=False))
    ]
    traj = time_parameterize(path, machine)
    expected = 0.0
    for a, b in zip(pts, pts[1:], strict=False):
        d = np.array([b[0] - a[0], b[1] - a[1], 0.0]) / 40.0
        expected += rest_to_rest(40.0, *line_limits(machine, d, 200.0))
    assert traj.duration == pytest.approx(expected, rel=1e-3)
    if machine is ISO:
        assert traj.duration == pytest.approx(1.2, rel=1e-3)
    assert len(traj.sections) == 4
