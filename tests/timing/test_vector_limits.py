"""Vector (path) limits in the timing stage: |v| ≤ V, |a| ≤ A, |j| ≤ J beside the per-axis limits."""

from __future__ import annotations

import json
import math
import time

import numpy as np
import pytest

from trcopt import Arc, AxisLimits, Line, Machine, Plane, Role, Segment, SourceSpan
from trcopt.config import PathLimits
from trcopt.timing import time_parameterize
from trcopt.timing.doubles import double_s_time
from trcopt.timing.jerk import jerk_limited
from trcopt.timing.toppra_engine import PATH_ACC_EDGES, path_acceleration_rows

V, A, J = 100.0, 3000.0, 60000.0
# axis limits far above the vector ones: only the vector limits bind
GENEROUS = (
    ("X", AxisLimits(1e4, 1e6, 1e8)),
    ("Y", AxisLimits(1e4, 1e6, 1e8)),
    ("Z", AxisLimits(1e4, 1e6, 1e8)),
)
VECTOR = Machine(name="vector", rapid_mm_min=60000.0, axes=GENEROUS, path=PathLimits(V, A, J))
ACC_ONLY = Machine(name="acc", rapid_mm_min=60000.0, axes=GENEROUS, path=PathLimits(amax_mm_s2=A))
AXES = (("X", AxisLimits(250.0, 2000.0)), ("Y", AxisLimits(200.0, 1500.0)), ("Z", AxisLimits(100.0, 1000.0)))


def seg(g, feed=1000.0, block="N10"):
    return Segment(g, Plane.G17, Role.CONTOUR, SourceSpan("t.mpf", 1, 1, block), feed)


def trapezoid(length: float, v: float, a: float) -> float:
    """Rest-to-rest time on a line under speed v and acceleration a."""
    return length / v + v / a if length >= v * v / a else 2.0 * math.sqrt(length / a)


def line_arc_line(radius: float = 5.0, feed: float = 1000.0) -> list[Segment]:
    return [
        seg(Line((-30.0, -radius, 0.0), (0.0, -radius, 0.0)), feed, "N10"),
        seg(Arc((0.0, 0.0), radius, -math.pi / 2, math.pi), feed, "N20"),
        seg(Line((0.0, radius, 0.0), (-30.0, radius, 0.0)), feed, "N30"),
    ]


@pytest.mark.parametrize("engine", ["own", "toppra"])
@pytest.mark.parametrize("length", [50.0, 2.0])
@pytest.mark.parametrize("angle", [0.0, 30.0])
def test_straight_line_is_the_trapezoid_of_the_vector_limits(engine, length, angle):
    t = np.array([math.cos(math.radians(angle)), math.sin(math.radians(angle)), 0.0])
    line = Line((1.0, 2.0, 0.0), tuple(np.array([1.0, 2.0, 0.0]) + length * t))
    traj = time_parameterize([seg(line)], VECTOR, engine=engine)
    assert traj.duration == pytest.approx(trapezoid(length, V, A), rel=1e-9)
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok, str(rep)
    assert rep.path_v_ratio <= 1 + 1e-9 and rep.path_a_ratio == pytest.approx(1.0, rel=1e-9)
    assert rep.path_j_ratio is None  # the acceleration-limited profile does not bound the jerk


def test_vector_speed_limit_caps_the_feed_under_axis_acceleration():
    machine = Machine(name="v", rapid_mm_min=60000.0, axes=AXES, path=PathLimits(vmax_mm_s=V))
    traj = time_parameterize([seg(Line((0.0, 0.0, 0.0), (40.0, 0.0, 0.0)), 250.0)], machine)
    assert traj.duration == pytest.approx(trapezoid(40.0, V, 2000.0), rel=1e-9)
    assert traj.binding_constraints() == ["path velocity"]


@pytest.mark.parametrize("engine", ["own", "toppra"])
@pytest.mark.parametrize("radius", [2.0, 10.0])
def test_circle_at_high_feed_runs_at_most_sqrt_a_r(engine, radius):
    circle = Arc((0.0, 0.0), radius, 0.0, 2 * math.pi)
    traj = time_parameterize([seg(circle, 1000.0)], ACC_ONLY, engine=engine)
    smp = traj.sample(1e-4)
    grid = traj.grid_states()
    cruise = math.sqrt(A * radius)
    for states in (smp, grid):
        assert states.speed.max() <= cruise * (1 + 1e-9)
        assert np.linalg.norm(states.a, axis=1).max() <= A * (1 + 1e-6)
    # time-optimal: the exact solver reaches the maximum-velocity curve, toppra's polygon nearly
    assert smp.speed.max() >= cruise * (1 - 1e-6 if engine == "own" else 1e-3)
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok and rep.path_v_ratio is None and rep.path_a_ratio <= 1 + 1e-6
    assert traj.binding_constraints() == ["path acceleration"]


