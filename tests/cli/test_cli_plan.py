"""`trcopt plan` end to end: outputs, exit codes, and diagnostics for bad input (never a traceback)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from trcopt.cli import main

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "problems" / "siemens" / "ex02_square_g450.mpf"
TOOL = "$TC_DP1[1,1]=120 $TC_DP6[1,1]=5\n"


def _run(tmp_path: Path, text: str, *extra: str) -> tuple[int, dict, str]:
    prog = tmp_path / "prog.mpf"
    prog.write_text(text)
    out = tmp_path / "plan.json"
    rc = main(["plan", str(prog), "--no-timing", "--json", str(out), *extra])
    return rc, json.loads(out.read_text()), str(prog)


def test_plan_writes_json_gcode_svg(tmp_path: Path, capsys) -> None:
    rc = main(
        [
            "plan", str(SQUARE), "--no-timing",
            "--json", str(tmp_path / "p.json"), "--gcode", str(tmp_path / "p.nc"), "--svg", str(tmp_path / "p.svg"),
        ]
    )
    assert rc == 0
    out = capsys.readouterr().out
    assert "9 blocks" in out and "10 tool-centre segments" in out
    # path: rapid from the origin + 25 (approach) + 4 × 40 + 3 quarter circles R5 + 25 (retraction)
    import math

    assert f"path length {math.hypot(20, 20) + 2 * math.hypot(15, 20) + 160 + 1.5 * math.pi * 5:.3f} mm" in out
    plan = json.loads((tmp_path / "p.json").read_text())
    assert plan["schema"] == "trcopt.plan/1" and plan["ok"] is True and plan["dialect"] == "siemens"
    arcs = [s for s in plan["toolpath"] if s["kind"] == "arc"]
    assert [a["center"][:2] for a in arcs] == [[0, 40], [40, 40], [40, 0]]
    assert all(a["ccw"] is False and a["role"] == "corner" and a["radius"] == 5.0 for a in arcs)
    assert plan["toolpath"][1]["feed_mm_min"] == pytest.approx(500.0)
    gcode = (tmp_path / "p.nc").read_text()
    code = "\n".join(ln.split(";")[0] for ln in gcode.splitlines())  # the program's comment names G41
    assert "G41" not in code and "G42" not in code
    assert "G2 X0 Y45 I5 J0" in gcode.replace(".0000", "").replace("X0. ", "X0 ")
    assert (tmp_path / "p.svg").read_text().startswith("<")


def test_python_m_trcopt_matches_console_script() -> None:
    proc = subprocess.run(
        [sys.executable, "-m", "trcopt", "plan", str(SQUARE), "--no-timing"], capture_output=True, text=True
    )
    assert proc.returncode == 0 and "tool-centre segments" in proc.stdout


@pytest.mark.parametrize(
    "name, text, code, line, column, block",
    [
        ("truncated word", "N10 G0 X0 Y0\nN20 G1 X10 Y\n", "NC-SYNTAX", 2, 12, "N20"),
        ("arc end radius", "N10 G0 X0 Y0\nN20 G2 X10 Y0 I5.01 J0 F100\nM30\n", "NC-ARC-RADIUS", 2, 15, "N20"),
        ("no tool", "N10 G0 X-10 Y0\nN20 G1 G41 X0 Y0 F100\nN30 X10\nN40 G40 X20 Y-10\nM30\n", "10750", 2, 5, "N20"),
        (
            "arc selection block",
            TOOL + "N10 T1 D1 G0 X-10 Y0\nN20 G2 G41 X0 Y10 I5 J5 F100\nN30 G1 X10\nN40 G40 X20\nM30\n",
            "10753", 3, 5, "N20",
        ),
        (
            "plane change",
            TOOL + "N10 T1 D1 G0 X-10 Y0\nN20 G1 G41 X0 Y0 F100\nN30 X10\nN40 G18 X20\nM30\n",
            "10757", 5, 5, "N40",
        ),
        (
            "inside arc smaller than the tool",
            TOOL + "N10 T1 D1 G0 X-10 Y10\nN20 G1 G41 X0 Y0 F100\nN30 X20\nN40 G3 X26 Y0 I3 J0\nN50 G1 X40\n"
            "N60 G40 X50 Y10\nM30\n",
            "10751", 5, 5, "N40",
        ),
    ],
)
def test_bad_program_gives_located_diagnostic_and_exit_1(tmp_path, capsys, name, text, code, line, column, block):
    rc, plan, prog = _run(tmp_path, text)
    assert rc == 1
    err = capsys.readouterr().err
    assert f"prog.mpf:{line}:{column}: error {code} ({block})" in err
    assert "Traceback" not in err
    assert plan["ok"] is False
    errors = [d for d in plan["diagnostics"] if d["severity"] == "error"]
    assert errors[0]["code"] == code and errors[0]["line"] == line and errors[0]["block"] == block
    assert errors[0]["column"] == column


def test_unknown_word_is_a_warning_not_dropped(tmp_path, capsys) -> None:
    rc, plan, _ = _run(tmp_path, TOOL + "N10 T1 D1 G0 X0 Y0 QQ5\nN20 G1 X10 F100\nM30\n")
    assert rc == 0
    warnings = [d for d in plan["diagnostics"] if d["severity"] == "warning"]
    assert warnings and warnings[0]["code"] == "NC-UNSUPPORTED-WORD" and warnings[0]["block"] == "N10"
    assert "QQ5" in warnings[0]["message"]


def test_alarm_keeps_the_path_up_to_the_alarm(tmp_path) -> None:
    text = (ROOT / "problems" / "siemens" / "ex01_seed_g460.mpf").read_text()
    rc, plan, _ = _run(tmp_path, text)
    assert rc == 1
    assert [s["block"] for s in plan["toolpath"]] == ["N40", "N50"]
    assert plan["diagnostics"][-1]["alarm"] == 10751


def test_usage_and_io_errors_exit_2(tmp_path, capsys) -> None:
    assert main(["plan", str(tmp_path / "missing.mpf")]) == 2
    assert "cannot read" in capsys.readouterr().err
    bad_machine = tmp_path / "m.toml"
    bad_machine.write_text("[axes.X]\nvmax_mm_s = 1\namax_mm_s2 = 1\nspeed = 3\n")
    assert main(["plan", str(SQUARE), "--machine", str(bad_machine)]) == 2
    assert "axes.X.speed" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exc:
        main(["plan", str(SQUARE), "--dialect", "fanuc"])
    assert exc.value.code == 2


def test_failed_output_leaves_no_half_written_file(tmp_path) -> None:
    target = tmp_path / "dir_as_file"
    target.mkdir()
    rc = main(["plan", str(SQUARE), "--no-timing", "--json", str(target)])
    assert rc == 2
    assert not list(tmp_path.glob("*.tmp*"))


PEER = ROOT / ".." / "shared" / "peer_cases" / "linuxcnc" / "ccomp-mill-line-arc-entry"


@pytest.mark.skipif(not PEER.is_dir(), reason="LinuxCNC peer data not beside the checkout")
def test_rs274_program_with_a_tool_table_option(tmp_path, capsys) -> None:
    prog = tmp_path / "entry.ngc"
    prog.write_text((PEER / "test.ngc").read_text())
    out = tmp_path / "p.json"
    rc = main(["plan", str(prog), "--no-timing", "--tool-table", str(PEER / "test.tbl"), "--json", str(out)])
    assert rc == 0
    plan = json.loads(out.read_text())
    assert plan["dialect"] == "rs274" and plan["profile"] == "linuxcnc"
    radii = {round(s["radius"], 9) for s in plan["toolpath"] if s["side"]}
    assert radii == {12.7}  # T4 D1.0 inch in the table: r = 0.5 in
    assert main(["plan", str(prog), "--tool-table", str(tmp_path / "none.tbl")]) == 2
    assert "cannot read tool table" in capsys.readouterr().err


def test_corner_blends_through_the_cli(tmp_path) -> None:
    out = tmp_path / "c.json"
    prog = ROOT / "problems" / "corners" / "corner_30deg.mpf"
    assert main(["plan", str(prog), "--corners", "arc", "--tolerance", "0.1", "--json", str(out)]) == 0
    plan = json.loads(out.read_text())
    assert plan["corners"]["mode"] == "arc" and plan["corners"]["blended"] == 1
    assert 0.05 < plan["corners"]["max_deviation_mm"] <= 0.1
    exact = tmp_path / "e.json"
    assert main(["plan", str(prog), "--json", str(exact)]) == 0
    assert plan["timing"]["duration_s"] < json.loads(exact.read_text())["timing"]["duration_s"]


def test_jerk_limited_feed_through_the_cli(tmp_path, capsys) -> None:
    prog = ROOT / "problems" / "corners" / "pocket_square.mpf"
    acc, jerk = tmp_path / "a.json", tmp_path / "j.json"
    assert main(["plan", str(prog), "--json", str(acc)]) == 0
    assert main(["plan", str(prog), "--jerk", "--json", str(jerk), "--csv", str(tmp_path / "j.csv")]) == 0
    assert "jerk-limited cycle time" in capsys.readouterr().out
    a, j = json.loads(acc.read_text())["timing"], json.loads(jerk.read_text())["timing"]
    assert j["jerk_limited"] is True and j["limits_ok"] is True
    assert max(j["max_jerk_ratio"].values()) <= 1.0 + 1e-3 and j["jerk_report"]["ok"] is True
    # bounded jerk costs time: never faster than the acceleration-limited optimum of the same path
    assert j["acceleration_limited_duration_s"] == pytest.approx(a["duration_s"], rel=1e-9)
    assert a["duration_s"] < j["duration_s"] < 2.0 * a["duration_s"]
    header = (tmp_path / "j.csv").read_text().splitlines()[0].split(",")
    assert {"jx_mm_s3", "jy_mm_s3", "jz_mm_s3"} <= set(header)


def test_jerk_mode_without_jerk_limits_keeps_the_acceleration_limited_feed(tmp_path, capsys) -> None:
    machine = tmp_path / "m.toml"
    machine.write_text(
        'name = "no jerk"\n'
        "[axes.X]\nvmax_mm_s = 250\namax_mm_s2 = 2000\n"
        "[axes.Y]\nvmax_mm_s = 250\namax_mm_s2 = 2000\n"
        "[axes.Z]\nvmax_mm_s = 100\namax_mm_s2 = 1000\n"
    )
    out = tmp_path / "p.json"
    assert main(["plan", str(SQUARE), "--jerk", "--machine", str(machine), "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "jerk-limited feed not computed" in text and "jmax_mm_s3" in text
    timing = json.loads(out.read_text())["timing"]
    assert timing["duration_s"] > 0 and not timing.get("jerk_limited", False)


def test_jerk_limited_feed_that_fails_its_check_is_reported(tmp_path, capsys, monkeypatch) -> None:
    import dataclasses

    from trcopt.timing.jerk import JerkTrajectory

    real = JerkTrajectory.check_limits

    def failing(self, *args, **kwargs):  # type: ignore[no-untyped-def]
        return dataclasses.replace(real(self, *args, **kwargs), ok=False, jerk_ratio=(1.0523, 0.9, 0.0))

    monkeypatch.setattr(JerkTrajectory, "check_limits", failing)
    prog = ROOT / "problems" / "corners" / "pocket_square.mpf"
    out = tmp_path / "j.json"
    assert main(["plan", str(prog), "--jerk", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "jerk-limited feed check" in text and "jerk measure 1.0523" in text
    plan = json.loads(out.read_text())
    assert any("jerk measure 1.0523" in d["message"] for d in plan["diagnostics"])


@pytest.mark.parametrize("value", ["-1", "0", "nan", "inf", "abc"])
def test_a_tolerance_that_is_not_a_positive_length_is_a_usage_error(value, capsys):
    program = str(ROOT / "problems" / "siemens" / "ex02_square_g450.mpf")
    with pytest.raises(SystemExit) as exc:
        main(["plan", program, "--no-timing", "--corners", "arc", f"--tolerance={value}"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "--tolerance" in err and value in err and "Traceback" not in err


@pytest.mark.parametrize("value", [-1.0, 0.0, float("nan"), float("inf")])
def test_plan_options_reject_a_tolerance_that_is_not_a_positive_length(value):
    from trcopt.errors import TrcoptError
    from trcopt.pipeline import PlanOptions

    with pytest.raises(TrcoptError, match="--tolerance") as exc:
        PlanOptions(corners="arc", tolerance_mm=value)
    assert exc.value.code == "USAGE"
