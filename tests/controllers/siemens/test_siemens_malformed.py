"""SINUMERIK input validation found by the fuzz run: negative $TC_DP6, and the KONTC approach into
an inside arc of the tool's radius that used to sample its polynomial without end."""

from __future__ import annotations

import time

from trcopt.codes import Code
from trcopt.pipeline import PlanOptions, plan

KONTC = """$TC_DP1[1,1]=120 $TC_DP6[1,1]={r}
N10 G0 X26.45783105565463 Y7.587539664936749 T1 D1
N20 G1 {side} KONTC X11.215620811121344 Y11.713625073394496 F600
N30 G2 X11.423090915767862 Y10.259863175226458 I=AC(10.024468493750112) J=AC(10.80194741280324)
N40 G1 X22 Y0
N50 G40 X30 Y-5
N60 M30
"""


def test_a_negative_tool_radius_is_an_error_at_its_assignment() -> None:
    result = plan(KONTC.format(r="-1.5", side="G41"), file="p.mpf", options=PlanOptions(timing=False))
    err = result.errors[0]
    assert err.code is Code.NC_TOOL_RADIUS
    assert (err.span.line, err.span.column) == (1, 18)
    assert "$TC_DP6[1,1]=-1.5" in err.message


def test_a_negative_wear_may_still_swap_the_side() -> None:
    text = (
        "$TC_DP1[1,1]=120 $TC_DP6[1,1]=1 $TC_DP15[1,1]=-3\n"
        "N10 G0 X0 Y0 T1 D1\nN20 G1 G41 X20 F100\nN30 G40 X30\nM30\n"
    )
    result = plan(text, file="p.mpf", options=PlanOptions(timing=False))
    assert not any(d.code is Code.NC_TOOL_RADIUS for d in result.diagnostics)


def test_kontc_into_an_inside_arc_of_the_tool_radius_is_alarm_10751_at_once() -> None:
    # the offset arc has radius 4e-16 mm: a point, not a carrier of curvature 1/r for KONTC
    start = time.perf_counter()
    result = plan(KONTC.format(r="1.5", side="G42"), file="p.mpf", options=PlanOptions())
    assert time.perf_counter() - start < 10.0
    err = result.errors[0]
    assert err.alarm == 10751 and err.span.block == "N30"


def test_a_form_feed_before_the_block_number_is_white_space() -> None:
    text = "N10 G0 X0 Y0\n\x0cN20 G1 X10 F100 Q?\nM30\n"
    result = plan(text, file="p.mpf", options=PlanOptions(timing=False))
    err = result.errors[0]
    assert (err.span.line, err.span.block) == (2, "N20")
