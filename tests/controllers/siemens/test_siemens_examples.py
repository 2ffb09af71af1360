"""Every example program of spec §C (sinumerik_trc.md) read by the SINUMERIK front end."""

from __future__ import annotations

import math

import pytest

from trcopt.controllers import read_program
from trcopt.errors import Severity
from trcopt.geometry.plane import Plane
from trcopt.modes import (
    ApproachMode,
    ApproachStrategy,
    CollisionMode,
    CornerMode,
    LeadSegmentation,
    LeadSide,
    SarContour,
    Side,
)
from trcopt.nc import MoveKind, ToolEdge

MILL5 = {(1, 1): ToolEdge(type=120, radius=5.0)}
MILL4 = {(1, 1): ToolEdge(type=120, radius=4.0)}

EX1 = """\
N10 $TC_DP1[1,1]=120 ; milling tool
N20 $TC_DP6[1,1]=10  ; radius
N30 X0 Y0 F10000 T1 D1
N40 Y20
N50 G42 X50 Y5 G461
N60 Y0 F600
N70 X30
N80 X20 Y-5
N90 X0 Y0 G40
N100 M30
"""

EX2 = """\
$TC_DP1[1,1]=120  $TC_DP6[1,1]=5
N10 G17 G90 T1 D1 G0 X-20 Y-20 Z0
N20 G1 G41 NORM G450 X0 Y0 F500
N30 Y40
N40 X40
N50 Y0
N60 X0
N70 G40 X-20 Y-20
M30
"""

EX3 = """\
N10 G17 G90 T1 D1 G0 X-10 Y10
N20 G1 G41 X0 Y0 F300          ; NORM
N30 X20
N40 G2 X40 Y20 I20 J0          ; centre (40,0), rho 20, CW
N50 G3 X60 Y40 I0 J20          ; centre (40,40), rho 20, CCW (concave for G41)
N60 G1 Y60
N70 G40 X40 Y80
M30
"""

EX4 = """\
N10 G17 G90 T1 D1 G0 X-10 Y10
N20 G1 G41 G450 X0 Y0 F300
N30 X20 Y0
N40 X40 Y-2
N50 G40 X50 Y-10
M30
"""

EX5 = """\
N10 G17 T1 G0 X35 Y0 Z0 F500
N20 G1 Z-5
N30 G41 KONT G450 X10 Y10
N40 Y60
N50 X50 Y30
N60 X10 Y10
N80 G40 X-20 Y50       ; manual comment: retract on transition circle
N90 G0 Y100
N100 X200 M30
"""

EX6 = """\
N10 G17 T1 D1 G0 X-10 Y10
N20 G1 G41 X0 Y0 F400   ; NORM
N30 X20                 ; L1
N40 Y-20                ; L2
N50 X26                 ; L3 (slot width 6 < 2R)
N60 Y0                  ; L4
N70 X50                 ; L5
N80 G40 X60 Y10
M30
"""

EX7 = """\
$TC_DP1[1,1]=120  $TC_DP6[1,1]=7
N10 G90 G0 X0 Y0 Z30 D1 T1
N20 X10
N30 G41 G147 DISCL=3 DISR=13 Z=0 F1000
N40 G1 X40 Y-10
N50 G1 X50
M30
"""

EX8 = """\
$TC_DP1[1,1]=120  $TC_DP6[1,1]=7
N10 G90 G0 X0 Y0 Z20 D1 T1
N20 G41 G341 G247 DISCL=AC(5) DISR=13 FAD 500 X40 Y-10 Z=0 F200
N30 X50
N40 X60
M30
"""

EX9 = """\
$TC_DP1[1,1]=120  $TC_DP6[1,1]=10
N10 G0 X0 Y0 Z20 G64 D1 T1 OFFN=5
N20 G41 G247 G341 Z0 DISCL=AC(7) DISR=10 F1500 FAD=200
N30 G1 X30 Y-10
N40 X40 Z2
N50 X50
N60 G248 G340 X70 Y0 Z20 DISCL=6 DISR=5 G40 F10000
N70 X80 Y0
N80 M30
"""

EX10 = """\
N10 G17 G90 T1 D1 G0 X0 Y30 Z10
N20 G42 G347 G340 G143 DISR=6 DISCL=2 F300 X20 Y0 Z-5
N30 G1 X60
M30
"""

