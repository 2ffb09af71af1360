"""The command line on hostile input and environments: binary files, closed pipes, timing that is
not there for --csv, a cycle too long to sample; never a traceback."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from trcopt.cli import main
from trcopt.errors import TimingError
from trcopt.timing.trajectory import MAX_SAMPLES, sample_times

ROOT = Path(__file__).resolve().parents[2]
GEAR = ROOT / "problems" / "corners" / "gear_12.mpf"


@pytest.mark.parametrize("data", [bytes(range(256)) * 8, b"N10 G1 X1\x00\x00\x00 Y2\n", b"\xff\xfe\x00\xd8"])
def test_a_binary_file_is_not_a_text_file(tmp_path: Path, capsys, data: bytes) -> None:
    prog = tmp_path / "prog.mpf"
    prog.write_bytes(data)
    out = tmp_path / "plan.json"
    assert main(["plan", str(prog), "--json", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"{prog}" in err and "error NC-NOT-TEXT" in err and "not a text file" in err
    assert "Traceback" not in err
    assert not out.exists()
    if b"\x00" in data and data.startswith(b"N10"):
        # a NUL byte is placed at its line, column and block
        assert f"{prog}:1:10: error NC-NOT-TEXT (N10): not a text file (NUL byte at offset 9)" in err


def test_a_nul_byte_after_a_form_feed_names_the_block(tmp_path: Path, capsys) -> None:
    prog = tmp_path / "prog.mpf"
    prog.write_bytes(b"G0 X0\n\x0cN10 G17\x00 X1\n")
    assert main(["plan", str(prog)]) == 2
    assert f"{prog}:2:9: error NC-NOT-TEXT (N10): not a text file" in capsys.readouterr().err


def test_a_file_of_control_characters_is_placed_at_the_first_one(tmp_path: Path, capsys) -> None:
    prog = tmp_path / "prog.mpf"
    prog.write_bytes(b"N10 G1 X1\nN20 \x01\x02\x03\x04\x05\x06\x07\x08\xff\x0e\x0f\x10\n")
    assert main(["check", str(prog)]) == 2
    err = capsys.readouterr().err
    assert f"{prog}:2:5: error NC-NOT-TEXT (N20): not a text file (11 of 27 bytes are control characters, the first at offset 14)" in err


def test_utf16_and_latin1_programs_are_still_read(tmp_path: Path) -> None:
    text = GEAR.read_text()
    for name, data in (("u16.mpf", text.encode("utf-16")), ("l1.mpf", ("; Maß °\n" + text).encode("latin-1"))):
        prog = tmp_path / name
        prog.write_bytes(data)
        assert main(["check", str(prog)]) == 0


def test_a_closed_standard_output_is_silent() -> None:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    # the reader closes its end at once; trcopt then writes into a closed pipe
    proc = subprocess.run(
        f"{sys.executable} -m trcopt plan {GEAR} | (exec 0<&-; true)",
        shell=True, capture_output=True, text=True, env=env, cwd=ROOT,
    )
    assert "Traceback" not in proc.stderr and "BrokenPipe" not in proc.stderr, proc.stderr
    assert proc.stderr == ""


def test_csv_with_no_timing_is_a_usage_error_before_anything_is_written(tmp_path: Path, capsys) -> None:
    out = tmp_path / "plan.json"
    assert main(["plan", str(GEAR), "--no-timing", "--csv", str(tmp_path / "f.csv"), "--json", str(out)]) == 2
    assert "--no-timing" in capsys.readouterr().err
    assert not out.exists()


def test_csv_after_an_alarm_before_any_motion_is_a_note_not_a_usage_error(tmp_path: Path, capsys) -> None:
    prog = tmp_path / "prog.mpf"
    prog.write_text("N10 G1 X1000000000000 F100\nM30\n")
    csv = tmp_path / "f.csv"
    assert main(["plan", str(prog), "--csv", str(csv)]) == 1
    captured = capsys.readouterr()
    assert f"{prog}: note: --csv/--png not written" in captured.out
    assert f"{prog}:1:" in captured.err and "NC-RANGE" in captured.err
    assert not csv.exists()


def test_sampling_a_cycle_beyond_the_sample_bound_is_a_timing_error() -> None:
    assert len(sample_times(1.0, 1e-3)) == 1001
    with pytest.raises(TimingError, match="MAX_SAMPLES"):
        sample_times(MAX_SAMPLES * 1e-3 * 2, 1e-3)
    with pytest.raises(TimingError):
        sample_times(float("nan"), 1e-3)


def test_an_output_that_cannot_be_rendered_names_the_program(tmp_path: Path, capsys, monkeypatch) -> None:
    from trcopt.io.plan_json import PlanJsonError
    from trcopt.pipeline import PlanResult

    def non_finite(self: object, **kw: object) -> object:
        yield "{"  # part of the file is written before the bad number is met
        raise PlanJsonError("non-finite number in plan JSON at toolpath[3].t_end_s")

    monkeypatch.setattr(PlanResult, "json_chunks", non_finite)
    out, svg = tmp_path / "plan.json", tmp_path / "plan.svg"
    assert main(["plan", str(GEAR), "--no-timing", "--json", str(out), "--svg", str(svg)]) == 2
    err = capsys.readouterr().err
    assert f"{GEAR}: error PLAN-JSON: non-finite number in plan JSON at toolpath[3]" in err
    assert not out.exists() and not svg.exists()


def test_ctrl_c_while_the_command_is_loaded_exits_130_without_a_traceback(monkeypatch, capsys) -> None:
    import trcopt.cli

    def interrupted(name: str) -> object:
        raise KeyboardInterrupt

    monkeypatch.setattr(trcopt.cli.importlib, "import_module", interrupted)
    try:
        status = main(["plan", str(GEAR)])
    except KeyboardInterrupt:  # (would stop the whole test run)
        pytest.fail("the interrupt escaped main()")
    assert status == 130
    assert capsys.readouterr().err == ""


def test_running_out_of_memory_is_one_error_line_and_no_output(tmp_path: Path, monkeypatch, capsys) -> None:
    import trcopt.verify.plan

    def exhausted(*args: object, **kwargs: object) -> object:
        raise MemoryError

    monkeypatch.setattr(trcopt.verify.plan, "verify_plan", exhausted)
    out = tmp_path / "plan.json"
    status = main(["plan", str(GEAR), "--no-timing", "--json", str(out)])
    err = capsys.readouterr().err
    assert status == 2 and err.startswith("trcopt: error MEMORY: out of memory") and "Traceback" not in err
    assert os.listdir(tmp_path) == []


def test_ctrl_c_while_writing_leaves_no_file(tmp_path: Path, monkeypatch, capsys) -> None:
    calls: list[int] = []
    real_fsync = os.fsync

    def fsync(fd: int) -> None:  # the second output is interrupted before it is complete
        calls.append(fd)
        if len(calls) == 2:
            raise KeyboardInterrupt
        real_fsync(fd)

    monkeypatch.setattr(os, "fsync", fsync)
    out, nc = tmp_path / "plan.json", tmp_path / "plan.nc"
    try:
        status = main(["plan", str(GEAR), "--no-timing", "--json", str(out), "--gcode", str(nc)])
    except KeyboardInterrupt:  # (would stop the whole test run)
        pytest.fail("the interrupt escaped main()")
    assert status == 130
    assert capsys.readouterr().err == ""
    # the outputs are put in place together or not at all: neither, nor a temporary file
    assert os.listdir(tmp_path) == []


def test_ctrl_c_in_a_real_process_exits_130_silently(tmp_path: Path) -> None:
    # SIGINT arrives while the program is planned (the signal, not a simulated exception); the child
    # restores Python's handler, which a shell leaves out for background jobs (SIGINT ignored)
    script = (
        "import os, signal, sys\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "import trcopt.pipeline as p\n"
        "p.plan_file = lambda *a, **k: (os.kill(os.getpid(), signal.SIGINT), signal.pause())\n"
        "from trcopt.cli import main\n"
        "sys.exit(main(sys.argv[1:]))\n"
    )
    out = tmp_path / "plan.json"
    proc = subprocess.run(
        [sys.executable, "-c", script, "plan", str(GEAR), "--json", str(out)],
        capture_output=True, text=True, env={**os.environ, "PYTHONPATH": str(ROOT)}, cwd=ROOT, timeout=60,
    )
    assert proc.returncode == 130 and proc.stderr == "", proc.stderr
    assert os.listdir(tmp_path) == []


def test_a_cycle_longer_than_the_sampling_bound_is_still_checked(tmp_path: Path, monkeypatch, capsys) -> None:
    # a feed of 60 mm/min over 100 mm: a 100 s cycle, 10⁵ samples at the 1 ms check step, over
    # the (lowered) bound; the limit check samples coarser instead of failing the plan
    import json

    import trcopt.timing.checks as checks
    import trcopt.timing.trajectory as trajectory

    monkeypatch.setattr(trajectory, "MAX_SAMPLES", 20_000)
    monkeypatch.setattr(checks, "MAX_SAMPLES", 20_000)
    prog = tmp_path / "slow.mpf"
    prog.write_text("N10 G0 X0 Y0\nN20 G1 X100 F60\nN30 M30\n")
    out = tmp_path / "slow.json"
    assert main(["plan", str(prog), "--gcode", str(tmp_path / "slow.nc"), "--json", str(out)]) == 0
    captured = capsys.readouterr()
    assert "cycle time 10" in captured.out and captured.err == ""
    assert (tmp_path / "slow.nc").exists()
    data = json.loads(out.read_text())  # the JSON's limit check samples coarser as well
    assert data["ok"] and data["timing"]["limits_ok"]