def test_own_and_toppra_agree_on_a_vector_limited_line_arc_line():
    own = time_parameterize(line_arc_line(), ACC_ONLY, engine="own")
    ref = time_parameterize(line_arc_line(), ACC_ONLY, engine="toppra")
    assert own.engines == ["own"] and ref.engines == ["toppra"]
    # toppra plans with an inscribed polygon (and a margin on curved sections): never faster
    assert own.duration <= ref.duration <= own.duration * 1.01


@pytest.mark.parametrize("engine", ["own", "toppra"])
def test_axis_and_vector_limits_hold_together(engine):
    both = Machine(name="both", rapid_mm_min=60000.0, axes=AXES, path=PathLimits(120.0, 1800.0))
    axis_only = Machine(name="axes", rapid_mm_min=60000.0, axes=AXES)
    vector_only = Machine(name="vec", rapid_mm_min=60000.0, axes=GENEROUS, path=PathLimits(120.0, 1800.0))
    path = line_arc_line(radius=8.0, feed=250.0)
    traj = time_parameterize(path, both, engine=engine)
    smp = traj.sample(1e-4)
    for states in (smp, traj.grid_states()):
        assert (np.abs(states.v) / np.array([250.0, 200.0, 100.0])).max() <= 1 + 1e-6
        assert (np.abs(states.a) / np.array([2000.0, 1500.0, 1000.0])).max() <= 1.001
        assert states.speed.max() <= 120.0 * (1 + 1e-6)
        assert np.linalg.norm(states.a, axis=1).max() <= 1800.0 * (1 + 1e-6)
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok, str(rep)
    slower = max(time_parameterize(path, axis_only, engine=engine).duration,
                 time_parameterize(path, vector_only, engine=engine).duration)
    assert traj.duration >= slower * (1 - 1e-9)
    kinds = set(traj.binding_constraints())
    assert kinds <= {"feed", "velocity X", "velocity Y", "acceleration X", "acceleration Y",
                     "path velocity", "path acceleration"}


def test_without_path_limits_the_profile_is_unchanged():
    path = line_arc_line(radius=5.0, feed=150.0)
    plain = time_parameterize(path, Machine(name="m", rapid_mm_min=60000.0, axes=AXES))
    empty = time_parameterize(path, Machine(name="m", rapid_mm_min=60000.0, axes=AXES, path=PathLimits()))
    assert plain.duration == empty.duration
    assert np.array_equal(plain.s, empty.s) and np.array_equal(plain.x, empty.x)
    data = plain.to_json()
    assert "path" not in data["machine"] and "path" not in data["max_ratios"]
    assert "path" not in str(plain.check_limits())


def test_plan_json_reports_vector_limits_and_ratios():
    traj = time_parameterize(line_arc_line(), VECTOR)
    data = json.loads(json.dumps(traj.to_json()))
    assert data["machine"]["path"] == {"vmax_mm_s": V, "amax_mm_s2": A, "jmax_mm_s3": J}
    ratios = data["max_ratios"]["path"]
    assert ratios["v"] <= 1.001 and ratios["a"] <= 1.001 and ratios["j"] is None
    assert data["limits_ok"] is True
    rep = traj.check_limits()
    assert "path |v|/vmax" in str(rep) and rep.to_json()["path_ratio"]["a"] == rep.path_a_ratio


def test_a_violated_vector_limit_fails_the_check():
    traj = time_parameterize(line_arc_line(), ACC_ONLY)
    stricter = Machine(name="s", rapid_mm_min=60000.0, axes=GENEROUS, path=PathLimits(amax_mm_s2=0.5 * A))
    traj.machine = stricter  # the same profile checked against half the acceleration
    rep = traj.check_limits()
    assert not rep.ok and rep.path_a_ratio == pytest.approx(2.0, rel=1e-6)


def test_toppra_rows_are_an_inscribed_polygon_of_the_acceleration_disc():
    rng = np.random.default_rng(7)
    n = 200
    d1 = rng.normal(size=(n, 3))
    d1 /= np.linalg.norm(d1, axis=1)[:, None]
    d2 = rng.normal(size=(n, 3)) * rng.uniform(0.0, 2.0, size=(n, 1))
    a, b, c, F, g = path_acceleration_rows(d1, d2, A)
    assert F.shape == (PATH_ACC_EDGES, 2)
    u = rng.uniform(-2 * A, 2 * A, size=n)
    x = rng.uniform(0.0, 2 * A, size=n) / np.maximum(np.linalg.norm(d2, axis=1), 1e-3)
    w = a * u[:, None] + b * x[:, None] + c
    # the frame is orthonormal: |w| is |p''|
    assert np.allclose(np.linalg.norm(w, axis=1), np.linalg.norm(d1 * u[:, None] + d2 * x[:, None], axis=1))
    inside = (w @ F.T <= g[None, :]).all(axis=1)
    assert inside.any()
    assert np.all(np.linalg.norm(w[inside], axis=1) <= A * (1 + 1e-12))
    # exact where it matters: a straight ramp at A and the maximum-velocity curve |c|·x = A
    assert np.all(np.array([A, 0.0]) @ F.T <= g * (1 + 1e-12))
    assert np.all(np.array([0.0, A]) @ F.T <= g * (1 + 1e-12))


