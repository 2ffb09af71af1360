"""Safe tool-centre G-code of a whole plan: the program's non-motion words in
order at the place they act, no invented motion, the alarm and omitted blocks named, the program's
units, each motion traceable; and the round trip — the written program, planned again, gives the
same tool-centre path and the same words in the same order."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from trcopt import PlanOptions, controllers, plan, plan_file
from trcopt.io.gcode_program import kept_words
from trcopt.io.gcode_program import plan_to_gcode as _plan_to_gcode

PROBLEMS = Path(__file__).resolve().parents[2] / "problems"

CAM_SIEMENS = """; CAM-post style program
$TC_DP1[3,1]=120 $TC_DP6[3,1]=4
N5 G54 G17 G90
N10 T3 M6
N15 D1 S8000 M3 M8
N20 MSG("roughing")
N25 G0 X-20 Y-20
N26 Z2
N30 G1 Z-1 F200
N35 G41 X0 Y0 F500
N40 Y40
N45 G4 F1.5
N50 X40 M0
N60 Y0
N70 X0
N80 G40 X-20 Y-20 M5 M9
N85 G0 Z50
N90 M30
"""

CAM_RS274_INCH = """(CAM post, inch)
G20 G17 G90 G40
G54
T2 M6
S12000 M3
M8
G0 X-1 Y-1
G0 Z0.1
G1 Z-0.05 F10
G41.1 D0.25 G1 X0 Y0 F20
G1 Y2
G4 P0.5
G1 X2
G2 X3 Y1 I0 J-1
G1 Y0
G1 X0
G40 G1 X-1 Y-1
M5 M9
G0 Z1
M2
"""

OPTS = PlanOptions(timing=False)


def plan_to_gcode(result, flavor=None, **kw):
    """The writer with the reading controller's flavour unless another is given."""
    return _plan_to_gcode(result, flavor=flavor or controllers.get(result.dialect).gcode, **kw)


def _planned(text: str, file: str, **kw):
    return plan(text, file=file, options=PlanOptions(timing=False, **kw))


def _points(toolpath, n: int = 40) -> np.ndarray:
    pts = []
    for s in toolpath:
        g = s.geometry
        pts += [s.plane.to_xyz(g.point(g.length * k / n)) for k in range(n + 1)]
    return np.array(pts)


def _hausdorff(a, b) -> float:
    pa, pb = _points(a), _points(b)
    d = np.sqrt(((pa[:, None, :] - pb[None, :, :]) ** 2).sum(axis=2))
    return float(max(d.min(axis=1).max(), d.min(axis=0).max()))


def _words(result) -> list[str]:
    blocks = [(m.span.line, m.actions) for m in result.nc.moves]
    blocks += [(span.line, actions) for span, actions in result.nc.extras.get("words", ())]
    return [w for _, actions in sorted(blocks, key=lambda b: b[0]) for w in kept_words(actions)]


def _body(text: str) -> list[str]:
    return [ln for ln in text.splitlines() if not ln.startswith((";", "("))]


def _code(line: str) -> str:
    return re.sub(r"\(.*?\)|;.*$", "", line).strip()


# ------------------------------------------------------------------------------ round trip
@pytest.mark.parametrize(
    ("source", "file", "flavor", "again_file", "decimals"),
    [
        (CAM_SIEMENS, "cam.mpf", "siemens", "out.mpf", 6),
        (CAM_SIEMENS, "cam.mpf", "siemens", "out.mpf", 4),
        (CAM_RS274_INCH, "cam.ngc", "linuxcnc", "out.ngc", 5),
        ((PROBLEMS / "heidenhain" / "h04_appr_dep_lt.h").read_text(), "h04.h", "heidenhain", "out.mpf", 6),
        ((PROBLEMS / "siemens" / "ex06_bottleneck_cdon.mpf").read_text(), "ex06.mpf", "siemens", "out.mpf", 6),
    ],
)
def test_the_written_program_replans_to_the_same_path_and_words(source, file, flavor, again_file, decimals) -> None:
    first = _planned(source, file)
    text = plan_to_gcode(first, flavor=controllers.get(flavor).gcode, decimals=decimals)
    # the written program is read as it is (a Heidenhain plan is written as ISO G-code)
    again = _planned(text, again_file, corners="exact")
    assert again.ok, [d.format() for d in again.errors]
    inch = "G20" in text.split("\n", 4)[3] or "G70" in text
    written = 0.5 * 10.0**-decimals * (25.4 if inch else 1.0) * math.sqrt(3)
    assert _hausdorff(first.toolpath, again.toolpath) <= max(1e-6, written)
    assert again.path_length == pytest.approx(first.path_length, abs=max(1e-6, 10 * written))
    assert _words(again) == _words(first)


