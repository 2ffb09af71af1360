"""The tool-centre G-code of a program with feed per revolution (G95) or inverse time (G93): every
feed is written per minute under the preamble's G94 — the program's G93/G95 becomes a comment, never
a word that would turn the written F values into feeds per revolution — and the written program,
planned again, has the same feeds and cycle time."""

from __future__ import annotations

import re

import pytest

from trcopt import controllers
from trcopt.io.flavors import GRBL
from trcopt.io.gcode_program import carries_words, kept_words, plan_to_gcode
from trcopt.pipeline import PlanOptions, plan

SIEMENS = """N10 $TC_DP1[1,1]=120 $TC_DP6[1,1]=4
N20 T1 D1 S1200 M3
N30 G0 X-20 Y-20 Z0
N40 G95 G41 G1 X0 Y0 F0.25
N50 S800 X40
N60 G3 X40 Y40 CR=20
N70 G94 G1 X0 F500
N80 G95 F0.1 Y0
N90 G40 G0 X-20 Y-20 M5
N100 M30
"""
FEEDS = [300.0, 200.0, 200.0, 500.0, 80.0]  # mm/min of the feed segments, F × S under G95
RS274 = "G21 G17\nS1000 M3\nG0 X0 Y0\nG95 G1 X20 F0.3\nS500 Y20\nG93 G2 X0 Y20 R10 F5\nG94 G1 Y0 F400\nM5\nM2\n"


def _feeds(result) -> list[float]:
    return [round(s.feed_mm_s * 60.0, 3) for s in result.toolpath if s.kind != "rapid"]


def _words(text: str) -> list[str]:
    """Every word of the written program outside its comments."""
    code = re.sub(r"\([^)]*\)|;.*$", " ", text, flags=re.M)
    return code.split()


@pytest.mark.parametrize(
    ("source", "file", "flavor", "again_file"),
    [
        (SIEMENS, "p.mpf", controllers.get("siemens").gcode, "o.mpf"),
        (SIEMENS, "p.mpf", controllers.get("linuxcnc").gcode, "o.ngc"),
        (SIEMENS, "p.mpf", GRBL, "o.ngc"),
        (RS274, "p.ngc", controllers.get("linuxcnc").gcode, "o.ngc"),
        (RS274, "p.ngc", controllers.get("siemens").gcode, "o.mpf"),
    ],
)
def test_the_written_program_has_the_same_feeds_and_cycle_time(source, file, flavor, again_file) -> None:
    first = plan(source, file=file, options=PlanOptions(corners="exact"))
    assert first.ok, [d.format() for d in first.errors]
    if source is SIEMENS:
        assert [f for f in _feeds(first) if f] == pytest.approx(FEEDS)
    text = plan_to_gcode(first, flavor=flavor, dialect="grbl" if flavor is GRBL else None)
    words = _words(text)
    assert not {"G93", "G95"} & set(words) and "G94" in words
    assert "G95 (feed per revolution, F × S) of the program" in text.replace("[", "(").replace("]", ")")
    again = plan(text, file=again_file, options=PlanOptions(corners="exact"))
    assert again.ok, [d.format() for d in again.errors]
    assert _feeds(again) == pytest.approx(_feeds(first), abs=1e-3)
    assert again.timing.duration == pytest.approx(first.timing.duration, rel=0.01)


def test_an_inch_program_writes_its_feeds_per_revolution_as_inch_per_minute() -> None:
    source = "G700 T1 D0 S100 M3\nG0 X0 Y0\nG95 G1 X1 F0.01\nY1\nM30\n"
    first = plan(source, file="p.mpf", options=PlanOptions(timing=False))
    assert _feeds(first) == [25.4, 25.4]  # 0.01 inch/rev × 100 rev/min = 1 inch/min
    text = plan_to_gcode(first, flavor=controllers.get("siemens").gcode)
    assert "F1" in _words(text) and "G700" in _words(text)
    again = plan(text, file="o.mpf", options=PlanOptions(timing=False))
    assert _feeds(again) == _feeds(first)


def test_a_program_run_out_of_line_order_names_its_feed_mode_too(tmp_path) -> None:
    (tmp_path / "SIDE.SPF").write_text("G95 G1 X10 F0.1\nRET\n")
    main = tmp_path / "main.mpf"
    main.write_text("S1000 M3\nG0 X0 Y0\nSIDE\nG1 Y10\nM30\n")
    first = plan(main.read_text(), file=str(main), options=PlanOptions(timing=False))
    assert first.ok and _feeds(first) == [100.0, 100.0]
    text = plan_to_gcode(first, flavor=controllers.get("siemens").gcode)
    assert "G95 (feed per revolution, F × S) of the program" in text and "G95" not in _words(text)
    again = plan(text, file="o.mpf", options=PlanOptions(timing=False))
    assert _feeds(again) == _feeds(first)


def test_feed_mode_words_are_comments_not_words() -> None:
    assert kept_words(("G95", "S1000", "M3", "F0.2")) == ["S1000", "M3"]
    assert kept_words(("G93", "G9", "G64")) == []
    assert carries_words(("G95",)) and carries_words(("G93",)) and not carries_words(("F0.2",))