EX11 = """\
N10 G17 G90 T1 D1 G0 X0 Y20 Z0
N20 G1 G41 X20 Y0 F1000
N40 G1 X40 Y0
N50 G40 G148 G341 DISR=10 DISCL=2 X60 Y20 Z10 F2000
M30
"""

EX12 = """\
$TC_DP1[1,1]=120  $TC_DP6[1,1]=10
N10 G17 G90 T1 D1 G0 X0 Y30 Z20
N20 G41 G247 G142 DISR=8 X20 Y0 Z0 F500
N30 G1 X60
N40 G147 DISR=-12 X70
N50 G147 DISR=-9.5 X80
N60 G247 X90
N70 G341 G247 DISCL=AC(25) DISR=5 X100
N80 G341 G247 DISCL=AC(20.005) DISR=5 X110
N90 G248 G143 G40 DISR=5
N100 M30
"""

EXAMPLES = {
    "ex1": (EX1, None),
    "ex2": (EX2, None),
    "ex3": (EX3, MILL5),
    "ex4": (EX4, MILL5),
    "ex5": (EX5, MILL5),
    "ex6": (EX6, MILL5),
    "ex7": (EX7, None),
    "ex8": (EX8, {(1, 1): {"type": 120, "radius": 7.0}}),
    "ex9": (EX9, None),
    "ex10": (EX10, MILL4),
    "ex11": (EX11, MILL5),
    "ex12": (EX12, None),
}


def by_block(prog):
    return {m.span.block: m for m in prog.moves if m.span.block}


def errors(prog):
    return [d for d in prog.diagnostics if d.severity is Severity.ERROR]


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_example_reads_without_errors(name):
    text, tools = EXAMPLES[name]
    prog = read_program(text, file=f"{name}.mpf", tools=tools)
    assert errors(prog) == []
    assert prog.dialect == "siemens"
    assert not any(d.code == "NC-NO-END" for d in prog.diagnostics)
    assert len(prog.moves) == prog.blocks
    # moves chain: each starts where the previous ended
    for a, b in zip(prog.moves, prog.moves[1:], strict=False):
        assert b.start == a.end


def test_example1_modal_state_and_feeds():
    prog = read_program(EX1, file="ex1.mpf")
    m = by_block(prog)
    assert prog.blocks == 10
    assert m["N10"].kind is MoveKind.NONE and m["N10"].plane_programmed is False
    assert m["N30"].kind is MoveKind.LINE  # G1 is the default motion
    assert m["N30"].feed_mm_s == pytest.approx(10000 / 60)
    assert m["N40"].end == (0.0, 20.0, 0.0)
    n50 = m["N50"]
    assert n50.end == (50.0, 5.0, 0.0)
    assert n50.comp.side is Side.RIGHT and n50.comp.side_programmed
    assert n50.comp.strategy is ApproachStrategy.G461
    assert n50.feed_mm_s == pytest.approx(10000 / 60)
    n60 = m["N60"]
    assert n60.start == (50.0, 5.0, 0.0) and n60.end == (50.0, 0.0, 0.0)
    assert n60.comp.side is Side.RIGHT and not n60.comp.side_programmed
    assert n60.comp.radius == 10.0 and n60.comp.tool_active
    assert n60.comp.strategy is ApproachStrategy.G461
    assert n60.feed_mm_s == pytest.approx(10.0)
    assert n60.actions == ("F600",)
    assert n60.span.line == 6 and n60.span.column == 5
    assert m["N80"].end == (20.0, -5.0, 0.0)
    n90 = m["N90"]
    assert n90.comp.side is Side.OFF and n90.comp.side_programmed
    assert m["N100"].actions == ("M30",)
    assert m["N30"].actions == ("F10000", "T1", "D1")
    assert prog.extras["tools"][(1, 1)] == ToolEdge(type=120, radius=10.0)


def test_example1_with_g460_reads_the_same_geometry():
    prog = read_program(EX1.replace("G461", "G460"))
    assert errors(prog) == []
    assert by_block(prog)["N60"].comp.strategy is ApproachStrategy.G460


