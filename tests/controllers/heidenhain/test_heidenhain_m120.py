"""M120 LA n — the TNC's radius-compensated look-ahead: modelled as the engine's
collision detection (SINUMERIK CDON) with the search limit LA; switched off by M120 LA0, M120
without LA, R0, DEP and CALL PGM; refused where the TNC refuses it."""

from __future__ import annotations

from pathlib import Path

import pytest

from trcopt.codes import Code
from trcopt.controllers.heidenhain.lexer import lex_block
from trcopt.controllers.heidenhain.m120 import lookahead_of
from trcopt.controllers.heidenhain.reader import read_heidenhain
from trcopt.modes import CollisionMode
from trcopt.pipeline import PlanOptions, plan, plan_file

PROBLEMS = Path(__file__).resolve().parents[3] / "problems"
HEAD = "0 BEGIN PGM T MM\n1 TOOL DEF 1 L+50 R+5\n2 TOOL CALL 1 Z S3000\n3 L X-10 Y+10 R0 FMAX\n"
# a slot 6 mm wide in a contour milled with a 10 mm tool (the geometry of SINUMERIK example 6)
SLOT = ("L X+20", "L Y-20", "L X+26", "L Y+0", "L X+50", "L X+60 Y+10 R0")


def prog(*blocks: str) -> str:
    body = "".join(f"{k + 4} {b}\n" for k, b in enumerate(blocks))
    return HEAD + body + f"{len(blocks) + 4} END PGM T MM\n"


def run(*blocks: str):
    return plan(prog(*blocks), file="t.h", options=PlanOptions(timing=False))


def found(result):
    return [(d.severity.value, str(d.code), d.span.block) for d in result.diagnostics if d.severity.value != "info"]


def geometry(result):
    return [
        (s.kind, s.start_xyz, s.end_xyz, s.center_xyz) for s in result.toolpath
    ]


def test_m120_leaves_out_the_slot_the_tool_cannot_machine():
    r = run("L X+0 Y+0 RL F400 M120 LA3", *SLOT)
    assert r.ok
    assert found(r) == [("warning", "10763", "7"), ("warning", "10763", "8")]
    assert all("M120" in d.message for d in r.diagnostics if str(d.code) == "10763")
    arcs = [s for s in r.toolpath if s.kind == "arc"]
    # the transition arcs about (20, 0) and (26, 0), radius 5, meet at (23, 4)
    assert [s.span.block for s in arcs] == ["6", "9"]
    assert arcs[0].end_xyz == pytest.approx((23.0, 4.0, 0.0), abs=1e-12)
    assert arcs[1].start_xyz == pytest.approx((23.0, 4.0, 0.0), abs=1e-12)


def test_m120_gives_the_path_of_sinumerik_cdon_on_the_same_contour():
    hh = plan_file(PROBLEMS / "heidenhain" / "h29_m120_slot.h", PlanOptions(timing=False))
    sie = plan_file(PROBLEMS / "siemens" / "ex06_bottleneck_cdon.mpf", PlanOptions(timing=False))
    a, b = geometry(hh), geometry(sie)
    assert len(a) == len(b) == 7
    for x, y in zip(a, b, strict=True):
        assert x[0] == y[0]
        for p, q in zip(x[1:], y[1:], strict=True):
            assert (p is None) == (q is None)
            if p is not None:
                assert p == pytest.approx(q, abs=1e-9)


@pytest.mark.parametrize(("la", "ok"), [(1, False), (2, False), (3, True), (99, True)])
def test_the_look_ahead_is_the_number_of_blocks_searched(la, ok):
    # block 6's path meets the contour again in block 9: three blocks ahead
    r = run(f"L X+0 Y+0 RL F400 M120 LA{la}", *SLOT)
    assert r.ok is ok
    if not ok:
        assert found(r) == [("error", "HH-TOOL-RADIUS-TOO-LARGE", "7")]


def test_without_m120_the_slot_is_tool_radius_too_large():
    r = run("L X+0 Y+0 RL F400", *SLOT)
    assert found(r) == [("error", "HH-TOOL-RADIUS-TOO-LARGE", "7")]