# ------------------------------------------------------------------------------ 1. words
def test_non_motion_words_are_written_in_order_where_they_act() -> None:
    text = plan_to_gcode(_planned(CAM_SIEMENS, "cam.mpf"))
    code = [ln.split(";")[0].strip() for ln in _body(text)]  # MSG("…") has parentheses
    stripped = [re.sub(r"^N\d+ ", "", c) for c in code]
    idx = {c: i for i, c in enumerate(stripped)}
    first_motion = next(i for i, c in enumerate(stripped) if re.match(r"G[0-3] ", c))
    # tool change, spindle, coolant, work offset and message before the first motion, in order
    assert idx["G54"] < idx["T3 M6"] < idx["D1 S8000 M3 M8"] < idx['MSG("roughing")'] < first_motion
    # the dwell between the motions of N40 and N50
    assert stripped[idx["G4 F1.5"] - 1] == "G1 Y40"
    # M0 acts at the end of its block N50: after the motion of N50, before the motions of N60
    assert stripped[idx["M0"] - 1] == "G1 X40" and "N50" in _body(text)[idx["M0"]]
    # M5 M9 after the retract of their block N80, before the rapid of N85
    assert stripped[idx["M5 M9"] - 1] == "G1 X-20 Y-20" and stripped[idx["M5 M9"] + 1] == "G0 Z50"
    assert stripped[-1] == "M30" and stripped.count("M30") == 1


def test_the_words_of_a_heidenhain_tool_call_and_stop_are_kept() -> None:
    source = (PROBLEMS / "heidenhain" / "h04_appr_dep_lt.h").read_text().replace(
        "5 L X+0 Y+40", "5 L X+0 Y+40 M8\n5 STOP M5"
    )
    text = plan_to_gcode(_planned(source, "h.h"))
    code = [re.sub(r"^N\d+ ", "", _code(ln)) for ln in _body(text)]
    assert code[1] == "T1 S3000"  # TOOL CALL 1 Z S3000, before the first motion
    assert "M8" in code and "M0 M5" in code and code.index("M8") < code.index("M0 M5")


def test_words_another_flavour_cannot_read_become_comments() -> None:
    text = plan_to_gcode(_planned(CAM_SIEMENS, "cam.mpf"), flavor=controllers.get("linuxcnc").gcode)
    assert "(MSG, roughing)" in text.splitlines()
    assert "G4 P1.5 (N45 L12)" in text.splitlines()
    assert "(L2 not written in linuxcnc G-code: $TC_DP1[3,1]=120)" in text.splitlines()
    assert "T3 M6 (N10 L4)" in text.splitlines() and "S8000 M3 M8 (N15 L5)" in text.splitlines()


def test_the_program_path_control_is_a_comment_not_a_second_rounding() -> None:
    source = CAM_SIEMENS.replace("N5 G54 G17 G90", "N5 G54 G17 G90 G642 ADIS=0.5")
    text = plan_to_gcode(_planned(source, "cam.mpf"))
    assert "ADIS" not in "".join(_code(ln) for ln in text.splitlines())
    assert "; N5 L3 path control G642 ADIS=0.5: its rounding is in the tool-centre path" in text


