"""Corners, knots, helices, rapids, failures, exports and the limit check of every plan."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from trcopt import DEFAULT_MACHINE, Arc, AxisLimits, Line, Machine, Plane, Poly, Role, Segment, SourceSpan, TimingError
from trcopt.geometry import hermite_curve
from trcopt.modes import Side
from trcopt.timing import time_parameterize

ISO = Machine(
    name="iso", rapid_mm_min=6000.0,
    axes=(("X", AxisLimits(200.0, 2000.0)), ("Y", AxisLimits(200.0, 2000.0)), ("Z", AxisLimits(200.0, 2000.0))),
)


def seg(g, feed=200.0, block="N10", plane=Plane.G17, role=Role.CONTOUR, **kw):
    return Segment(g, plane, role, SourceSpan("t.mpf", 3, 1, block), feed, **kw)


def test_sharp_corner_stops_and_respects_axis_limits_at_10khz():
    path = [seg(Line((0, 0, 0), (30, 0, 0)), block="N10"), seg(Line((30, 0, 0), (30, 30, 0)), block="N20")]
    traj = time_parameterize(path, ISO)
    assert len(traj.sections) == 2
    t_corner = traj.time_at(np.array([30.0]))[0]
    state = traj.evaluate(np.array([t_corner]))
    assert state.speed[0] < 1e-6
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok and max(rep.a_ratio) <= 1.001 and rep.corner_speed_mm_s <= 1e-6


@pytest.mark.parametrize("engine", ["own", "toppra"])
def test_arc_to_line_knot_overshoot_below_half_percent(engine):
    arc = Arc((0.0, 10.0), 10.0, -math.pi / 2, math.pi / 2)  # ends at (10, 10) heading +Y
    line = Line((10.0, 10.0, 0.0), (10.0, 60.0, 0.0))
    traj = time_parameterize([seg(arc, 250.0), seg(line, 250.0)], ISO, engine=engine)
    rep = traj.check_limits(dt=1e-4)
    assert max(rep.a_ratio) <= 1.005
    assert rep.ok


def test_helix_three_axes():
    machine = Machine(axes=(("X", AxisLimits(200, 2000)), ("Y", AxisLimits(200, 2000)), ("Z", AxisLimits(3, 1000))))
    helix = Arc((0.0, 0.0), 10.0, 0.0, 6 * math.pi, 0.0, -6.0)
    own = time_parameterize([seg(helix, 250.0)], machine)
    ref = time_parameterize([seg(helix, 250.0)], machine, engine="toppra")
    assert own.duration == pytest.approx(ref.duration, rel=1e-3)
    rep = own.check_limits()
    assert rep.ok
    assert rep.v_ratio[2] == pytest.approx(1.0, abs=1e-3)  # the Z speed binds (3 mm/s)


def test_helix_in_g18_maps_axes():
    helix = Arc((0.0, 0.0), 5.0, 0.0, 2 * math.pi, 0.0, 10.0)
    traj = time_parameterize([seg(helix, 100.0, plane=Plane.G18)], ISO)
    smp = traj.sample(1e-3)
    assert np.ptp(smp.xyz[:, 1]) == pytest.approx(10.0, abs=1e-6)  # w = Y in G18
    assert traj.check_limits().ok


def test_rapid_runs_at_machine_rapid_feed():
    rapid = seg(Line((0, 0, 0), (200, 0, 0)), feed=None, role=Role.RAPID)
    traj = time_parameterize([rapid], ISO)
    assert traj.sample(1e-3).speed.max() == pytest.approx(ISO.rapid_mm_s, rel=1e-9)
    assert traj.duration == pytest.approx(200 / 100.0 + 100.0 / 2000.0, rel=1e-9)
    fast = time_parameterize([rapid], DEFAULT_MACHINE)  # rapid 333 mm/s > vmax 250
    assert fast.sample(1e-3).speed.max() == pytest.approx(250.0, rel=1e-9)


def test_toppra_failure_is_a_typed_error(monkeypatch):
    import toppra.algorithm as algo

    def broken(self, sd_start, sd_end, return_data=False):
        K = np.zeros((len(self.gridpoints), 2))
        K[7] = np.nan
        return None, None, None, K

    monkeypatch.setattr(algo.TOPPRA, "compute_parameterization", broken)
    path = [seg(Line((0, 0, 0), (10, 0, 0)), block="N10"), seg(Line((10, 0, 0), (20, 0, 0)), block="N20")]
    with pytest.raises(TimingError) as info:
        time_parameterize(path, ISO, engine="toppra")
    msg = str(info.value)
    assert "section 0" in msg and "s=" in msg and "N10" in msg and "remedy" in msg


def test_zero_length_section_is_a_typed_error():
    path = [seg(Line((0, 0, 0), (10, 0, 0))), seg(Line((10, 0, 0), (10, 0, 0)), block="N20")]
    with pytest.raises(TimingError, match=r"section 1.*s=10\.0.*N20.*remedy"):
        time_parameterize(path, ISO)


def test_poly_sections_use_the_own_solver_and_agree_with_toppra():
    curve = hermite_curve((0, 0, 0), (20, 0, 0), (10, 10, 0), (0, 20, 0))
    assert isinstance(curve, Poly)
    traj = time_parameterize([seg(curve, 150.0)], ISO)
    assert traj.engines == ["own"]
    assert traj.check_limits().ok
    ref = time_parameterize([seg(curve, 150.0)], ISO, engine="toppra")
    assert ref.engines == ["toppra"]
    # the own solver keeps the limits inside every interval of the curve (a little slower)
    assert ref.duration <= traj.duration <= 1.02 * ref.duration


def test_engines_agree_on_line_arc_line_acceleration_limited():
    l1 = Line((-20.0, -5.0, 0.0), (0.0, -5.0, 0.0))
    arc = Arc((0.0, 0.0), 5.0, -math.pi / 2, math.pi)
    l2 = Line((0.0, 5.0, 0.0), (-20.0, 5.0, 0.0))
    path = [seg(l1, 250.0), seg(arc, 250.0), seg(l2, 250.0)]
    own = time_parameterize(path, ISO)
    ref = time_parameterize(path, ISO, engine="toppra")
    assert own.duration == pytest.approx(ref.duration, rel=2e-3)
    assert own.check_limits().ok and ref.check_limits().ok


def test_contour_feed_reference_scales_arcs():
    # tool-centre arc R=5 of a G41 contour arc R=10 turning left (inside): centre feed F·5/10
    arc = Arc((0.0, 0.0), 5.0, 0.0, math.pi)
    s = seg(arc, 100.0, side=Side.LEFT, radius=5.0)
    centre = time_parameterize([s], ISO)
    contour = time_parameterize([s], Machine(name="c", rapid_mm_min=6000.0, axes=ISO.axes, feed_reference="contour"))
    assert contour.sample(1e-3).speed.max() == pytest.approx(50.0, rel=1e-6)
    assert centre.sample(1e-3).speed.max() == pytest.approx(100.0, rel=1e-6)


def test_plan_json_timing_and_segment_times():
    # the CSV feed profile and the speed plot of the same path: tests/io/test_feed_exports.py
    path = [
        seg(Line((0, 0, 0), (20, 0, 0)), block="N10"),
        seg(Arc((20.0, 5.0), 5.0, -math.pi / 2, math.pi), block="N20"),
    ]
    traj = time_parameterize(path, ISO)
    data = traj.to_json(samples="profile.csv")
    json.dumps(data)
    assert data["duration_s"] == pytest.approx(traj.duration)
    assert data["samples"] == "profile.csv"
    assert set(data["machine"]["axes"]) == {"X", "Y", "Z"}
    assert data["sections"][0]["binding"] in {"feed", "acceleration X", "acceleration Y", "velocity X"}
    assert data["limits_ok"] is True and data["max_ratios"]["a"]["X"] <= 1.001
    timed = traj.segments_with_times()
    assert timed[0].t_start_s == 0.0 and timed[-1].t_end_s == pytest.approx(traj.duration)
    assert timed[0].t_end_s == pytest.approx(timed[1].t_start_s)
    assert timed[0].to_json()["t_end_s"] > 0


def test_import_stays_cheap():
    code = "import sys, trcopt.timing; print('toppra' in sys.modules, 'matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "False"]


def test_empty_toolpath():
    traj = time_parameterize([], ISO)
    assert traj.duration == 0.0 and traj.segments_with_times() == []


@st.composite
def random_paths(draw):
    n = draw(st.integers(1, 6))
    p = np.array([0.0, 0.0, 0.0])
    heading = draw(st.floats(0, 2 * math.pi))
    out = []
    for i in range(n):
        feed = draw(st.sampled_from([30.0, 120.0, 300.0]))
        if draw(st.booleans()):
            heading += draw(st.sampled_from([0.0, 0.0, 0.7, -1.5]))
            length = draw(st.floats(0.05, 40.0))
            q = p + length * np.array([math.cos(heading), math.sin(heading), draw(st.sampled_from([0.0, 0.3]))])
            out.append(seg(Line(tuple(p), tuple(q)), feed, f"N{i}"))
            p = q
        else:
            r = draw(st.floats(0.2, 30.0))
            sweep = draw(st.floats(0.1, 5.0)) * draw(st.sampled_from([1, -1]))
            side = 1 if sweep > 0 else -1
            c = p[:2] + r * np.array([-math.sin(heading), math.cos(heading)]) * side
            a0 = math.atan2(p[1] - c[1], p[0] - c[0])
            arc = Arc((float(c[0]), float(c[1])), r, a0, sweep, float(p[2]), float(p[2]))
            out.append(seg(arc, feed, f"N{i}"))
            p = np.array(arc.end)
            heading += sweep
    return out


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(random_paths())
def test_every_plan_passes_check_limits(path):
    traj = time_parameterize(path, ISO)
    rep = traj.check_limits(dt=2e-4)
    assert rep.ok, str(rep)
    assert traj.duration >= sum(s.length / s.feed_mm_s for s in path) * (1 - 1e-9)
