"""G460/G461/G462 and the end point behind the contour (sinumerik_trc.md R31–R35, example 1)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from trcopt.pipeline import PlanOptions, plan, plan_file

ROOT = Path(__file__).resolve().parents[2]
X461 = (50 - 10 * math.cos(math.radians(30)), 10.0)  # 30° up the auxiliary circle around (50, 5)


def approx(p, q, tol=1e-9):
    return all(abs(a - b) <= tol for a, b in zip(p, q, strict=True))


def test_seed_g461_feeds_and_path() -> None:
    r = plan_file(ROOT / "problems" / "siemens" / "ex01_seed_g461.mpf", PlanOptions(timing=False))
    n50, n70 = r.toolpath[1], r.toolpath[2]
    assert approx(n50.end_xyz, (*X461, 0.0)) and approx(n70.start_xyz, (*X461, 0.0))
    # N50 keeps F10000 from N30; N60's F600 is executed at the intersection, so N70 runs at F600
    assert n50.feed_mm_s == pytest.approx(10000 / 60) and n70.feed_mm_s == pytest.approx(600 / 60)
    assert [(d.alarm, d.span.block) for d in r.diagnostics] == [(10763, "N60")]


MIRROR = """$TC_DP1[1,1]=120 $TC_DP6[1,1]=10
N10 G0 X0 Y0 T1 D1
N20 G1 G41 X20 Y-5 F600
N30 X30 Y0
N40 X50
N50 Y5
N60 G40 {approach} {strategy} X{tx} Y{ty}
N70 M30
"""


@pytest.mark.parametrize("strategy, end", [("G461", X461), ("G462", (40.0, 10.0))])
def test_retraction_is_the_mirror_of_the_approach(strategy, end) -> None:
    text = MIRROR.format(approach="NORM", strategy=strategy, tx=0, ty=20)
    r = plan(text, file="m.mpf", options=PlanOptions(timing=False))
    blocks = [(s.span.block, s.kind) for s in r.toolpath]
    assert blocks == [("N20", "line"), ("N30", "line"), ("N40", "arc"), ("N40", "line"), ("N60", "line")]
    assert approx(r.toolpath[1].start_xyz, (20 - 10 / math.sqrt(5), -5 + 20 / math.sqrt(5), 0), 1e-9)
    assert approx(r.toolpath[3].end_xyz, (*end, 0.0)) and approx(r.toolpath[4].start_xyz, (*end, 0.0))
    assert approx(r.toolpath[4].end_xyz, (0, 20, 0))
    assert [(d.alarm, d.span.block) for d in r.diagnostics] == [(10763, "N50")]


def test_retraction_g460_includes_the_retraction_line_in_the_search_r31() -> None:
    # G460: the NORM retraction line (40, 5) → (0, 20) meets N40's transition circle around (30, 0):
    # 1825 t² − 650 t + 25 = 0, t = (650 + √240000) / 3650 — N50 and the rest of N40 stay unmachined
    text = MIRROR.format(approach="NORM", strategy="G460", tx=0, ty=20)
    r = plan(text, file="m.mpf", options=PlanOptions(timing=False))
    t = (650 + math.sqrt(240000)) / 3650
    x = (40 - 40 * t, 5 + 15 * t, 0.0)
    blocks = [(s.span.block, s.kind) for s in r.toolpath]
    assert blocks == [("N20", "line"), ("N30", "line"), ("N40", "arc"), ("N60", "line")]
    assert approx(r.toolpath[2].end_xyz, x) and approx(r.toolpath[3].start_xyz, x)
    assert [(d.alarm, d.span.block) for d in r.diagnostics] == [(10763, "N50")]


@pytest.mark.parametrize("strategy", ["G460", "G461", "G462"])
def test_end_point_behind_the_contour_intersects_the_bypass_circle_r35(strategy) -> None:
    # KONT, end point (70, 20) behind the contour: the G450 bypass circle around E = (50, 5) from
    # (40, 5) to F = (44, 13) meets N40's offset y = 10 where G461 would; the rest of the circle is
    # still traversed, then the straight line to T. G460–G462 make no difference here.
    text = MIRROR.format(approach="KONT", strategy=strategy, tx=70, ty=20)
    r = plan(text, file="m.mpf", options=PlanOptions(timing=False))
    tail = r.toolpath[-3:]
    assert [(s.span.block, s.kind, s.role.value) for s in tail] == [
        ("N40", "line", "contour"), ("N60", "arc", "retract"), ("N60", "line", "retract")
    ]
    assert approx(tail[0].end_xyz, (*X461, 0.0))
    assert approx(tail[1].center_xyz, (50, 5, 0)) and approx(tail[1].end_xyz, (44, 13, 0))
    assert approx(tail[2].end_xyz, (70, 20, 0))
    assert [(d.alarm, d.span.block) for d in r.diagnostics] == [(10763, "N50")]