# ------------------------------------------------------------------------------ 2. no invented motion
def test_no_motion_the_program_did_not_command() -> None:
    text = plan_to_gcode(plan_file(PROBLEMS / "siemens" / "ex02_square_g450.mpf", OPTS))
    assert "X0 Y0 Z0" not in text and "start of path" not in text
    motions = [_code(ln) for ln in _body(text) if re.search(r" G[0-3] ", ln)]
    assert motions[0] == "N60 G0 X-20 Y-20 Z0"  # N10 … G0 X-20 Y-20 Z0, as programmed


def test_an_axis_the_program_has_not_moved_is_not_written() -> None:
    source = "N10 T1 D1 S1000 M3\nN20 G0 Z50\nN30 G0 X10\nN40 G1 Z-1 F300\nN50 X20\nN60 M30\n"
    text = plan_to_gcode(_planned(source, "p.mpf"))
    motions = [re.sub(r"^N\d+ ", "", _code(ln)) for ln in _body(text) if re.search(r" G[0-3] ", ln)]
    # Y is never programmed: never written (the machine keeps its Y)
    assert motions == ["G0 Z50", "G0 X10", "G1 Z-1 F300", "G1 X20"]


# ------------------------------------------------------------------------------ 3. alarm, omitted blocks
def test_a_program_stopped_by_an_alarm_ends_with_a_comment_naming_it() -> None:
    result = plan_file(PROBLEMS / "heidenhain" / "h02_pocket_r16_too_large.h", OPTS)
    assert not result.ok
    text = plan_to_gcode(result)
    lines = text.splitlines()
    assert not any(re.search(r"\bM(30|2|02)\b", _code(ln)) for ln in lines)
    alarm = result.errors[0]
    assert alarm.code in lines[-2] and alarm.message in lines[-2]
    assert f"h02_pocket_r16_too_large.h:{alarm.span.line}:" in lines[-2]


def test_omitted_blocks_are_named() -> None:
    result = plan_file(PROBLEMS / "siemens" / "ex06_bottleneck_cdon.mpf", OPTS)
    omitted = [d for d in result.diagnostics if d.code == "10763"]
    assert omitted
    text = plan_to_gcode(result)
    for d in omitted:
        note = next(ln for ln in text.splitlines() if "omitted block" in ln and f"{d.span.block} L{d.span.line}" in ln)
        assert "10763" in note


def test_transitions_name_their_source_block() -> None:
    result = plan_file(PROBLEMS / "corners" / "corner_30deg.mpf", PlanOptions(timing=False, corners="arc"))
    assert result.extra["corners"]["blended"] > 0
    text = plan_to_gcode(result)
    corners = [ln for ln in text.splitlines() if re.search(r"; N\d+ L\d+ corner$", ln)]
    assert len(corners) >= result.extra["corners"]["blended"]


# ------------------------------------------------------------------------------ 4. units
@pytest.mark.parametrize(
    ("source", "file", "unit_word", "feed"),
    [
        (CAM_RS274_INCH, "p.ngc", "G20", "F20.0"),
        (CAM_SIEMENS.replace("N5 G54 G17 G90", "N5 G54 G17 G90 G700"), "p.mpf", "G700", "F500"),
        (CAM_SIEMENS.replace("N5 G54 G17 G90", "N5 G54 G17 G90 G70"), "p.mpf", "G70", "F500"),
    ],
)
def test_an_inch_program_is_written_in_inch(source, file, unit_word, feed) -> None:
    result = _planned(source, file)
    text = plan_to_gcode(result)
    assert _body(text)[0].split()[:2] in ([unit_word, "G90"], ["N10", unit_word])
    assert feed in text  # G70 keeps feeds in mm/min, G700 and G20 have them in inch/min
    again = _planned(text, "again" + Path(file).suffix, corners="exact")
    assert _hausdorff(result.toolpath, again.toolpath) < 0.5e-5 * 25.4 * math.sqrt(3)


# ------------------------------------------------------------------------------ 5. traceability
def test_every_motion_names_its_source_line_or_continues_a_named_one() -> None:
    result = _planned(CAM_SIEMENS, "cam.mpf")
    text = plan_to_gcode(result)
    source = CAM_SIEMENS.splitlines()
    named = 0
    for ln in _body(text):
        m = re.search(r"; (N\d+ )?L(\d+)", ln)
        if re.search(r" G[0-3] ", ln):
            assert m is not None or named  # a piece of a segment follows its named first piece
        if m:
            named += 1
            block, line = m.group(1), int(m.group(2))
            if block:
                assert source[line - 1].startswith(block.strip())
    assert named


