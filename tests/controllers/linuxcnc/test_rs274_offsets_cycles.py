"""Work offsets, G92, G28/G30, G53, tool words, canned cycles and messages of the rs274 reader.
Expected numbers are LinuxCNC's (``rs274`` output of the same programs, written down here), in
the G54 system, mm."""

from __future__ import annotations

import pytest

from trcopt.controllers import read_program
from trcopt.errors import Severity
from trcopt.nc.model import MoveKind
from trcopt.pipeline import PlanOptions, plan

TBL = "T1 P1 D0.125 Z0.511\nT2 P2 D0.0625 Z0.1\n"


def _read(text: str, tmp_path=None, tbl: str | None = None, unit: str = "program", toml: str | None = None):  # type: ignore[no-untyped-def]
    if tmp_path is None:
        return read_program(text, dialect="rs274", tool_unit=unit)
    if tbl is not None:
        (tmp_path / "p.tbl").write_text(tbl)
    if toml is not None:
        (tmp_path / "rs274ngc.toml").write_text(toml)
    src = tmp_path / "p.ngc"
    src.write_text(text)
    return read_program(src, dialect="rs274", tool_unit=unit)


def _ends(prog) -> list[tuple[float, ...]]:  # type: ignore[no-untyped-def]
    return [tuple(round(v, 4) for v in m.end) for m in prog.moves if m.kind is not MoveKind.NONE]


def _error(prog):  # type: ignore[no-untyped-def]
    return next(d for d in prog.diagnostics if d.severity is Severity.ERROR)


