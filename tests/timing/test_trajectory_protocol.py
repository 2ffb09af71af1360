"""Both timing results are :class:`trcopt.Trajectory` objects returning the shared value types."""

from __future__ import annotations

import math

import numpy as np
import pytest

import trcopt
from trcopt import Arc, AxisLimits, Line, Machine, Plane, Role, Segment, SourceSpan
from trcopt.timing import LimitReport, Samples, TimedTrajectory, Trajectory, time_parameterize
from trcopt.timing.jerk import JerkTrajectory, jerk_limited

J = 5e4  # mm/s³
ISO = Machine(
    name="iso",
    rapid_mm_min=12000.0,
    axes=(
        ("X", AxisLimits(200.0, 2000.0, J)),
        ("Y", AxisLimits(200.0, 2000.0, J)),
        ("Z", AxisLimits(200.0, 2000.0, J)),
    ),
)


def seg(g, block):
    return Segment(g, Plane.G17, Role.CONTOUR, SourceSpan("t.mpf", 3, 1, block), 150.0)


@pytest.fixture(scope="module")
def both() -> tuple[TimedTrajectory, JerkTrajectory]:
    path = [seg(Line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0)), "N10"), seg(Arc((10.0, 3.0), 3.0, -math.pi / 2, 1.0), "N20")]
    acceleration_limited = time_parameterize(path, ISO)
    return acceleration_limited, jerk_limited(path, ISO, base=acceleration_limited)


def test_both_result_kinds_are_trajectories(both):
    acc, jerk = both
    assert isinstance(acc, Trajectory) and isinstance(jerk, Trajectory)
    assert trcopt.Trajectory is Trajectory
    assert (acc.jerk_limited, jerk.jerk_limited) == (False, True)
    assert acc.machine is ISO and jerk.machine is ISO
    assert acc.length == pytest.approx(jerk.length) == pytest.approx(13.0)


def test_both_return_the_shared_value_types(both):
    for traj in both:
        smp = traj.sample(1e-2)
        assert isinstance(smp, Samples) and isinstance(traj.evaluate(np.array([0.0])), Samples)
        assert smp.t[-1] == pytest.approx(traj.duration)
        report = traj.check_limits(dt=1e-3)
        assert isinstance(report, LimitReport) and report.ok
        assert traj.to_json()["duration_s"] == pytest.approx(traj.duration)
        assert len(traj.segments_with_times()) == len(traj.segments) == traj.feeds.shape[0] == 2
    acc, jerk = both
    assert acc.sample(1e-2).j is None  # the acceleration-limited jerk is unbounded, not sampled
    assert jerk.sample(1e-2).j.shape == (jerk.sample(1e-2).t.shape[0], 3)


def test_an_empty_path_is_a_trajectory():
    empty = time_parameterize([], ISO)
    assert isinstance(empty, Trajectory) and empty.duration == 0.0 and empty.check_limits().ok


def test_limit_checks_in_chunks_equal_the_checks_at_once(monkeypatch) -> None:
    # the limit check and the jerk estimate sample in bounded chunks; the maxima are
    # those of all samples at once, bit for bit
    import trcopt.timing.checks as checks_module
    from trcopt.errors import SourceSpan
    from trcopt.geometry import Line, Plane
    from trcopt.path import Role, Segment
    from trcopt.timing import time_parameterize

    pts = [(0.0, 0.0), (30.0, 0.0), (30.0, 20.0), (5.0, 25.0), (0.0, 0.0)]
    path = [
        Segment(Line((*a, 0.0), (*b, 0.0)), Plane.G17, Role.CONTOUR, SourceSpan("p", k + 1, 1), 50.0)
        for k, (a, b) in enumerate(zip(pts, pts[1:], strict=False))
    ]
    whole = time_parameterize(path)
    rep, jerk = whole.check_limits(1e-3), checks_module.max_jerk(whole)
    monkeypatch.setattr(checks_module, "SAMPLE_CHUNK", 37)
    monkeypatch.setattr(checks_module.sample_chunks, "__defaults__", (37, 0))
    chunked = time_parameterize(path)
    assert chunked.check_limits(1e-3) == rep
    assert np.array_equal(checks_module.max_jerk(chunked), jerk)