def test_the_command_line_writes_the_safe_program(tmp_path: Path) -> None:
    from trcopt.cli import main

    program = tmp_path / "cam.mpf"
    program.write_text(CAM_SIEMENS)
    out = tmp_path / "out.mpf"
    main(["plan", str(program), "--no-timing", "-q", "--gcode", str(out)])
    text = out.read_text()
    assert "N60 T3 M6 ; N10 L4" in text and "D1 S8000 M3 M8" in text and "X0 Y0 Z0" not in text


# ------------------------------------------------------------------------------ grbl
def test_the_grbl_flavour_is_plain_iso_that_replans_to_the_same_path() -> None:
    """grbl output: no block numbers, no path-control or tool-change words, parenthesised comments,
    arcs with incremental centres; read back as RS274NGC it gives the same tool-centre path."""
    from trcopt.io.flavors import GRBL

    first = _planned(CAM_SIEMENS, "cam.mpf")
    text = plan_to_gcode(first, flavor=GRBL, dialect="grbl", decimals=6)
    codes = [c for c in (_code(ln) for ln in text.splitlines()) if c]
    assert codes[0].split() == ["G21", "G90", "G94", "G40", "G17"]
    assert codes[-1] == "M2"
    assert not any(re.match(r"N\d", c) for c in codes)
    assert not any(re.search(r"\b(M0*6|T\d+|G64|G642|CTOL|D\d|G91\.1)\b", c) for c in codes), codes
    assert not any(";" in ln for ln in text.splitlines())
    # the tool change is a spindle stop and a program stop, named in a comment
    stop = next(i for i, ln in enumerate(text.splitlines()) if _code(ln) == "M5 M0")
    assert "tool change T3 M6" in text.splitlines()[stop - 1]
    # the program's words grbl reads, in order
    kept = [w for c in codes for w in c.split() if re.fullmatch(r"(M\d+|S\d+|G54)", w)]
    assert kept == ["G54", "M5", "M0", "S8000", "M3", "M8", "M0", "M5", "M9", "M2"]
    again = _planned(text, "out.ngc", corners="exact")
    assert again.ok, [d.format() for d in again.errors]
    assert _hausdorff(first.toolpath, again.toolpath) <= 1e-5
    assert again.path_length == pytest.approx(first.path_length, abs=1e-5)


def test_the_command_line_writes_grbl(tmp_path: Path) -> None:
    from trcopt.cli import main

    out = tmp_path / "p.nc"
    prog = PROBLEMS / "siemens" / "ex17_cam_post.mpf"
    assert main(["plan", str(prog), "--no-timing", "-q", "--gcode", str(out), "--gcode-flavor", "grbl"]) == 0
    text = out.read_text()
    assert "G0 G53 Z0.0" in text  # the SUPA retract stays in machine coordinates
    assert "M5 M0" in text and text.rstrip().endswith("M2")


def test_a_linuxcnc_message_is_written_as_a_message_comment() -> None:
    first = _planned("G21 G90\nG0 X0 Y0 Z5\n(MSG, profile with T1)\nG1 X10 F100\nM2\n", "m.ngc")
    text = plan_to_gcode(first, decimals=4)
    assert "(MSG, profile with T1)" in text.splitlines() and 'MSG("' not in text
    again = _planned(text, "again.ngc", corners="exact")
    assert again.ok, [d.format() for d in again.errors]


