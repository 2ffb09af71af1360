"""Literature corner-smoothing baselines in ``benchmarks/baselines.py``: the G01 junction-speed
planner's published reference value, the geometry of the Zhao, Zhu & Ding (2013) B-spline
transitions (tolerance, G2, no overlap) and the limits of the jerk-limited S-curve."""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.interpolate import BSpline

ROOT = Path(__file__).resolve().parents[2]
_NAME = "trcopt_benchmarks_baselines"


def _load():
    if _NAME in sys.modules:
        return sys.modules[_NAME]
    spec = importlib.util.spec_from_file_location(_NAME, ROOT / "benchmarks" / "baselines.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[_NAME] = module  # dataclasses resolve their module through sys.modules
    spec.loader.exec_module(module)
    return module


bl = _load()
LIM = bl.Limits(V=100.0, A=3000.0, J=60000.0, Ts=0.0005)
PATHS = {
    "square": (bl.rotated_square(), 0.2),
    "butterfly": (bl.butterfly(), 0.05),
    "zigzag": (bl.zigzag(), 0.05),
}


def _dist_to_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ab = b - a
    t = np.clip(((p - a) @ ab) / (ab @ ab), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * ab), axis=1)


def _check_limits(profile, V: float, A: float, J: float, dt: float = 1e-4) -> None:
    """Sample s(t) and check V, A, J on its finite differences (averages of v, a, j, so bounded
    by the same limits) and on the exact samples; check the end state."""
    n = max(int(math.ceil(profile.duration / dt)), 8)
    t = np.linspace(0.0, profile.duration, n + 1)
    h = t[1] - t[0]
    s, v, a, j = profile.sample(t)
    v_fd = np.diff(s) / h
    a_fd = np.diff(v_fd) / h
    j_fd = np.diff(a_fd) / h
    assert v_fd.max() <= V * (1 + 1e-6) and v_fd.min() >= -1e-9
    assert np.abs(a_fd).max() <= A * (1 + 1e-6)
    assert np.abs(j_fd).max() <= J * (1 + 1e-6) + 1.0
    assert v.max() <= V * (1 + 1e-9) and v.min() >= -1e-9
    assert np.abs(a).max() <= A * (1 + 1e-9) and np.abs(j).max() <= J * (1 + 1e-12)
    end = profile.knots()[-1]
    assert end[1] == pytest.approx(profile.length, rel=1e-9, abs=1e-12)
    assert end[2] == pytest.approx(profile.v_exit, rel=1e-9, abs=1e-9)
    assert abs(end[3]) <= 1e-9 * A


# ------------------------------------------------------------------------------------ G01


def test_g01_reference_rotated_square():
    res = bl.g01_baseline(bl.rotated_square(), LIM)
    assert res.total_time == pytest.approx(0.45382, rel=5e-3)
    vj = LIM.A * LIM.Ts / (2 * math.sin(math.pi / 4) + 1e-6)
    np.testing.assert_allclose(res.junction_speeds, [0.0, vj, vj, vj, 0.0], rtol=1e-12)


def test_g01_straight_vertex_does_not_limit():
    pts = np.array([(0.0, 0.0), (10.0, 0.0), (20.0, 0.0)])
    res = bl.g01_baseline(pts, LIM)
    one = bl.g01_baseline(np.array([(0.0, 0.0), (20.0, 0.0)]), LIM)
    assert res.total_time == pytest.approx(one.total_time, rel=1e-9)


# ---------------------------------------------------------------------------- S-curve


def test_phase_closed_form():
    A, J = 3000.0, 60000.0
    assert bl.accel_time(100.0, A, J) == pytest.approx(2 * math.sqrt(100.0 / J))
    assert bl.accel_time(400.0, A, J) == pytest.approx(400.0 / A + A / J)
    # continuous at the knee Δv = A²/J
    knee = A * A / J
    assert bl.accel_time(knee * (1 + 1e-12), A, J) == pytest.approx(bl.accel_time(knee, A, J), rel=1e-9)
    assert bl.accel_distance(10.0, 60.0, A, J) == pytest.approx(35.0 * 2 * math.sqrt(50.0 / J))


