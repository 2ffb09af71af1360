"""Jerk-limited feed against the closed-form double-S (spec timing.md §4.2, §6.2c: B1 and B7)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from trcopt import AxisLimits, Line, Machine, Plane, Role, Segment, SourceSpan
from trcopt.timing import time_parameterize
from trcopt.timing.doubles import double_s_line_time, double_s_polyline_time, double_s_time, line_limits
from trcopt.timing.jerk import jerk_limited

ISO = Machine(
    name="isotropic",
    rapid_mm_min=12000.0,
    axes=(
        ("X", AxisLimits(200.0, 2000.0, 5e4)),
        ("Y", AxisLimits(200.0, 2000.0, 5e4)),
        ("Z", AxisLimits(200.0, 2000.0, 5e4)),
    ),
)
ANISO = Machine(
    name="anisotropic",
    rapid_mm_min=15000.0,
    axes=(
        ("X", AxisLimits(250.0, 3000.0, 5e4)),
        ("Y", AxisLimits(200.0, 2000.0, 5e4)),
        ("Z", AxisLimits(100.0, 1000.0, 5e4)),
    ),
)


def seg(g, feed, n=0):
    return Segment(g, Plane.G17, Role.CONTOUR, SourceSpan("t.mpf", n + 1, 1, f"N{10 * (n + 1)}"), feed)


# -- the closed form itself --------------------------------------------------------------------------
def test_double_s_cruise_case():
    # v J = 200·5e4 ≥ a² → Ta = v/a + a/J = 0.1 + 0.04; L ≥ v Ta → T = L/v + Ta
    assert double_s_time(50.0, 200.0, 2000.0, 5e4) == pytest.approx(50 / 200 + 0.14, rel=1e-12)


def test_double_s_short_move_has_no_cruise():
    # L = 0.2 mm: acceleration never reaches a, the profile is four jerk phases: T = 4·(L/(2J))^(1/3)
    assert double_s_time(0.2, 200.0, 2000.0, 5e4) == pytest.approx(4 * (0.2 / (2 * 5e4)) ** (1 / 3), rel=1e-9)


def test_double_s_is_slower_than_the_trapezoid_by_a_over_j_on_long_moves():
    trap = 50 / 200 + 200 / 2000
    assert double_s_time(50.0, 200.0, 2000.0, 5e4) - trap == pytest.approx(2000 / 5e4, rel=1e-12)


def test_line_limits_project_per_axis():
    c = math.cos(math.radians(30))
    v, a, j = line_limits((c, 0.5, 0.0), ANISO, 250.0)
    assert v == pytest.approx(min(250 / c, 200 / 0.5, 250.0))
    assert a == pytest.approx(min(3000 / c, 2000 / 0.5))
    assert j == pytest.approx(5e4 / c)


# -- B1: single lines -------------------------------------------------------------------------------
B1 = [(ang, L) for ang in (0, 30, 45) for L in (0.2, 2.0, 50.0)]


@pytest.mark.parametrize("machine", [ISO, ANISO], ids=["iso", "aniso"])
@pytest.mark.parametrize(("ang", "length"), B1, ids=[f"{a}deg-L{L}" for a, L in B1])
def test_b1_line_within_2_percent_of_double_s(ang, length, machine):
    t = (math.cos(math.radians(ang)), math.sin(math.radians(ang)), 0.0)
    path = [seg(Line((0.0, 0.0, 0.0), tuple(length * c for c in t)), 250.0)]
    ref = double_s_line_time((0, 0, 0), path[0].geometry.end, machine, 250.0)
    traj = jerk_limited(path, machine)
    assert traj.duration >= ref * (1 - 1e-6)  # the double-S is the optimum
    assert traj.duration <= 1.02 * ref
    assert traj.duration == pytest.approx(ref, rel=5e-3)  # measured: ≤ 1e-3
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok, str(rep)
    assert max(rep.jerk_ratio) <= 1.01 and max(rep.a_ratio) <= 1.001 and max(rep.v_ratio) <= 1.001
    assert rep.feed_ratio <= 1.001


# -- B7: square with sharp corners (stop at every corner) ---------------------------------------------
@pytest.mark.parametrize("machine", [ISO, ANISO], ids=["iso", "aniso"])
def test_b7_square_is_the_sum_of_double_s(machine):
    pts = [(0.0, 0.0, 0.0), (40.0, 0.0, 0.0), (40.0, 40.0, 0.0), (0.0, 40.0, 0.0), (0.0, 0.0, 0.0)]
    path = [seg(Line(a, b), 200.0, i) for i, (a, b) in enumerate(zip(pts, pts[1:], strict=False))]
    ref = double_s_polyline_time(pts, machine, 200.0)
    base = time_parameterize(path, machine)
    traj = jerk_limited(path, machine, base=base)
    assert len(traj.sections) == 4
    assert ref * (1 - 1e-6) <= traj.duration <= 1.02 * ref
    assert traj.duration == pytest.approx(ref, rel=5e-3)
    assert traj.duration > base.duration  # T_jerk ≥ T_acc (spec §4.6)
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok and rep.corner_speed_mm_s <= 1e-6, str(rep)
    # at every corner the tool is at rest with zero path acceleration
    for sol in traj.solutions:
        p = sol.geometry
        assert p.v[0] == 0.0 and p.v[-1] == 0.0 and p.a[0] == 0.0 and p.a[-1] == 0.0


@settings(max_examples=8, derandomize=True, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    ang=st.floats(0.0, 360.0),
    length=st.floats(0.05, 80.0),
    feed=st.floats(20.0, 300.0),
)
def test_random_lines_match_double_s(ang, length, feed):
    t = (math.cos(math.radians(ang)), math.sin(math.radians(ang)), 0.0)
    path = [seg(Line((1.0, 2.0, 0.0), (1.0 + length * t[0], 2.0 + length * t[1], 0.0)), feed)]
    ref = double_s_time(length, *line_limits(np.array(t), ANISO, feed))
    traj = jerk_limited(path, ANISO)
    assert ref * (1 - 1e-6) <= traj.duration <= 1.02 * ref
    assert traj.check_limits(dt=2e-4).ok
