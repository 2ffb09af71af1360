"""The rs274 reader, the .tbl tool table, the linuxcnc profile's rules on small programs, and
the tool-centre G-code trcopt writes re-read as RS274NGC."""

from __future__ import annotations

import math

import pytest

from trcopt import controllers
from trcopt.controllers import read_program
from trcopt.controllers.linuxcnc.tooltable import parse_tbl
from trcopt.errors import ConfigError, Severity
from trcopt.io import check_gcode_arcs, toolpath_to_gcode
from trcopt.modes import Side
from trcopt.nc.model import MoveKind
from trcopt.pipeline import PlanOptions, plan

TBL = "T1 P1 D0.25 Z0.5 ;quarter inch\nT2 P2 D6.0 ;metric mill\n"


def _plan(text: str, **kw):  # type: ignore[no-untyped-def]
    return plan(text, file="t.ngc", options=PlanOptions(dialect="rs274", timing=False, **kw))


def test_tbl_unit_is_explicit() -> None:
    inch = parse_tbl(TBL, "inch")
    assert inch.get(1).diameter_mm == pytest.approx(6.35)  # type: ignore[union-attr]
    assert inch.get(1).radius_mm == pytest.approx(3.175)  # type: ignore[union-attr]
    assert parse_tbl(TBL, "mm").get(2).radius_mm == pytest.approx(3.0)  # type: ignore[union-attr]
    with pytest.raises(ConfigError, match="unit"):
        parse_tbl(TBL, "furlong")
    with pytest.raises(ConfigError, match="unknown word"):
        parse_tbl("T1 P1 K3\n")
    with pytest.raises(ConfigError, match="twice"):
        parse_tbl("T1 D1\nT1 D2\n")


