"""SINUMERIK feed per revolution (G95): the path feed is F × S of the master spindle; a change of feed
type deletes F (alarm 10860 at the next feed motion without F); no turning spindle is NC-FEED-MODE;
FAD=PR and FAD under G95 are per revolution; SAVE restores the feed type; the feed types trcopt does
not model stop the program."""

from __future__ import annotations

import pytest

from trcopt.controllers import read_program
from trcopt.errors import Severity
from trcopt.nc import MoveKind
from trcopt.pipeline import PlanOptions, plan


def read(text: str, file: str = "t.mpf"):
    return read_program(text, file=file, dialect="siemens")


def feeds(text: str) -> list[float | None]:
    """The feed (mm/min) of every feed motion of a program that reads without an error."""
    prog = read(text)
    errors = [d.format() for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert errors == []
    return [
        None if m.feed_mm_s is None else round(m.feed_mm_s * 60.0, 9)
        for m in prog.moves
        if m.kind in (MoveKind.LINE, MoveKind.ARC)
    ]


def error(text: str):
    prog = read(text)
    (err,) = [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    return prog, err


def test_the_path_feed_is_f_times_the_spindle_speed() -> None:
    text = "S1000 M3\nG95 G1 X10 F0.2\nS500 Y10\nG2 X0 Y10 CR=5\nS2000 F0.05 G1 X-5\nM30\n"
    assert feeds(text) == [200.0, 100.0, 100.0, 100.0]


def test_s_and_m3_of_the_motion_block_act_at_its_start_m5_at_its_end() -> None:
    assert feeds("G95 F0.1 S800 M4 G1 X10\nM5 Y10\nM30\n") == [80.0, 80.0]
    prog, err = error("S800 M3\nG95 F0.1 G1 X10\nM5 Y10\nN40 X0\nM30\n")
    assert err.code == "NC-FEED-MODE" and (err.span.line, err.span.block) == (4, "N40")
    assert "stopped by M5 in line 3" in err.message
    assert len([m for m in prog.moves if m.kind is MoveKind.LINE]) == 2


def test_spindle_one_is_the_master_spindle() -> None:
    assert feeds("S1=1200 M1=3\nG95 G1 X10 F0.5\nM1=5 X20\nM30\n") == [600.0, 600.0]
    prog, _ = error("S1=1200 M1=3\nG95 G1 X10 F0.5\nM1=5 X20\nX30\nM30\n")
    assert prog.moves[0].actions == ("S1200", "M3")


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        ("G95 G1 X10 F0.2\nM30\n", "no spindle speed S programmed"),
        ("S0 M3 G95 G1 X10 F0.2\nM30\n", "the spindle speed is S0"),
        ("S1000 G95 G1 X10 F0.2\nM30\n", "the spindle has not been started (M3/M4)"),
    ],
)
def test_feed_per_revolution_without_a_turning_spindle_is_an_error(text: str, reason: str) -> None:
    _, err = error(text)
    assert err.code == "NC-FEED-MODE" and reason in err.message
    assert (err.span.line, err.span.column) == (1, 1)


def test_a_rapid_needs_no_spindle_under_g95() -> None:
    prog = read("G95 F0.2 G0 X10\nM30\n")
    assert [d.code for d in prog.diagnostics] == []


def test_a_change_of_feed_type_deletes_f() -> None:
    text = "S1000 M3 G1 X1 F300\nN20 G95 G0 X2\nN30 G1 X3\nM30\n"
    prog, err = error(text)
    assert err.code == "10860" and err.alarm == 10860
    assert (err.span.line, err.span.block) == (3, "N30")  # the first feed motion, not the rapid
    assert "the change to G95 in line 2" in err.message
    assert feeds("S1000 M3 G1 X1 F300\nG95 G0 X2\nG1 X3 F0.1\nG94 F250 X4\nM30\n") == [300.0, 100.0, 250.0]
    _, err = error("S1000 M3 G95 G1 X1 F0.1\nG94 X2\nM30\n")
    assert err.code == "10860" and err.span.line == 2


def test_the_feed_type_in_force_programmed_again_keeps_f() -> None:
    assert feeds("S1000 M3 G95 G1 X1 F0.1\nG95 X2\nG94 F100 X3\nG94 X4\nM30\n") == [100.0, 100.0, 100.0, 100.0]


def test_inch_feeds_per_revolution() -> None:
    assert feeds("G700 S100 M3 G95 G1 X1 F0.01\nM30\n") == [pytest.approx(0.01 * 25.4 * 100)]
    assert feeds("G70 S100 M3 G95 G1 X1 F0.01\nM30\n") == [pytest.approx(0.01 * 100)]  # G70: feeds in mm


