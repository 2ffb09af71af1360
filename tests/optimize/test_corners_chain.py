"""Runs of small-deflection corners (CAM polylines) as one G2 smoothing spline."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from gouge import gouges  # noqa: E402

from trcopt.cli import main  # noqa: E402
from trcopt.geometry import Line, Poly  # noqa: E402
from trcopt.modes import TransitionKind  # noqa: E402
from trcopt.optimize.corners import blend_corners  # noqa: E402
from trcopt.pipeline import PlanOptions, plan  # noqa: E402
from trcopt.timing import time_parameterize  # noqa: E402

EPS = 0.01
RADIUS = 3.0


def _cam_arc(side: str, chords: int, radius: float = 20.0, chord: float = 1.0) -> str:
    """CCW chords of ``chord`` mm on a circle of ``radius`` (deflection 2.87° at 1 mm / R 20),
    entered and left along straight lines."""
    step = 2 * math.asin(chord / (2 * radius))
    pts = [(radius * math.sin(i * step), -radius * math.cos(i * step)) for i in range(chords + 1)]
    out = [
        f"$TC_DP1[1,1]=120 $TC_DP6[1,1]={RADIUS:g}",
        "N10 G17 G90 T1 D1 G0 X-10 Y-30 Z0",
        f"N20 G1 {side} X{pts[0][0]:.6f} Y{pts[0][1]:.6f} F6000",
    ]
    out += [f"N{30 + 10 * i} X{x:.6f} Y{y:.6f}" for i, (x, y) in enumerate(pts[1:])]
    end = pts[-1]
    out += [f"N{40 + 10 * chords} G40 X{end[0] + 10:.6f} Y{end[1] + 10:.6f}", f"N{50 + 10 * chords} M30"]
    return "\n".join(out) + "\n"


@pytest.fixture(scope="module")
def outside():
    r = plan(_cam_arc("G42", 16), options=PlanOptions(timing=False))
    assert r.ok
    spline = blend_corners(r.toolpath, r.programmed, tolerance_mm=EPS, mode="optimal", select=False)
    return r, spline


def test_outside_run_is_one_spline_flatter_than_the_r_circle(outside):
    # per corner, an outside corner below MD20230 leaves only a sliver of ≈ 1 µm outside the
    # circle of radius R around the vertex: curvature ≥ 1/R = 0.333/mm. One spline across the
    # run may leave ε between the vertices and follows the circle R 20 + 3 the chords approximate.
    r, res = outside
    assert res.count(TransitionKind.SPLINE) == len(res.corners) == 15
    kmax = max(c.max_curvature for c in res.corners)
    assert 1 / 23.0 < kmax < 0.1
    assert res.max_deviation_mm <= EPS
    assert not gouges(r.programmed, res.segments)
    # every chord keeps its block: one spline piece per element of the run, in program order
    pieces = [s for s in res.segments if isinstance(s.geometry, Poly)]
    assert len(pieces) == 16
    lines = [s.span.line for s in pieces]
    assert lines == sorted(lines) and len(set(lines)) == 16


def test_spline_is_curvature_continuous_and_joins_the_lines_g2(outside):
    _, res = outside
    segs = res.segments
    idx = [i for i, s in enumerate(segs) if isinstance(s.geometry, Poly)]
    assert idx == list(range(idx[0], idx[-1] + 1))
    for a, b in zip(segs[idx[0] - 1 : idx[-1] + 1], segs[idx[0] : idx[-1] + 2], strict=True):
        ga, gb = a.geometry, b.geometry
        assert math.dist(ga.end, gb.start) < 1e-9
        ta, tb = np.array(ga.end_tangent()), np.array(gb.start_tangent())
        assert abs(ta[0] * tb[1] - ta[1] * tb[0]) < 1e-7 and ta @ tb > 0
        ka = np.array(ga.curvatures[-1][:2]) if isinstance(ga, Poly) else np.zeros(2)
        kb = np.array(gb.curvatures[0][:2]) if isinstance(gb, Poly) else np.zeros(2)
        assert np.hypot(*(ka - kb)) < 1e-6
    assert isinstance(segs[idx[0] - 1].geometry, Line) and isinstance(segs[idx[-1] + 1].geometry, Line)


def test_spline_beats_circular_blends_and_per_corner_g2(outside):
    # per-corner transitions with the selection: the fastest of G2 quintics, same-ε circular blends
    # and their mix (never slower than the circular blends)
    r, spline = outside
    single = blend_corners(r.toolpath, r.programmed, tolerance_mm=EPS, mode="optimal", chains=False)
    assert single.count(TransitionKind.SPLINE) == 0 and min(c.max_curvature for c in single.corners) > 1 / RADIUS - 1e-6
    chosen = blend_corners(r.toolpath, r.programmed, tolerance_mm=EPS, mode="optimal")
    t_spline, t_single = time_parameterize(spline.segments).duration, time_parameterize(single.segments).duration
    # 16 mm of chords between a lead-in and a lead-out, which take most of the cycle time
    assert t_spline < 0.99 * t_single < time_parameterize(r.toolpath).duration
    assert chosen.count(TransitionKind.SPLINE) == 15
    assert time_parameterize(chosen.segments).duration == pytest.approx(t_spline, rel=1e-12)


def test_inside_run_never_slower_than_circular_blends():
    r = plan(_cam_arc("G41", 8), options=PlanOptions(timing=False))
    res = blend_corners(r.toolpath, r.programmed, tolerance_mm=EPS, mode="optimal")
    arc = blend_corners(r.toolpath, r.programmed, tolerance_mm=EPS, mode="arc")
    assert time_parameterize(res.segments).duration <= time_parameterize(arc.segments).duration * (1 + 1e-12)
    assert res.max_deviation_mm <= EPS and not gouges(r.programmed, res.segments)
    forced = blend_corners(r.toolpath, r.programmed, tolerance_mm=EPS, mode="optimal", select=False)
    assert forced.count(TransitionKind.SPLINE) == 7
    assert forced.max_deviation_mm <= EPS and not gouges(r.programmed, forced.segments)


def test_two_small_corners_are_not_a_run():
    r = plan(_cam_arc("G42", 3), options=PlanOptions(timing=False))
    res = blend_corners(r.toolpath, r.programmed, tolerance_mm=EPS, mode="optimal", select=False)
    assert res.count(TransitionKind.SPLINE) == 0 and res.count(TransitionKind.QUINTIC) == 2


def test_cli_reports_spline_corners(tmp_path, capsys):
    prog = tmp_path / "cam.mpf"
    prog.write_text(_cam_arc("G42", 6))
    out = tmp_path / "plan.json"
    assert main(["plan", str(prog), "--corners", "optimal", "--tolerance", "0.01", "--json", str(out)]) == 0
    plan_json = json.loads(out.read_text())
    corners = plan_json["corners"]
    assert corners["spline"] == 5 and corners["blended"] == 5
    assert corners["max_deviation_mm"] <= EPS
    assert "5 on G2 splines" in capsys.readouterr().out


def test_long_runs_are_split_into_splines_that_meet_mid_chord(outside, monkeypatch):
    import trcopt.optimize.corners.chain as chain_mod

    r, whole = outside
    monkeypatch.setattr(chain_mod, "CHAIN_MAX_CORNERS", 7)
    split = blend_corners(r.toolpath, r.programmed, tolerance_mm=EPS, mode="optimal", select=False)
    assert split.count(TransitionKind.SPLINE) == 15
    polys = [s for s in split.segments if isinstance(s.geometry, Poly)]
    # 15 corners in runs of 5 (16 elements; the two shared chords hold the end of one spline and the
    # start of the next, so 18 pieces)
    assert len(polys) == 18
    for a, b in zip(split.segments[:-1], split.segments[1:], strict=True):
        assert math.dist(a.geometry.end, b.geometry.start) < 1e-9
    assert split.max_deviation_mm <= EPS and not gouges(r.programmed, split.segments)
    assert time_parameterize(whole.segments).duration <= time_parameterize(split.segments).duration * (1 + 1e-9)


def test_jerk_mode_times_run_splines_within_the_jerk_measure(tmp_path):
    # the jerk rows follow the quintic pieces of the spline exactly (benchmarks/JERK.md)
    prog = tmp_path / "cam.mpf"
    prog.write_text(_cam_arc("G42", 4))
    res = plan(prog.read_text(), options=PlanOptions(corners="optimal", tolerance_mm=EPS, jerk=True))
    corners = res.extra["corners"]
    assert corners["spline"] == 3 and corners["blended"] == 3
    rep = res.timing.check_limits(dt=1e-4)
    assert rep.ok and max(rep.jerk_ratio) <= 1.01, str(rep)
    assert not [d for d in res.diagnostics if "jerk-limited feed" in d.message]
