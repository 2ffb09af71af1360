"""Heidenhain Q parameters, program flow (LBL, CALL LBL, REP, FN 9–12, CALL PGM), coordinate
transformation cycles (CYCL DEF 7/8/10/11/26) and the errors of bad input."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from trcopt.cli import main
from trcopt.codes import Code
from trcopt.controllers.heidenhain.qparams import QError, QParams, eval_fn, evaluate
from trcopt.controllers.heidenhain.reader import read_heidenhain
from trcopt.controllers.heidenhain.state import HeidenhainOptions
from trcopt.modes import Side
from trcopt.pipeline import PlanOptions, plan, plan_file

PROBLEMS = Path(__file__).resolve().parents[3] / "problems" / "heidenhain"
PAIRS = sorted(PROBLEMS.glob("*_explicit.h"))
HEAD = "0 BEGIN PGM T MM\n1 TOOL DEF 1 L+0 R+5\n2 TOOL CALL 1 Z S3000\n"


def prog(*blocks: str) -> str:
    body = "".join(f"{k + 3} {b}\n" for k, b in enumerate(blocks))
    return HEAD + body + f"{len(blocks) + 3} END PGM T MM\n"


def read(*blocks: str, **options):
    return read_heidenhain(prog(*blocks), file="t.h", options=HeidenhainOptions(**options))


def errors(p):
    return [(d.code, d.span.block, d.span.column) for d in p.diagnostics if d.severity.value == "error"]


def ends(p):
    return [tuple(round(c, 6) + 0.0 for c in m.end) for m in p.moves]


# ------------------------------------------------------------------------------ the acceptance pairs
def test_every_feature_problem_has_its_explicit_twin():
    assert {p.name for p in PAIRS} >= {
        "h20_qparams_explicit.h",
        "h21_labels_repeats_explicit.h",
        "h22_frames_explicit.h",
        "h25_call_pgm_explicit.h",
        "h26_cam_post_explicit.h",
    }


@pytest.mark.parametrize("explicit", PAIRS, ids=[p.stem for p in PAIRS])
def test_the_features_give_the_path_written_out_explicitly(explicit: Path):
    feature = explicit.with_name(explicit.name.replace("_explicit", ""))
    a, b = plan_file(feature, PlanOptions(timing=False)), plan_file(explicit, PlanOptions(timing=False))
    assert a.ok and b.ok, [d.message for d in (*a.errors, *b.errors)]
    assert [d.code for d in a.diagnostics if d.severity.value != "info"] == []
    assert len(a.toolpath) == len(b.toolpath) > 5
    for s, t in zip(a.toolpath, b.toolpath, strict=True):
        assert (s.kind, s.role) == (t.kind, t.role)
        for p, q in ((s.start_xyz, t.start_xyz), (s.end_xyz, t.end_xyz), (s.center_xyz, t.center_xyz)):
            assert (p is None) == (q is None)
            if p is not None:
                assert max(abs(u - v) for u, v in zip(p, q, strict=True)) <= 1e-9, (s, t)


def test_the_manual_examples_need_the_revised_r9_reading():
    for name in ("h27_tnc426_linear.h", "h28_tnc426_circular.h"):
        assert plan_file(PROBLEMS / name, PlanOptions(timing=False)).ok
    r = plan_file(PROBLEMS / "h28_tnc426_circular.h", PlanOptions(timing=False, appr_radius="contour"))
    assert [(d.code, d.span.block) for d in r.errors] == [("HH-TOOL-RADIUS-TOO-LARGE", "8")]


# ------------------------------------------------------------------------------ formulas and FN
@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("5 * 3 + 2 * 10", 35.0),
        ("SQ 10 - 3^3", 73.0),
        ("(1 + 2) * -3", -9.0),
        ("2 ^ 3 ^ 2", 512.0),
        ("SQRT (Q1 * 4)", 4.0),
        ("SIN 30 + COS 60 + TAN 45", 2.0),
        ("ASIN 0.5 + ACOS 0.5 + ATAN 1", 135.0),
        ("ABS -2.5 + INT -2.7 + FRAC 3.25 + SGN -7", -0.25),
        ("PI / 2 - ATAN 1 * PI / 180", math.pi / 4),
        ("-Q1 + QL2", -1.0),
    ],
)
def test_formula_values(text, value):
    q = QParams()
    q.set("Q1", 4.0)
    q.set("QL2", 3.0)
    assert evaluate(text, 1, q) == pytest.approx(value, abs=1e-12)


@pytest.mark.parametrize(
    ("text", "code", "column"),
    [
        ("5 / (Q1 - 4)", Code.HH_Q_MATH, 3),
        ("SQRT -1", Code.HH_Q_MATH, 1),
        ("ASIN 2", Code.HH_Q_MATH, 1),
        ("Q7 + 1", Code.HH_Q_UNDEFINED, 1),
        ("3 +* 2", Code.HH_SYNTAX, 4),
        ("(3 + 2", Code.HH_SYNTAX, 1),
        ("10 ^ 400", Code.HH_Q_MATH, 4),
    ],
)
def test_formula_errors_name_the_column(text, code, column):
    q = QParams()
    q.set("Q1", 4.0)
    with pytest.raises(QError) as info:
        evaluate(text, 1, q)
    assert info.value.code is code and info.value.column == column


@pytest.mark.parametrize(
    ("fn", "rhs", "value"),
    [
        (0, "-12.5", -12.5),
        (1, "+Q1 + -1", 3.0),
        (2, "+Q1 - +10", -6.0),
        (3, "+Q1 * -Q1", -16.0),
        (4, "+Q1 DIV +8", 0.5),
        (5, "SQRT +Q1", 2.0),
        (6, "SIN +90", 1.0),
        (7, "COS +180", -1.0),
        (8, "+3 LEN -Q1", 5.0),
        (13, "+0 ANG +1", 90.0),
        (13, "-1 ANG -1", 225.0),
    ],
)
def test_fn_functions(fn, rhs, value):
    q = QParams()
    q.set("Q1", 4.0)
    assert eval_fn(fn, rhs, 1, q) == pytest.approx(value, abs=1e-12)


def test_q_parameters_in_values_and_the_preassigned_tool_radius():
    p = read("FN 0: Q1 = +30", "Q2 = Q108 * 2", "L X+Q1 Y-Q2 Z+2 R0 FMAX", "L IX-Q1 FQ1", "L Y+0")
    assert errors(p) == []
    assert ends(p) == [(30.0, -10.0, 2.0), (0.0, -10.0, 2.0), (0.0, 0.0, 2.0)]
    assert p.moves[1].feed_mm_s == pytest.approx(0.5)  # F Q1 = 30 mm/min
    assert errors(read("L X+Q5 R0 FMAX")) == [(Code.HH_Q_UNDEFINED, "3", 7)]
    assert errors(read("FN 4: Q1 = +1 DIV +0")) == [(Code.HH_Q_MATH, "3", 21)]
    assert errors(read("QS1 = 'A'")) == [(Code.HH_NOT_MODELLED, "3", 3)]


# ------------------------------------------------------------------------------ program flow
def test_section_repeats_and_subprograms_run_as_the_tnc_runs_them():
    p = read(
        "L X+0 Y+0 Z+0 R0 FMAX",
        "LBL 1",
        "L IX+1 F100",
        "LBL 2",
        "L IY+1",
        "CALL LBL 2 REP 1",  # the inner section twice per outer run
        "CALL LBL 1 REP 2",  # the outer section three times
        "CALL LBL 9",
        "L Z+50 FMAX M30",
        "LBL 9",
        "L IZ-1",
        "LBL 0",
    )
    assert errors(p) == []
    assert [m.end for m in p.moves][-3:] == [(3.0, 6.0, 0.0), (3.0, 6.0, -1.0), (3.0, 6.0, 50.0)]
    assert len(p.moves) == 3 * 3 + 2  # the first block does not move


def test_jumps_skip_blocks_and_labels_may_be_names():
    p = read(
        "FN 0: Q1 = +0",
        "L X+0 Y+0 Z+0 R0 FMAX",
        'LBL "UP"',
        "FN 1: Q1 = +Q1 + +1",
        "L Z+Q1 F100",
        'FN 12: IF +Q1 LT +3 GOTO LBL "UP"',
        "FN 9: IF +Q1 EQU +3 GOTO LBL 5",
        "L X+500",
        "LBL 5",
        "FN 10: IF +Q1 NE +3 GOTO LBL 5",
        "FN 11: IF +Q1 GT +3 GOTO LBL 5",
    )
    assert errors(p) == []
    assert [m.end[2] for m in p.moves] == [1.0, 2.0, 3.0]


@pytest.mark.parametrize(
    ("blocks", "code", "block"),
    [
        (("CALL LBL 4",), Code.HH_LABEL, "3"),
        (("FN 9: IF +0 EQU +1 GOTO LBL 4",), Code.HH_LABEL, "3"),  # missing even when not taken
        (("LBL 1", "LBL 1"), Code.HH_LABEL, "4"),
        (("LBL 0",), Code.HH_LABEL, "3"),
        (("CALL LBL 0",), Code.HH_LABEL, "3"),
        (("CALL LBL 1 REP 2", "LBL 1"), Code.HH_NOT_MODELLED, "3"),
        (("LBL 1", "CALL LBL 1"), Code.HH_LOOP_LIMIT, "4"),  # recursion: nesting limit
        (("LBL 1", "FN 9: IF +0 EQU +0 GOTO LBL 1"), Code.HH_LOOP_LIMIT, "4"),
        (("CALL LBL 1", "LBL 1", "L X+1 R0 FMAX"), Code.HH_LABEL, "6"),  # no LBL 0 before END PGM
        (("FN 14: ERROR = 1",), Code.HH_NOT_MODELLED, "3"),
        (("CYCL CALL",), Code.HH_NOT_MODELLED, "3"),
        (("CYCL DEF 1.0 PECKING",), Code.HH_NOT_MODELLED, "3"),
        (("L X+0 Y+0 R0 FMAX M91",), Code.HH_NOT_MODELLED, "3"),
        (("L X+0 Y+0 R0 FMAX M120 LA5",), Code.HH_M120, "3"),
        (("CALL PGM NOT_THERE",), Code.HH_PGM_MISSING, "3"),
        # a name the file system refuses (too long) is not there either
        (("CALL PGM " + "N" * 300,), Code.HH_PGM_MISSING, "3"),
    ],
)
def test_bad_flow_is_an_error_at_its_block(blocks, code, block):
    p = read(*blocks)
    assert [(c, b) for c, b, _ in errors(p)] == [(code, block)]


def test_the_loop_limit_is_a_setting():
    blocks = ("FN 0: Q1 = +0", "LBL 1", "FN 1: Q1 = +Q1 + +1", "FN 12: IF +Q1 LT +50 GOTO LBL 1")
    assert errors(read(*blocks)) == []
    assert errors(read(*blocks, max_iterations=20)) == [(Code.HH_LOOP_LIMIT, "6", 3)]
    assert errors(read(*blocks, max_blocks=30)) == [(Code.HH_LOOP_LIMIT, "4", 3)]
    # the block limit counts blocks run again: a program read straight through is never cut
    straight = [f"L X+{k} Y+0 R0 F1000" for k in range(40)]
    assert errors(read(*straight, max_blocks=30)) == []


def test_call_pgm_runs_the_file_beside_the_program(tmp_path: Path):
    (tmp_path / "SUB.h").write_text("0 BEGIN PGM SUB MM\n1 QL1 = 5\n2 L X+Q1 Y+QL1 R0 FMAX\n3 END PGM SUB MM\n")
    main_file = tmp_path / "main.h"
    main_file.write_text(
        HEAD + "3 Q1 = 7\n4 QL1 = 1\n5 CALL PGM TNC:\\X\\SUB\n6 L X+QL1 FMAX\n7 CALL PGM SUB.h\n8 END PGM T MM\n"
    )
    p = read_heidenhain(main_file.read_text(), file=str(main_file))
    assert errors(p) == []
    assert ends(p) == [(7.0, 5.0, 0.0), (1.0, 5.0, 0.0), (7.0, 5.0, 0.0)]
    assert p.moves[0].span.file == str(tmp_path / "SUB.h") and p.moves[0].span.line == 3
    (tmp_path / "SUB.h").write_text("0 BEGIN PGM SUB MM\n1 L X+1 R0 FMAX M30\n2 END PGM SUB MM\n")
    p = read_heidenhain(main_file.read_text(), file=str(main_file))
    assert [(d.code, d.span.file) for d in p.diagnostics] == [(Code.HH_NOT_MODELLED, str(tmp_path / "SUB.h"))]


def test_m2_ends_the_run_before_the_subprograms():
    p = read("L X+1 Y+0 R0 FMAX M2", "L X+99")
    assert errors(p) == [] and ends(p) == [(1.0, 0.0, 0.0)]


# ------------------------------------------------------------------------------ frames
def test_mirror_reverses_the_side_and_the_arcs_and_the_radius_is_not_scaled():
    contour = ("L X+0 Y+0 RL F100", "L Y+20", "CR X+20 Y+20 R+10 DR-", "L Y+0", "L X+10 Y-10 R0")
    plain = read("L X-10 Y-10 R0 FMAX", *contour)
    mirrored = read("CYCL DEF 8.0 MIRROR IMAGE", "CYCL DEF 8.1 X", "L X-10 Y-10 R0 FMAX", *contour)
    assert errors(plain) == errors(mirrored) == []
    assert [m.comp.side for m in mirrored.moves if m.comp.side is not Side.OFF][0] is Side.RIGHT
    arc = [m for m in mirrored.moves if m.center is not None][0]
    assert arc.ccw is True and arc.center[:2] == pytest.approx((-10.0, 20.0))
    scaled = read("CYCL DEF 11.0 SCALING", "CYCL DEF 11.1 SCL 2", "L X-10 Y-10 R0 FMAX", *contour)
    assert {m.comp.radius for m in scaled.moves if m.comp.side is not Side.OFF} == {5.0}
    assert ends(scaled)[-1] == (20.0, -20.0, 0.0)


def test_datum_shift_incremental_rotation_and_reset():
    p = read(
        "CYCL DEF 7.0 DATUM SHIFT",
        "CYCL DEF 7.1 X+10",
        "CYCL DEF 7.2 Y+5",
        "CYCL DEF 7.0 DATUM SHIFT",
        "CYCL DEF 7.1 IX+10",
        "CYCL DEF 10.0 ROTATION",
        "CYCL DEF 10.1 ROT+45",
        "CYCL DEF 10.1 IROT+45",
        "L X+1 Y+0 Z+0 R0 FMAX",
        "L IX+1 F100",  # incremental along the rotated X: +Y in the work system
        "CYCL DEF 10.1 ROT+0",
        "CYCL DEF 7.1 X+0 Y+0",
        "L X+1 F100",
    )
    assert errors(p) == []
    assert ends(p) == [(20.0, 6.0, 0.0), (20.0, 7.0, 0.0), (1.0, 7.0, 0.0)]


@pytest.mark.parametrize(
    ("blocks", "code", "column"),
    [
        (("CYCL DEF 11.1 SCL 0",), Code.HH_FRAME, 17),
        (("CYCL DEF 11.1 SCL-2",), Code.HH_FRAME, 17),
        (("CYCL DEF 26.1 X0 Y1",), Code.HH_FRAME, 17),
        (("CYCL DEF 7.1 #3",), Code.HH_NOT_MODELLED, 16),
        (("CYCL DEF 8.1 Z",), Code.HH_NOT_MODELLED, 16),
        (("CYCL DEF 10.1 X+5",), Code.HH_SYNTAX, 17),
        (("CYCL DEF 26.1 X2 Y1", "L X+0 Y+0 R0 FMAX", "CC X+5 Y+0", "C X+10 Y+0 DR+ F100"), Code.HH_NOT_MODELLED, 3),
        (("CYCL DEF 10.1 ROT+30", "L X+0 Y+0 R0 FMAX", "L X+10 R+ F100"), Code.HH_NOT_MODELLED, 10),
    ],
)
def test_bad_frames_are_errors_with_their_column(blocks, code, column):
    got = errors(read(*blocks))
    assert len(got) == 1 and got[0][0] is code and got[0][2] == column


# ------------------------------------------------------------------------------ end to end
def test_the_cam_post_program_runs_through_trcopt_plan(tmp_path: Path, capsys):
    out = tmp_path / "h26.json"
    assert main(["plan", str(PROBLEMS / "h26_cam_post.h"), "--no-timing", "--json", str(out)]) == 0
    assert '"trcopt.plan/1"' in out.read_text()
    capsys.readouterr()
    r = plan_file(PROBLEMS / "h26_cam_post.h", PlanOptions(timing=False))
    assert {m.control.tolerance_mm for m in r.nc.moves if m.kind.value != "rapid" and m.control.tolerance_mm} >= {0.02}
    depths = sorted({round(s.end_xyz[2], 6) for s in r.toolpath if s.role.name == "CONTOUR"})
    assert depths == [-9.0, -6.0, -3.0]


@pytest.mark.parametrize(
    ("name", "where"),
    [
        ("e8_q_undefined", "e8_q_undefined.h:8:7"),
        ("e9_q_division_by_zero", "e9_q_division_by_zero.h:9:22"),
        ("e10_label_missing", "e10_label_missing.h:6:12"),
        ("e11_endless_loop", "e11_endless_loop.h:8:3"),
        ("e12_pgm_missing", "e12_pgm_missing.h:5:12"),
        ("e13_scale_zero", "e13_scale_zero.h:6:17"),
    ],
)
def test_bad_input_is_a_located_error_without_traceback(name, where, capsys):
    assert main(["plan", str(PROBLEMS / f"{name}.h"), "--no-timing"]) == 1
    out = capsys.readouterr()
    text = out.out + out.err
    assert where in text and "Traceback" not in text


def test_plan_text_without_a_file_looks_for_called_programs_in_the_working_directory(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    r = plan(prog("CALL PGM P1"), options=PlanOptions(timing=False))
    assert [d.code for d in r.errors] == ["HH-PGM-MISSING"]