def test_s_in_a_dwell_block_is_revolutions_not_a_speed() -> None:
    assert feeds("S1000 M3 G95 G1 X1 F0.1\nG4 S5\nX2\nM30\n") == [100.0, 100.0]


def test_fad_follows_the_feed_type_unless_pm_or_pr() -> None:
    base = "$TC_DP1[1,1]=120 $TC_DP6[1,1]=2\nT1 D1 S500 M3 {g} G1 X0 Y20 Z10 F{f}\n"
    sar = "G41 G147 G341 DISR=5 DISCL=2 {fad} X30 Y0 Z0\nG1 X60\nG40 G0 X70 Y20\nM30\n"
    cases = [("G95", "0.4", "FAD=0.2", 100.0), ("G95", "0.4", "FAD=PM(150)", 150.0), ("G94", "200", "FAD=150", 150.0),
             ("G94", "200", "FAD=PR(0.1)", 50.0)]  # fmt: skip
    for g, f, fad, expected in cases:
        prog = read(base.format(g=g, f=f) + sar.format(fad=fad))
        assert [d for d in prog.diagnostics if d.severity is Severity.ERROR] == []
        (spec,) = [m.sar for m in prog.moves if m.sar is not None]
        assert spec.fad[0] * 60.0 == pytest.approx(expected), fad


def test_save_restores_the_feed_type_and_a_change_deletes_f(tmp_path) -> None:
    (tmp_path / "REV.SPF").write_text("PROC REV SAVE\nG95 G1 X5 F0.1\nRET\n")
    (tmp_path / "KEEP.SPF").write_text("PROC KEEP SAVE\nG1 X5 F80\nRET\n")
    main = tmp_path / "main.mpf"
    main.write_text("S1000 M3 G1 X1 F300\nREV\nN30 G1 X10\nM30\n")
    prog = read(main.read_text(), file=str(main))
    (err,) = [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert err.code == "10860" and err.span.block == "N30" and "SAVE" in err.message
    assert [round(m.feed_mm_s * 60) for m in prog.moves if m.kind is MoveKind.LINE] == [300, 100]
    main.write_text("S1000 M3 G1 X1 F300\nKEEP\nG1 X10\nREV\nG1 X12 F200\nM30\n")
    prog = read(main.read_text(), file=str(main))
    assert [d for d in prog.diagnostics if d.severity is Severity.ERROR] == []
    # F is no G function: the subprogram's F80 stays; the restored G94 after REV needs a new F
    assert [round(m.feed_mm_s * 60) for m in prog.moves if m.kind is MoveKind.LINE] == [300, 80, 80, 100, 200]


def test_drilling_cycle_under_g95() -> None:
    cycle = "G17 G0 X10 Y10 Z20\nCYCLE81(10, 0, 2, -5)\nM30\n"
    assert feeds("S1000 M3 G95 F0.05\n" + cycle) == [50.0]
    _, err = error("G95 F0.05\n" + cycle)
    assert err.code == "NC-FEED-MODE" and err.span.line == 3


@pytest.mark.parametrize("g", ["G93", "G96", "G97", "G961", "G971", "G931", "G942", "G952", "G962", "G972", "G973"])
def test_the_feed_types_trcopt_does_not_model_stop_the_program(g: str) -> None:
    _, err = error(f"G1 X1 F100 S200 M3\nX2 {g}\nM30\n")
    assert err.code == "NC-UNSUPPORTED" and (err.span.line, err.span.column) == (2, 4)
    assert g in err.message and "not modelled" in err.message


def test_two_feed_types_in_one_block() -> None:
    _, err = error("G94 G95 G1 X1 F1\nM30\n")
    assert err.code == "NC-SYNTAX" and err.span.column == 5


def test_the_plan_json_carries_f_times_s() -> None:
    text = (
        "$TC_DP1[1,1]=120 $TC_DP6[1,1]=3\nT1 D1 S1500 M3\nG0 X-10 Y-10\nG95 G1 G41 X0 Y0 F0.12\nX40\nY30\n"
        "G40 X50 Y40\nM30\n"
    )
    result = plan(text, file="p.mpf", options=PlanOptions(timing=False))
    assert result.ok, [d.format() for d in result.errors]
    doc = result.to_json()
    segments = [s for s in doc["toolpath"] if s["kind"] != "rapid"]
    assert segments and [s["feed_mm_min"] for s in segments] == [pytest.approx(180.0)] * len(segments)