def test_the_linuxcnc_cam_post_program_replans_with_its_machine_moves(tmp_path: Path) -> None:
    """The Fusion-style LinuxCNC program (work offsets, G28 retracts, a drilling cycle, G43): its
    output starts with no move the program did not command, keeps the G28 retracts as G53 moves and
    re-plans (on the same machine settings) to the same path and words."""
    folder = PROBLEMS / "rs274"
    for name in ("rs274ngc.toml", "tools.tbl"):
        (tmp_path / name).write_text((folder / name).read_text())
    src = folder / "cam_fusion_drill_profile.ngc"
    first = plan_file(src, PlanOptions(timing=False))
    assert first.ok
    text = plan_to_gcode(first, decimals=4)
    codes = [c for c in (_code(ln) for ln in text.splitlines()) if c]
    first_move = next(c for c in codes if re.match(r"G[0123]\b", c))
    assert first_move == "G0 X10.0 Y10.0"  # the program's first motion, from where it starts
    assert "G0 G53 Z0.0" in codes
    out = tmp_path / "out.ngc"
    out.write_text(text)
    again = plan_file(out, PlanOptions(timing=False, corners="exact"))
    assert again.ok, [d.format() for d in again.errors]
    assert _hausdorff(first.toolpath, again.toolpath) <= 1e-4
    assert _words(again) == _words(first)


def test_the_linuxcnc_tool_length_offset_is_written_where_it_acts(tmp_path: Path) -> None:
    """The tool-centre coordinates are the tool tip's: the program's G43 H…/G49 are written where
    they act (a machine without them would run each tool its length too deep); its work systems
    are comments, their offsets being in the coordinates already."""
    folder = PROBLEMS / "rs274"
    for name in ("rs274ngc.toml", "tools.tbl"):
        (tmp_path / name).write_text((folder / name).read_text())
    first = plan_file(folder / "cam_fusion_drill_profile.ngc", PlanOptions(timing=False))
    text = plan_to_gcode(first, decimals=4)
    codes = [c for c in (_code(ln) for ln in text.splitlines()) if c]
    order = [c for c in codes if re.match(r"(T\d|G43|G49|G0 Z15\.0|M9)", c)]
    assert order == [
        "T2 M6", "G43 H2", "G0 Z15.0", "G0 Z15.0", "M9", "G49", "T1 M6", "G43 H1", "G0 Z15.0", "G0 Z15.0", "M9", "G49",
    ]
    assert not any(re.search(r"\bG5[4-9]\b", c) for c in codes)  # not a second shift
    assert "(L15 work system G54: its offset is in the coordinates [those of the start's work system])" in text
    assert "(L10 path control G64 P0.01: its rounding is in the tool-centre path)" in text
    out = tmp_path / "out.ngc"
    out.write_text(text)
    again = plan_file(out, PlanOptions(timing=False, corners="exact"))
    assert again.ok and _hausdorff(first.toolpath, again.toolpath) <= 1e-4
    # written once more, the words are the same: none lost, none added
    twice = [c for c in (_code(ln) for ln in plan_to_gcode(again, decimals=4).splitlines()) if c]
    assert [c for c in twice if re.match(r"(T\d|G43|G49|M\d|S\d)", c)] == [
        c for c in codes if re.match(r"(T\d|G43|G49|M\d|S\d)", c)
    ]


@pytest.mark.parametrize(
    ("block", "words", "notes"),
    [
        ("g 4 3 h 2 (tool 2)", ["G43 H2"], []),
        ("G43.1 Z-1.5", ["G43.1 Z-1.5"], []),
        ("N20 G49 M5", ["G49"], []),
        ("G43 H#1", [], ["tool length offset G43 with a computed value: not written, set it by hand"]),
        ("G55 G0 X1", [], ["work system G55: its offset is in the coordinates (those of the start's work system)"]),
        ("G92 X10", [], ["axis offset G92: its offset is in the coordinates"]),
        ("G64 P0.02 Q0.01", ["G64 P0.02 Q0.01"], []),
        ("(G43 H2 in a comment) G1 X1", [], []),
        ("o100 if [#1 GT 43]", [], []),
    ],
)
def test_the_words_the_linuxcnc_reader_resolves_are_read_from_the_block(block, words, notes) -> None:
    from trcopt.io.ngc_source_words import source_words

    assert source_words(block) == (words, notes)
    if words:  # a word the reader kept itself is not added again
        assert source_words(block, actions=(words[0],)) == (words[1:], notes)


