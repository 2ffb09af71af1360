"""Heidenhain Klartext front end: words, numbers, tool data, polar/incremental, errors with blocks."""

from __future__ import annotations

import math

import pytest

from trcopt.controllers import detect, read_program
from trcopt.controllers.heidenhain.lexer import lex_block
from trcopt.controllers.heidenhain.reader import read_heidenhain
from trcopt.controllers.heidenhain.state import HeidenhainOptions
from trcopt.controllers.heidenhain.tooltable import HhTool, compensation_value, tool_table_from_dict
from trcopt.modes import Side
from trcopt.nc.model import MoveKind
from trcopt.pipeline import PlanOptions, plan

HEAD = "0 BEGIN PGM T MM\n1 TOOL DEF 1 L+50 R+5\n2 TOOL CALL 1 Z S3000\n"


def prog(*blocks: str, head: str = HEAD) -> str:
    body = "".join(f"{k + 3} {b}\n" for k, b in enumerate(blocks))
    return head + body + f"{len(blocks) + 3} END PGM T MM\n"


def errors(p):
    return [
        (d.code, d.span.block, d.span.line) for d in p.diagnostics if d.severity.value == "error"
    ]


def ends(p):
    return [tuple(round(c, 4) for c in m.end[:2]) for m in p.moves]


# --- the seed's formula: compensation value = R + DR_TOOLCALL + DR_TAB ---------------------------
@pytest.mark.parametrize(
    ("r", "dr_tab", "dr_call", "expected"),
    [
        (6.0, -0.05, 0.3, 6.25),
        (5.0, 0.0, 0.0, 5.0),
        (5.0, 0.0, 0.5, 5.5),
        (10.0, -0.02, -0.1, 9.88),
    ],
)
def test_seed_compensation_value_formula(r, dr_tab, dr_call, expected):
    assert compensation_value(r, dr_tab, dr_call) == pytest.approx(expected)
    tools = {1: HhTool(1, radius=r, dr=dr_tab)}
    text = prog(
        "L X-10 Y-10 R0 FMAX",
        "L X+0 Y+0 RR F200",
        "L X+100 Y+0",
        "L X+100 Y+50 R0",
        head=f"0 BEGIN PGM T MM\n1 TOOL CALL 1 Z DR{dr_call:+g}\n2 L Z+0 FMAX\n",
    )
    p = read_heidenhain(text, options=HeidenhainOptions(tools=tools))
    assert not errors(p)
    radii = [m.comp.radius for m in p.moves if m.comp.side is Side.RIGHT]
    assert radii and radii == pytest.approx([expected] * len(radii))


def test_tool_table_toml_and_tool_name():
    table = tool_table_from_dict({"tool": {"3": {"NAME": "MILL_D12", "R": 6.0, "DR": -0.05}}})
    assert table[3] == HhTool(3, "MILL_D12", 0.0, 6.0, 0.0, -0.05)
    text = prog(
        "L X-10 Y-10 R0 FMAX",
        "L X+0 Y+0 RR F200",
        "L X+100 Y+0",
        "L X+100 Y+50 R0",
        head='0 BEGIN PGM T MM\n1 TOOL CALL "MILL_D12" Z S2000 DR+0.3\n2 L Z+0 FMAX\n',
    )
    p = read_heidenhain(text, options=HeidenhainOptions(tools=table))
    assert p.moves[-2].comp.radius == pytest.approx(6.25)


def test_tool_table_unknown_key_is_an_error():
    with pytest.raises(ValueError, match="'RADIUS'"):
        tool_table_from_dict({"tool": {"3": {"RADIUS": 6.0}}})


def test_negative_compensation_value_rejected():
    text = prog(
        "L X-10 Y-10 R0 FMAX",
        "L X+0 Y+0 RL F200",
        head="0 BEGIN PGM T MM\n1 TOOL DEF 1 R+1\n2 TOOL CALL 1 Z DR-2\n",
    )
    assert errors(read_heidenhain(text))[0][0] == "HH-TRC-NEG-RADIUS"