def test_example2_square():
    prog = read_program(EX2)
    m = by_block(prog)
    assert prog.moves[0].span.block is None and prog.moves[0].kind is MoveKind.NONE
    assert m["N10"].kind is MoveKind.RAPID and m["N10"].feed_mm_s is None
    assert m["N10"].end == (-20.0, -20.0, 0.0)
    n20 = m["N20"]
    assert n20.comp.side is Side.LEFT and n20.comp.radius == 5.0
    assert n20.comp.approach is ApproachMode.NORM
    assert n20.comp.corner is CornerMode.TRANSITION_CIRCLE
    assert n20.feed_mm_s == pytest.approx(500 / 60)
    ends = [m[f"N{n}"].end[:2] for n in (30, 40, 50, 60, 70)]
    assert ends == [(0.0, 40.0), (40.0, 40.0), (40.0, 0.0), (0.0, 0.0), (-20.0, -20.0)]
    g451 = by_block(read_program(EX2.replace("G450", "G451")))
    assert g451["N30"].comp.corner is CornerMode.INTERSECTION


def test_example3_arcs():
    m = by_block(read_program(EX3, tools=MILL5))
    n40, n50 = m["N40"], m["N50"]
    assert n40.kind is MoveKind.ARC and n40.ccw is False
    assert n40.start == (20.0, 0.0, 0.0) and n40.end == (40.0, 20.0, 0.0)
    assert n40.center == pytest.approx((40.0, 0.0, 0.0))
    assert n50.kind is MoveKind.ARC and n50.ccw is True
    assert n50.center == pytest.approx((40.0, 40.0, 0.0))
    assert n50.end == (60.0, 40.0, 0.0)
    assert m["N60"].kind is MoveKind.LINE and m["N60"].end == (60.0, 60.0, 0.0)
    assert n40.feed_mm_s == pytest.approx(5.0)
    assert n40.comp.radius == 5.0 and n40.comp.side is Side.LEFT


def test_example4_almost_tangential_corner():
    m = by_block(read_program(EX4, tools=MILL5))
    assert m["N40"].start == (20.0, 0.0, 0.0) and m["N40"].end == (40.0, -2.0, 0.0)


def test_example5_kont_and_tool_without_data():
    prog = read_program(EX5, tools=MILL5)
    m = by_block(prog)
    assert m["N10"].kind is MoveKind.RAPID and m["N10"].end == (35.0, 0.0, 0.0)
    # F500 in a G0 block is stored modally
    assert m["N20"].kind is MoveKind.LINE and m["N20"].feed_mm_s == pytest.approx(500 / 60)
    assert m["N20"].end == (35.0, 0.0, -5.0) and m["N20"].plane_programmed is False
    n30 = m["N30"]
    assert n30.comp.approach is ApproachMode.KONT and n30.comp.side is Side.LEFT
    assert n30.comp.tool_active and n30.comp.radius == 5.0  # T1 activates edge D1
    assert m["N80"].comp.approach is ApproachMode.KONT
    assert m["N90"].kind is MoveKind.RAPID and m["N90"].end == (-20.0, 100.0, -5.0)
    assert m["N100"].end == (200.0, 100.0, -5.0) and "M30" in m["N100"].actions
    # without any tool data, G41 with T1 D1 is alarm 10750 naming the edge and where it was looked for
    plain = read_program(EX5)
    err = plain.diagnostics[-1]
    assert err.alarm == 10750 and err.span.block == "N30"
    assert "T1 D1" in err.message and "no tool table" in err.message and "$TC_DP" in err.message
    assert "N30" not in by_block(plain)


def test_example6_bottleneck_program():
    m = by_block(read_program(EX6, tools=MILL5))
    assert [m[f"N{n}"].end[:2] for n in (30, 40, 50, 60, 70, 80)] == [
        (20.0, 0.0), (20.0, -20.0), (26.0, -20.0), (26.0, 0.0), (50.0, 0.0), (60.0, 10.0)
    ]  # fmt: skip
    assert m["N50"].comp.collision is CollisionMode.CDOF
    cdon = by_block(read_program("CDON\n" + EX6, tools=MILL5))
    assert cdon["N50"].comp.collision is CollisionMode.CDON


def test_example7_sar_g147():
    m = by_block(read_program(EX7))
    n30 = m["N30"]
    assert n30.kind is MoveKind.RAPID  # G0 from N10 stays in force
    assert n30.end == (10.0, 0.0, 0.0) and n30.plane_programmed is False
    sar = n30.sar
    assert sar is not None and sar.contour is SarContour.G147
    assert sar.discl == (3.0, False) and sar.disr == 13.0
    assert sar.side is LeadSide.FROM_COMPENSATION and sar.segmentation is LeadSegmentation.SPATIAL
    assert sar.end_programmed == (False, False, True)
    assert n30.comp.side is Side.LEFT and n30.comp.radius == 7.0
    assert m["N40"].sar is None and m["N40"].feed_mm_s == pytest.approx(1000 / 60)
    assert m["N40"].end == (40.0, -10.0, 0.0)


