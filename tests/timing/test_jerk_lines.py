"""Jerk-limited feed: closed-form line sections (double-S) and the NLP's shared rows and IPOPT options."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from trcopt import Arc, AxisLimits, Line, Machine, Plane, Role, Segment, SourceSpan
from trcopt.config import PathLimits
from trcopt.timing import time_parameterize
from trcopt.timing.doubles import double_s_phases, double_s_time, line_limits
from trcopt.timing.jerk import jerk_limited
from trcopt.timing.jerk_lines import SOLVER, line_section_limits
from trcopt.timing.jerk_problem import JerkProblem
from trcopt.timing.path import PathArrays
from trcopt.timing.sections import axis_limits, segment_feeds, split_sections

J = 5e4
ISO = Machine(
    name="iso",
    rapid_mm_min=12000.0,
    axes=tuple((k, AxisLimits(200.0, 2000.0, J)) for k in "XYZ"),
)
ANISO = Machine(
    name="aniso",
    rapid_mm_min=15000.0,
    axes=(
        ("X", AxisLimits(250.0, 3000.0, J)),
        ("Y", AxisLimits(200.0, 2000.0, J)),
        ("Z", AxisLimits(100.0, 1000.0, J)),
    ),
)
GENEROUS = tuple((k, AxisLimits(1e4, 1e6, 1e8)) for k in "XYZ")
VECTOR = Machine(name="vector", rapid_mm_min=60000.0, axes=GENEROUS, path=PathLimits(100.0, 3000.0, 60000.0))


def seg(g, feed=150.0, block="N10"):
    return Segment(g, Plane.G17, Role.CONTOUR, SourceSpan("t.mpf", 3, 1, block), feed)


def integrate(h, jj):
    s = v = a = 0.0
    vs, acc = [0.0], [0.0]
    for hi, ji in zip(h, jj, strict=True):
        s, v, a = s + v * hi + a * hi * hi / 2 + ji * hi**3 / 6, v + a * hi + ji * hi * hi / 2, a + ji * hi
        vs.append(v)
        acc.append(a)
    return s, np.array(vs), np.array(acc)


# -- the phases of the double-S -----------------------------------------------------------------------
@pytest.mark.parametrize(
    ("length", "v", "a", "j"),
    [
        (50.0, 200.0, 2000.0, J),  # cruise at v, acceleration reaches a
        (2.0, 200.0, 2000.0, J),  # no cruise, acceleration reaches a
        (0.2, 200.0, 2000.0, J),  # no cruise, acceleration stays below a
        (50.0, 20.0, 2000.0, J),  # cruise, acceleration stays below a (v·J < a²)
        (1e-4, 200.0, 2000.0, J),
    ],
)
def test_double_s_phases_end_at_rest_after_the_length_in_the_double_s_time(length, v, a, j):
    h, jj = double_s_phases(length, v, a, j)
    assert h.shape[0] <= 7 and np.all(h > 0) and set(np.abs(jj)) <= {0.0, j}
    s, vs, acc = integrate(h, jj)
    assert s == pytest.approx(length, rel=1e-12)
    assert abs(vs[-1]) <= 1e-9 * v and abs(acc[-1]) <= 1e-9 * a
    assert vs.max() <= v * (1 + 1e-12) and np.abs(acc).max() <= a * (1 + 1e-12)
    # the closed form of the peak speed against a bisection of vp·Ta(vp) = L
    ta = lambda vp: vp / a + a / j if vp * j >= a * a else 2 * math.sqrt(vp / j)  # noqa: E731
    lo, hi = 0.0, v
    for _ in range(200):
        lo, hi = ((lo + hi) / 2, hi) if (lo + hi) / 2 * ta((lo + hi) / 2) < length else (lo, (lo + hi) / 2)
    ref = length / v + ta(v) if length >= v * ta(v) else 2 * ta(lo)
    assert h.sum() == pytest.approx(ref, rel=1e-9) and double_s_time(length, v, a, j) == h.sum()


def test_double_s_phases_reject_a_zero_length():
    with pytest.raises(ValueError):
        double_s_phases(0.0, 1.0, 1.0, 1.0)


# -- line sections in jerk_limited --------------------------------------------------------------------
@settings(max_examples=12, derandomize=True, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(ang=st.floats(0.0, 360.0), length=st.floats(0.05, 80.0), feed=st.floats(20.0, 300.0))
def test_line_section_is_the_double_s_and_passes_every_check(ang, length, feed):
    t = (math.cos(math.radians(ang)), math.sin(math.radians(ang)), 0.0)
    path = [seg(Line((1.0, 2.0, 0.0), (1.0 + length * t[0], 2.0 + length * t[1], 0.0)), feed)]
    traj = jerk_limited(path, ANISO)
    (sol,) = traj.solutions
    assert sol.solver == SOLVER and sol.iterations == 0 and sol.ok
    assert traj.duration == pytest.approx(double_s_time(length, *line_limits(np.array(t), ANISO, feed)), rel=1e-9)
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok, str(rep)
    assert max(rep.jerk_ratio) <= 1 + 1e-9 and max(rep.a_ratio) <= 1 + 1e-9 and rep.feed_ratio <= 1 + 1e-9


@pytest.mark.parametrize("machine", [ISO, ANISO], ids=["iso", "aniso"])
@pytest.mark.parametrize("length", [0.2, 2.0, 50.0])
def test_closed_form_line_is_never_slower_than_the_nlp_and_within_one_percent(machine, length):
    t = (math.cos(math.radians(30)), math.sin(math.radians(30)), 0.0)
    path = [seg(Line((0.0, 0.0, 0.0), tuple(length * c for c in t)), 250.0)]
    base = time_parameterize(path, machine)
    closed = jerk_limited(path, machine, base=base)
    nlp = jerk_limited(path, machine, base=base, closed_form=False)
    assert nlp.solutions[0].solver == "ipopt" and closed.solutions[0].solver == SOLVER
    assert closed.duration <= nlp.duration * (1 + 1e-9)
    assert nlp.duration <= 1.01 * closed.duration


def test_collinear_lines_with_one_feed_are_one_double_s_split_at_the_joints():
    xs = [0.0, 1.0, 1.3, 21.3]
    path = [
        seg(Line((a, 0.0, 0.0), (b, 0.0, 0.0)), 200.0, f"N{10 * (i + 1)}")
        for i, (a, b) in enumerate(zip(xs, xs[1:], strict=False))
    ]
    traj = jerk_limited(path, ISO)
    assert len(traj.sections) == 1 and traj.solutions[0].solver == SOLVER
    assert traj.duration == pytest.approx(double_s_time(21.3, 200.0, 2000.0, J), rel=1e-9)
    # every interval lies on its own segment, and every segment has intervals
    start, length = traj.arrays.start[traj.iseg], traj.arrays.length[traj.iseg]
    assert np.all(traj.s0 >= start - 1e-12) and np.all(traj.s1 <= start + length + 1e-12)
    assert set(traj.iseg.tolist()) == {0, 1, 2}
    times = [(sg.t_start_s, sg.t_end_s) for sg in traj.segments_with_times()]
    assert all(a < b for a, b in times) and times[-1][1] == pytest.approx(traj.duration)
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok, str(rep)
    sections = traj.to_json()["sections"]
    assert [s["engine"] for s in sections] == ["double-s"] and sections[0]["iterations"] == 0


def test_collinear_lines_with_different_feeds_and_arcs_go_to_the_nlp():
    path = [seg(Line((0.0, 0.0, 0.0), (5.0, 0.0, 0.0)), 200.0), seg(Line((5.0, 0.0, 0.0), (9.0, 0.0, 0.0)), 80.0)]
    arrays = PathArrays(path)
    vmax, amax = axis_limits(ISO)
    (sec,) = split_sections(path, arrays)
    assert line_section_limits(sec, arrays, segment_feeds(path, ISO), vmax, amax, np.full(3, J)) is None
    traj = jerk_limited(path, ISO)
    assert traj.solutions[0].solver == "ipopt" and traj.check_limits(dt=1e-4).ok
    arc = [seg(Line((-10.0, -5.0, 0.0), (0.0, -5.0, 0.0))), seg(Arc((0.0, 0.0), 5.0, -math.pi / 2, math.pi))]
    mixed = jerk_limited(arc, ISO)
    assert mixed.to_json()["sections"][0]["engine"] == "casadi-ipopt"


@pytest.mark.parametrize("length", [50.0, 2.0])
def test_line_under_vector_limits_is_the_double_s_of_the_vector_limits(length):
    t = np.array([math.cos(0.4), math.sin(0.4), 0.0])
    path = [seg(Line((1.0, 2.0, 0.0), tuple(np.array([1.0, 2.0, 0.0]) + length * t)), 1000.0)]
    traj = jerk_limited(path, VECTOR)
    assert traj.solutions[0].solver == SOLVER
    assert traj.duration == pytest.approx(double_s_time(length, 100.0, 3000.0, 60000.0), rel=1e-9)
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok, str(rep)
    assert rep.path_j_ratio <= 1 + 1e-9 and rep.path_a_ratio <= 1 + 1e-9


# -- the NLP: shared acceleration rows, fast IPOPT options ---------------------------------------------
def line_arc_line(radius=5.0, feed=150.0):
    return [
        seg(Line((-30.0, -radius, 0.0), (0.0, -radius, 0.0)), feed, "N10"),
        seg(Arc((0.0, 0.0), radius, -math.pi / 2, math.pi), feed, "N20"),
        seg(Line((0.0, radius, 0.0), (-30.0, radius, 0.0)), feed, "N30"),
    ]


def problem(fast: bool) -> JerkProblem:
    path = line_arc_line()
    arrays = PathArrays(path)
    (sec,) = split_sections(path, arrays)
    vmax, amax = axis_limits(ISO)
    base = time_parameterize(path, ISO)
    return JerkProblem(sec, arrays, segment_feeds(path, ISO), vmax, amax, np.full(3, J), base.s, base.sd, fast=fast)


def test_acceleration_rows_are_shared_inside_a_segment_but_not_at_knots():
    pb = problem(fast=True)
    shared = pb.shared_nodes()
    g = pb.grid
    assert not shared[-1]
    assert not np.any(shared[g.knot_nodes - 1])  # a curvature jump has two one-sided rows
    inner = np.nonzero(g.iseg[1:] == g.iseg[:-1])[0]
    assert np.all(shared[inner])
    sol = pb.solve()
    assert sol.ok
    # the profile holds the acceleration rows at both ends of every interval
    assert sol.constraint_violation["acceleration"] == 0.0


def test_fast_ipopt_options_give_the_profile_of_the_adaptive_barrier():
    fast, slow = problem(fast=True).solve(), problem(fast=False).solve()
    assert fast.ok and slow.ok
    assert fast.cost == pytest.approx(slow.cost, rel=1e-6)