def test_tool_zero_has_radius_zero():
    text = prog(
        "L X-10 Y-10 R0 FMAX",
        "L X+0 Y+0 RL F200",
        "L X+10",
        "L X+20 Y+5 R0",
        head="0 BEGIN PGM T MM\n1 TOOL CALL 0 Z\n2 L Z+0 FMAX\n",
    )
    p = read_heidenhain(text)
    assert not errors(p) and all(m.comp.radius == 0.0 for m in p.moves)


# --- detection, lexing ---------------------------------------------------------------------------
def test_auto_detection_from_begin_pgm_and_extension():
    assert detect(None, "0 BEGIN PGM X MM\n1 L X+0\n").name == "heidenhain"
    assert detect(None, "BEGIN PGM X INCH\n").name == "heidenhain"
    assert detect("part.h", "L X+0").name == "heidenhain"
    p = read_program(prog("L X+10 Y+0 R0 FMAX"), dialect="auto")
    assert p.dialect == "heidenhain" and ends(p) == [(10.0, 0.0)]


def test_lexer_words_flags_and_columns():
    b = lex_block("15 L X+10.5 IY-5 RL F200 M3 ; note", 7)
    assert (b.number, b.statement, b.comment) == ("15", "L", "note")
    assert [(w.address, w.value, w.column) for w in b.words] == [
        ("X", 10.5, 6),
        ("IY", -5.0, 13),
        ("RL", None, 18),
        ("F", 200.0, 21),
        ("M", 3.0, 26),
    ]
    b = lex_block("APPR LCT X+0 Y+20 R10 RL", 1)
    assert b.statement == "APPR LCT" and b.words[2].address == "R"
    assert [w.address for w in lex_block("L X+1 R+", 1).words] == ["X", "R+"]
    assert [w.address for w in lex_block("C X+1 DR\u2212", 1).words] == ["X", "DR-"]
    assert lex_block("L X+1 R+0", 1).words[1] == lex_block("L X+1 R+0", 1).words[1]
    assert lex_block("L X+1 R+0", 1).words[1].address == "R"  # R+0 is a radius, R0 no compensation
    assert lex_block("L X+1 R0", 1).words[1].address == "R0"


def test_inch_program_converts_to_mm():
    p = read_heidenhain("0 BEGIN PGM T INCH\n1 L X+1 Y+2 R0 FMAX\n2 END PGM T INCH\n")
    assert p.moves[0].end[:2] == pytest.approx((25.4, 50.8))


def test_tool_axis_y_uses_the_zx_plane():
    text = prog(
        "L X+0 Z+0 R0 FMAX",
        "L X+10 Z+0 F100",
        head="0 BEGIN PGM T MM\n1 TOOL DEF 1 R+2\n2 TOOL CALL 1 Y\n",
    )
    p = read_heidenhain(text)
    assert p.moves[-1].plane.value == "G18"


# --- incremental and polar words -----------------------------------------------------------------
def test_incremental_words_refer_to_the_last_position():
    p = read_heidenhain(prog("L X+10 Y+10 R0 FMAX", "L IX+5 IY-15 F100", "L IX+1"))
    assert ends(p) == [(10, 10), (15, -5), (16, -5)]


def test_polar_lp_pa_ipa_and_modal_pr():
    p = read_heidenhain(
        prog(
            "L X+90 Y+25 R0 FMAX",
            "CC X+45 Y+25",
            "LP PR+30 PA+0 F300",
            "LP PA+60",
            "LP IPA+60",
            "LP IPR+10 IPA-30",
        )
    )
    assert ends(p)[1:] == [
        (75, 25),
        (60, 50.9808),
        (30, 50.9808),
        pytest.approx((45 + 40 * math.cos(math.radians(90)), 65), abs=1e-4),
    ]


def test_incremental_cc_and_cp_arc_about_the_pole():
    p = read_heidenhain(prog("L X+10 Y+0 R0 FMAX", "CC IX-10 IY+0", "CP IPA+90 DR+ F100"))
    arc = p.moves[-1]
    assert arc.kind is MoveKind.ARC and arc.ccw is True
    assert arc.center[:2] == pytest.approx((0, 0)) and arc.end[:2] == pytest.approx(
        (0, 10), abs=1e-12
    )