@pytest.mark.parametrize("v0", [0.0, 5.0, 80.0, 400.0])
def test_reachable_speed_inverts_distance(v0):
    A, J = 3000.0, 60000.0
    for length in (0.1, 1.0, 5.0, 40.0, 200.0):
        v = bl.reachable_speed(v0, length, A, J)
        assert bl.accel_distance(v0, v, A, J) == pytest.approx(length, rel=1e-9)
        assert bl.reachable_speed(v0, length, A, J, vmax=v0 + 1.0) <= v0 + 1.0
    # tiny lengths: the change is below the resolution of v0, but never infeasible
    for length in (0.0, 1e-12, 1e-9, 1e-6, 1e-3):
        v = bl.reachable_speed(v0, length, A, J)
        assert v >= v0 and bl.accel_distance(v0, v, A, J) <= length


def test_scurve_random_blocks_respect_limits():
    rng = np.random.default_rng(7)
    for _ in range(40):
        V = rng.uniform(20.0, 300.0)
        A = rng.uniform(500.0, 5000.0)
        J = rng.uniform(5e3, 2e5)
        v0, v1 = rng.uniform(0.0, V, 2) * (rng.uniform(size=2) < 0.8)
        direct = bl.accel_distance(v0, v1, A, J)
        length = direct + rng.choice([0.0, rng.uniform(0.0, 0.5), rng.uniform(0.5, 50.0)])
        prof = bl.plan_block(length, v0, v1, V, A, J)
        assert prof.v_peak <= V * (1 + 1e-12) and prof.v_peak >= max(v0, v1) - 1e-9
        _check_limits(prof, V, A, J)


def test_scurve_constant_acceleration_phase_and_cruise():
    prof = bl.plan_block(100.0, 0.0, 0.0, 300.0, 3000.0, 60000.0)  # Δv = 300 > A²/J = 150
    assert any(j == 0.0 for _, j in prof.pieces[:3])
    assert prof.v_peak == pytest.approx(300.0)
    _check_limits(prof, 300.0, 3000.0, 60000.0)


def test_infeasible_block_raises():
    with pytest.raises(ValueError):
        bl.plan_block(0.1, 0.0, 100.0, 100.0, 3000.0, 60000.0)


@pytest.mark.parametrize("name", sorted(PATHS))
def test_whole_plans_respect_limits_and_are_feasible(name):
    pts, eps = PATHS[name]
    for res in (bl.g01_baseline(pts, LIM), bl.zhao2013(pts, eps, LIM)):
        v = res.junction_speeds
        assert v[0] == 0.0 and v[-1] == 0.0
        for p, cap in zip(res.profiles, res.caps, strict=True):
            _check_limits(p, min(cap, LIM.V), LIM.A, LIM.J, dt=2e-4)
        assert res.total_time == pytest.approx(sum(p.duration for p in res.profiles))


# ------------------------------------------------------------------- Zhao et al. 2013


@pytest.mark.parametrize("name", sorted(PATHS))
def test_zhao_transitions_respect_tolerance_and_never_overlap(name):
    pts, eps = PATHS[name]
    pts = bl._clean(pts)
    lengths = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    trans = bl.zhao_transitions(pts, eps)
    assert len(trans) == len(pts) - 2
    used_start = np.zeros(len(lengths))  # length taken at the start / end of every line
    used_end = np.zeros(len(lengths))
    u = np.linspace(0.0, 1.0, 4001)  # contains u = 1/2
    for k, t in enumerate(trans):
        if t is None:
            continue
        used_end[k] = t.span
        used_start[k + 1] = t.span
        curve = t.evaluate(u)
        # deviation: the corner vertex is within ε of the curve (closest at the middle) ...
        vertex_dist = np.linalg.norm(curve - pts[k + 1], axis=1).min()
        assert vertex_dist <= eps * (1 + 1e-6)
        assert vertex_dist == pytest.approx(t.deviation, rel=1e-9)
        if not t.shortened:
            assert t.deviation == pytest.approx(eps, rel=1e-12)
        # ... and every curve point within ε of the corner it replaces
        corner = np.minimum(_dist_to_segment(curve, pts[k], pts[k + 1]),
                            _dist_to_segment(curve, pts[k + 1], pts[k + 2]))
        assert corner.max() <= eps * (1 + 1e-6)
        # ends on the lines, tangent to them, zero curvature there (G2)
        np.testing.assert_allclose(curve[0], pts[k + 1] + t.span * t.a, atol=1e-12)
        np.testing.assert_allclose(curve[-1], pts[k + 1] + t.span * t.b, atol=1e-12)
        d1 = t.evaluate(np.array([0.0, 1.0]), 1)
        unit = d1 / np.linalg.norm(d1, axis=1)[:, None]
        np.testing.assert_allclose(unit, [-t.a, t.b], atol=1e-12)
        assert np.all(t.curvature(np.array([0.0, 1.0])) <= 1e-9 * t.kappa_max)
    assert np.all(used_start + used_end <= lengths * (1 + 1e-12))
    assert np.all(used_start <= 0.5 * lengths * (1 + 1e-12)) and np.all(used_end <= 0.5 * lengths * (1 + 1e-12))


