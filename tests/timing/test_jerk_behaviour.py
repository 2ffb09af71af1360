"""Jerk-limited feed: curvature-jump knots, the inspectable problem, exports and failures."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from trcopt import Arc, AxisLimits, ConfigError, Line, Machine, Plane, Role, Segment, SourceSpan, TimingError
from trcopt.solution import SolveStatus
from trcopt.timing import time_parameterize
from trcopt.timing.jerk import JerkTrajectory, jerk_limited
from trcopt.timing.jerk_problem import JerkProblem
from trcopt.timing.path import PathArrays
from trcopt.timing.sections import axis_limits, segment_feeds, split_sections

J = 5e4
ISO = Machine(
    name="iso",
    rapid_mm_min=12000.0,
    axes=(
        ("X", AxisLimits(200.0, 2000.0, J)),
        ("Y", AxisLimits(200.0, 2000.0, J)),
        ("Z", AxisLimits(200.0, 2000.0, J)),
    ),
)


def seg(g, feed=150.0, block="N10"):
    return Segment(g, Plane.G17, Role.CONTOUR, SourceSpan("t.mpf", 3, 1, block), feed)


def line_arc_line(R=5.0, feed=150.0):
    return [
        seg(Line((-30.0, -R, 0.0), (0.0, -R, 0.0)), feed, "N10"),
        seg(Arc((0.0, 0.0), R, -math.pi / 2, math.pi), feed, "N20"),
        seg(Line((0.0, R, 0.0), (-30.0, R, 0.0)), feed, "N30"),
    ]


@pytest.fixture(scope="module")
def lal() -> tuple[list[Segment], JerkTrajectory]:
    path = line_arc_line()
    return path, jerk_limited(path, ISO)


def test_line_arc_knots_are_passed_at_the_jerk_bounded_speed(lal):
    path, traj = lal
    # curvature jump 1/R on one axis at both knots: |Δq″| v² ≤ J·T_c  →  v ≤ sqrt(J·T_c·R)
    cap = math.sqrt(J * 1e-3 * 5.0)
    assert traj.knot_s.shape == (2,)
    assert np.allclose(traj.knot_s, [30.0, 30.0 + 5.0 * math.pi])
    assert np.all(traj.knot_v <= cap * (1 + 1e-6))
    assert np.all(traj.knot_v >= 0.99 * cap)  # the cap binds (time-optimal)
    steps = traj.knot_steps()
    assert steps.max() <= J * 1e-3 * (1 + 1e-6)
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok, str(rep)
    assert max(rep.jerk_knot_ratio) == pytest.approx(1.0, abs=0.01)
    assert max(rep.jerk_smooth_ratio) <= 1.01 and max(rep.jerk_ratio) <= 1.01


def test_longer_cycle_passes_knots_faster():
    path = line_arc_line()
    fast = jerk_limited(path, ISO, cycle_s=4e-3)
    slow = jerk_limited(path, ISO, cycle_s=1e-3)
    assert fast.knot_v.min() > slow.knot_v.max()
    assert fast.duration < slow.duration


def test_jerk_limited_is_never_faster_than_acceleration_limited(lal):
    path, traj = lal
    assert traj.duration >= traj.base.duration
    assert traj.base.duration == pytest.approx(time_parameterize(path, ISO).duration)


def test_profile_is_consistent_in_time(lal):
    _, traj = lal
    smp = traj.sample(1e-4)
    # s(t) integrates the path speed; the speed integrates the path acceleration
    s_int = np.concatenate(([0.0], np.cumsum(0.5 * (smp.speed[1:] + smp.speed[:-1]) * np.diff(smp.t))))
    assert np.abs(s_int - smp.s).max() < 1e-3
    assert smp.s[-1] == pytest.approx(traj.length)
    assert smp.speed[0] == 0.0 and smp.speed[-1] == pytest.approx(0.0, abs=1e-9)
    assert np.all(np.diff(smp.s) >= -1e-12)


def test_axis_jerk_is_the_derivative_of_axis_acceleration(lal):
    _, traj = lal
    ts = np.linspace(0.05, traj.duration - 0.05, 400)
    dt = 1e-6
    a0, a1 = traj.evaluate(ts - dt).a, traj.evaluate(ts + dt).a
    mid = traj.evaluate(ts)
    fd = (a1 - a0) / (2 * dt)
    knots = [traj.time_at_segment_starts()[1], traj.time_at_segment_starts()[2]]
    away = np.all(np.abs(ts[:, None] - np.array(knots)[None, :]) > 2 * dt, axis=1)
    interior = away & np.isin(np.searchsorted(traj.t0, ts + dt, "right"), np.searchsorted(traj.t0, ts - dt, "right"))
    assert np.allclose(fd[interior], mid.j[interior], atol=1e-3 * J)


def test_segments_with_times_and_json(lal):
    path, traj = lal
    timed = traj.segments_with_times()
    assert timed[0].t_start_s == 0.0 and timed[-1].t_end_s == pytest.approx(traj.duration)
    assert all(a.t_end_s == pytest.approx(b.t_start_s) for a, b in zip(timed, timed[1:], strict=False))
    assert all(s.t_end_s > s.t_start_s for s in timed)
    js = traj.to_json()
    json.dumps(js)
    assert js["jerk_limited"] is True
    assert js["duration_s"] == pytest.approx(traj.duration)
    assert js["limits_ok"] is True
    assert max(js["max_jerk_ratio"].values()) <= 1.01
    assert js["sections"][0]["status"] == "optimal" and js["sections"][0]["first_block"] == "N10"
    assert js["acceleration_limited_duration_s"] < js["duration_s"]
    # its CSV feed profile: tests/io/test_feed_exports.py


def test_problem_is_inspectable_before_solving():
    path = line_arc_line()
    arrays = PathArrays(path)
    feeds = segment_feeds(path, ISO)
    (sec,) = split_sections(path, arrays)
    vmax, amax = axis_limits(ISO)
    base = time_parameterize(path, ISO)
    pb = JerkProblem(sec, arrays, feeds, vmax, amax, np.full(3, J), base.s, base.sd, points=80)
    # knots are nodes, each interval lies on one segment, the arc gets ≥ π/0.05 intervals
    grid = pb.grid
    assert 30.0 in grid.s and pytest.approx(30.0 + 5 * math.pi) in list(grid.s)
    assert np.count_nonzero(grid.iseg == 1) >= math.ceil(math.pi / 0.05)
    assert grid.vcap[0] == 0.0 and grid.vcap[-1] == 0.0
    assert grid.vcap[grid.knot_nodes] == pytest.approx(math.sqrt(J * 1e-3 * 5.0))
    opti = pb.opti
    n = pb.intervals
    assert opti.nx == (n - 1) * 2 + 2 * n
    assert set(pb.variables) == {"V", "A", "H", "J"}
    sol = pb.solve()
    assert sol.status is SolveStatus.OPTIMAL and sol.iterations > 0 and sol.solve_time_s > 0
    assert sol.cost == pytest.approx(sol.geometry.duration)
    assert sol.raise_for_status() is sol
    assert sol.constraint_violation["dynamics_mm"] < 1e-6


def test_ipopt_failure_names_section_and_block(monkeypatch):
    monkeypatch.setattr(JerkProblem, "ipopt_options", {**JerkProblem.ipopt_options, "max_iter": 1})
    path = line_arc_line()  # one section with an arc: solved by the NLP (lines alone are closed-form)
    with pytest.raises(TimingError) as info:
        jerk_limited(path, ISO)
    msg = str(info.value)
    assert "section 0" in msg and "N10" in msg and "IPOPT" in msg
    assert info.value.code == "TIMING-JERK-SOLVER"


def test_machine_without_jerk_limits_is_rejected():
    m = Machine(
        name="nojerk",
        axes=(("X", AxisLimits(200.0, 2000.0)), ("Y", AxisLimits(200.0, 2000.0)), ("Z", AxisLimits(200.0, 2000.0))),
    )
    with pytest.raises(ConfigError, match="jmax_mm_s3"):
        jerk_limited([seg(Line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0)))], m)


def test_acceleration_limited_profile_violates_the_jerk_limit(lal):
    path, traj = lal
    from trcopt.timing.checks import max_jerk

    assert max_jerk(traj.base).max() > 10 * J  # why jerk mode exists (spec §0.7)
    assert traj.check_limits(dt=1e-3).jerk_fd_1khz_ratio[0] < 1.1


def test_helix_three_axes():
    helix = Arc((0.0, 0.0), 10.0, 0.0, 2 * math.pi, 0.0, -2.0)
    traj = jerk_limited([seg(helix, 250.0)], ISO)
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok, str(rep)
    assert rep.v_ratio[2] > 0  # Z moves
    smp = traj.sample(1e-3)
    assert smp.xyz[-1] == pytest.approx([10.0, 0.0, -2.0], abs=1e-9)


def test_parallel_sections_give_the_same_profile():
    path = [
        seg(Line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0)), block="N10"),
        seg(Line((10.0, 0.0, 0.0), (10.0, 10.0, 0.0)), block="N20"),
        seg(Line((10.0, 10.0, 0.0), (0.0, 10.0, 0.0)), block="N30"),
    ]
    one = jerk_limited(path, ISO)
    two = jerk_limited(path, ISO, workers=2)
    assert two.duration == pytest.approx(one.duration, rel=1e-9)
    assert np.allclose(two.h, one.h)


def test_poly_transition_nodes_on_every_hermite_joint_and_limits_hold():
    from trcopt.geometry import hermite_curve

    # a G2 quintic 90° transition between two lines, stored as a Poly with its sample curvatures
    # (quintic Hermite pieces, curvature-continuous)
    quint = hermite_curve(
        (9.0, 0.0, 0.0), (2.0, 0.0, 0.0), (10.0, 1.0, 0.0), (0.0, 2.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    )
    path = [
        seg(Line((0.0, 0.0, 0.0), (9.0, 0.0, 0.0)), block="N10"),
        seg(quint, block="N20"),
        seg(Line((10.0, 1.0, 0.0), (10.0, 10.0, 0.0)), block="N30"),
    ]
    traj = jerk_limited(path, ISO)
    assert len(traj.sections) == 1
    start = traj.time_at_segment_starts()
    joints = np.asarray(quint.cum)[1:-1] + 9.0
    assert np.all(np.isin(np.round(joints, 9), np.round(traj.s0, 9)))  # every Hermite joint is a node
    # curvature-continuous: no knot anywhere (the quintic meets the lines with zero curvature)
    assert traj.knot_s.shape[0] == 0
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok, str(rep)
    assert max(rep.jerk_smooth_ratio) <= 1.01 and max(rep.jerk_knot_ratio) <= 1.0 + 1e-6
    assert start[1] < start[2] < traj.duration
    # the same samples as cubic Hermite pieces (tangents only): q″ jumps at every joint, each one a
    # knot with its own speed cap; both feeds respect the limits
    cubic = dataclasses.replace(quint, curvatures=None)
    traj_c = jerk_limited([path[0], seg(cubic, block="N20"), path[2]], ISO)
    assert traj_c.knot_s.shape[0] >= joints.shape[0]
    assert traj_c.check_limits(dt=1e-4).ok
    assert traj.duration == pytest.approx(traj_c.duration, rel=0.01)


def test_sharp_g2_transition_grid_follows_the_third_derivative():
    from trcopt.geometry import hermite_curve
    from trcopt.timing.jerk_grid import _refine_third

    # a short, sharp quintic (150° turn within 0.05 mm): q‴ changes tenfold within single pieces
    quint = hermite_curve(
        (0.0, 0.0, 0.0), (0.02, 0.0, 0.0), (0.01, 0.02, 0.0), (-0.017, 0.01, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    )
    loc = np.asarray(quint.cum, dtype=float)
    fine = _refine_third(quint, loc)
    assert fine.shape[0] > loc.shape[0] and np.all(np.isin(loc, fine))
    third = np.array([quint.third(float(x)) for x in 0.5 * (fine[1:] + fine[:-1])])
    left = np.array([quint.third(float(x) + 1e-9) for x in fine[:-1]])
    right = np.array([quint.third(float(x) - 1e-9) for x in fine[1:]])
    # the linear model of q‴ across each interval is within a few per cent at its middle
    lin = 0.5 * (left + right)
    scale = np.maximum(np.linalg.norm(left, axis=1), np.linalg.norm(right, axis=1))
    small = np.diff(fine) <= 2e-7
    assert np.all((np.linalg.norm(third - lin, axis=1) <= 0.05 * scale) | small)
    # and the jerk-limited feed through it keeps the documented jerk measure
    path = [
        seg(Line((-10.0, 0.0, 0.0), (0.0, 0.0, 0.0)), block="N10"),
        seg(quint, block="N20"),
        seg(Line(quint.end, (quint.end[0] - 10 * 0.862, quint.end[1] + 10 * 0.507, 0.0)), block="N30"),
    ]
    traj = jerk_limited(path, ISO)
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok and max(rep.jerk_ratio) <= 1.01, str(rep)


def _spline_wave(points: int, length: float):
    """A C2 cubic interpolating spline (q‴ jumps at its knots) through a sine wave, as the
    curvature-continuous Poly that run splines become: quintic Hermite pieces that straddle a
    knot have a q‴ that bulges inside the piece."""
    from scipy.interpolate import make_interp_spline

    from trcopt.geometry.poly import parametric_curve

    u = np.linspace(0.0, 1.0, points)
    x = np.linspace(0.0, length, points)
    sx, sy = make_interp_spline(u, x, k=3), make_interp_spline(u, 1.5 * np.sin(x / 4.0), k=3)
    return parametric_curve(
        lambda t: (float(sx(t)), float(sy(t)), 0.0),
        lambda t: (float(sx(t, 1)), float(sy(t, 1)), 0.0),
        lambda t: (float(sx(t, 2)), float(sy(t, 2)), 0.0),
    )


def test_poly_higher_derivatives_give_the_exact_taylor_expansion_of_a_piece():
    g = _spline_wave(7, 30.0)
    cum = np.asarray(g.cum)
    for i in (0, len(cum) // 2, len(cum) - 2):
        s0, s1 = cum[i] + 1e-9, cum[i + 1] - 1e-9
        p, d1, d2 = (np.array(x) for x in g.derivatives(s0))
        d3 = np.array(g.third(s0))
        d4, d5 = (np.array(x) for x in g.higher(s0))
        for sig in (0.3 * (s1 - s0), s1 - s0):
            taylor = p + d1 * sig + d2 * sig**2 / 2 + d3 * sig**3 / 6 + d4 * sig**4 / 24 + d5 * sig**5 / 120
            assert np.allclose(taylor, g.point(s0 + sig), atol=1e-12)
            q3 = d3 + d4 * sig + d5 * sig**2 / 2
            assert np.allclose(q3, g.third(s0 + sig), rtol=1e-6, atol=1e-9)
    # cubic pieces (no sample curvatures) have no fourth or fifth derivative
    assert dataclasses.replace(g, curvatures=None).higher(1.0) == ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))


def test_spline_poly_keeps_the_jerk_measure_where_q3_peaks_inside_an_interval():
    # 60 mm wave at F 150: q‴·v³ binds; the Poly rows use the exact quadratic q‴ of each quintic
    # piece (a linear q‴ between the interval ends gave a jerk measure of 1.055 here)
    path = [seg(_spline_wave(13, 60.0), feed=150.0)]
    traj = jerk_limited(path, ISO)
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok, str(rep)
    assert max(rep.jerk_smooth_ratio) <= 1.01
    assert max(rep.jerk_smooth_ratio) >= 0.99  # the jerk limit binds somewhere on the wave