def test_cr_centres_of_the_four_arcs_h9():
    for word, centre in [
        ("R+20 DR-", (55, 26.7712)),
        ("R+20 DR+", (55, 53.2288)),
        ("R-20 DR-", (55, 53.2288)),
        ("R-20 DR+", (55, 26.7712)),
    ]:
        p = read_heidenhain(prog("L X+40 Y+40 R0 F100", f"CR X+70 Y+40 {word}"))
        assert p.moves[-1].center[:2] == pytest.approx(centre, abs=1e-4), word


def test_ct_without_a_previous_element():
    p = read_heidenhain("0 BEGIN PGM T MM\n1 CT X+10 Y+10 F100\n2 END PGM T MM\n")
    assert errors(p) == [("HH-CT-NO-TANGENT", "1", 2)]


# --- bad input: diagnostics with line and block number --------------------------------------------
@pytest.mark.parametrize(
    ("blocks", "code", "block"),
    [
        (("L X+0 Y+0 R0 FMAX", "L X+10 LEN5 F100"), "HH-SYNTAX", "4"),
        (("L X+0 Y+0 R0 FMAX", "L X+10 QQ F100"), "HH-SYNTAX", "4"),
        (("L X+0 Y+0 R0 FMAX", "CC X+1 Y+1 F100"), "HH-SYNTAX", "4"),
        (("FOO X+1",), "HH-SYNTAX", "3"),
        (("L X+0 Y+0 RL F100", "L X+10 Y+0", "L X+10 Y+10 RR"), "HH-TRC-SIDE-SWITCH", "5"),
        (("L X+0 Y+0 RL F100", "L X+10 Y+0", "L Z+5 R0", "L X+10 Y+10 RR"), "HH-SYNTAX", "5"),
        (("L X+0 Y+0 R0 F100", "CC X+5 Y+0", "C X+10 Y+0 DR+ RL"), "HH-TRC-IN-CIRCLE", "5"),
        (
            ("L X+0 Y+0 R0 FMAX", "APPR LT X+0 Y+0 LEN10 RL F200", "END PGM T MM"),
            "HH-APPR-NO-CONTOUR",
            "4",
        ),
        (
            ("L X+0 Y+0 R0 FMAX", "APPR LT X+0 Y+0 LEN10 RL F200", "L X+10 Y+0 R0"),
            "HH-TRC-SIDE-SWITCH",
            "5",
        ),
        (("L X+0 Y+0 R0 FMAX", "L X+50 Y+10 R+ F100"), "HH-PARAXIAL-NOT-PARAXIAL", "4"),
        (("L X+0 Y+0 R0 FMAX", "L X+10 Y+0 F100", "CHF 5"), "HH-SYNTAX", "5"),
        (("L X+0 Y+0 R0 FMAX", "L X+10 Y+0 F100", "CHF 20", "L X+10 Y+10"), "HH-CHF-TOO-LARGE", "6"),
        (
            ("L X+0 Y+0 R0 FMAX", "L X+10 Y+0 F100", "RND R50", "L X+10 Y+10"),
            "HH-RND-TOO-LARGE",
            "6",
        ),
        (("L X+0 Y+0 R0 FMAX", "L X+10 Y+0"), "HH-NO-FEED", "4"),
        # RND, CT and DEP after an infeed-only move: no direction in the working plane to continue
        (("L X+0 Y+0 R0 FMAX", "L Z-5 F100", "RND R2", "L X+10 Y+0"), "HH-NO-DIRECTION", "6"),
        (("L X+0 Y+0 R0 FMAX", "L Z-5 F100", "CT X+10 Y+10"), "HH-NO-DIRECTION", "5"),
        (("L X+0 Y+0 R0 FMAX", "L Z-5 F100", "DEP LT LEN10 F100"), "HH-NO-DIRECTION", "5"),
        # a number no program uses stops at its word, before any geometry is computed from it
        (("L X+30 Y+0 R0 F1000", "APPR CT X+999999999999 Y+20 CCA90 R-10 RL F200", "L X+0 Y+40"), "NC-RANGE", "4"),
    ],
)
def test_bad_input_diagnostics(blocks, code, block):
    text = prog(*blocks)
    p = read_heidenhain(text, file="bad.h")
    errs = errors(p)
    assert errs and errs[0][:2] == (code, block), p.diagnostics
    line = next(k for k, t in enumerate(text.splitlines(), start=1) if t.startswith(f"{block} "))
    assert errs[0][2] == line and p.diagnostics[-1].span.file == "bad.h"


