"""expand_sar: SAR blocks → canonical moves.

Feeds R43/R44, P4 and tangent R45, TRC R46, other content R47, the SAR alarms.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from trcopt.compensation import compensate
from trcopt.config import TrcSettings
from trcopt.controllers import read_program
from trcopt.controllers.siemens.sar import PREPROCESSING_STOP, expand_sar
from trcopt.errors import Diagnostic
from trcopt.modes import Side
from trcopt.nc import MoveKind
from trcopt.path import Role

SIEMENS = Path(__file__).resolve().parents[3] / "problems" / "siemens"
TOOL = "$TC_DP1[1,1]=120 $TC_DP6[1,1]={r}\n"


def expand(text: str, settings: TrcSettings | None = None, r: float = 5.0):
    nc = read_program(TOOL.format(r=r) + text, file="t.mpf", dialect="siemens")
    diags: list[Diagnostic] = []
    moves = list(expand_sar(nc.moves, settings or TrcSettings(), diags))
    return nc, moves, diags


def toolpath(moves, settings: TrcSettings | None = None):
    diags: list[Diagnostic] = []
    return list(compensate(moves, settings or TrcSettings(), diags)), diags


def errors(diags):
    return [
        (d.alarm if d.alarm is not None else d.code, d.span.line, d.span.block)
        for d in diags
        if d.severity.value == "error"
    ]


@pytest.mark.parametrize(
    "name", ["ex01_seed_g461", "ex02_square_g450", "ex05_kont_g450", "ex06_bottleneck_cdon"]
)
def test_no_op_without_sar(name: str) -> None:
    nc = read_program((SIEMENS / f"{name}.mpf").read_text(), file=name, dialect="siemens")
    diags: list[Diagnostic] = []
    out = list(expand_sar(nc.moves, TrcSettings(), diags))
    assert len(out) == len(nc.moves) and all(a is b for a, b in zip(out, nc.moves, strict=True))
    assert diags == []


def test_approach_sub_moves_comp_state_actions_and_origin() -> None:
    """R46/R47: G41 rides on P0→P1 together with the block's other content; the rest are plain."""
    nc, moves, diags = expand(
        "N10 G17 G90 T1 D1 G0 X0 Y20 Z10\n"
        "N20 G41 G247 G341 DISR=5 DISCL=2 X30 Y0 Z0 F300 M8\n"
        "N30 G1 X60\nN40 G40 G0 X70 Y20\nM30\n"
    )
    assert diags == []
    sar = [m for m in moves if m.span.block == "N20"]
    assert [m.origin for m in sar] == ["approach"] * 4
    assert [m.kind for m in sar] == [MoveKind.RAPID, MoveKind.RAPID, MoveKind.LINE, MoveKind.ARC]
    assert sar[0].comp.side is Side.LEFT and sar[0].comp.side_programmed
    assert not any(m.comp.side_programmed for m in sar[1:]) and all(
        m.comp.side is Side.LEFT for m in sar
    )
    assert "M8" in sar[0].actions and all("M8" not in m.actions for m in sar[1:])
    # the internal programmed circle: ρp = DISR + s·σ·R = 5 + 5
    arc = sar[3]
    assert arc.center == pytest.approx((30, 10, 0)) and arc.ccw is True
    assert arc.start == pytest.approx((20, 10, 0)) and arc.end == pytest.approx((30, 0, 0))
    segs, tdiags = toolpath(moves)
    assert not errors(tdiags)
    arc_seg = next(s for s in segs if s.kind == "arc")
    assert arc_seg.role is Role.APPROACH and arc_seg.geometry.radius == pytest.approx(5.0)


def test_approach_without_compensation_is_the_programmed_lead() -> None:
    nc, moves, diags = expand(
        "N10 G17 G90 T1 D1 G0 X0 Y20 Z10\nN20 G247 G340 DISR=5 DISCL=2 X30 Y0 Z0 F300\n"
        "N30 G1 X60\nM30\n"
    )
    assert diags == []
    segs, _ = toolpath(moves)
    helix = next(s for s in segs if s.kind == "arc")
    # G140 without TRC behaves like G143: P0 (0,20) lies left of the tangent (1,0)
    # → CCW, centre (30,5)
    assert helix.center_xyz == pytest.approx((30, 5, 2)) and helix.geometry.radius == pytest.approx(
        5.0
    )
    assert helix.start_xyz == pytest.approx((25, 5, 2)) and helix.end_xyz == pytest.approx(
        (30, 0, 0)
    )


