"""Optimal corner mode on short-chord polylines: G2 where it is faster, circular blends where the
G2 quintic is slower or infeasible, never slower than the same-ε circular blends (per-corner
transitions: the runs of small corners as one spline are tested in test_corners_chain.py)."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from gouge import gouges  # noqa: E402

from trcopt.modes import TransitionKind  # noqa: E402
from trcopt.optimize.corners import blend_corners  # noqa: E402
from trcopt.pipeline import PlanOptions, plan  # noqa: E402
from trcopt.timing import time_parameterize  # noqa: E402

EPS = 0.01


def _arc_polyline(side: str, radius: float = 20.0, chords: int = 6, chord: float = 1.0) -> str:
    """CCW polyline on a circle of ``radius`` (chords of ``chord`` mm) with a straight lead-in."""
    step = 2 * math.asin(chord / (2 * radius))
    pts = [(radius * math.sin(i * step), -radius * math.cos(i * step)) for i in range(chords + 1)]
    lines = [
        "$TC_DP1[1,1]=120 $TC_DP6[1,1]=3",
        "N10 G17 G90 T1 D1 G0 X-10 Y-30 Z0",
        f"N20 G1 {side} X{pts[0][0]:.6f} Y{pts[0][1]:.6f} F6000",
    ]
    lines += [f"N{30 + 10 * i} X{x:.6f} Y{y:.6f}" for i, (x, y) in enumerate(pts[1:])]
    end = pts[-1]
    lines += [f"N900 G40 X{end[0] + 10:.6f} Y{end[1] + 10:.6f}", "N910 M30"]
    return "\n".join(lines) + "\n"


@pytest.fixture(scope="module")
def inside():
    r = plan(_arc_polyline("G41"), options=PlanOptions(timing=False))
    assert r.ok
    return r


@pytest.mark.parametrize("objective", ["curvature", "jerk"])
def test_never_slower_than_circular_blends_and_within_tolerance(inside, objective):
    opt = blend_corners(
        inside.toolpath, inside.programmed, tolerance_mm=EPS, mode="optimal", chains=False, objective=objective
    )
    arc = blend_corners(inside.toolpath, inside.programmed, tolerance_mm=EPS, mode="arc")
    t_opt = time_parameterize(opt.segments).duration
    t_arc = time_parameterize(arc.segments).duration
    t_exact = time_parameterize(inside.toolpath).duration
    assert t_opt <= t_arc * (1 + 1e-12) < t_exact
    assert opt.blended == len(opt.corners) == 5
    assert opt.count(TransitionKind.QUINTIC) + opt.count(TransitionKind.ARC) == 5
    transitions = (TransitionKind.QUINTIC, TransitionKind.ARC)
    if objective == "jerk":  # G2 quintics solved at every corner, then the choice by time
        assert all(c.transition in transitions and c.solution is not None for c in opt.corners)
    else:  # the closed-form circles, no quintic solved: the same path as the arc strategy
        assert opt.count(TransitionKind.ARC) == 5 and all(c.solution is None for c in opt.corners)
        assert [s.geometry for s in opt.segments] == [s.geometry for s in arc.segments]
    # every circular corner says why
    assert all(c.reason for c in opt.corners if c.transition is TransitionKind.ARC)
    assert opt.max_deviation_mm <= EPS and not gouges(inside.programmed, opt.segments)


def test_without_selection_g2_transitions_are_kept(inside):
    g2 = blend_corners(inside.toolpath, inside.programmed, tolerance_mm=EPS, mode="optimal", select=False, chains=False)
    assert g2.count(TransitionKind.QUINTIC) == 5 and g2.count(TransitionKind.ARC) == 0
    assert g2.max_deviation_mm <= EPS and not gouges(inside.programmed, g2.segments)


def test_outside_corners_of_small_deflection_keep_r_from_the_programmed_vertex():
    # G42 on the CCW polyline: outside corners below MD20230 (10°) meet at the intersection of the
    # offsets; every transition must stay R from the programmed vertex, so only a sliver of
    # R·(1/cos(δ/2) − 1) ≈ 0.9 µm is left. The circle of radius R around the vertex fits it
    # (curvature 1/R); a G2 transition needs a higher peak (its ends have zero curvature).
    r = plan(_arc_polyline("G42"), options=PlanOptions(timing=False))
    assert r.ok
    g2 = blend_corners(r.toolpath, r.programmed, tolerance_mm=EPS, mode="optimal", select=False, chains=False)
    arc = blend_corners(r.toolpath, r.programmed, tolerance_mm=EPS, mode="arc")
    assert g2.blended == arc.blended == 5 and g2.count(TransitionKind.QUINTIC) == 5
    for q, c in zip(g2.corners, arc.corners, strict=True):
        assert c.max_curvature == pytest.approx(1 / 3.0, rel=1e-5)
        assert 1 / 3.0 < q.max_curvature < 1.2 / 3.0
    assert not gouges(r.programmed, g2.segments) and not gouges(r.programmed, arc.segments)
    best = blend_corners(r.toolpath, r.programmed, tolerance_mm=EPS, mode="optimal", chains=False)
    t_best, t_arc = time_parameterize(best.segments).duration, time_parameterize(arc.segments).duration
    assert t_best <= t_arc * (1 + 1e-12) < time_parameterize(r.toolpath).duration


def test_per_corner_mix_is_timed_and_kept_only_when_faster(inside, monkeypatch):
    import trcopt.optimize.corners.selection as selection_mod

    # force a mix (odd corners G2, even circular) through the local estimate
    calls = iter(range(100))
    monkeypatch.setattr(selection_mod, "_local_time", lambda *a: -1.0 if next(calls) % 2 else 1.0)
    # the jerk objective solves a G2 quintic at every corner (the curvature objective takes circles)
    opt = blend_corners(
        inside.toolpath, inside.programmed, tolerance_mm=EPS, mode="optimal", chains=False, objective="jerk"
    )
    assert next(calls) > 0  # the local estimate was asked
    arc = blend_corners(inside.toolpath, inside.programmed, tolerance_mm=EPS, mode="arc")
    assert time_parameterize(opt.segments).duration <= time_parameterize(arc.segments).duration * (1 + 1e-12)
    assert opt.max_deviation_mm <= EPS and isinstance(opt.max_deviation_mm, float)
    assert not gouges(inside.programmed, opt.segments)