@pytest.mark.parametrize("turn_deg", [1.0, 10.0, 45.0, 90.0, 135.0, 170.0, 179.0])
def test_zhao_closed_forms_match_the_bspline(turn_deg):
    th = math.radians(turn_deg)
    arm = 5.0 * 2 * 0.05 / math.sin(th / 2)  # long enough for the full ε transition
    pts = np.array([(-arm, 0.0), (0.0, 0.0), (arm * math.cos(th), arm * math.sin(th))])
    (t,) = bl.zhao_transitions(pts, 0.05)
    assert not t.shortened and t.d == pytest.approx(2 * 0.05 / math.sin(th / 2))
    ref = BSpline(t.knots, t.control_points, 3)
    u = np.linspace(0.0, 1.0, 2001)
    np.testing.assert_allclose(t.evaluate(u), ref(u), atol=1e-12)
    np.testing.assert_allclose(t.evaluate(u, 1), ref.derivative(1)(u), rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(t.evaluate(u, 2), ref.derivative(2)(u), rtol=1e-9, atol=1e-9)
    kap = t.curvature(u)
    assert np.argmax(kap) == 1000  # the maximum is at the middle
    assert kap.max() == pytest.approx(t.kappa_max, rel=1e-9)
    fine = np.linspace(0.0, 1.0, 400001)
    speed = np.linalg.norm(ref.derivative(1)(fine), axis=1)
    assert t.arc_length == pytest.approx(float(np.sum(0.5 * (speed[1:] + speed[:-1]) * np.diff(fine))), rel=1e-8)


def test_zhao_rotated_square_in_the_published_region():
    res = bl.zhao2013(bl.rotated_square(), 0.2, LIM)
    cap = bl.transition_cap(res.transitions[0], LIM)
    kap = 2 * math.tan(math.pi / 4) ** 2 / (3 * 0.2)
    assert cap == pytest.approx(min(100.0, math.sqrt(3000.0 / kap), (60000.0 / kap**2) ** (1 / 3)))
    np.testing.assert_allclose(res.junction_speeds[1:-1], cap, rtol=1e-12)
    # published for the same case: G01 0.45382 s, Xu & Sun 2018 0.40467 s
    assert 0.3 < res.total_time < 0.45382
    # the conservative variant is slower but still a valid plan
    slow = bl.zhao2013(bl.rotated_square(), 0.2, LIM, transition_speed="constant")
    assert slow.total_time > res.total_time


def test_cli_prints_every_path_and_method(capsys):
    assert bl.main([]) == 0
    out = capsys.readouterr().out
    for text in ("rotated square", "butterfly", "zig-zag", "G01 junction speed", "Zhao, Zhu & Ding 2013"):
        assert text in out


def test_every_jerk_term_is_checked_and_the_every_term_cap_holds_it():
    """The midpoint and whole-transition readings bound only κ²v³; counting κ′v³ (the curvature
    change) they break J on the square, and the every-term cap keeps |j| within it."""
    pts = bl._clean(bl.rotated_square())
    for mode in ("midpoint", "constant"):
        res = bl.zhao2013(pts, 0.2, LIM, transition_speed=mode)
        acc, jerk = bl.vector_load(res, LIM)
        n_acc, n_jerk = bl.normal_load(res, LIM)
        assert acc >= n_acc - 1e-12 and jerk > 1.05 > n_jerk
    safe = bl.zhao2013(pts, 0.2, LIM, transition_speed="every-term")
    assert bl.vector_load(safe, LIM)[1] <= 1.001
    assert safe.total_time > bl.zhao2013(pts, 0.2, LIM, transition_speed="constant").total_time