def test_jerk_limited_feed_respects_the_vector_jerk_on_a_line():
    start = time.perf_counter()
    line = [seg(Line((0.0, 0.0, 0.0), (30.0, 10.0, 0.0)), 150.0)]
    traj = jerk_limited(line, VECTOR)
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok, str(rep)
    assert rep.path_j_ratio <= 1.0 and rep.path_a_ratio <= 1.0 and rep.path_v_ratio <= 1.001
    smp = traj.sample(1e-4)
    assert np.linalg.norm(smp.j, axis=1).max() <= J * (1 + 1e-6)
    # near the double-S optimum of the vector limits (the NLP keeps a 0.1 % margin)
    ref = double_s_time(math.hypot(30.0, 10.0), V, A, J)
    assert ref <= traj.duration <= ref * 1.01
    assert traj.to_json()["max_ratios"]["path"]["j"] == rep.path_j_ratio
    assert time.perf_counter() - start < 5.0


def test_jerk_limited_feed_passes_curvature_jumps_at_the_vector_jerk_cap():
    radius = 5.0
    traj = jerk_limited(line_arc_line(radius, 150.0), VECTOR)
    # a step of 1/R in curvature: |Δq″|·v² ≤ J·T_c  →  v ≤ sqrt(J·T_c·R)
    cap = math.sqrt(J * 1e-3 * radius)
    assert traj.knot_v.shape == (2,) and np.all(traj.knot_v <= cap * (1 + 1e-6))
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok, str(rep)
    assert rep.path_j_ratio <= 1.0 + 1e-6
    smp = traj.sample(1e-4)
    assert np.linalg.norm(smp.a, axis=1).max() <= A * (1 + 1e-6)
    assert np.linalg.norm(smp.j, axis=1).max() <= J * (1 + 1e-6)


def test_sharp_g2_transition_keeps_the_vector_acceleration_between_grid_points():
    """A 170° turn blended within 0.05 mm by a G2 B-spline peaks at a curvature near 10³/mm within
    a few µm: the curve's grid must follow its turning there (an even spacing gave 1.33× A)."""
    from trcopt.optimize.corners.blend import blend_corners

    a, b, c = (0.0, 0.0), (5.0, 0.0), (5.0 - 5.0 * math.cos(math.radians(10.0)), 5.0 * math.sin(math.radians(10.0)))
    path = [seg(Line((*a, 0.0), (*b, 0.0)), V), seg(Line((*b, 0.0), (*c, 0.0)), V)]
    res = blend_corners(path, path, tolerance_mm=0.05, machine=VECTOR, mode="optimal", kind="vertex", objective="jerk")
    assert any(s.geometry.__class__.__name__ == "Poly" for s in res.segments)
    traj = time_parameterize(res.segments, VECTOR)
    rep = traj.check_limits(dt=1e-4)
    assert rep.ok, str(rep)
    assert rep.path_a_ratio <= 1.001


def test_axis_rows_implied_by_the_vector_rows_are_left_out_with_the_same_profile(monkeypatch):
    """With axis limits at or above the vector ones the per-axis acceleration and jerk rows follow
    from the vector rows: the NLP leaves them out (fewer constraints) and finds the same profile,
    which still meets every per-axis row; an axis limit below the vector one keeps its rows."""
    from trcopt.timing.jerk_problem import JerkProblem

    path = line_arc_line(5.0, 150.0)
    # the X/Y jerk limits equal to the vector one: still implied (|j_k| ≤ |j| ≤ J)
    close = tuple((k, AxisLimits(1e4, 1e6, J)) for k in "XYZ")
    machine = Machine(name="close", rapid_mm_min=60000.0, axes=close, path=PathLimits(V, A, J))
    pruned = jerk_limited(path, machine)
    sizes: dict[bool, int] = {}
    build = JerkProblem.build

    def counting(self):
        opti = build(self)
        sizes[self._axis_row_implied("j", 0)] = opti.ng
        return opti

    monkeypatch.setattr(JerkProblem, "build", counting)
    jerk_limited(path, machine)
    monkeypatch.setattr(JerkProblem, "_axis_row_implied", lambda self, kind, k, tighten=1.0: False)
    full = jerk_limited(path, machine)
    assert sizes[True] < 0.8 * sizes[False]
    assert pruned.duration == pytest.approx(full.duration, rel=1e-6)
    rep = pruned.check_limits(dt=1e-4)
    assert rep.ok, str(rep)
    # a per-axis jerk limit below the vector one binds: its rows stay and hold
    low = tuple((k, AxisLimits(1e4, 1e6, 0.5 * J)) for k in "XYZ")
    monkeypatch.undo()
    tight = jerk_limited(path, Machine(name="low", rapid_mm_min=60000.0, axes=low, path=PathLimits(V, A, J)))
    rep = tight.check_limits(dt=1e-4)
    assert rep.ok, str(rep)
    assert tight.duration > pruned.duration * 1.01