FEED_PROGRAM = (
    "N10 G17 G90 T1 D1 G1 X0 Y20 Z10 F900\n"
    "N20 G41 G147 {seg} DISR=5 DISCL=2 {fad} X30 Y0 Z0 F300\n"
    "N30 G1 X60\nN40 G40 G0 X70 Y20\nM30\n"
)


@pytest.mark.parametrize(
    ("seg", "fad", "expected"),
    [
        # G341: P0→P1, P1→P2 old feed; P2→P3 FAD (else F); P3→P4 F.  (§D-10a)
        ("G341", "", [900, 900, 300, 300]),
        ("G341", "FAD=150", [900, 900, 150, 300]),
        ("G341", "FAD=PM(120)", [900, 900, 120, 300]),
        # G340: P0→P1, P1→P3 old feed; FAD on the slanted line up to P4, F from P4 on
        ("G340", "", [900, 900, 300]),
        ("G340", "FAD=150", [900, 900, 150]),
    ],
)
def test_approach_feeds(seg: str, fad: str, expected: list[float]) -> None:
    nc, moves, diags = expand(FEED_PROGRAM.format(seg=seg, fad=fad))
    assert diags == []
    sar = [m for m in moves if m.span.block == "N20"]
    assert [round(m.feed_mm_s * 60.0, 9) for m in sar] == expected
    n30 = next(m for m in moves if m.span.block == "N30")
    assert n30.feed_mm_s * 60.0 == pytest.approx(300.0)  # the SAR block's F from P4 on


def test_fad_pr_is_the_value_per_revolution_times_the_spindle_speed() -> None:
    nc, moves, diags = expand("S1500 M3\n" + FEED_PROGRAM.format(seg="G341", fad="FAD=PR(0.2)"))
    assert diags == [] and nc.diagnostics == ()
    sar = [m for m in moves if m.span.block == "N20"]
    assert sar[2].feed_mm_s * 60.0 == pytest.approx(0.2 * 1500)  # FAD 0.2 mm/rev at S1500


def test_fad_pr_without_a_turning_spindle_is_an_error_at_the_fad_word() -> None:
    text = FEED_PROGRAM.format(seg="G341", fad="FAD=PR(0.2)")
    nc, _, _ = expand(text)
    (err,) = nc.diagnostics
    assert err.code == "NC-FEED-MODE" and err.span.block == "N20"
    assert err.span.column == text.splitlines()[1].index("FAD") + 1
    assert "no spindle speed S programmed" in err.message


def test_approach_motion_type_before_the_sar_block() -> None:
    """R43: rapid up to P2/P3 when G0 was active; a G0 SAR block's F applies to the contour."""
    nc, moves, _ = expand(
        "N10 G17 G90 T1 D1 G0 X0 Y20 Z10\nN20 G41 G147 DISR=5 DISCL=2 X30 Y0 Z0 F300\n"
        "N30 G1 X60\nM30\n"
    )
    sar = [m for m in moves if m.span.block == "N20"]
    assert [m.kind for m in sar] == [MoveKind.RAPID, MoveKind.RAPID, MoveKind.LINE]
    assert sar[2].feed_mm_s * 60.0 == pytest.approx(300.0)


RETRACT_PROGRAM = (
    "N10 G17 G90 T1 D1 G0 X0 Y-20 Z0\nN20 G41 G1 X0 Y0 F500\nN30 X40\n"
    "N40 G40 {contour} {seg} DISR=10 DISCL=2 {fad} {end} F2000 M9\nN50 G0 X100\nM30\n"
)


