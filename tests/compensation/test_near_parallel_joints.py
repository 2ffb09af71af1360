"""Joints whose offsets are all but parallel (CAM chords rounded to 1e-5 mm, far from the origin):
the offsets' intersection is ill-conditioned, yet the tool path has no gap at the joint."""

from __future__ import annotations

import math

from trcopt.pipeline import PlanOptions, plan

# chords of a large-radius contour as a CAM post writes them (5 decimals, 55 m from the origin)
CHORDS = """N3394880 X-12416.93639 Y53834.84201
N3394890 X-12417.13172 Y53834.45328
N3394900 X-12417.32706 Y53834.06453
N3394910 X-12417.52238 Y53833.67578
N3394920 X-12417.71770 Y53833.28701
N3394930 X-12417.91302 Y53832.89824
N3394940 X-12418.10833 Y53832.50946
N3394950 X-12418.30363 Y53832.12067
N3394960 X-12418.49893 Y53831.73187"""


def test_no_gap_where_the_offsets_are_nearly_parallel():
    text = (
        "N10 $TC_DP1[1,1]=120 $TC_DP6[1,1]=2\nN20 G17 G90 G71 T1 D1 G0 X-12400 Y53900 Z0\n"
        "N30 G42 G1 X-12416.74105 Y53835.23073 F6000\n" + CHORDS + "\nN40 G40 G1 X-12500 Y53700\nN50 M30\n"
    )
    result = plan(text, file="chords.mpf", options=PlanOptions(timing=False))
    assert result.ok and not result.warnings, [d.format() for d in result.diagnostics]
    path = result.toolpath
    gaps = [math.dist(a.geometry.end, b.geometry.start) for a, b in zip(path, path[1:], strict=False)]
    assert max(gaps) <= 1e-9
    assert result.verification.ok
