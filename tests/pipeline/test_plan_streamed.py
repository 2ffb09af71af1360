"""A plan made window by window (``trcopt.pipeline.stream``) equals the whole plan: the same JSON
(segment and section times to rounding: each window's times start at the sum of the previous
windows'), the same G-code text, the same summary and exit code — on the problem suite, with
windows of a few segments so that every kind of joint meets a window end."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

import pytest

from trcopt import controllers
from trcopt.cli import main
from trcopt.io.gcode_program import plan_to_gcode_chunks
from trcopt.pipeline import PlanOptions, plan_file
from trcopt.pipeline.stream import Unstreamable, plan_streamed

ROOT = Path(__file__).resolve().parents[2]
PROBLEMS = sorted(
    p for p in (ROOT / "problems").rglob("*") if p.suffix.lower() in (".ngc", ".mpf", ".spf", ".h", ".nc")
)
sys.path.insert(0, str(ROOT / "tests" / "fuzz"))
from plancompare import disagreement  # noqa: E402


def _compare(whole_json: dict[str, Any], streamed_json: dict[str, Any]) -> None:
    assert disagreement(whole_json, streamed_json) is None, disagreement(whole_json, streamed_json)


@pytest.mark.parametrize("path", PROBLEMS, ids=lambda p: p.name)
def test_streamed_plan_equals_the_whole_plan(path: Path) -> None:
    opts = PlanOptions()
    whole = plan_file(path, opts)
    flavor = controllers.get(whole.dialect).gcode
    for window in (2, 37):
        try:
            streamed = plan_streamed(str(path), opts, json=True, gcode=True, window=window)
        except Unstreamable:
            pytest.skip("the program needs the whole plan")
        gcode_whole = "".join(plan_to_gcode_chunks(whole, flavor=flavor, program_name="p"))
        gcode_streamed = "".join(plan_to_gcode_chunks(streamed, flavor=flavor, program_name="p"))
        assert gcode_streamed == gcode_whole
        _compare(json.loads("".join(whole.json_chunks())), json.loads("".join(streamed.json_chunks())))
        assert streamed.ok == whole.ok
        assert streamed.summary().splitlines()[1:] == whole.summary().splitlines()[1:]


def test_most_problems_stream() -> None:
    """The fallback is for what needs it, not the rule."""
    taken = 0
    for path in PROBLEMS:
        try:
            plan_streamed(str(path), PlanOptions(timing=False, verify=False))
            taken += 1
        except Unstreamable:
            pass
    assert taken >= 0.8 * len(PROBLEMS)


@pytest.mark.parametrize(
    ("text", "options", "why"),
    [
        ("G21 G90\nG64 P0.01\nG1 F600 X10\nX10 Y10\nM2\n", {}, "rounds corners"),
        ("G21 G90\nG1 F600 X10\nX10 Y10\nM2\n", {"jerk": True}, "jerk"),
        ("G21 G90\nG1 F600 X10\nX10 Y10\nM2\n", {"corners": "arc"}, "corners"),
        ("G21 G90\no100 sub\nG1 X5\no100 endsub\nG1 F600 X10\no100 call\nM2\n", {}, "out of line order"),
    ],
)
def test_what_needs_the_whole_plan_is_refused_before_any_output(
    tmp_path: Path, text: str, options: dict[str, Any], why: str
) -> None:
    prog = tmp_path / "p.ngc"
    prog.write_text(text)
    with pytest.raises(Unstreamable, match=why):
        plan_streamed(str(prog), PlanOptions(**options), json=True, gcode=True)


def test_cli_stream_on_writes_what_the_whole_plan_writes(tmp_path: Path, capsys: Any) -> None:
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from bench_cam_scale import contour

    prog = tmp_path / "cam.ngc"
    prog.write_text(contour(300, compensated=True))
    outs = {}
    for mode in ("on", "off"):
        j, g = tmp_path / f"{mode}.json", tmp_path / f"{mode}.ngc"
        rc = main(["plan", str(prog), "--stream", mode, "--json", str(j), "--gcode", str(g)])
        outs[mode] = (rc, capsys.readouterr().out, json.loads(j.read_text()), g.read_text())
    (rc_on, out_on, json_on, g_on), (rc_off, out_off, json_off, g_off) = outs["on"], outs["off"]
    assert rc_on == rc_off == 0 and out_on == out_off and g_on == g_off
    _compare(json_off, json_on)


def test_cli_stream_reports_an_alarm_as_the_whole_plan(tmp_path: Path, capsys: Any) -> None:
    prog = tmp_path / "bad.ngc"
    prog.write_text("G21 G90 G17\nG0 X0 Y0\nG41.1 D2\nG1 F600 X10 Y0\nX10 Y10\nX0 Y10\nG2 X0 Y10 I-1\nQ5\nM2\n")
    results = []
    for mode in ("on", "off"):
        j = tmp_path / f"{mode}.json"
        rc = main(["plan", str(prog), "--stream", mode, "--json", str(j)])
        results.append((rc, capsys.readouterr(), json.loads(j.read_text())))
    (rc_on, cap_on, json_on), (rc_off, cap_off, json_off) = results
    assert rc_on == rc_off == 1 and not json_on["ok"] and cap_on.out == cap_off.out and cap_on.err == cap_off.err
    _compare(json_off, json_on)


def test_a_plan_leaves_no_object_out_of_the_collectors_sight() -> None:
    """``plan`` takes its moves and segments out of the cyclic collector's walks while it runs and
    gives every object back when it returns or raises."""
    import gc

    path = ROOT / "problems" / "siemens" / "ex02_square_g450.mpf"
    assert gc.get_freeze_count() == 0
    plan_file(path, PlanOptions())
    assert gc.get_freeze_count() == 0
    from trcopt.nc.collector import kept_from_collector

    with pytest.raises(RuntimeError), kept_from_collector() as freeze:
        freeze()
        assert gc.get_freeze_count() > 0
        raise RuntimeError
    assert gc.get_freeze_count() == 0


def test_a_long_stretch_without_a_stop_is_one_window(tmp_path: Path) -> None:
    """A tangent-continuous spiral of 3 000 arcs: one timing section, so one window, found without
    splitting the growing window at every segment; the plan equals the whole plan."""
    lines = ["G21 G90 G17 G40", "G0 X2 Y0", "G1 F3000 X2 Y0"]
    for k in range(3000):
        r0, r1 = 2 + 0.001 * k, 2 + 0.001 * (k + 1)  # a cycle under an hour: 1 ms sampling both ways
        # half circles alternating sides, each tangent to the next: a growing spiral
        lines.append(f"G3 X{-r1 if k % 2 == 0 else r1:.4f} Y0 R{(r0 + r1) / 2:.4f}")
    lines.append("M2")
    prog = tmp_path / "spiral.ngc"
    prog.write_text("\n".join(lines) + "\n")
    calls = []
    import trcopt.pipeline.stream as stream

    original = stream._Run.cut

    def counted(self: Any, buf: list, tee: Any, final: bool) -> Any:
        calls.append(len(buf))
        return original(self, buf, tee, final)

    stream._Run.cut = counted  # type: ignore[method-assign]
    try:
        streamed = plan_streamed(str(prog), PlanOptions(), json=True, window=50)
    finally:
        stream._Run.cut = original  # type: ignore[method-assign]
    assert len(calls) < 20, calls  # doubling: about log2(3000/50) tries, not 3000
    whole = plan_file(prog, PlanOptions())
    assert whole.timing is not None and len(whole.timing.sections) <= 3
    _compare(json.loads("".join(whole.json_chunks())), json.loads("".join(streamed.json_chunks())))


def test_a_limit_exceeded_between_grid_points_is_one_warning_both_ways(monkeypatch: pytest.MonkeyPatch) -> None:
    """A feed whose limit check fails (forced: every check reports a violation, with the real
    ratios scaled up) gives one TIMING-LIMITS warning at the worst block, the same whole and
    window by window."""
    import dataclasses

    from trcopt.codes import Code
    from trcopt.timing.trajectory import TimedTrajectory

    real = TimedTrajectory.check_limits

    def failing(self: Any, dt: float = 1e-4, tolerance: float = 1.001) -> Any:
        rep = real(self, dt, tolerance)
        return dataclasses.replace(rep, ok=False, a_ratio=tuple(1.5 * a for a in rep.a_ratio))

    monkeypatch.setattr(TimedTrajectory, "check_limits", failing)
    path = ROOT / "problems" / "siemens" / "ex05_kont_g451.mpf"
    whole = plan_file(path, PlanOptions())
    streamed = plan_streamed(str(path), PlanOptions(), window=3)
    warned = [d for d in whole.diagnostics if d.code == Code.TIMING_LIMITS]
    assert len(warned) == 1 and "acceleration" in warned[0].message and warned[0].span.line > 0
    assert [(d.code, d.message, d.span) for d in streamed.diagnostics] == [
        (d.code, d.message, d.span) for d in whole.diagnostics
    ]