@pytest.mark.parametrize(
    ("seg", "fad", "expected"),
    [
        ("G341", "", [500, 500, 2000, 2000]),  # contour + P3→P2 old feed (§D-10), F from P2
        ("G341", "FAD=100", [500, 100, 2000, 2000]),  # FAD on the mirrored P3→P2
        ("G340", "", [500, 2000, 2000]),
        ("G340", "FAD=100", [100, 2000, 2000]),  # FAD on the mirrored P4→P3
    ],
)
def test_retraction_feeds_and_deactivation(seg: str, fad: str, expected: list[float]) -> None:
    nc, moves, diags = expand(
        RETRACT_PROGRAM.format(contour="G148", seg=seg, fad=fad, end="X60 Y20 Z10")
    )
    assert diags == []
    sar = [m for m in moves if m.span.block == "N40"]
    assert [round(m.feed_mm_s * 60.0, 9) for m in sar] == expected
    assert all(m.origin == "retract" for m in sar)
    assert [m.comp.side for m in sar] == [Side.LEFT] * (len(sar) - 1) + [
        Side.OFF
    ]  # G40 on the last
    assert (
        sar[-1].actions and "M9" in sar[-1].actions and all("M9" not in m.actions for m in sar[:-1])
    )
    assert sar[-1].end == pytest.approx((60, 20, 10))
    segs, tdiags = toolpath(moves)
    assert not errors(tdiags)
    assert segs[-2].role is Role.RETRACT and segs[-2].end_xyz == pytest.approx((60, 20, 10))


def test_retraction_without_geometry_axes_ends_in_p2_and_the_program_continues_there() -> None:
    nc, moves, diags = expand(RETRACT_PROGRAM.format(contour="G148", seg="G341", fad="", end=""))
    assert diags == []
    sar = [m for m in moves if m.span.block == "N40"]
    assert sar[-1].end == pytest.approx((55, 0, 2))
    n50 = next(m for m in moves if m.span.block == "N50")
    assert n50.start == pytest.approx((55, 0, 2)) and n50.end == pytest.approx((100, 0, 2))


def test_retraction_with_only_the_applicate_ends_in_p1() -> None:
    nc, moves, diags = expand(RETRACT_PROGRAM.format(contour="G248", seg="G341", fad="", end="Z15"))
    assert diags == []
    sar = [m for m in moves if m.span.block == "N40"]
    # G140 with G41 → left; ρp = 10 + 5 = 15, M = (40, 15), P3 = M + 15·t = (55, 15)
    assert sar[-1].end == pytest.approx((55, 15, 15))
    n50 = next(m for m in moves if m.span.block == "N50")
    assert n50.start == pytest.approx((55, 15, 15)) and n50.end == pytest.approx((100, 15, 15))


def test_retraction_g143_without_end_point_is_10747() -> None:
    nc, moves, diags = expand(
        RETRACT_PROGRAM.format(contour="G248 G143", seg="G341", fad="", end="")
    )
    assert errors(diags) == [(10747, 5, "N40")]
    assert all(
        m.span.block != "N40" and m.span.block != "N50" for m in moves
    )  # nothing after the alarm


# ---- P4 and the tangent from later blocks (R45) -------------------------------------------------


def test_p4_from_the_next_block_with_dummy_blocks_in_between() -> None:
    nc, moves, diags = expand(
        "N10 G17 G90 T1 D1 G0 X0 Y20 Z10\nN20 G41 G147 DISR=5 DISCL=2 Z0 F300\nN22 M8\n"
        "N24 M3 S1000\n"
        "N30 G1 X30 Y0\nN35 M7\nN40 X60\nM30\n"
    )
    assert diags == []
    blocks = [(m.span.block, m.kind, m.origin) for m in moves]
    i = blocks.index(("N22", MoveKind.NONE, "approach"))
    assert blocks[i + 1] == ("N24", MoveKind.NONE, "approach")
    assert blocks[i + 2] == ("N30", MoveKind.LINE, "approach")  # the lead line is traversed in N30
    assert blocks[i + 3][0] == "N35" and blocks[i + 4][0] == "N40"
    n30 = moves[i + 2]
    assert n30.start == pytest.approx((20, 0, 2)) and n30.end == pytest.approx((30, 0, 0))
    segs, tdiags = toolpath(moves)
    assert not errors(tdiags)