def test_example8_sar_g247_fad_with_space():
    prog = read_program(EX8, tools={(1, 1): {"type": 120, "radius": 7.0}})
    n20 = by_block(prog)["N20"]
    sar = n20.sar
    assert sar.contour is SarContour.G247 and sar.segmentation is LeadSegmentation.PLANAR
    assert sar.discl == (5.0, True)
    assert sar.disr == 13.0
    assert sar.fad == (pytest.approx(500 / 60), "")
    assert sar.end_programmed == (True, True, True)
    assert n20.end == (40.0, -10.0, 0.0)
    assert n20.feed_mm_s is None  # G0 block; F200 is modal for later G1 blocks
    assert "F200" in n20.actions


def test_example9_offn_and_retraction():
    prog = read_program(EX9)
    m = by_block(prog)
    assert [d.code for d in prog.diagnostics] == []  # G64 is a path-control mode trcopt models
    assert m["N10"].control.word == "G64"
    assert "G64" in m["N10"].actions
    assert m["N10"].comp.radius == 15.0  # DP6 10 + OFFN 5
    n20 = m["N20"]
    assert n20.sar.contour is SarContour.G247 and n20.sar.discl == (7.0, True)
    assert n20.sar.disr == 10.0 and n20.sar.fad == (pytest.approx(200 / 60), "")
    assert n20.sar.end_programmed == (False, False, True)
    assert n20.sar.segmentation is LeadSegmentation.PLANAR
    n60 = m["N60"]
    assert n60.sar.contour is SarContour.G248 and n60.sar.segmentation is LeadSegmentation.SPATIAL
    assert n60.sar.discl == (6.0, False) and n60.sar.disr == 5.0 and n60.sar.fad is None
    assert n60.comp.side is Side.OFF and n60.comp.side_programmed
    assert n60.end == (70.0, 0.0, 20.0) and n60.kind is MoveKind.LINE
    assert n60.feed_mm_s == pytest.approx(10000 / 60)
    assert m["N40"].end == (40.0, -10.0, 2.0)


def test_example10_g347_g143():
    n20 = by_block(read_program(EX10, tools=MILL4))["N20"]
    assert n20.sar.contour is SarContour.G347 and n20.sar.side is LeadSide.AUTOMATIC
    assert n20.sar.disr == 6.0 and n20.sar.discl == (2.0, False)
    assert n20.comp.side is Side.RIGHT and n20.comp.radius == 4.0
    assert n20.end == (20.0, 0.0, -5.0)


def test_example11_retraction_g148():
    n50 = by_block(read_program(EX11, tools=MILL5))["N50"]
    assert n50.sar.contour is SarContour.G148 and n50.sar.segmentation is LeadSegmentation.PLANAR
    assert n50.sar.disr == 10.0 and n50.sar.discl == (2.0, False)
    assert n50.start == (40.0, 0.0, 0.0) and n50.end == (60.0, 20.0, 10.0)
    assert n50.feed_mm_s == pytest.approx(2000 / 60)


def test_example12_alarm_programs_are_readable():
    m = by_block(read_program(EX12))
    assert m["N20"].sar.side is LeadSide.RIGHT and m["N20"].sar.disr == 8.0
    assert m["N40"].sar.disr == -12.0
    assert m["N60"].sar.disr is None  # DISR is block-local: missing
    assert m["N70"].sar.discl == (25.0, True)
    assert m["N80"].sar.discl == (20.005, True)
    n90 = m["N90"]
    assert n90.sar.side is LeadSide.AUTOMATIC and n90.sar.end_programmed == (False, False, False)
    assert n90.kind is MoveKind.NONE  # no axis: the SAR engine raises 10747
    # G142/G341 remain modal
    assert m["N30"].sar is None
    assert m["N40"].sar.side is LeadSide.RIGHT


def test_example_moves_are_in_plane_g17():
    for text, tools in EXAMPLES.values():
        prog = read_program(text, tools=tools)
        assert all(m.plane is Plane.G17 for m in prog.moves)


def test_example3_arc_radius_equal_at_both_ends():
    m = by_block(read_program(EX3, tools=MILL5))
    for b in ("N40", "N50"):
        mv = m[b]
        rs = math.dist(mv.start[:2], mv.center[:2])
        re_ = math.dist(mv.end[:2], mv.center[:2])
        assert rs == pytest.approx(20.0) and re_ == pytest.approx(20.0)
