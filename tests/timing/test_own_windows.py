"""The own solver over bounded windows gives the whole-section passes' profile bit for bit."""

from __future__ import annotations

import math

import numpy as np
import pytest

from trcopt import Arc, AxisLimits, Line, Machine, Plane, Role, Segment, SourceSpan
from trcopt.config import DEFAULT_MACHINE, PathLimits
from trcopt.timing import time_parameterize
from trcopt.timing.own import solve_own
from trcopt.timing.path import PathArrays
from trcopt.timing.sections import axis_limits, path_speed_caps, segment_feeds, split_sections

AXES = (("X", AxisLimits(250.0, 2000.0)), ("Y", AxisLimits(200.0, 1500.0)), ("Z", AxisLimits(100.0, 1000.0)))
VECTOR = Machine(name="vector", rapid_mm_min=60000.0, axes=AXES, path=PathLimits(120.0, 1800.0))


def seg(g, feed: float) -> Segment:
    return Segment(g, Plane.G17, Role.CONTOUR, SourceSpan("t.ngc", 1, 1, "N10"), feed)


def blended_polyline(n: int, seed: int) -> list[Segment]:
    """A tangent-continuous chain: random lines joined by tangent arcs (one long section), with
    feeds changing along it, so the profile rises and falls many times inside a window."""
    rng = np.random.default_rng(seed)
    out: list[Segment] = []
    p = np.zeros(2)
    heading = 0.0
    for _ in range(n):
        feed = float(rng.choice([20.0, 60.0, 150.0, 400.0]))
        length = float(rng.uniform(0.2, 8.0))
        q = p + length * np.array([math.cos(heading), math.sin(heading)])
        out.append(seg(Line((*p, 0.0), (*q, 0.0)), feed))
        turn = float(rng.uniform(-2.5, 2.5))
        r = float(rng.uniform(0.3, 20.0))
        side = 1.0 if turn > 0 else -1.0
        centre = q + side * r * np.array([-math.sin(heading), math.cos(heading)])
        a0 = math.atan2(q[1] - centre[1], q[0] - centre[0])
        arc = Arc(tuple(centre), r, a0, turn)
        out.append(seg(arc, feed))
        heading += turn
        p = np.array(arc.end[:2])
    return out


def profiles(path: list[Segment], machine: Machine, window: int | None) -> dict:
    arrays = PathArrays(path)
    speed = path_speed_caps(segment_feeds(path, machine), machine)
    vmax, amax = axis_limits(machine)
    secs = split_sections(path, arrays, 1e-6)
    solved, failed = solve_own(secs, arrays, speed, vmax, amax, machine.path.amax_mm_s2, window=window)
    assert not failed
    return solved


@pytest.mark.parametrize("machine", [DEFAULT_MACHINE, VECTOR], ids=["axes", "vector"])
@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("window", [8, 33, 200])
def test_windows_reproduce_the_whole_section_solve(machine, seed, window):
    path = blended_polyline(60, seed)
    whole = profiles(path, machine, None)
    parts = profiles(path, machine, window)
    assert whole.keys() == parts.keys()
    assert len(whole) == 1  # one tangent-continuous section, much longer than the window
    for k, (s, x, iseg) in whole.items():
        s2, x2, iseg2 = parts[k]
        assert s2.shape[0] > 4 * window or window == 200
        np.testing.assert_array_equal(s2, s)
        np.testing.assert_array_equal(x2, x)
        np.testing.assert_array_equal(iseg2, iseg)


def test_many_short_sections_in_bounded_groups():
    # a polyline of sharp corners: every line is its own section (speed 0 at each corner)
    pts = [(0.0, 0.0), (10.0, 0.0), (10.0, 3.0), (0.5, 3.0), (0.5, 9.0), (7.0, 2.0), (1.0, 1.0)]
    path = [seg(Line((*a, 0.0), (*b, 0.0)), 300.0) for a, b in zip(pts, pts[1:], strict=False)]
    path += [seg(Arc((1.0, 2.0), 1.0, -math.pi / 2, 3.0), 300.0)]
    arrays = PathArrays(path)
    speed = path_speed_caps(segment_feeds(path, DEFAULT_MACHINE), DEFAULT_MACHINE)
    vmax, amax = axis_limits(DEFAULT_MACHINE)
    secs = split_sections(path, arrays, 1e-6)
    whole, _ = solve_own(secs, arrays, speed, vmax, amax, window=None)
    small, _ = solve_own(secs, arrays, speed, vmax, amax, window=8, group_budget=8)
    for k in whole:
        for a, b in zip(whole[k], small[k], strict=True):
            np.testing.assert_array_equal(a, b)


def test_time_parameterize_uses_the_windows_and_keeps_the_limits():
    path = blended_polyline(400, 7)
    traj = time_parameterize(path, VECTOR)
    assert traj.duration > 0
    rep = traj.check_limits(dt=1e-3)
    assert rep.ok, str(rep)


def test_every_interval_lies_on_its_own_segment_after_toppra():
    """A section with a Poly (here a blend in space between a plunge and the contour) timed by
    toppra, whose grid points on the knots round to either side; every interval must still be
    evaluated on the segment it lies on (an interval assigned to the curve before it evaluated
    that curve far beyond its end: 37× the Z acceleration limit, wrong positions in the samples)."""
    from trcopt.pipeline import PlanOptions, plan

    lines = ["G21 G17 G90 G40 F6000", "G0 X50 Y0 Z1", "G1 Z0"]
    for i in range(401):
        t = 2 * math.pi * i / 400
        r = 30 + 5 * math.sin(5 * t) + 2 * math.cos(11 * t)
        lines.append(f"G1 X{r * math.cos(t):.5f} Y{r * math.sin(t):.5f}")
    text = "\n".join([*lines, "G0 Z5", "M2"]) + "\n"
    res = plan(text, file="cam.ngc", options=PlanOptions(corners="arc", tolerance_mm=0.01, verify=False, timing=False))
    traj = time_parameterize(res.toolpath, engine="toppra")  # the own solver times Poly sections too
    assert "toppra" in traj.engines
    start = traj.arrays.start
    length = traj.arrays.length
    mid = 0.5 * (traj.s[:-1] + traj.s[1:])
    k = traj.iseg
    assert np.all(mid >= start[k] - 1e-9) and np.all(mid <= start[k] + length[k] + 1e-9)
    rep = traj.check_limits(dt=1e-3)
    assert rep.ok, str(rep)