@pytest.mark.parametrize(
    ("dummies", "limit", "alarm"), [(5, 5, None), (6, 5, 10740), (2, 1, 10740)]
)
def test_too_many_dummy_blocks_md20202(dummies: int, limit: int, alarm) -> None:
    filler = "".join(f"N{21 + k} M{k + 10}\n" for k in range(dummies))
    nc, moves, diags = expand(
        "N10 G17 G90 T1 D1 G0 X0 Y20 Z10\nN20 G41 G147 DISR=5 DISCL=2 X30 Y0 Z0 F300\n"
        + filler
        + "N30 G1 X60\nM30\n",
        TrcSettings(wab_maxnum_dummy_blocks=limit),
    )
    if alarm is None:
        assert diags == []
    else:
        assert errors(diags) == [(10740, 3 + limit + 1, f"N{21 + limit}")]
        assert all(m.span.block not in ("N20", "N30") for m in moves)


def test_preprocessing_stop_between_sar_block_and_tangent_block() -> None:
    nc, moves, diags = expand(
        "N10 G17 G90 T1 D1 G0 X0 Y20 Z10\nN20 G41 G147 DISR=5 DISCL=2 X30 Y0 Z0 F300\n"
        "N25 STOPRE\nN30 G1 X60\nM30\n"
    )
    assert errors(diags) == [(PREPROCESSING_STOP, 4, "N25")]


def test_no_direction_after_the_sar_block_is_10744() -> None:
    nc, moves, diags = expand(
        "N10 G17 G90 T1 D1 G0 X0 Y20 Z10\nN20 G41 G147 DISR=5 X30 Y0 Z0 F300\nN30 M9\nM30\n"
    )
    assert [e[0] for e in errors(diags)] == [10744]


def test_second_sar_block_before_the_direction_is_10743() -> None:
    nc, moves, diags = expand(
        "N10 G17 G90 T1 D1 G0 X0 Y20 Z10\nN20 G41 G147 DISR=5 F300\nN30 G147 DISR=5 X30 Y0 Z0\n"
        "N40 G1 X60\nM30\n"
    )
    assert errors(diags) == [(10743, 4, "N30")]


def test_alarm_diagnostics_carry_line_and_block_number() -> None:
    nc, moves, diags = expand(
        "N10 G17 G90 T1 D1 G0 X0 Y20 Z10\nN20 G41 G247 X30 Y0 Z0 F300\nN30 G1 X60\nM30\n", r=10.0
    )
    (d,) = diags
    assert d.alarm == 10742 and d.code == "10742" and d.span.line == 3 and d.span.block == "N20"
    assert d.format().startswith("t.mpf:3:")


def test_tangent_from_an_arc_block() -> None:
    """The approach tangent is the start tangent of the following block, here a G2 arc."""
    nc, moves, diags = expand(
        "N10 G17 G90 T1 D1 G0 X0 Y30 Z10\nN20 G41 G147 DISR=5 X20 Y0 Z0 F300\n"
        "N30 G2 X40 Y0 I10 J0\nN40 G1 X50\nM30\n"
    )
    assert diags == []
    lead = next(m for m in moves if m.origin == "approach" and m.kind is MoveKind.LINE)
    # the G2 arc centred at (30,0) starts at (20,0) heading +Y: P3 = P4 − 10·(0,1); without
    # DISCL (G340) P3 stays at the level of P1 and the line descends to P4 (§D-3)
    assert lead.start == pytest.approx((20, -10, 10)) and lead.end == pytest.approx((20, 0, 0))


def test_g18_plane_quadrant() -> None:
    nc, moves, diags = expand(
        "N10 G18 G90 T1 D1 G0 X20 Y10 Z0\nN20 G41 G247 DISR=5 DISCL=2 Z30 X0 Y0 F300\n"
        "N30 G1 Z60\nM30\n"
    )
    assert diags == []
    arc = next(m for m in moves if m.kind is MoveKind.ARC)
    # G18: (u, v, w) = (Z, X, Y); tangent +u; left side → centre at v = 0 + ρp = 10
    assert arc.end == pytest.approx((0, 0, 30)) and arc.center == pytest.approx((10, 2, 30))