@pytest.mark.parametrize("off", ["M120 LA0", "M120"])
def test_m120_la0_and_m120_without_la_switch_it_off(off):
    r = run("L X+0 Y+0 RL F400 M120 LA3", f"L X+20 {off}", *SLOT[1:])
    assert found(r) == [("error", "HH-TOOL-RADIUS-TOO-LARGE", "7")]


def test_r0_cancels_m120():
    r = run("L X+0 Y+0 RL F400 M120 LA3", "L X+10", "L X+10 Y+20 R0", "L X+0 Y+0 RL", *SLOT)
    assert found(r) == [("error", "HH-TOOL-RADIUS-TOO-LARGE", "10")]


def test_dep_cancels_m120():
    r = run(
        "L X+0 Y+0 RL F400 M120 LA3", "L X+10", "DEP LT LEN5", "L X+0 Y+10 R0 FMAX", "L X+0 Y+0 RL F400", *SLOT
    )
    assert found(r) == [("error", "HH-TOOL-RADIUS-TOO-LARGE", "11")]


def test_m120_in_an_appr_block():
    r = run("APPR LCT X+0 Y+0 R5 RL F400 M120 LA3", *SLOT)
    assert r.ok
    assert [b for _, _, b in found(r)] == ["7", "8"]


def test_the_moves_of_an_m120_section_carry_cdon_and_la():
    p = read_heidenhain(prog("L X+0 Y+0 RL F400 M120 LA4", "L X+20", "L X+30 Y+10 R0", "L X+40"), file="t.h")
    got = [(m.span.block, m.comp.collision, lookahead_of(m)) for m in p.moves]
    assert got == [
        ("3", CollisionMode.CDOF, 0),
        ("4", CollisionMode.CDON, 4),
        ("5", CollisionMode.CDON, 4),
        ("6", CollisionMode.CDOF, 0),
        ("7", CollisionMode.CDOF, 0),
    ]
    # M120 is in the tool-centre path: the output does not carry it
    assert all("M120" not in m.actions for m in p.moves)


def test_call_pgm_cancels_m120(tmp_path):
    (tmp_path / "SUB.h").write_text("0 BEGIN PGM SUB MM\n1 L X+1 R0 FMAX\n2 END PGM SUB MM\n")
    main = tmp_path / "main.h"
    main.write_text(prog("L X+0 Y+0 RL F400 M120 LA4", "L X+20", "CALL PGM SUB", "L X+0 Y+0 RL F400", "L X+20"))
    p = read_heidenhain(main.read_text(), file=str(main))
    assert [lookahead_of(m) for m in p.moves if m.span.block in ("4", "5")] == [4, 4]
    assert [lookahead_of(m) for m in p.moves if m.span.block in ("7", "8")] == [0, 0]


@pytest.mark.parametrize("text", ["L X+0 RL F400 M120 LA5", "L X+0 RL F400 M120 LA 5"])
def test_la_is_read_glued_and_apart(text):
    words = {w.address: w.value for w in lex_block(text, 1).words}
    assert words["LA"] == 5.0


@pytest.mark.parametrize(
    ("blocks", "block", "column"),
    [
        (("L X+0 Y+0 RL F400 M120 LA100",), "4", 26),  # at most 99
        (("L X+0 Y+0 RL F400 M120 LA2.5",), "4", 26),  # whole blocks
        (("L X+0 Y+0 R0 F400 M120 LA2",), "4", 21),  # needs RL/RR
        (("L X+0 Y+0 RL F400 LA2",), "4", 21),  # LA without M120
        (("STOP M120",), "4", 8),  # not a positioning block
        (("L X+0 Y+0 RL F400", "L X+20", "DEP LT LEN5 M120"), "6", 15),
        (("L X+0 Y+0 RL F400 M120 LA2", "CYCL DEF 32.0 TOLERANCE"), "5", 12),  # cancel M120 first
    ],
)
def test_m120_where_the_tnc_refuses_it_is_a_located_error(blocks, block, column):
    p = read_heidenhain(prog(*blocks), file="t.h")
    errs = [(str(d.code), d.span.block, d.span.column) for d in p.diagnostics if d.severity.value == "error"]
    assert errs == [("HH-M120", block, column)]
    assert Code.HH_M120 == "HH-M120"