def test_rl_then_rr_after_an_r0_traversing_block_is_fine():
    p = read_heidenhain(
        prog(
            "L X+0 Y+0 RL F100",
            "L X+10 Y+0",
            "L X+20 Y+0 R0",
            "L X+30 Y+0 RR",
            "L X+40 Y+0",
            "L X+50 Y+0 R0",
        )
    )
    assert not errors(p)


def test_error_stops_moves_before_the_block_and_plan_reports_it():
    text = prog("L X+1 Y+0 R0 FMAX", "L X+10 Y+0 F100", "L X+10 Y+10 LEN5", "L X+20 Y+0")
    r = plan(text, file="bad.h", options=PlanOptions(dialect="heidenhain", timing=False))
    assert not r.ok and r.errors[0].span.block == "5"
    assert ends(r.nc) == [(1, 0), (10, 0)]


def test_rnd_between_a_line_and_an_arc_is_tangent_to_both():
    p = read_heidenhain(
        prog("L X-20 Y+0 R0 FMAX", "CC X+0 Y+0", "L X-10 Y+0 F100", "RND R2", "C X+0 Y+10 DR-")
    )
    assert not errors(p)
    line, fillet, arc = p.moves[-3:]
    assert fillet.kind is MoveKind.ARC
    assert math.dist(fillet.center[:2], line.end[:2]) == pytest.approx(2.0)
    assert math.dist(fillet.center[:2], (0, 0)) == pytest.approx(
        12.0
    )  # left of the CW arc: outside it
    assert math.dist(arc.start[:2], (0, 0)) == pytest.approx(10.0)


def test_m97_sets_the_intersection_on_the_following_block():
    p = read_heidenhain(
        prog("L X-30 Y+0 R0 FMAX", "L X+0 Y+0 RR F200", "L X+50 Y+0 M97", "L IY+0.5")
    )
    assert [m.comp.corner.value for m in p.moves[-2:]] == ["G450", "G451"]
    assert "M97" in p.moves[-2].actions


def test_appr_with_r0_warns_and_uses_radius_zero():
    p = read_heidenhain(
        prog("L X-20 Y-20 R0 F500", "APPR LT X+0 Y+0 LEN10 R0 F200", "L X+0 Y+40", "L X+10 Y+40")
    )
    assert not errors(p) and any(d.code == "HH-APPR-R0" for d in p.diagnostics)
    assert ends(p)[1:3] == [(0, -10), (0, 0)]


def test_appr_tool_axis_coordinate_moves_plane_first():
    p = read_heidenhain(
        prog("L X-20 Y-20 Z+10 R0 F500", "APPR LT X+0 Y+0 Z-5 LEN10 RL F200", "L X+0 Y+40")
    )
    zs = [(m.start[2], m.end[2]) for m in p.moves[1:4]]
    assert zs == [(10, 10), (10, -5), (-5, -5)]


def test_f_max_written_with_a_space_is_rapid():
    """The TNC 426/430 manual's example programs write ``F MAX`` (and ``F AUTO``) with a space."""
    block = lex_block("3 L X+0 Y+0 Z+5 R0 F MAX", 4)
    assert [w.address for w in block.words][-1] == "FMAX" and block.words[-1].column == 20
    text = "0 BEGIN PGM T MM\n1 TOOL DEF 1 L+0 R5\n2 TOOL CALL 1 Z S1000\n3 L X+0 Y+0 Z+5 R0 F MAX\n"
    text += "4 L Z-5 F100\n5 L X+10 F MAX\n6 END PGM T MM\n"
    prog = read_heidenhain(text, "t.h")
    assert not [d for d in prog.diagnostics if d.severity.value == "error"]
    assert [(m.kind, m.span.block) for m in prog.moves] == [
        (MoveKind.RAPID, "3"), (MoveKind.LINE, "4"), (MoveKind.RAPID, "5")
    ]
