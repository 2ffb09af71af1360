"""SINUMERIK program flow, subprograms, frames, polar input, CIP/CT, drilling cycles, zero offsets and
tool tables: the golden pairs plan to the same tool-centre path as their explicit
programs, the CAM-post program runs end to end through ``trcopt plan``, and bad input is a located
error."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import pytest

from trcopt.controllers import read_program
from trcopt.errors import ConfigError, Severity
from trcopt.modes import Side
from trcopt.nc import MoveKind
from trcopt.pipeline import PlanOptions, plan, plan_file

PROBLEMS = Path(__file__).resolve().parents[3] / "problems" / "siemens"
PAIRS = ["ex14_flow", "ex15_frames", "ex16_drilling", "ex18_branch"]
TOOL = "$TC_DP1[1,1]=120 $TC_DP6[1,1]=5\n"


def _path(result):
    return [(s.kind, s.start_xyz, s.end_xyz, s.center_xyz) for s in result.toolpath]


@pytest.mark.parametrize("pair", PAIRS)
def test_features_give_the_path_of_the_explicit_program(pair):
    a = plan_file(PROBLEMS / f"{pair}_features.mpf", PlanOptions(timing=False))
    b = plan_file(PROBLEMS / f"{pair}_explicit.mpf", PlanOptions(timing=False))
    assert a.ok and b.ok, [d.format() for d in (*a.diagnostics, *b.diagnostics)]
    pa, pb = _path(a), _path(b)
    assert len(pa) == len(pb) > 10
    for (ka, sa, ea, ca), (kb, sb, eb, cb) in zip(pa, pb, strict=True):
        assert ka == kb
        assert math.dist(sa, sb) <= 1e-9 and math.dist(ea, eb) <= 1e-9
        assert (ca is None) == (cb is None) and (ca is None or math.dist(ca, cb) <= 1e-9)


def moves(text, file="p.mpf", **kw):
    prog = read_program(text, file=file, **kw)
    errs = [d.format() for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert errs == []
    return [m for m in prog.moves if m.kind is not MoveKind.NONE]


def error_of(text, file="p.mpf", **kw):
    prog = read_program(text, file=file, **kw)
    errs = [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert len(errs) == 1, [d.format() for d in prog.diagnostics]
    return errs[0], prog


# ---------------------------------------------------------------- program flow
def test_gotof_skips_the_plunge_and_conditional_jumps_loop():
    ms = moves("N10 G0 X0 Y0 Z5\nN20 GOTOF SKIP\nN30 G0 Z-50\nN40 SKIP: G1 X10 F100\nR1=0\n"
               "N50 LAB: R1=R1+1\nN60 G1 Y=R1\nN70 IF R1<3 GOTOB LAB\nN80 GOTOC NOWHERE\nM30")  # fmt: skip
    assert all(m.end[2] == 5.0 for m in ms)
    assert [m.end[1] for m in ms if m.span.block == "N60"] == [1.0, 2.0, 3.0]


def test_structures_and_section_repetition():
    ms = moves("DEF INT KK\nFOR KK=0 TO 2\nIF KK==1\nG1 X1 F100\nELSE\nG1 X=10+KK F100\nENDIF\nENDFOR\n"
               "R1=0\nWHILE R1<2\nR1=R1+1\nENDWHILE\nREPEAT\nR1=R1-1\nUNTIL R1==0\nLOOP\nR1=R1+1\n"
               "IF R1>1 GOTOF OUT\nENDLOOP\nOUT: G1 Y1\nSTART: G91 Y1\nG90\nREPEAT START P=2\n"
               "ONE: G1 Z1\nREPEATB ONE P=2\nM30")  # fmt: skip
    assert [m.end[0] for m in ms[:3]] == [10.0, 1.0, 12.0]
    assert [m.end[1] for m in ms[3:7]] == [1.0, 2.0, 3.0, 4.0]
    assert [m.span.line for m in ms[-3:]] == [24, 24, 24]


def test_nesting_error_is_alarm_12640_before_anything_runs():
    err, prog = error_of("G0 X1\nWHILE R1<2\nIF R1>1\nENDWHILE\nM30")
    assert err.alarm == 12640 and err.span.line == 4 and prog.moves == ()


def test_endless_loop_hits_the_iteration_limit_with_its_place():
    err, _ = error_of("N10 LOOP\nN20 G1 X1 F100\nN30 ENDLOOP\nM30")
    assert err.code == "NC-LOOP-LIMIT" and err.span.block == "N30" and "100000" in err.message
    err, _ = error_of("R1=1\nN5 A: G1 X1 F100\nN6 IF R1>0 GOTOB A\nM30")
    assert err.code == "NC-LOOP-LIMIT" and err.span.block == "N6"


def test_jump_to_a_missing_label_names_it():
    err, _ = error_of("N10 G0 X0\nN20 GOTOB NOPE\nM30")
    assert err.alarm == 14080 and err.span.block == "N20" and err.span.column == 5 and "NOPE" in err.message


def test_undefined_variable_in_a_condition_is_12550():
    err, _ = error_of("N10 IF UNKNOWN>1 GOTOF A\nA: M30")
    assert err.alarm == 12550 and err.span.block == "N10" and err.span.column == 8


# ---------------------------------------------------------------- subprograms
def test_subprograms_parameters_var_save_and_modal_state(tmp_path):
    (tmp_path / "STEP.SPF").write_text("PROC STEP(REAL DX, VAR REAL OUT) SAVE\nG91 G1 X=DX F100\nOUT=OUT+DX\nRET\n")
    (tmp_path / "modal.spf").write_text("G91\nM17\n")
    main = tmp_path / "main.mpf"
    main.write_text("DEF REAL SUM=0\nG0 X0 Y0\nSTEP(5, SUM) P=3\nG1 X=SUM\nMODAL\nG1 X1\nM30\n")
    ms = moves(main.read_text(), file=str(main))
    assert [m.end[0] for m in ms] == [0.0, 5.0, 10.0, 15.0, 15.0, 16.0]  # SAVE restores G90; MODAL leaves G91
    assert ms[1].span.file.endswith("STEP.SPF") and ms[1].span.line == 2


def test_missing_subprogram_says_where_it_looked(tmp_path):
    main = tmp_path / "main.mpf"
    err, _ = error_of("N10 G0 X0\nN20 NOTHERE(1)\nM30", file=str(main))
    assert err.alarm == 14011 and err.span.block == "N20" and "NOTHERE.spf" in err.message
    assert str(tmp_path) in err.message


def test_too_many_arguments_and_recursion(tmp_path):
    (tmp_path / "ONE.spf").write_text("PROC ONE(REAL A)\nRET\n")
    (tmp_path / "SELF.spf").write_text("SELF\nRET\n")
    main = str(tmp_path / "m.mpf")
    err, _ = error_of("ONE(1, 2)\nM30", file=main)
    assert err.code == "NC-CALL" and "1 parameter" in err.message
    err, _ = error_of("SELF\nM30", file=main)
    assert err.code == "NC-CALL" and "16 program levels" in err.message


# ---------------------------------------------------------------- frames and zero offsets
def test_frames_compose_as_the_manual_says():
    ms = moves("TRANS X10\nAROT RPL=90\nG1 X5 Y0 F100\nSCALE X2 Y2\nATRANS X1\nG1 X0 Y0\nTRANS\nG1 X1 Y1\nM30")
    assert ms[0].end == pytest.approx((10.0, 5.0, 0.0))
    assert ms[1].end == pytest.approx((2.0, 0.0, 0.0))  # SCALE replaces the frame; ATRANS is scaled
    assert ms[2].end == (1.0, 1.0, 0.0)


def test_mirror_swaps_the_circle_sense_and_the_side():
    ms = moves(TOOL + "T1 D1\nMIRROR X0\nG1 G41 X10 Y0 F100\nG3 X0 Y10 CR=10\nM30")
    assert ms[0].end == (-10.0, 0.0, 0.0) and ms[0].comp.side is Side.RIGHT
    assert ms[1].ccw is False and ms[1].center == pytest.approx((0.0, 0.0, 0.0))


def test_scale_zero_and_tilting_frames_are_located_errors():
    err, _ = error_of("N10 SCALE X0 Y1\nG1 X1 F100\nM30")
    assert err.code == "NC-FRAME" and err.span.block == "N10" and "scale factor 0" in err.message
    err, _ = error_of("ROT X30\nN20 G1 Y5 F100\nM30")
    assert err.code == "NC-FRAME" and err.span.block == "N20"
    err, _ = error_of("SCALE X2\nN20 G2 X10 Y0 CR=5 F100\nM30")
    assert err.code == "NC-FRAME" and "ellipse" in err.message


def test_supa_needs_the_zero_offsets_and_uses_them(tmp_path):
    err, _ = error_of("G54\nN20 G0 SUPA Z0\nM30")
    assert err.code == "NC-FRAME" and err.span.block == "N20" and "G54" in err.message
    offsets = tmp_path / "z.toml"
    offsets.write_text("[G54]\nZ = -300\n[G55]\nX = 10\n")
    ms = moves("G54\nG0 X1 Y2 Z3\nG0 SUPA Z0\nG55\nG0 X0\nM30", zero_offsets=offsets)
    assert ms[1].end == (1.0, 2.0, 300.0) and ms[1].span.machine == (None, None, 0.0)
    assert ms[2].end == (10.0, 2.0, 300.0)  # G55 in the G54 system: 10 further in X, 300 up in Z
    with pytest.raises(ConfigError, match="G60"):
        bad = tmp_path / "bad.toml"
        bad.write_text("[G60]\nX = 1\n")
        read_program("M30", zero_offsets=bad)


def test_change_of_zero_offset_after_motion_needs_the_file():
    err, _ = error_of("G54\nG0 X0\nN30 G55\nN40 G0 X1\nM30")
    assert err.code == "NC-FRAME" and err.span.block == "N40"


# ---------------------------------------------------------------- polar, CIP, CT
def test_polar_cip_and_ct():
    ms = moves("G111 X10 Y0\nG1 AP=90 RP=5 F100\nG3 AP=180\nG1 X0 Y0\nCIP X10 Y0 I1=5 J1=5\nCT X20 Y0\nM30")
    assert ms[0].end == pytest.approx((10.0, 5.0, 0.0))
    assert ms[1].center == (10.0, 0.0, 0.0) and ms[1].end == pytest.approx((5.0, 0.0, 0.0)) and ms[1].ccw
    assert ms[3].center == pytest.approx((5.0, 0.0, 0.0)) and ms[3].ccw is False
    assert ms[4].center == pytest.approx((15.0, 0.0, 0.0)) and ms[4].ccw is True  # tangent (0,-1) at (10,0)


# ---------------------------------------------------------------- cycles and tools
def test_cycle_errors_name_the_parameter():
    err, _ = error_of("G0 X0 Z10 F100\nN20 CYCLE81(10, 0, 2)\nM30")
    assert err.code == "NC-CYCLE" and "DP or DPR" in err.message and err.span.block == "N20"
    err, _ = error_of("G0 X0 Z10 F100\nN20 CYCLE83(10, 0, 2, -10, , -2, , , , , , 1, 3)\nM30")
    assert err.code == "NC-CYCLE" and "_AXN" in err.message


def test_tool_table_and_missing_tool(tmp_path):
    table = tmp_path / "t.toml"
    table.write_text("[T3.D2]\ntype = 120\nradius = 4.0\nwear = -0.5\n")
    ms = moves("T3 D2\nG1 G41 X10 Y0 F100\nM30", tool_table=table)
    assert ms[0].comp.radius == 3.5
    err, _ = error_of("T3 D1\nN20 G1 G42 X10 F100\nM30", tool_table=table)
    assert err.alarm == 10750 and err.span.block == "N20" and "T3 D1" in err.message and str(table) in err.message
    bad = tmp_path / "bad.toml"
    bad.write_text("[T1.D1]\nradius = -1\n")
    with pytest.raises(ConfigError, match="negative"):
        read_program("M30", tool_table=bad)


def test_cam_post_program_runs_end_to_end_through_the_cli(tmp_path):
    out = tmp_path / "out.spf"
    program = str(PROBLEMS / "ex17_cam_post.mpf")
    run = subprocess.run(
        [sys.executable, "-m", "trcopt", "plan", program, "--no-timing", "--gcode", str(out)],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert run.returncode == 0, run.stdout + run.stderr
    text = out.read_text()
    assert "G0 SUPA Z0" in text and 'MSG("OPERATION 2: CONTOUR")' in text and text.rstrip().endswith("M30")
    assert "Traceback" not in run.stderr


def test_bad_program_through_the_cli_is_a_located_error(tmp_path):
    prog = tmp_path / "bad.mpf"
    prog.write_text("N10 G0 X0 Y0 Z5\nN20 GOTOF MISSING\nN30 G0 Z-50\nM30\n")
    out = tmp_path / "out.spf"
    run = subprocess.run(
        [sys.executable, "-m", "trcopt", "plan", str(prog), "--no-timing", "--gcode", str(out)],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert run.returncode == 1 and "Traceback" not in run.stderr
    assert f"{prog}:2:5" in run.stdout + run.stderr and "14080" in run.stdout + run.stderr
    if out.exists():  # what is written stops before the jump and says so
        text = out.read_text()
        assert "Z-50" not in text and "stopped by" in text and text.splitlines()[-1].startswith(";")


def test_plan_of_text_without_a_folder_still_reports_the_call():
    r = plan("N10 SUB\nM30\n", file="<program>", options=PlanOptions(timing=False))
    assert not r.ok and r.errors[0].alarm == 14011


def test_gcode_of_loops_and_subprograms_keeps_their_words_in_run_order(tmp_path):
    from trcopt import controllers
    from trcopt.io.gcode_program import plan_to_gcode

    (tmp_path / "COOL.spf").write_text("M8\nG1 Y5\nRET\n")
    main = tmp_path / "main.mpf"
    main.write_text("DEF INT KK\nG0 X0 Y0 Z5\nFOR KK=1 TO 2\nM7 G1 X=KK*10 F100\nENDFOR\nCOOL\nG0 SUPA Z0\nM30\n")
    offsets = tmp_path / "main.offsets.toml"
    offsets.write_text("[G500]\nZ = -100\n")
    r = plan_file(main, PlanOptions(timing=False))
    assert r.ok, [d.format() for d in r.diagnostics]
    text = plan_to_gcode(r, flavor=controllers.get("siemens").gcode)
    body = [ln.split(";")[0].split(" ", 1)[1].strip() for ln in text.splitlines() if ln.startswith("N")]
    i = body.index("G1 X10 F100")
    assert body[i - 1] == "M7" and body[i + 1] == "M7" and body[i + 2] == "G1 X20"
    assert body[i + 3] == "M8" and body[i + 4] == "G1 Y5" and body[i + 5] == "G0 SUPA Z0"
    again = plan(text, file="again.mpf", options=PlanOptions(timing=False, zero_offsets=str(offsets)))
    assert again.ok
    got, want = [s.end_xyz for s in again.toolpath], [s.end_xyz for s in r.toolpath]
    assert len(got) == len(want) and all(math.dist(a, b) < 1e-9 for a, b in zip(got, want, strict=True))


def test_extern_is_accepted_and_a_misplaced_flow_word_is_a_syntax_error(tmp_path):
    (tmp_path / "SUBX.spf").write_text("PROC SUBX(REAL A)\nG1 X=A F100\nM17\n")
    main = str(tmp_path / "m.mpf")
    assert [m.end[0] for m in moves("EXTERN SUBX(REAL)\nSUBX(7)\nM30", file=main)] == [7.0]
    err, _ = error_of("N10 G1 X1 F100 GOTOF\nM30")
    assert err.code == "NC-SYNTAX" and err.span.column == 16 and "program-flow" in err.message


def test_the_block_limit_counts_blocks_run_again(monkeypatch):
    import trcopt.controllers.siemens.runner as runner

    monkeypatch.setattr(runner, "MAX_BLOCKS", 30)
    straight = "\n".join(f"G1 X{k} F100" for k in range(60)) + "\nM30"
    assert len(moves(straight)) == 60  # read straight through: never cut, whatever its length
    err, _ = error_of("R1=0\nA: G1 X=R1 F100\nR1=R1+1\nIF R1<50 GOTOB A\nM30")
    assert err.code == "NC-LOOP-LIMIT" and "run again" in err.message
