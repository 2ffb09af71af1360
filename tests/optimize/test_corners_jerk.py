"""Corner transitions for jerk-limited timing: the curvature-rate objective."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from gouge import gouges  # noqa: E402

from trcopt.cli import main  # noqa: E402
from trcopt.config import DEFAULT_MACHINE, AxisLimits, Machine  # noqa: E402
from trcopt.errors import ConfigError  # noqa: E402
from trcopt.modes import TransitionKind  # noqa: E402
from trcopt.optimize.corners import CornerBlendProblem, blend_corners, find_corner_sites  # noqa: E402
from trcopt.pipeline import PlanOptions, plan_file  # noqa: E402
from trcopt.timing.jerk import jerk_limited  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
PROG = ROOT / "problems" / "corners" / "corner_30deg.mpf"
EPS = 0.1


@pytest.fixture(scope="module")
def corner():
    r = plan_file(PROG, PlanOptions(timing=False))
    assert r.ok
    return r


def _x_of(geom) -> np.ndarray:  # type: ignore[no-untyped-def]
    """Decision vector (sa, α, β, sb, γ, δ) of a solved transition (the neighbours are lines)."""
    d0, a0, a1, d1 = (np.array(v) for v in (geom.d0, geom.a0, geom.a1, geom.d1))
    ta, tb = d0 / np.linalg.norm(d0), d1 / np.linalg.norm(d1)
    return np.array([geom.sa, np.linalg.norm(d0), a0 @ ta, geom.sb, np.linalg.norm(d1), a1 @ tb])


def test_jerk_objective_trades_peak_curvature_for_a_slower_curvature_change(corner):
    ((_, site),) = find_corner_sites(corner.toolpath, corner.programmed, tolerance_mm=EPS)
    limits = (2000.0, 50000.0)
    curv = CornerBlendProblem(site, EPS).solve()
    jerk_p = CornerBlendProblem(site, EPS, limits=limits)
    jerk = jerk_p.solve()
    assert curv.ok and jerk.ok
    for sol in (curv, jerk):
        assert sol.geometry.max_deviation <= EPS and sol.geometry.min_clearance >= site.radius - 2e-9
    # each solution is the better one by its own measure
    x_c, x_j = _x_of(curv.geometry), _x_of(jerk.geometry)
    assert np.allclose(CornerBlendProblem(site, EPS).coefficients(x_c)[2], curv.geometry.a0)
    ev_c, ev_j = jerk_p.evaluate(x_c, dense=True), jerk_p.evaluate(x_j, dense=True)
    cost_c, cost_j = jerk_p.objective_samples(ev_c).max(), jerk_p.objective_samples(ev_j).max()
    assert cost_j < cost_c
    assert jerk.cost == pytest.approx(cost_j, rel=1e-9)
    assert curv.geometry.max_curvature <= jerk.geometry.max_curvature
    # the cost is the larger of |κ| and amax·(|dκ/ds|/jmax)^(2/3); here the curvature rate dominates
    k, dk = np.abs(ev_j["kappa"]), np.abs(ev_j["dkappa"])
    assert np.allclose(jerk_p.objective_samples(ev_j), np.maximum(k, 2000.0 * (dk / 50000.0) ** (2 / 3)))
    assert (2000.0 * (dk / 50000.0) ** (2 / 3)).max() > k.max()


def test_jerk_objective_is_faster_under_jerk_limits(corner):
    m = DEFAULT_MACHINE
    curv = blend_corners(corner.toolpath, corner.programmed, tolerance_mm=EPS, select=False)
    jerk = blend_corners(corner.toolpath, corner.programmed, tolerance_mm=EPS, select=False, objective="jerk")
    arc = blend_corners(corner.toolpath, corner.programmed, tolerance_mm=EPS, mode="arc")
    times = {}
    for name, res in (("curvature", curv), ("jerk", jerk), ("arc", arc)):
        assert res.blended == 1 and res.max_deviation_mm <= EPS
        assert not gouges(corner.programmed, res.segments)
        traj = jerk_limited(res.segments, m)
        rep = traj.check_limits(dt=1e-4)
        assert rep.ok and max(rep.jerk_ratio) <= 1.01, (name, str(rep))
        times[name] = traj.duration
    assert times["jerk"] < times["curvature"] and times["jerk"] < times["arc"]


def test_objective_is_validated_and_needs_jerk_limits(corner):
    with pytest.raises(ValueError, match="objective"):
        blend_corners(corner.toolpath, corner.programmed, tolerance_mm=EPS, objective="speed")
    no_jerk = Machine(axes=(("X", AxisLimits(250, 2000)), ("Y", AxisLimits(250, 2000)), ("Z", AxisLimits(100, 1000))))
    with pytest.raises(ConfigError, match="jmax_mm_s3"):
        blend_corners(corner.toolpath, corner.programmed, tolerance_mm=EPS, objective="jerk", machine=no_jerk)


def test_plan_with_corners_and_jerk_uses_the_jerk_objective(tmp_path):
    out = tmp_path / "p.json"
    rc = main(["plan", str(PROG), "--corners", "optimal", "--tolerance", str(EPS), "--jerk", "--json", str(out)])
    assert rc == 0
    plan = json.loads(out.read_text())
    assert plan["corners"]["objective"] == "jerk" and plan["corners"]["quintic"] == 1
    assert plan["timing"]["jerk_limited"] is True and plan["timing"]["limits_ok"] is True


@pytest.mark.parametrize(("name", "kept"), [("pocket_square", "exact"), ("obround_pocket", "transitions")])
def test_under_jerk_limits_corners_are_never_slower_than_the_exact_path(name, kept):
    """The transitions are kept only where the jerk-limited feed is faster with them (the square
    pocket's four sharp corners at ε 0.01 are faster as exact stops; benchmarks/JERK.md)."""
    program = ROOT / "problems" / "corners" / f"{name}.mpf"
    exact = plan_file(program, PlanOptions(jerk=True, verify=False))
    best = plan_file(program, PlanOptions(jerk=True, corners="optimal", tolerance_mm=0.01, verify=False))
    corners = best.extra["corners"]
    assert corners["kept"] == kept and corners["blended"] == 4
    assert corners["exact_duration_s"] == pytest.approx(exact.duration, rel=1e-9)
    assert best.duration == pytest.approx(min(corners["exact_duration_s"], corners["transitions_duration_s"]))
    assert best.duration <= exact.duration * (1 + 1e-9)
    if kept == "exact":
        assert [s.geometry for s in best.toolpath] == [s.geometry for s in exact.toolpath]
        assert "exact path is faster" in best.summary()
    else:
        assert best.duration < 0.95 * exact.duration and len(best.toolpath) > len(exact.toolpath)


BOSS_CORNER = """$TC_DP1[1,1]=120 $TC_DP6[1,1]=3
N10 G17 G90 T1 D1 G0 X0 Y-30 Z0
N20 G1 G42 X0 Y-10 F6000
N30 X40
N40 Y30
N50 G40 X60 Y30
N60 M30
"""


@pytest.mark.parametrize("chains", [False, True])
def test_g450_transition_circle_is_replaced_by_a_g2_transition_under_the_jerk_objective(chains):
    from trcopt.geometry import Arc, Poly
    from trcopt.optimize.corners import JUMP_SMOOTHED
    from trcopt.path import Role
    from trcopt.pipeline import plan

    r = plan(BOSS_CORNER, options=PlanOptions(timing=False))
    assert r.ok
    circles = [s for s in r.toolpath if s.role is Role.CORNER and isinstance(s.geometry, Arc)]
    assert len(circles) == 1  # the outside corner at X40 Y-10 gets a G450 circle of radius R
    # acceleration-limited (curvature objective): the circle is already the least-curvature transition
    plain = blend_corners(r.toolpath, r.programmed, tolerance_mm=0.01, select=False, chains=chains)
    assert plain.corners == [] and plain.segments == r.toolpath
    res = blend_corners(r.toolpath, r.programmed, tolerance_mm=0.01, select=False, objective="jerk", chains=chains)
    if chains:
        # the circle's two curvature jumps as one G2 spline from line to line (a piece per element)
        smoothed = (True, TransitionKind.SPLINE, JUMP_SMOOTHED)
        assert [(c.blended, c.transition, c.reason) for c in res.corners] == [smoothed] * 2
        assert res.curvature_jumps == 2
    else:
        # a quintic SQP transition replaces the circle
        (rec,) = res.corners
        assert rec.blended and rec.transition is TransitionKind.QUINTIC, rec.reason
    corner = [s for s in res.segments if s.role is Role.CORNER]
    assert len(corner) == (3 if chains else 1) and all(isinstance(c.geometry, Poly) for c in corner)
    # the transition stays outside the circle around the vertex: the vertex keeps at least R (no
    # gouge) and the cut part leaves at most ε
    pts = np.array(
        [c.geometry.point(x)[:2] for c in corner for x in np.linspace(0.0, c.geometry.length, 400)]
    )
    d = np.hypot(pts[:, 0] - 40.0, pts[:, 1] + 10.0)
    assert d.min() >= 3.0 - 1e-8
    assert res.max_deviation_mm <= 0.01 and not gouges(r.programmed, res.segments)
    # no curvature jump of 1/R at the ends any more: faster under jerk limits
    exact, smooth = jerk_limited(r.toolpath, DEFAULT_MACHINE), jerk_limited(res.segments, DEFAULT_MACHINE)
    assert smooth.check_limits(dt=1e-4).ok
    assert smooth.duration < 0.97 * exact.duration