def test_a_plan_made_window_by_window_writes_the_tool_length_offset_too(tmp_path: Path) -> None:
    from trcopt.cli import main

    (tmp_path / "tools.tbl").write_text("T1 P1 D6.0 Z50 ;6 mm end mill\n")
    prog = tmp_path / "p.ngc"
    prog.write_text(
        "G21 G90 G17\nG54\nT1 M6\nG43 H1\nS1000 M3\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nG1 Y10\nG49\nG0 Z50\nM2\n"
    )
    texts = {}
    for mode in ("on", "off"):
        out = tmp_path / f"{mode}.ngc"
        assert main(["plan", str(prog), "--no-timing", "-q", "--stream", mode, "--gcode", str(out)]) == 0
        texts[mode] = out.read_text()
    assert texts["on"] == texts["off"]
    codes = [c for c in (_code(ln) for ln in texts["on"].splitlines()) if c]
    assert codes.index("T1 M6") < codes.index("G43 H1") < codes.index("G0 X0.0 Y0.0 Z5.0")
    assert codes.index("G1 Y10.0") < codes.index("G49") < codes.index("G0 Z50.0")


def test_the_text_is_scanned_for_those_words_only_in_a_program_without_o_word_flow() -> None:
    from trcopt.io.ngc_source_words import resolved_lines

    flat = ["G21", "T1 M6", "G43 H1 (length)", "G0 X0", "(G49 in a comment)", "G49", "G0 Z5 G55", "M2"]
    assert resolved_lines(flat) == [3, 6, 7]
    assert resolved_lines(flat, last=5) == [3]  # not after the alarm that stopped the program
    assert resolved_lines([*flat[:4], "o1 if [#1 GT 0]", "G43 H2", "o1 endif", "M2"]) == []
    assert resolved_lines([*flat, "G43 H3"]) == [3, 6, 7]  # not after the program end


@pytest.mark.parametrize(
    ("text", "dialect", "comments"),
    [
        ("(Drill1)", "rs274", ["Drill1"]),
        ("G0 X1 (first) Y2 (second; still) ; the rest", "rs274", ["first", "second; still", "the rest"]),
        ("(MSG, profile with T1)", "rs274", []),  # an active comment: the reader's message
        ("(debug, #1)", "rs274", []),
        ('N20 MSG("A;B") ; op 1', "siemens", ["op 1"]),
        ("N30 G1 X1 ;", "siemens", []),
        ("3 * - CONTOUR 80 X 50", "heidenhain", ["CONTOUR 80 X 50"]),
        ("12 Q1 = 80 ; width", "heidenhain", ["width"]),
        ("5 L X+1 R0 F100", "heidenhain", []),
        ("; a comment of a dialect trcopt does not know", "toy", []),
    ],
)
def test_the_comments_of_a_program_line(text: str, dialect: str, comments: list[str]) -> None:
    from trcopt.io.program_comments import program_comments

    assert program_comments(text, dialect) == comments


def test_the_programs_comments_are_kept_at_their_place() -> None:
    first = plan_file(PROBLEMS / "rs274" / "cam_fusion_drill_profile.ngc", PlanOptions(timing=False))
    lines = plan_to_gcode(first, decimals=4).splitlines()
    at = {ln: i for i, ln in enumerate(lines)}
    assert at["(L12: Drill1)"] < at["T2 M6 (L13)"] < at["(L31: 2D Contour1)"] < at["(MSG, profile with T1)"]
    assert at["(L4: T1  D=6. CR=0. - ZMIN=-5. - flat end mill)"] < at["(L12: Drill1)"]
    assert not any("L32:" in ln for ln in lines)  # the message is written once, as a message
    siemens = plan_to_gcode(_planned(CAM_SIEMENS, "cam.mpf")).splitlines()
    assert siemens.index("; L1: CAM-post style program") < next(i for i, ln in enumerate(siemens) if "T3 M6" in ln)
    # a comment after the last motion (after an alarm, after the end) is not written
    tail = _planned("N10 G0 X0 Y0 Z5\nN20 G1 X10 F100\nN30 M30\n; after the end\n", "t.mpf")
    assert "after the end" not in plan_to_gcode(tail)