def test_reader_units_incremental_and_arcs() -> None:
    prog = read_program(
        "G20 G90 F10 (comment)\nG1 X1 Y0 ; tail\nG91 G1 X1\nG90 G3 X3 Y1 I0 J1\nG2 X4 Y0 R1\nM2\nG1 X9\n",
        dialect="rs274",
    )
    assert not prog.diagnostics
    moves = [m for m in prog.moves if m.kind is not MoveKind.NONE]
    assert moves[0].end == pytest.approx((25.4, 0.0, 0.0))
    assert moves[1].end == pytest.approx((50.8, 0.0, 0.0))
    assert moves[2].center == pytest.approx((50.8, 25.4, 0.0)) and moves[2].ccw
    assert moves[3].center == pytest.approx((76.2, 0.0, 0.0), abs=1e-9) and not moves[3].ccw
    assert moves[0].feed_mm_s == pytest.approx(10 * 25.4 / 60)
    assert moves[-1].end[0] == pytest.approx(101.6)  # nothing after M2


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        ("M98 P1000 X1\nM2\nO1000\nM99\n", "M98 with other words"),
        ("G41.1 D1 G1 X10 F1\nG1 X#<_x>\n", "#<_x>"),  # the position under compensation
        ("G76 P1 Z-1 I1 J1 K1\n", "G76"),
        ("G96 S100\n", "G96"),
        ("M98 P100 L0\nM2\nO100\nM99\n", "M98 L0"),
    ],
)
def test_unsupported_features_are_named(text: str, fragment: str) -> None:
    prog = read_program(text, dialect="rs274")
    err = [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert err and err[0].code == "NC-UNSUPPORTED" and fragment in err[0].message


def test_arc_radius_mismatch_is_an_error() -> None:
    prog = read_program("G21 F100\nG1 X0 Y0\nG2 X10 Y0 I5.2 J0\n", dialect="rs274")
    assert prog.diagnostics[-1].code == "LCNC-ARC-RADIUS"


def test_tool_table_d_word_and_g41_1_diameter(tmp_path) -> None:  # type: ignore[no-untyped-def]
    (tmp_path / "p.tbl").write_text(TBL)
    src = tmp_path / "p.ngc"
    src.write_text(
        "G21 F100\nT1 M6\nG41 G1 X20 Y0\nG1 X40\nG40 G1 X50\nG42.1 D4 G1 X60 Y-20\nG40 G1 X70\nM2\n"
    )
    prog = read_program(src, dialect="rs274", tool_unit="inch")
    comps = [m.comp for m in prog.moves if m.kind is MoveKind.LINE]
    assert comps[0].side is Side.LEFT and comps[0].radius == pytest.approx(3.175)  # T1, inch table
    assert comps[3].side is Side.RIGHT and comps[3].radius == pytest.approx(2.0)  # D = diameter
    assert any(d.code == "LCNC-TOOL-TABLE" and "inch" in d.message for d in prog.diagnostics)
    # by default the table is in the program's unit: D0.25 in a G21 program is 0.25 mm
    prog = read_program(src, dialect="rs274")
    comps = [m.comp for m in prog.moves if m.kind is MoveKind.LINE]
    assert comps[0].radius == pytest.approx(0.125)
    assert any(d.code == "LCNC-TOOL-TABLE" and "program's unit" in d.message for d in prog.diagnostics)


def _square(extra: str = "") -> str:
    return (
        "G21 F600\nG0 X-20 Y0\n"
        f"G41.1 D10 {extra}G1 X0 Y0\n"
        "G1 X40\nY30\nX0\nY5\nG40 G1 X-20 Y5\nM2\n"
    )


def test_outside_corners_are_tool_radius_arcs_and_entry_is_perpendicular() -> None:
    r = _plan(_square().replace("G41.1", "G42.1"))
    assert r.ok, [d.format() for d in r.errors]
    tp = r.toolpath
    entry = tp[1]
    assert entry.role.value == "approach"
    assert entry.end_xyz == pytest.approx((0.0, -5.0, 0.0))  # perpendicular to the entry line
    corners = [s for s in tp if s.role.value == "corner"]
    assert len(corners) == 3
    for c in corners:
        assert c.kind == "arc" and c.geometry.radius == pytest.approx(5.0)  # type: ignore[union-attr]
    assert tp[-1].role.value == "retract" and tp[-1].start_xyz == pytest.approx((-5.0, 5.0, 0.0))


def test_inside_corners_are_trimmed_to_the_intersection() -> None:
    r = _plan(_square())  # G41 on a CCW square: every corner is inside
    assert r.ok
    contour = [s for s in r.toolpath if s.role.value == "contour"]
    assert [s.end_xyz[:2] for s in contour[:3]] == [
        pytest.approx((35.0, 5.0)),
        pytest.approx((35.0, 25.0)),
        pytest.approx((5.0, 25.0)),
    ]
    assert not [s for s in r.toolpath if s.role.value == "corner"]


def test_negative_diameter_swaps_the_side() -> None:
    a = _plan(_square().replace("G41.1 D10", "G41.1 D-10"))
    b = _plan(_square().replace("G41.1 D10", "G42.1 D10"))
    assert len(a.toolpath) == len(b.toolpath)
    flat_a = [c for s in a.toolpath for c in s.end_xyz]
    flat_b = [c for s in b.toolpath for c in s.end_xyz]
    assert flat_a == pytest.approx(flat_b, abs=1e-9)


@pytest.mark.parametrize(
    ("text", "code"),
    [
        ("G21 F100\nG41.1 D10 G1 X4\nX20\nG40 X30\nM2\n", "LCNC-ENTRY-TOO-SHORT"),
        ("G21 F100\nG41.1 D10 G1 X20\nG41.1 D10 X30\nM2\n", "LCNC-COMP-ALREADY-ON"),
        ("G21 F100\nG41.1 D10 G1 X20\nG19 X30\nM2\n", "LCNC-COMP-ACTIVE"),  # a plane change
        ("G21 F100\nG19 G41.1 D10 G1 Y20\nM2\n", "LCNC-YZ-PLANE"),
        (
            "G21 F100\nG41.1 D10 G1 X20\nG3 X30 Y10 J10\nG3 X34 Y10 I2\nG40 G1 X40\nM2\n",
            "LCNC-ARC-TOO-SMALL",
        ),
    ],
)
def test_linuxcnc_errors(text: str, code: str) -> None:
    r = _plan(text)
    assert not r.ok and r.errors[0].code == code


def test_near_tangent_join_is_left_untouched() -> None:
    # 0.02 rad kink (< 0.05): no arc, no trim — the next line starts where the tool is
    y = 20 * math.tan(0.02)
    r = _plan(f"G21 F100\nG42.1 D4 G1 X20 Y0\nX40\nX60 Y{y:.6f}\nG40 X80\nM2\n")
    assert r.ok
    contour = [s for s in r.toolpath if s.role.value == "contour"]
    assert contour[1].start_xyz == pytest.approx(contour[0].end_xyz)
    assert not [s for s in r.toolpath if s.role.value == "corner"]


def test_rapid_corner_gets_no_arc() -> None:
    r = _plan("G21 F100\nG42.1 D4 G1 X20 Y0\nG0 X40\nY20\nG1 X0\nG40 X-20\nM2\n")
    assert r.ok
    corners = [s for s in r.toolpath if s.role.value == "corner"]
    assert corners and all(s.kind == "rapid" for s in corners if s.span.line == 4)


@pytest.mark.parametrize("variant", ["G41.1", "G42.1"])
def test_written_gcode_is_valid_rs274(variant: str) -> None:
    text = (
        "G21 F600\nG0 X-20 Y0 Z5\nG1 Z-1\n"
        f"{variant} D6 G1 X0 Y0\nG1 X40\nG3 X50 Y10 R10\nG1 Y30\nG2 X40 Y40 I-10 J0\nG1 X5\nG3 X0 Y35 J-5\nG1 Y5\n"
        "G40 G1 X-20 Y5\nG0 Z5\nM2\n"
    )
    r = _plan(text)
    assert r.ok, [d.format() for d in r.errors]
    gcode = toolpath_to_gcode(r.toolpath, flavor=controllers.get("rs274").gcode, program_name="t.ngc")
    assert check_gcode_arcs(gcode) == []
    assert "G41" not in gcode and "G42" not in gcode
    again = read_program(gcode, dialect="rs274")
    assert not [d for d in again.diagnostics if d.severity is Severity.ERROR], [
        d.format() for d in again.diagnostics
    ]
    moved = [m for m in again.moves if m.kind is not MoveKind.NONE]
    assert moved[-1].end == pytest.approx(r.toolpath[-1].end_xyz, abs=1e-4)
    # the re-read plain program runs through the pipeline unchanged (compensation off) …
    back = _plan(gcode, corners="exact")
    assert back.ok
    ends = [s.end_xyz for s in back.toolpath]
    for seg in r.toolpath:
        assert min(math.dist(seg.end_xyz, e) for e in ends) < 1e-3
    # … and with its continuous-path word (G64 P0.001 Q0, written when there are transition arcs:
    # G42.1 has outside corners) the remaining sharp corners are rounded within 1 µm of their points
    corners = _plan(gcode).extra.get("corners")
    assert ("G64 P0.001 Q0" in gcode) == (variant == "G42.1") == (corners is not None)
    assert corners is None or 0.0 < corners["max_vertex_mm"] <= 0.001 + 1e-12
