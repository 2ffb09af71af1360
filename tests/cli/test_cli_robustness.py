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
    assert f"{prog}: not a text file" in err
    assert "Traceback" not in err
    assert not out.exists()


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
    import trcopt.io
    from trcopt.io.plan_json import PlanJsonError

    def non_finite(d: object) -> str:
        raise PlanJsonError("non-finite number in plan JSON at toolpath[3].t_end_s")

    monkeypatch.setattr(trcopt.io, "dumps_plan", non_finite)
    out, svg = tmp_path / "plan.json", tmp_path / "plan.svg"
    assert main(["plan", str(GEAR), "--no-timing", "--json", str(out), "--svg", str(svg)]) == 2
    err = capsys.readouterr().err
    assert f"trcopt: error: {GEAR}: non-finite number in plan JSON at toolpath[3]" in err
    assert not out.exists() and not svg.exists()
