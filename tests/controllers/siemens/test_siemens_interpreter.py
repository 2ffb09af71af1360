"""SINUMERIK modal interpreter: arcs in every plane, units, modes, tool data, diagnostics."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from trcopt.config import Tolerances
from trcopt.controllers import read_program
from trcopt.errors import Severity
from trcopt.geometry.plane import Plane
from trcopt.modes import Side
from trcopt.nc import MoveKind, ToolEdge
from trcopt.nc.modal import arc_centre_from_radius


def read(text, **kw):
    return read_program(text + "\nM30\n", file="t.mpf", **kw)


def only_moves(text, **kw):
    prog = read(text, **kw)
    errs = [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert errs == [], [d.format() for d in errs]
    return [m for m in prog.moves if m.actions != ("M30",)]


def error_of(text, **kw):
    prog = read_program(text, file="t.mpf", **kw)
    errs = [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert len(errs) == 1, [d.format() for d in prog.diagnostics]
    return prog, errs[0]


# ---------------------------------------------------------------- arcs
def test_g17_arc_i_j_incremental():
    (m,) = only_moves("G3 X0 Y10 I0 J5 F100")
    assert m.kind is MoveKind.ARC and m.ccw is True and m.plane is Plane.G17
    assert m.center == pytest.approx((0.0, 5.0, 0.0))


def test_a_rounded_centre_is_corrected_onto_the_chords_bisector():
    # the end radius differs by 0.0005 mm (within 0.002): the control keeps the end point and
    # moves the centre so that the circle runs through both points
    (m,) = only_moves("G3 X0 Y10 I0.0004 J5.0003 F100")
    cu, cv, _ = m.center
    assert math.hypot(cu, cv) == pytest.approx(math.hypot(cu - 0.0, cv - 10.0), abs=1e-12)
    assert cv == pytest.approx(5.0, abs=1e-12) and cu == pytest.approx(0.0004, abs=1e-12)
    from trcopt.pipeline import plan

    result = plan("G17 G0 X0 Y0\nG1 X10 F100\nG3 X10 Y20 I0.0004 J10.0003\nG1 X0\nM30", file="t.mpf")
    assert result.ok and not result.warnings and result.verification.ok
    (arc,) = [s for s in result.toolpath if s.kind == "arc"]
    assert arc.geometry.point2(1.0) == pytest.approx((10.0, 20.0), abs=1e-12)


def test_g18_arc_uses_k_and_i():
    moves = only_moves("G0 Z10\nG18 G3 X10 Z0 I0 K-10 F100\nG2 X0 Z-10 K0 I-10")
    a, b = moves[1], moves[2]
    assert a.plane is Plane.G18 and a.ccw is True
    assert a.start == (0.0, 0.0, 10.0) and a.end == (10.0, 0.0, 0.0)
    assert a.center == pytest.approx((0.0, 0.0, 0.0))
    # (u, v) = (Z, X): start (10, 0), end (0, 10) → counter-clockwise quarter
    assert b.ccw is False and b.center == pytest.approx((0.0, 0.0, 0.0))
    assert b.end == (0.0, 0.0, -10.0)


def test_g19_arc_uses_j_and_k():
    moves = only_moves("G0 Y10\nG19 G3 Y0 Z10 J-10 K0 F100")
    arc = moves[1]
    assert arc.plane is Plane.G19 and arc.ccw is True
    assert arc.center == pytest.approx((0.0, 0.0, 0.0))
    assert arc.end == (0.0, 0.0, 10.0)


@pytest.mark.parametrize(
    ("words", "centre", "ccw"),
    [
        ("G2 X10 Y10 CR=10", (10.0, 0.0), False),
        ("G2 X10 Y10 CR=-10", (0.0, 10.0), False),
        ("G3 X10 Y10 CR=10", (0.0, 10.0), True),
        ("G3 X10 Y10 CR=-10", (10.0, 0.0), True),
        ("G2 X10 Y0 CR=5", (5.0, 0.0), False),
    ],
)
def test_cr_both_signs(words, centre, ccw):
    (m,) = only_moves(words + " F100")
    assert m.center[:2] == pytest.approx(centre)
    assert m.ccw is ccw


def test_cr_too_small_is_an_error():
    prog, err = error_of("N10 G2 X10 Y0 CR=4 F100")
    assert err.code == "NC-ARC-RADIUS" and err.span.column == 15 and err.span.block == "N10"


def test_i_ac_absolute_centre():
    moves = only_moves("G0 X2 Y0\nG3 X8 Y0 I=AC(5) J=AC(0) F100")
    assert moves[1].center == pytest.approx((5.0, 0.0, 0.0))
    moves = only_moves("G0 X2 Y0\nG3 X8 Y0 I=IC(3) F100")
    assert moves[1].center == pytest.approx((5.0, 0.0, 0.0))


def test_full_circle_with_i_only():
    moves = only_moves("G0 X0 Y0\nG2 I10 F100\nG3 X0 Y0 I10")
    for m in moves[1:]:
        assert m.kind is MoveKind.ARC and m.start == m.end == (0.0, 0.0, 0.0)
        assert m.center == pytest.approx((10.0, 0.0, 0.0))


def test_helix_centre_at_start_applicate():
    (m,) = only_moves("G3 X0 Y10 Z-5 I0 J5 F100")
    assert m.kind is MoveKind.ARC and m.end == (0.0, 10.0, -5.0)
    assert m.center == pytest.approx((0.0, 5.0, 0.0))
    (t,) = only_moves("G2 I5 Z-2 TURN=2 F100")
    assert t.turns == 2 and t.end == (0.0, 0.0, -2.0)


def test_arc_radius_mismatch_error_with_span():
    text = "N10 G1 X0 Y0 F100\nN20 G1 X0\nN60 G2 X10 Y1 I5 J0\nN70 X20\nM30\n"
    prog, err = error_of(text)
    assert err.code == "NC-ARC-RADIUS"
    assert err.span.line == 3 and err.span.column == 15 and err.span.block == "N60"
    assert "5.0000" in err.message and "5.0990" in err.message
    assert [m.span.block for m in prog.moves] == ["N10", "N20"]


def test_arc_tolerance_is_configurable():
    text = "G2 X10 Y0.5 I5 J0 F100"
    assert error_of(text)[1].code == "NC-ARC-RADIUS"
    only_moves(text, tolerances=Tolerances(arc_end_radius_mm=0.05))


def test_arc_without_centre_is_an_error():
    assert error_of("G2 X10 Y10 F100")[1].code == "NC-ARC-CENTRE"


# ---------------------------------------------------------------- positions and units
def test_g91_and_per_word_ac_ic():
    moves = only_moves("G91 X10 Y5 F100\nX10 Y5\nX=AC(3) Z-1\nG90 X=IC(2) Y7")
    assert [m.end for m in moves] == [
        (10.0, 5.0, 0.0), (20.0, 10.0, 0.0), (3.0, 10.0, -1.0), (5.0, 7.0, -1.0)
    ]  # fmt: skip


def test_g70_inch_geometry_g700_inch_feed():
    moves = only_moves("G70 X1 Y=2 F60\nG71 X10\nG700 X1 F60\nG710 F60")
    assert moves[0].end == pytest.approx((25.4, 50.8, 0.0))
    assert moves[0].feed_mm_s == pytest.approx(1.0)  # G70: feed stays mm/min
    assert moves[1].end == (10.0, 50.8, 0.0)
    assert moves[2].end[0] == pytest.approx(25.4) and moves[2].feed_mm_s == pytest.approx(25.4)
    assert moves[3].feed_mm_s == pytest.approx(1.0)


def test_plane_programmed_follows_active_plane():
    moves = only_moves("G0 Z5\nY3\nG18 Z7\nY4\nG19 X1")
    assert [m.plane_programmed for m in moves] == [False, True, True, False, False]
    assert moves[0].kind is MoveKind.RAPID and moves[0].feed_mm_s is None


def test_words_may_touch_and_case_does_not_matter():
    (m,) = only_moves("n5 g1x10y-2.5f120")
    assert m.end == (10.0, -2.5, 0.0) and m.feed_mm_s == pytest.approx(2.0)
    assert m.span.block == "N5" and m.span.column == 4


def test_block_skip_is_executed_and_labels_kept():
    moves = only_moves("/N10 G1 X5 F60\nSTART: X6")
    assert moves[0].end == (5.0, 0.0, 0.0)
    assert moves[1].actions == ("START:",) and moves[1].end == (6.0, 0.0, 0.0)


def test_g4_f_is_dwell_not_feed():
    moves = only_moves("G1 X1 F600\nG4 F2\nX2")
    assert moves[2].feed_mm_s == pytest.approx(10.0)


# ---------------------------------------------------------------- tools and compensation state
def test_tool_radius_wear_offn():
    text = "$TC_DP1[3,2]=120 $TC_DP6[3,2]=5 $TC_DP15[3,2]=-0.1\nT3 D2 OFFN=0.5\nG41 G1 X10 F100"
    moves = only_moves(text)
    assert moves[2].comp.radius == pytest.approx(5.4) and moves[2].comp.tool_active
    assert moves[2].comp.effective_side is Side.LEFT


def test_negative_offn_swaps_effective_side():
    moves = only_moves("T1 D1 OFFN=-7\nG41 X1 F100", tools={(1, 1): {"radius": 5}})
    assert moves[1].comp.radius == pytest.approx(-2.0)
    assert moves[1].comp.effective_side is Side.RIGHT


def test_d0_and_edges_without_data():
    moves = only_moves("T1 D0\nT1 D1\nD2\nT4", tools={(1, 1): ToolEdge(120, 3.0)})
    assert (moves[0].comp.tool_active, moves[0].comp.radius) == (True, 0.0)
    assert (moves[1].comp.tool_active, moves[1].comp.radius) == (True, 3.0)
    assert moves[2].comp.tool_active is False
    assert moves[3].comp.tool_active is False


def test_program_tool_data_overrides_preset():
    moves = only_moves("$TC_DP6[1,1]=8\nT1 D1", tools={(1, 1): {"type": 120, "radius": 5}})
    assert moves[1].comp.radius == 8.0


@pytest.mark.parametrize("tool_type", [220, 500, 410])
def test_unsupported_tool_type_for_trc(tool_type):
    text = f"$TC_DP1[2,1]={tool_type} $TC_DP6[2,1]=3\nN20 T2 D1\nN30 G1 G42 X10 F100\nM30"
    prog, err = error_of(text)
    assert err.code == "NC-TOOL-TYPE" and "unsupported tool type for TRC" in err.message
    assert err.span.line == 3 and err.span.column == 8 and err.span.block == "N30"
    assert len(prog.moves) == 2


def test_modal_compensation_words():
    moves = only_moves("G451 DISC=20 KONTC CDON G462 G41 X1 F100\nG450 NORM CDOF2 G40 X2")
    c0, c1 = moves[0].comp, moves[1].comp
    assert (c0.corner.value, c0.disc, c0.approach.value, c0.collision.value, c0.strategy.value) == (
        "G451",
        20,
        "KONTC",
        "CDON",
        "G462",
    )
    assert (c1.corner.value, c1.approach.value, c1.collision.value) == ("G450", "NORM", "CDOF2")
    assert c1.disc == 20 and c1.side is Side.OFF and c1.side_programmed


def test_disc_clamped_with_warning():
    prog = read("N10 DISC=80")
    assert prog.moves[0].comp.disc == 50
    (w,) = [d for d in prog.diagnostics if d.code == "NC-DISC-CLAMPED"]
    assert w.severity is Severity.WARNING and w.span.column == 5
    assert read("DISC=80", max_disc=100).moves[0].comp.disc == 80


def test_plane_change_with_trc_active_raises_10757():
    text = "T1 D1\nN20 G41 G1 X10 F100\nN30 G18 X20\nM30"
    prog, err = error_of(text, tools={(1, 1): {"radius": 2}})
    assert err.alarm == 10757 and err.code == "10757"
    assert err.span.line == 3 and err.span.column == 5 and err.span.block == "N30"
    assert len(prog.moves) == 2
    only_moves("G41 X1 F100\nG17 X2\nG40 X3\nG18 X4")  # same plane / after G40: fine


def test_feed_per_revolution_is_f_times_s():
    prog = read("S1000 M3\nG95 G1 X1 F0.2")
    assert prog.diagnostics == ()
    assert prog.moves[1].feed_mm_s == pytest.approx(0.2 * 1000 / 60)
    prog, err = error_of("G95 G1 X1 F0.2")  # no spindle speed: no path feed
    assert err.code == "NC-FEED-MODE" and prog.moves == ()


def test_a_feed_move_without_any_f_is_alarm_10860():
    prog, err = error_of("G0 X5\nG1 X1\nX2")
    assert err.alarm == 10860 and err.span.line == 2 and "no feedrate programmed" in err.message
    assert len(prog.moves) == 1  # the rapid before it
    prog, err = error_of("G0 X0 Y0 Z5\nCYCLE81(10, 0, 2, -5)")  # a drilling cycle's feed moves as well
    assert err.alarm == 10860
    assert read("G0 X5\nG1 X1 F100\nX2").diagnostics == ()  # F in force from the block on


# ---------------------------------------------------------------- SAR words
def test_sar_words_forms_and_block_locality():
    moves = only_moves(
        "G1 F100 G341 G141\nG147 DISR=2 DISCL=AC(5) DISRP=3 FAD=PM(600) X10\nX20\n"
        "G248 DISR=4 DISRP=AC(50) FAD 120 Z5"
    )
    s = moves[1].sar
    assert (s.disr, s.discl, s.disrp, s.fad) == (2.0, (5.0, True), (3.0, False), (10.0, "PM"))
    assert s.side.value == "G141" and s.segmentation.value == "G341"
    assert s.end_programmed == (True, False, False)
    assert moves[2].sar is None
    s3 = moves[3].sar
    assert s3.contour.value == "G248" and s3.disrp == (50.0, True) and s3.fad == (2.0, "")
    assert s3.discl is None and s3.end_programmed == (False, False, True)


def test_two_sar_words_in_one_block_raise_10743():
    prog, err = error_of("N10 G1 F100\nN20 G147 G247 DISR=3 X5\nM30")
    assert err.alarm == 10743 and err.span.column == 10 and err.span.block == "N20"


def test_sar_parameter_without_sar_word_warns():
    prog = read("G1 X1 F100 DISR=5")
    assert [d.code for d in prog.diagnostics] == ["NC-SAR-PARAM"]


def test_fad_pr_is_converted_with_the_spindle_speed():
    prog = read("S600 M4 G147 DISR=2 FAD=PR(0.1) X10 F100")
    assert prog.moves[0].sar.fad == (pytest.approx(0.1 * 600 / 60), "PR")
    assert prog.diagnostics == ()


# ---------------------------------------------------------------- toolholder data
def test_toolholder_data_collected():
    text = (
        '$TC_CARR1[1]=0 $TC_CARR23[1]="T"\n$TC_CARR13[1]=30 $TC_CARR7[2]=1\n'
        "N30 TCARR=1 TCOABS\nN40 TCOFR\nN50 TCARR=0\nM30"
    )
    prog = read_program(text)
    assert [d for d in prog.diagnostics] == []
    assert prog.extras["carriers"] == {1: {1: 0.0, 23: "T", 13: 30.0}, 2: {7: 1.0}}
    events = prog.extras["toolholder_events"]
    assert events == [
        {"line": 3, "block": "N30", "word": "TCARR", "value": 1},
        {"line": 3, "block": "N30", "word": "TCOABS", "value": None},
        {"line": 4, "block": "N40", "word": "TCOFR", "value": None},
        {"line": 5, "block": "N50", "word": "TCARR", "value": 0},
    ]
    assert prog.moves[2].actions == ("TCARR=1", "TCOABS")


# ---------------------------------------------------------------- diagnostics and program end
def test_truncated_word_at_end_of_file():
    prog, err = error_of("N10 G1 X10 F100\nN20 Y5 X")
    assert err.code == "NC-SYNTAX" and "X without a value" in err.message
    assert (err.span.line, err.span.column, err.span.block) == (2, 8, "N20")
    assert len(prog.moves) == 1 and prog.moves[0].end == (10.0, 0.0, 0.0)


def test_syntax_error_column():
    prog, err = error_of("N10 G1 X10 F100\nN20 G1 Y1.2.3\nM30")
    assert err.code == "NC-SYNTAX" and (err.span.line, err.span.column) == (2, 8)
    assert err.span.block == "N20" and "1.2.3" in err.message
    assert error_of("G1 X=AC(5 F100")[1].span.column == 4
    assert error_of("G1 X5 # F100")[1].span.column == 7
    assert error_of("$FOO X1")[1].code == "NC-SYNTAX"


def test_unknown_word_warns_and_is_kept():
    prog = read("N10 G1 X1 F100 G64 SOFT G54")
    warns = [d for d in prog.diagnostics if d.code == "NC-UNSUPPORTED-WORD"]
    assert [w.span.column for w in warns] == [20]  # G64 (path control) and G54 (zero offset) are modelled
    assert all(w.severity is Severity.WARNING for w in warns)
    assert "SOFT" in warns[0].message
    assert prog.moves[0].control.word == "G64"
    assert prog.moves[0].actions == ("F100", "G64", "SOFT", "G54")
    assert prog.moves[0].end == (1.0, 0.0, 0.0)


def test_geometry_changing_words_stop_the_program():
    assert error_of("CTRANS(X,10)\nM30")[1].code == "NC-UNSUPPORTED"
    assert error_of("G1 X=$AA_IW[X]+2 F100\nM30")[1].code == "NC-UNSUPPORTED-EXPR"
    assert error_of("G33 Z-10 K1\nM30")[1].code == "NC-UNSUPPORTED"


def test_cut2df_warns():
    prog = read("CUT2DF")
    assert [d.code for d in prog.diagnostics] == ["NC-UNSUPPORTED-WORD"]
    assert read("CUT2D").diagnostics == ()


def test_program_end_stops_reading_and_missing_end_warns():
    prog = read_program("G1 X1 F100\nM30\nthis is not NC ###\n")
    assert prog.diagnostics == () and len(prog.moves) == 2 and prog.blocks == 2
    prog = read_program("G1 X1 F100\nM17\nX5\n")
    assert len(prog.moves) == 2
    prog = read_program("G1 X1 F100\n; comment only\n\n")
    (w,) = prog.diagnostics
    assert w.code == "NC-NO-END" and w.severity is Severity.WARNING
    assert "no end" in w.message and prog.blocks == 1


def test_unknown_dialect_name_is_a_usage_error():
    with pytest.raises(ValueError, match="valid"):
        read_program("", dialect="fanuc")


def test_auto_dialect_and_path(tmp_path):
    path = tmp_path / "part.mpf"
    path.write_text("G1 X3 F100\nM30\n")
    prog = read_program(path, dialect="auto")
    assert prog.file == str(path) and prog.moves[0].end == (3.0, 0.0, 0.0)
    assert prog.moves[0].span.file == str(path)


# ---------------------------------------------------------------- properties
coord = st.floats(-500, 500, allow_nan=False).map(lambda v: round(v, 3))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(coord, coord, coord), min_size=1, max_size=15))
def test_absolute_and_incremental_programs_agree(points):
    absolute = "\n".join(f"G90 X{x} Y{y} Z{z}" for x, y, z in points)
    prev = (0.0, 0.0, 0.0)
    inc = []
    for p in points:
        inc.append(
            "G91 X="
            + "{:.3f} Y={:.3f} Z={:.3f}".format(*(a - b for a, b in zip(p, prev, strict=True)))
        )
        prev = p
    a = only_moves("F100\n" + absolute)[1:]
    b = only_moves("F100\n" + "\n".join(inc))[1:]
    for ma, mb, p in zip(a, b, points, strict=True):
        assert ma.end == pytest.approx(p, abs=1e-9)
        assert mb.end == pytest.approx(p, abs=1e-6)


@settings(max_examples=200, deadline=None)
@given(coord, coord, coord, coord, st.floats(1, 400), st.booleans(), st.booleans())
def test_cr_centre_is_equidistant_and_sweep_matches_sign(sx, sy, ex, ey, r, ccw, minor):
    chord = math.hypot(ex - sx, ey - sy)
    if chord < 1e-2 or chord / 2 > r:
        return
    radius = r if minor else -r
    cx, cy = arc_centre_from_radius((sx, sy), (ex, ey), radius, ccw, 0.002)
    assert math.hypot(sx - cx, sy - cy) == pytest.approx(r, rel=1e-9, abs=1e-6)
    assert math.hypot(ex - cx, ey - cy) == pytest.approx(r, rel=1e-9, abs=1e-6)
    a0 = math.atan2(sy - cy, sx - cx)
    a1 = math.atan2(ey - cy, ex - cx)
    sweep = (a1 - a0) % (2 * math.pi) if ccw else (a0 - a1) % (2 * math.pi)
    if minor:
        assert sweep <= math.pi + 1e-6
    else:
        assert sweep >= math.pi - 1e-6


def test_actions_are_normalised_and_f_twice_is_an_error():
    prog = read('g1 x1 f1234567 s1000.5 h2 m3 t2 d1 msg("Hello")')
    assert prog.moves[0].actions == ("F1234567", "S1000.5", "H2", "M3", "T2", "D1", 'msg("Hello")')
    err = error_of("N10 G1 X1 F1 F2\nM30")[1]
    assert err.code == "NC-SYNTAX" and err.span.column == 14


def test_ret_ends_a_subprogram():
    prog = read_program("G1 X1 F100\nRET\nX5\n", file="sub.spf")
    assert prog.diagnostics == () and len(prog.moves) == 2 and prog.moves[1].actions == ("RET",)
