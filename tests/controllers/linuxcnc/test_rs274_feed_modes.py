"""LinuxCNC feed modes: G95 (units per revolution: F × S), G93 (inverse time: the programmed length ×
F), G94; every G94/G95 word zeroes the feed rate; LinuxCNC's errors with its messages.

The stored feeds and errors are facts measured with LinuxCNC's own ``rs274`` (``rs274 -t sim.tbl -g
PROGRAM.ngc``): the feed of every STRAIGHT_FEED/ARC_FEED call — its last SET_FEED_RATE, times the
last SET_SPINDLE_SPEED after a SET_FEED_MODE(…, 1) — and the first line of its error output.
``test_stored_values_are_rs274s`` re-measures them where rs274 is installed.
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import pytest

from trcopt.controllers.linuxcnc.ngc_feed import arc_length
from trcopt.controllers.linuxcnc.reader import read_rs274
from trcopt.errors import Severity
from trcopt.nc.model import MoveKind
from trcopt.pipeline import PlanOptions, plan, plan_file

sys.path.insert(0, str(Path(__file__).resolve().parent))
from rs274diff import RS274, SIM_TBL, run_rs274  # noqa: E402
from test_lcnc_pairs import PEER  # noqa: E402

# name: (program, feeds of its feed moves in program units/min, (error message, line) or None)
PROGRAMS: dict[str, tuple[str, list[float], tuple[str, int] | None]] = {
    "per_rev": (
        "G21 G17 G90\nS1000 M3\nG95 F0.2\nG1 X10\nM5\nG1 X20\nS500 G1 X30\nG2 X40 Y0 R5\nG94 F300 G1 X50\nM2\n",
        [200.0, 200.0, 100.0, 100.0, 300.0], None,
    ),
    "per_rev_inch": ("G20 G17 G90\nS250 M3\nG95 F0.004 G1 X1\nG3 X0 Y1 I-0.5 J0.5 F0.002\nM2\n", [1.0, 0.5], None),
    "g95_resets_feed": ("G21\nS1000 M3\nF300 G1 X10\nG95 G1 X20\nM2\n", [300.0],
                        ("Cannot do g1 with zero feed rate", 4)),
    "g94_resets_feed": ("G21\nF300\nG1 X10\nG94\nG1 X20\nM2\n", [300.0], ("Cannot do g1 with zero feed rate", 5)),
    "zero_speed": ("G21\nG95 F0.2\nG1 X10\nM2\n", [], ("Cannot feed with zero spindle speed in feed per rev mode", 3)),
    "zero_speed_arc": ("G21\nS1 G95 F0.2\nG1 X10\nS0\nG2 X20 R5\nM2\n", [0.2],
                       ("Cannot feed with zero spindle speed in feed per rev mode", 5)),
    "inverse": (
        "G21 G17\nG93 G1 X10 F2\nG1 X20 Y10 F0.5\nG2 X30 Y0 R20 F1\nG0 X0 Y0\nG1 X0 Y0 F5\nG2 X0 Y0 I5 P2 F1\n"
        "G94 G1 X5 F100\nM2\n",
        [20.0, 7.0711, 14.4547, 0.1, 62.8319, 100.0], None,
    ),
    "inverse_helix_inch": ("G20 G17\nG1 X1 F10\nG93 G2 X3 Y0 Z1 I1 F2\nM2\n", [10.0, 6.5938], None),
    "inverse_needs_f": ("G21\nG93 G1 X10 F2\nG1 X20\nM2\n", [20.0], ("F word missing with inverse time g1 move", 3)),
    "inverse_arc_needs_f": ("G21\nG93 G1 X10 F2\nG2 X20 R5\nM2\n", [20.0],
                            ("F word missing with inverse time arc move", 3)),
    "inverse_cycle": ("G21 F100\nG93\nG81 X1 Y1 Z-1 R1 F1\nM2\n", [],
                      ("Cannot use inverse time feed with canned cycles", 3)),
    "g1_alone_zero_feed": ("G21\nG1\nM2\n", [], ("Cannot do g1 with zero feed rate", 2)),
    "per_rev_cycle": ("G21 S2000 M3\nG95 F0.05\nG81 X1 Y1 Z-1 R1\nG80\nM2\n", [100.0], None),
}  # fmt: skip


def _feeds(prog, unit: float) -> list[float]:
    return [round(m.feed_mm_s * 60.0 / unit, 4) for m in prog.moves if m.kind in (MoveKind.LINE, MoveKind.ARC)]


@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_feeds_and_errors_as_linuxcnc(name: str) -> None:
    text, feeds, error = PROGRAMS[name]
    prog = read_rs274(text, file="p.ngc")
    unit = 25.4 if text.startswith("G20") else 1.0
    assert _feeds(prog, unit) == pytest.approx(feeds, abs=1e-4)
    errors = [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    if error is None:
        assert errors == []
    else:
        assert [(d.code, d.message, d.span.line) for d in errors] == [("LCNC-WORDS" if "cycle" not in name else
                                                                       "LCNC-CYCLE", *error)]  # fmt: skip


@pytest.mark.skipif(not RS274.exists() or not SIM_TBL.exists(), reason="rs274 not installed")
def test_stored_values_are_rs274s() -> None:
    call = re.compile(r"^\s*\d+\s+N[\d.]+\s+([A-Z_0-9]+)\((.*)\)\s*$")
    for name, (text, feeds, error) in PROGRAMS.items():
        run = run_rs274(text)
        mode, rate, speed, got = 0, 0.0, 0.0, []
        for line in run["out"]:
            m = call.match(line)
            if m is None:
                continue
            args = [a.strip() for a in m.group(2).split(",")]
            if m.group(1) == "SET_FEED_MODE":
                mode = int(args[1])
            elif m.group(1) == "SET_FEED_RATE":
                rate = float(args[0])
            elif m.group(1) == "SET_SPINDLE_SPEED":
                speed = float(args[1])
            elif m.group(1) in ("STRAIGHT_FEED", "ARC_FEED"):
                got.append(rate * speed if mode else rate)
        assert got == pytest.approx(feeds, abs=1e-4), name
        if error is not None:
            assert error[0] in run["out"] + run["err"], name


@pytest.mark.parametrize(
    ("text", "fragment", "line"),
    [
        # LinuxCNC's interpreter runs these at feed 0 (the axes would not move): trcopt cannot time them
        ("G21 G95 F0.05\nG81 X1 Y1 Z-1 R1\nM2\n", "canned cycle under G95", 2),
        ("G21\nG93 G1 X10 F0\nM2\n", "inverse time F0", 2),
    ],
)
def test_moves_that_never_end_are_refused(text: str, fragment: str, line: int) -> None:
    prog = read_rs274(text, file="p.ngc")
    (err,) = [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert err.code == "NC-FEED-MODE" and fragment in err.message and err.span.line == line


def test_m5_does_not_stop_feed_per_revolution_and_the_column_is_the_motion_word() -> None:
    prog = read_rs274("G21 S100 M3 G95 F1\nM5 G1 X1\nS0\nN40 X2 G1\nM2\n", file="p.ngc")
    assert _feeds(prog, 1.0) == [100.0]
    (err,) = [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert (err.span.line, err.span.column, err.span.block) == (4, 8, "N40")


def test_feed_mode_parameters() -> None:
    text = (
        "G21 G95\n#1=#<_units_per_rev>\nG93\n#2=#<_inverse_time>\n#3=#<_units_per_minute>\nG94\n"
        "#4=#<_units_per_minute>\nG1 X#1 Y#2 Z#3 F[100*#4]\nM2\n"
    )
    prog = read_rs274(text, file="p.ngc")
    (move,) = [m for m in prog.moves if m.kind is MoveKind.LINE]
    assert move.end == (1.0, 1.0, 0.0) and move.feed_mm_s * 60.0 == pytest.approx(100.0)


def test_arc_length_of_a_helix_with_turns() -> None:
    prog = read_rs274("G21 G17 G1 X5 F1\nG3 X5 Y0 Z3 I-5 P3\nM2\n", file="p.ngc")
    arc = [m for m in prog.moves if m.kind is MoveKind.ARC][0]
    assert arc_length(arc) == pytest.approx(((3 * 2 * 3.141592653589793 * 5) ** 2 + 9) ** 0.5)


@pytest.mark.skipif(not PEER.is_dir(), reason="LinuxCNC peer data not found")
def test_inverse_time_under_compensation_has_linuxcncs_feeds() -> None:
    """The feed of every move: its programmed length × F, with and without compensation (the corner
    arc LinuxCNC inserts runs at the feed of the move it belongs to)."""
    folder = PEER / "interp-inverse-time-with-comp"
    rate, feeds = 0.0, []
    for line in (folder / "expected").read_text().splitlines():
        if "SET_FEED_RATE(" in line:
            rate = float(line.split("(", 1)[1].rstrip(")"))
        elif "STRAIGHT_FEED(" in line or "ARC_FEED(" in line:
            feeds.append(rate)
    result = plan_file(folder / "inverse.ngc", PlanOptions(dialect="rs274", timing=False, corners="exact"))
    assert result.ok, [d.format() for d in result.errors]
    expected = json.loads((folder / "expected.segments.json").read_text())
    kept = [f for f, e in zip(feeds, [e for e in expected if e["type"] != "rapid"], strict=True)
            if e["start"] != e["end"] or e["type"] == "arc"]  # fmt: skip
    ours = [s.feed_mm_s * 60.0 / 25.4 for s in result.toolpath if s.kind != "rapid"]
    assert ours == pytest.approx(kept, abs=1e-3)


def test_the_written_program_keeps_the_feeds(tmp_path: Path) -> None:
    text = "G21 G17\nS800 M3\nG0 X0 Y0\nG95 G1 X10 F0.25\nS400 Y10\nG93 G2 X0 Y10 R5 F4\nG94 G1 Y0 F150\nM2\n"
    first = plan(text, file="p.ngc", options=PlanOptions(timing=False))
    assert first.ok, [d.format() for d in first.errors]
    feeds = [round(s.feed_mm_s * 60.0, 3) for s in first.toolpath]
    assert feeds == [200.0, 100.0, round(3.141592653589793 * 5 * 4, 3), 150.0]
    from trcopt import controllers
    from trcopt.io.gcode_program import plan_to_gcode

    out = plan_to_gcode(first, flavor=controllers.get("linuxcnc").gcode)
    assert "G95" not in [w for ln in out.splitlines() for w in ln.split("(")[0].split()]
    assert "G95 [feed per revolution" in out and "G93 [inverse time]" in out
    again = plan(out, file="o.ngc", options=PlanOptions(timing=False))
    assert again.ok and [round(s.feed_mm_s * 60.0, 3) for s in again.toolpath] == feeds
