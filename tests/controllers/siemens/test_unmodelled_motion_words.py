"""SINUMERIK words that decide which blocks run or where the tool goes, and that trcopt does not
model, stop the program with a located error instead of being ignored (a `GOTOF` that skips a
plunge must not let the plunge be planned)."""

from __future__ import annotations

import pytest

from trcopt.pipeline import PlanOptions, plan

HEAD = "N10 T1 D1\n$TC_DP1[1,1]=120 $TC_DP6[1,1]=3\nN20 G17 G90 G0 X0 Y0 Z5\n"


def run(line: str):
    text = HEAD + f"N30 {line}\nN40 G1 Z-50 F100\nN50 X10\nN60 M30\n"
    return plan(text, file="w.mpf", options=PlanOptions(timing=False))


@pytest.mark.parametrize(
    ("line", "column", "what"),
    [
        ("TRAORI", 5, "kinematic transformation"),
        ("TRACYL(40)", 5, "kinematic transformation"),
        ("CALL BLOCK A TO B", 5, "CALL BLOCK"),  # CASE, CALL "NAME" and PCALL are modelled (test_siemens_branch)
        ("CALL _NAME", 5, "STRING"),
    ],
)
def test_unmodelled_motion_word_is_a_located_error(line, column, what):
    r = run(line)
    assert not r.ok
    (err,) = r.errors
    assert err.code == "NC-UNSUPPORTED"
    assert (err.span.line, err.span.column, err.span.block) == (4, column, "N30")
    assert what in err.message
    # nothing after the error is planned: the plunge of N40 is not in the path
    assert all(seg.span.line < 5 for seg in r.toolpath)


@pytest.mark.parametrize(
    "line", ["FFWON", "SOFT", "STOPRE", "G500", "R1=5", 'MSG("roughing")', "TRAFOOF",
             'WORKPIECE(,"",,"BOX",112,0,-20,-80,0,0,100,100)', "FGROUP(X,Y,Z)"],
)
def test_words_that_do_not_move_the_tool_still_plan(line):
    r = run(line)
    assert r.ok, [d.message for d in r.errors]
    assert any(seg.span.line == 5 for seg in r.toolpath)