def test_work_offsets_g92_g53_and_g28_in_the_g54_system() -> None:
    prog = _read(
        "G21 G90\nG10 L2 P2 X10 Y20 Z5\nG0 X1 Y1\nG55 G0 X1 Y1\nG92 X0 Y0\nG1 X5 F100\n"
        "G53 G0 Z0\nG28\nG92.1\nG0 X0 Y0\nM2\n"
    )
    assert not [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    # rs274: (1,1,0) in G54; (1,1,-5) in G55 = (11,21,0); G92 shifts by (1,1); G53 Z0 and G28
    # (reference point 0) are machine coordinates = the G54 system here
    assert _ends(prog) == [
        (1.0, 1.0, 0.0), (11.0, 21.0, 0.0), (16.0, 21.0, 0.0), (16.0, 21.0, 0.0), (16.0, 21.0, 0.0),
        (0.0, 0.0, 0.0), (10.0, 20.0, 0.0),
    ]  # fmt: skip


def test_g10_l20_g92_3_and_parameters(tmp_path) -> None:  # type: ignore[no-untyped-def]
    prog = _read(
        "G21\nG0 X3 Y4\nG10 L20 P0 X0 Y0\nG0 X1\n(DEBUG,#5221 #5222 x=#<_x> abs=#<_abs_x>)\n"
        "G92 X10\nG92.2\nG0 X1\nG92.3\n(DEBUG,#5211 cs=#<_coord_system>)\nM2\n",
        tmp_path,
    )
    assert _ends(prog) == [(3.0, 4.0, 0.0), (4.0, 4.0, 0.0), (4.0, 4.0, 0.0)]
    notes = [d.message for d in prog.diagnostics if d.code == "LCNC-MESSAGE"]
    # rs274 prints the same in inch, its machine unit (0.118110 0.157480 … -0.354331)
    assert notes == ["DEBUG: 3.000000 4.000000 x=1.000000 abs=4.000000", "DEBUG: -9.000000 cs=540.000000"]


def test_reference_points_from_the_parameter_file(tmp_path) -> None:  # type: ignore[no-untyped-def]
    toml = "[parameters]\n5161 = 5.0\n5162 = 6.0\n5163 = 50.0\n5221 = -100.0\n"
    prog = _read("G21\nG0 X1 Y1 Z2\nG28 Z10\nG28\nG0 X0\nG30\nM2\n", tmp_path, toml=toml)
    # the machine starts at its origin: X100 in G54; G28 Z10 passes Z10, homes only Z
    assert prog.moves[0].start == pytest.approx((100.0, 0.0, 0.0))
    assert _ends(prog)[1:6] == [
        (1.0, 1.0, 10.0),
        (1.0, 1.0, 50.0),
        (1.0, 1.0, 50.0),
        (105.0, 6.0, 50.0),
        (0.0, 6.0, 50.0),
    ]


def test_tool_length_offset_and_the_tool_in_the_spindle(tmp_path) -> None:  # type: ignore[no-untyped-def]
    prog = _read(
        "G20\nG0 Z1\nT1 M6\nG43 H1\nG0 Z1\nG53 G0 Z0\nG49\nG0 Z1\nG41 G1 X1 Y0 F10\nG40 G1 X2\nM2\n",
        tmp_path, TBL, unit="inch",
    )  # fmt: skip
    z = [e[2] / 25.4 for e in _ends(prog)]
    # G43 H1: Z is the tool tip, 0.511 in below the spindle; G53 Z0 is the spindle at machine 0
    assert z[:4] == pytest.approx([1.0, 1.0, -0.511, 1.0], abs=1e-4)
    comp = [m.comp for m in prog.moves if m.kind is MoveKind.LINE]
    assert comp[0].radius == pytest.approx(0.0625 * 25.4)  # G41 without D: the spindle tool T1


def test_tool_table_in_the_program_unit_by_default(tmp_path) -> None:  # type: ignore[no-untyped-def]
    text = "G21 F100\nT2 M6\nG41 D2 G1 X10 Y0\nG1 X20\nG40 G1 X30\nM2\n"
    r_prog = [m.comp.radius for m in _read(text, tmp_path, "T2 P2 D10\n").moves if m.kind is MoveKind.LINE][0]
    r_inch = [
        m.comp.radius for m in _read(text, tmp_path, "T2 P2 D10\n", unit="inch").moves if m.kind is MoveKind.LINE
    ][0]
    assert r_prog == pytest.approx(5.0) and r_inch == pytest.approx(127.0)


def test_canned_cycles_expand_as_rs274() -> None:
    prog = _read(
        "G21 G90 G0 Z1 X0 Y0\nG81 X10 Y10 Z-5 R2 F100\nG0 Z10\nG83 X1 Y1 Z-5 R2 Q2\n"
        "G73 X2 Y2 Z-5 R2 Q2 L2 G91\nG90 G80\nM2\n"
    )
    # rs274 with its default peck clearance (1 program unit in a metric machine)
    assert _ends(prog)[:18] == [
        (0.0, 0.0, 1.0), (0.0, 0.0, 2.0), (10.0, 10.0, 2.0), (10.0, 10.0, -5.0), (10.0, 10.0, 2.0),
        (10.0, 10.0, 10.0), (1.0, 1.0, 10.0), (1.0, 1.0, 2.0), (1.0, 1.0, 0.0), (1.0, 1.0, 2.0),
        (1.0, 1.0, 1.0), (1.0, 1.0, -2.0), (1.0, 1.0, 2.0), (1.0, 1.0, -1.0), (1.0, 1.0, -4.0),
        (1.0, 1.0, 2.0), (1.0, 1.0, -3.0), (1.0, 1.0, -5.0),
    ]  # fmt: skip
    # G73 G91 L2: R and Z from the starting height 10, X/Y added on every repeat
    assert _ends(prog)[19:22] == [(1.0, 1.0, 12.0), (3.0, 3.0, 12.0), (3.0, 3.0, 10.0)]
    kinds = [m.kind for m in prog.moves if m.kind is not MoveKind.NONE]
    assert kinds[3] is MoveKind.LINE and kinds[4] is MoveKind.RAPID


@pytest.mark.parametrize(
    ("text", "code", "message", "line", "col"),
    [
        ("G21 F100\nG41.1 D2 G1 X10\nG81 X1 Y1 Z-1 R1\nM2\n", "LCNC-COMP-ACTIVE",
         "Cannot use canned cycles with cutter compensation on", 3, 1),
        ("G21 F100\nG41.1 D2 G1 X10\nN30 G1 X20 G64 P0.01\nM2\n", "LCNC-CONTROL-MODE",
         "Cannot change control mode with cutter radius compensation on", 3, 12),
        ("G21 F100\nT0 M6\nG41.1 D2 G1 X10\nT0 M6\nM2\n", "LCNC-COMP-ACTIVE",
         "Cannot change tools with cutter radius compensation on", 4, 4),
        ("G21 F100\nG41.1 D2 G1 X10\nG92 X0\nM2\n", "LCNC-COMP-ACTIVE",
         "Cannot change axis offsets with cutter radius comp", 3, 1),
        ("G21 F100\nG41.1 D2 G1 X10\nG55\nM2\n", "LCNC-COMP-ACTIVE",
         "Cannot change coordinate systems with cutter radius compensation on", 3, 1),
        ("G21 F100\nG81 X1 Y1 Z-1\nM2\n", "LCNC-CYCLE", "R clearance plane unspecified in cycle", 2, 1),
        ("G21 F100\nG82 X1 Y1 Z-1 R1\nM2\n", "LCNC-CYCLE", "Dwell time p word missing with g82", 2, 1),
        ("G21 F100\nG81 X1 Y1 Z2 R1\nM2\n", "LCNC-CYCLE", "R less than z in cycle in xy plane", 2, 1),
        ("G21 F100\nG84 X1 Y1 Z-1 R1\nM2\n", "LCNC-CYCLE", "Spindle not turning in G84", 2, 1),
        ("G21\nG91 G53 G0 Z0\nM2\n", "LCNC-OFFSET", "Cannot use g53 incremental", 2, 5),
        ("G21\nG10 L2 P12 X1\nM2\n", "LCNC-OFFSET", "P value out of range (0-9) with G10 L2", 2, 8),
        ("G21\nG92\nM2\n", "LCNC-OFFSET", "All axes missing with g52 or g92", 2, 1),
        ("G21\nG0 G1 X1\nM2\n", "LCNC-WORDS", "Two g codes used from same modal group", 2, 4),
        ("G21\nG0 X1 D1\nM2\n", "LCNC-WORDS",
         "D word with no G41, G41.1, G42, G42.1, G71, G71.1, G71.2 G73, G83 or G96 to use it", 2, 7),
        ("G21\nX1\nM2\n", "LCNC-WORDS", "Cannot use axis values without a g code that uses them", 2, 1),
        ("G21\nM98 P100 L0\nM2\n", "NC-UNSUPPORTED", "M98 L0 (no run) is not modelled", 2, 1),
        ("G21\nG33 Z-1 K1\nM2\n", "NC-UNSUPPORTED", "G33 is not supported by the rs274 reader", 2, 1),
        ("G21\n(ABORT, stop at #<_x>)\nM2\n", "LCNC-ABORT", " stop at 0.000000", 2, 1),
    ],
)  # fmt: skip
def test_refused_blocks_name_linuxcnc_error_and_place(text: str, code: str, message: str, line: int, col: int) -> None:
    prog = _read(text)
    if not any(d.severity is Severity.ERROR for d in prog.diagnostics):
        result = plan(text, file="t.ngc", options=PlanOptions(dialect="rs274", timing=False))
        err = result.errors[0]
    else:
        err = _error(prog)
    assert (err.code, err.message, err.span.line, err.span.column) == (code, message, line, col)


def test_messages_comments_with_semicolons_and_percent() -> None:
    prog = _read("%\nG21 (a; comment) (MSG, tool 1; check it)\n#1=2.5 (DEBUG, #1 %d#1 %.2f#1 #<nope>)\nM2\n%\n")
    notes = [d.message for d in prog.diagnostics if d.code == "LCNC-MESSAGE"]
    # the last comment of a line counts; DEBUG sees the line's own settings
    assert notes == ["MSG:  tool 1; check it", "DEBUG:  2.500000 2 2.50 ######"]
    assert prog.moves[0].actions == ('MSG(" tool 1; check it")',)


def test_cam_post_program_runs_end_to_end() -> None:
    from pathlib import Path

    from trcopt.pipeline import plan_file

    path = Path(__file__).resolve().parents[3] / "problems" / "rs274" / "cam_fusion_drill_profile.ngc"
    result = plan_file(path, PlanOptions(timing=False))  # the program's G64 P0.01 blends corners
    assert result.ok, [d.format() for d in result.errors]
    kinds = [s.kind for s in result.toolpath]
    assert kinds.count("arc") >= 6 and kinds.count("line") >= 8
    assert min(s.end_xyz[2] for s in result.toolpath) == pytest.approx(-8.0)  # the G81 bottom


@pytest.mark.parametrize(("unit", "ok"), [("G21", True), ("G20", False)])
def test_arc_sweep_slack_depends_on_the_program_unit(unit: str, ok: bool) -> None:
    # an arc trimmed by the inside corner after it sweeps 0.0096 rad more than programmed: within
    # LinuxCNC's slack in a metric program (0.0254), a gouge in an inch one (0.001)
    k = 1.0 if unit == "G21" else 1 / 25.4
    pts = [(0.754, 0.0354), (-6.3934, -3.5583), (-11.0178, -5.8697)]
    text = f"{unit} G17 G90 F100\nG0 X{pts[0][0] * k:.6f} Y{pts[0][1] * k:.6f}\n"
    text += f"G42.1 D{1.6682 * k:.6f} G1 X{pts[1][0] * k:.6f} Y{pts[1][1] * k:.6f}\n"
    text += f"G1 X{pts[2][0] * k:.6f} Y{pts[2][1] * k:.6f}\n"
    text += f"G2 X{-17.3955 * k:.6f} Y{-5.7655 * k:.6f} R{6.6145 * k:.6f}\nG1 X{-24.0437 * k:.6f} Y{-5.2871 * k:.6f}\n"
    text += f"G1 X{-38.6389 * k:.6f} Y{-4.2814 * k:.6f}\nG40 G1 X{-33.6389 * k:.6f} Y{0.7186 * k:.6f}\nM2\n"
    result = plan(text, file="t.ngc", options=PlanOptions(dialect="rs274", timing=False, corners="exact"))
    assert result.ok is ok
    if not ok:
        assert result.errors[0].code == "LCNC-CONCAVE-GOUGE-ARC"


def test_peer_bad_spirals_g10_l1_tool_and_linuxcnc_arc_message() -> None:
    # upstream tp-bad-spirals-comp: G10 L1 P1 R.5 writes tool 1, T1 M6 G41 takes it; rs274
    # stops at the spiral arc with this message (stderr.generated.txt of the peer case)
    from pathlib import Path

    from trcopt.pipeline import plan_file

    peer = Path(__file__).resolve().parents[3] / ".." / "shared" / "peer_cases" / "linuxcnc"
    case = peer / "tp-bad-spirals-comp"
    if not case.is_dir():
        pytest.skip("LinuxCNC peer data not found")
    opts = PlanOptions(
        dialect="rs274", timing=False, tool_table=str(peer / "_default-tooltable" / "sim.tbl"), tool_unit="inch"
    )
    result = plan_file(case / "bad_spirals_comp.ngc", opts)
    expected = [ln for ln in (case / "stderr.generated.txt").read_text().splitlines() if ln.strip()][1]
    err = result.errors[0]
    assert (err.code, err.message, err.span.line) == ("LCNC-ARC-RADIUS", expected, 13)
