"""Progress and output hygiene of ``trcopt plan``: paths checked before the work, every output
rendered before any is written, the CSV step chosen by a row budget, progress only on a terminal,
one error form."""

from __future__ import annotations

import io
import json
import sys
from pathlib import Path

import pytest

import trcopt.pipeline
import trcopt.progress as progress
from trcopt.cli import main
from trcopt.errors import TimingError
from trcopt.io.feed_csv import CSV_MAX_ROWS, csv_step

ROOT = Path(__file__).resolve().parents[2]
GEAR = ROOT / "problems" / "corners" / "gear_12.mpf"
CORNER = ROOT / "problems" / "corners" / "corner_30deg.mpf"


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def _no_planning(monkeypatch: pytest.MonkeyPatch) -> None:
    def planned(*args: object, **kwargs: object) -> None:
        pytest.fail("the program was planned although an output path is wrong")

    monkeypatch.setattr(trcopt.pipeline, "plan_file", planned)


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda t: ["--json", str(t / "a.json"), "--csv", str(t / "folder")], "is a folder"),
        (lambda t: ["--json", str(t / "a.json"), "--svg", str(t / "file.txt" / "x.svg")], "is not a folder"),
        (lambda t: ["--json", str(t / "a.json"), "--gcode", str(t / "a.json")], "given for two outputs"),
        (lambda t: ["--json", str(t / "a.json"), "--gcode", str(t / "prog.mpf")], "would overwrite an input"),
    ],
    ids=["csv-to-a-folder", "parent-is-a-file", "same-path-twice", "over-the-program"],
)
def test_output_paths_are_checked_before_the_plan(tmp_path: Path, monkeypatch, capsys, make, message) -> None:
    (tmp_path / "folder").mkdir()
    (tmp_path / "file.txt").write_text("x")
    prog = tmp_path / "prog.mpf"
    prog.write_text(GEAR.read_text())
    _no_planning(monkeypatch)
    assert main(["plan", str(prog), *make(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("trcopt: error OUTPUT: ") and message in err and "Traceback" not in err
    assert not (tmp_path / "a.json").exists()
    assert prog.read_text() == GEAR.read_text()


def test_missing_output_folders_are_created(tmp_path: Path) -> None:
    out = tmp_path / "out" / "deep" / "plan.json"
    assert main(["plan", str(GEAR), "--no-timing", "--json", str(out), "-q"]) == 0
    assert json.loads(out.read_text())["ok"]


def test_every_output_is_rendered_before_any_is_written(tmp_path: Path, monkeypatch, capsys) -> None:
    import trcopt.io.plot as plot

    def failing(trajectory: object, path: object) -> None:
        raise TimingError("the picture cannot be drawn")

    monkeypatch.setattr(plot, "render_speed", failing)
    files = {k: tmp_path / f"plan.{k}" for k in ("json", "nc", "svg", "csv", "png")}
    argv = ["plan", str(GEAR), "--json", str(files["json"]), "--gcode", str(files["nc"]), "--svg", str(files["svg"])]
    assert main([*argv, "--csv", str(files["csv"]), "--png", str(files["png"])]) == 2
    assert f"{GEAR}: error TIMING: the picture cannot be drawn" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []  # the PNG comes last, and nothing was written before it


def test_csv_and_png_are_written_with_the_others(tmp_path: Path) -> None:
    csv, png, js = tmp_path / "f.csv", tmp_path / "speed.png", tmp_path / "plan.json"
    assert main(["plan", str(GEAR), "--csv", str(csv), "--png", str(png), "--json", str(js), "-q"]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert json.loads(js.read_text())["timing"]["samples"] == str(csv)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f.csv", "plan.json", "speed.png"]  # no temporaries


def test_csv_step(tmp_path: Path) -> None:
    csv = tmp_path / "f.csv"
    assert main(["plan", str(GEAR), "--csv", str(csv), "--csv-step", "0.01", "-q"]) == 0
    rows = csv.read_text().splitlines()[1:]
    times = [float(r.split(",")[0]) for r in rows]
    assert times[1] - times[0] == pytest.approx(0.01)
    duration = json.loads(_plan_json(tmp_path))["timing"]["duration_s"]
    assert len(rows) == pytest.approx(duration / 0.01 + 1, abs=1.01)
    # the default: 1 ms for a short cycle
    assert main(["plan", str(GEAR), "--csv", str(csv), "-q"]) == 0
    rows = csv.read_text().splitlines()[1:]
    assert float(rows[1].split(",")[0]) - float(rows[0].split(",")[0]) == pytest.approx(1e-3)


def _plan_json(folder: Path) -> str:
    out = folder / "p.json"
    assert main(["plan", str(GEAR), "--json", str(out), "-q"]) == 0
    return out.read_text()


@pytest.mark.parametrize("duration", [0.5, 10.0, 199.0, 200.5, 401.0, 3600.0, 36_000.0])
def test_the_default_csv_step_keeps_the_row_budget(duration: float) -> None:
    step = csv_step(duration)
    assert step >= 1e-3 and duration / step + 1 <= CSV_MAX_ROWS
    assert f"{step:.0e}"[0] in "125"  # 1, 2 or 5 × 10ⁿ
    finer = step / (2.5 if f"{step:.0e}"[0] == "5" else 2)
    assert step == 1e-3 or duration / finer + 1 > CSV_MAX_ROWS  # the finest that fits


@pytest.mark.parametrize("value", ["0", "-1", "nan", "x"])
def test_a_csv_step_that_is_not_a_positive_time_is_a_usage_error(value: str, capsys) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["plan", str(GEAR), "--csv", "f.csv", "--csv-step", value])
    assert exc.value.code == 2 and "--csv-step" in capsys.readouterr().err


def test_progress_on_a_terminal_and_none_with_quiet(monkeypatch, capsys) -> None:
    monkeypatch.setattr(progress, "DELAY_S", 0.0)
    monkeypatch.setenv("COLUMNS", "60")  # a narrow terminal: the stage running now is still shown
    terminal = _Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    assert main(["plan", str(CORNER), "--corners", "optimal", "--workers", "1"]) == 0
    shown = terminal.getvalue()
    for what in ("reading the program", "compensating", "verifying", "corners (optimal)", "timing"):
        assert what in shown
    assert all(len(line.replace("\x1b[K", "")) <= 59 for line in shown.split("\r"))
    assert "\r" in shown  # bars are redrawn in place and cleared
    terminal = _Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    assert main(["plan", str(CORNER), "-q"]) == 0
    assert terminal.getvalue() == ""
    capsys.readouterr()


def test_no_progress_when_stderr_is_not_a_terminal(capsys) -> None:
    assert progress.terminal_reporter(io.StringIO()) is None
    assert progress.terminal_reporter(_Terminal(), quiet=True) is None
    assert isinstance(progress.terminal_reporter(_Terminal()), progress.TerminalReporter)
    assert main(["plan", str(CORNER), "--corners", "optimal", "--workers", "1"]) == 0
    assert capsys.readouterr().err == ""


def test_the_stages_report_their_work() -> None:
    seen: list[list] = []

    class Recorder:
        def start(self, what: str, total: int | None = None) -> object:
            entry = [what, total, 0, False]
            seen.append(entry)

            class Task:
                def advance(self, n: int = 1) -> None:
                    entry[2] += n

                def close(self) -> None:
                    entry[3] = True

            return Task()

    from trcopt.pipeline import PlanOptions, plan_file

    with progress.reporting(Recorder()):  # under jerk limits the corner gets a G2 quintic (one QP problem)
        plan_file(CORNER, PlanOptions(corners="optimal", jerk=True))
    names = [s[0] for s in seen]
    assert names[:4] == ["reading the program", "compensating", "verifying", "corners (optimal)"]
    assert "timing" in names and "jerk-limited timing" in names
    problems = [s for s in seen if s[0] == "corner problems"]
    assert problems and all(s[1] == s[2] and s[1] > 0 for s in problems)  # every corner problem counted
    assert all(s[3] for s in seen)  # every stage closed
    seen.clear()
    plan_file(CORNER, PlanOptions(corners="arc"))  # no reporter: nothing reported
    assert seen == []


def test_one_error_form(tmp_path: Path, capsys) -> None:
    assert main(["plan", str(tmp_path / "missing.mpf")]) == 2
    assert capsys.readouterr().err.startswith(f"trcopt: error IO: cannot read {tmp_path / 'missing.mpf'}")
    bad = tmp_path / "bad.mpf"
    bad.write_text("N10 G1 X1 Y=(\nM30\n")
    assert main(["check", str(bad)]) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"{bad}:1:") and ": error NC-" in err
    assert main(["plan", str(GEAR), "--csv", str(tmp_path / "f.csv"), "--no-timing"]) == 2
    assert capsys.readouterr().err.startswith("trcopt: error USAGE: --csv/--png need the timing stage")


def test_png_without_matplotlib_is_a_usage_error_before_the_plan(tmp_path: Path, monkeypatch, capsys) -> None:
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # not installed
    _no_planning(monkeypatch)
    assert main(["plan", str(GEAR), "--png", str(tmp_path / "s.png"), "--json", str(tmp_path / "p.json")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("trcopt: error USAGE: --png needs matplotlib") and "Traceback" not in err
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["plan", str(GEAR), "--tolerance", "-1"], "trcopt plan: argument --tolerance: must be a positive finite"),
        (["plan", str(GEAR), "--no-such-option"], "trcopt: unrecognized arguments: --no-such-option"),
        (["batch"], "trcopt batch: the following arguments are required: sweep"),
    ],
)
def test_a_usage_error_has_the_one_error_form(argv: list[str], message: str, capsys) -> None:
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 2
    last = capsys.readouterr().err.rstrip("\n").splitlines()[-1]
    assert last.startswith("trcopt: error USAGE: ") and message in last


def test_a_narrow_status_line_drops_the_outer_stage_names_first() -> None:
    names = ["planning a_very_long_program_name_from_a_cam_post.mpf", "corners (optimal)", "corner problems"]
    assert progress._fit(names, 200) == " › ".join(names)
    assert progress._fit(names, 40) == "… › corners (optimal) › corner problems"
    assert progress._fit(names, 10) == "… › corner problems"  # the stage running now stays
