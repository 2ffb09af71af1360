"""The streaming verification equals ``verify_plan`` of the whole lists, for any cut points: the
same report (residuals, worst segments, notes, diagnostics), on the golden problems, on jittered
paths that fail every family, on CAM contours with near-tangent joints and closing joints."""

from __future__ import annotations

import random
from pathlib import Path

import pytest
from test_verify_arrays import _cam_contour, _jitter
from test_verify_joints import _plan as _joints_plan

from trcopt.config import TrcSettings
from trcopt.pipeline import PlanOptions, plan, plan_file
from trcopt.verify import verify_plan
from trcopt.verify.store import ProgramStore
from trcopt.verify.stream import StreamVerifier

PROBLEMS = Path(__file__).resolve().parents[2] / "problems"
PROGRAMS = sorted(p for p in PROBLEMS.rglob("*") if p.suffix in (".mpf", ".spf", ".h", ".ngc"))


def _pieces(n: int, rng: random.Random, count: int) -> list[int]:
    return [0, *sorted(rng.sample(range(1, n), min(count, n - 1))), n] if n > 1 else [0, n]


def _stream(programmed, toolpath, moves, rng, near, settings=None, part=True):  # type: ignore[no-untyped-def]
    """The report of random windows: the programmed pieces run ahead of the tool path's."""
    v = StreamVerifier(settings, near_tangent_rad=near, part=iter(list(programmed)) if part else None)
    cuts = _pieces(len(toolpath), rng, rng.choice([0, 1, 3, 8, len(toolpath)]))
    ahead = rng.randint(0, 6)
    moves = list(moves or ())
    for i in range(len(cuts) - 1):
        a = 0 if i == 0 else min(cuts[i] + ahead, len(programmed))
        b = len(programmed) if i == len(cuts) - 2 else min(cuts[i + 1] + ahead, len(programmed))
        v.add(programmed[a:b], toolpath[cuts[i] : cuts[i + 1]], moves if i == 0 else [])
    return v, v.finish()


def _same(programmed, toolpath, moves, near, rng, settings=None, trials=3):  # type: ignore[no-untyped-def]
    ref = verify_plan(programmed, toolpath, moves, settings, near_tangent_rad=near)
    for _ in range(trials):
        v, got = _stream(programmed, toolpath, moves, rng, near, settings)
        assert got.to_json() == ref.to_json()
        assert got.notes == ref.notes
        for name, f in got.families.items():
            assert f.max_residual.hex() == ref.families[name].max_residual.hex(), name
            assert f.span == ref.families[name].span, name
        for strict in (False, True):
            assert got.diagnostics(strict=strict) == ref.diagnostics(strict=strict)
    return v, ref


@pytest.mark.parametrize("program", PROGRAMS, ids=[str(p.relative_to(PROBLEMS)) for p in PROGRAMS])
def test_problems_stream_as_verify_plan(program: Path) -> None:
    r = plan_file(program, PlanOptions(timing=False, verify=False))
    rng = random.Random(program.name)
    for near in (0.0, 0.05):
        v, _ = _same(r.programmed, r.toolpath, r.nc.moves, near, rng, TrcSettings())
        # programs whose source lines never go back are verified window by window
        assert (v.store is not None) == ProgramStore(r.programmed).monotone
        _same(r.programmed, _jitter(r.toolpath, rng, 0.3), r.nc.moves, near, rng, TrcSettings(), trials=2)


def test_failing_families_stream_as_verify_plan() -> None:
    r = plan_file(PROBLEMS / "siemens" / "ex06_bottleneck_cdof.mpf", PlanOptions(timing=False, verify=False))
    _, ref = _same(r.programmed, r.toolpath, r.nc.moves, 0.0, random.Random(1))
    assert not ref.ok and ref.families["clearance"].max_residual > 1.0
    rng = random.Random(2)
    failed = set()
    for program in PROGRAMS[::7]:
        r = plan_file(program, PlanOptions(timing=False, verify=False))
        _, ref = _same(r.programmed, _jitter(r.toolpath, rng, 2.0), r.nc.moves, 0.05, rng, trials=2)
        failed |= {f.name for f in ref.failed}
    assert {"radius", "tangency", "continuity", "clearance"} <= failed


@pytest.mark.parametrize("side", ["G41.1 D2", "G42.1 D2"])
def test_cam_contour_streams_as_verify_plan(side: str) -> None:
    # near-tangent continuations, corners, the closing joint at the end against the first blocks
    r = plan(_cam_contour(300, side), file="cam.ngc", options=PlanOptions(timing=False, verify=False))
    rng = random.Random(5)
    v, ref = _same(r.programmed, r.toolpath, r.nc.moves, 0.05, rng, trials=6)
    assert ref.families["clearance"].checks >= 300
    assert not v.clear.waiting and not v.held_arcs  # everything settled
    for scale in (1e-7, 1e-4, 0.02, 0.5):
        _same(r.programmed, _jitter(r.toolpath, rng, scale), r.nc.moves, 0.05, rng, trials=2)


@pytest.mark.parametrize("case", ["closing", "near_tangent", "entry_arc"])
def test_joint_rules_stream_as_verify_plan(case: str) -> None:
    text = {
        "closing": "G21 G17 G90 F600\nG0 X-20 Y5\nG41.1 D10 G1 X0 Y0\nG1 X30 Y0\nG1 X30 Y30\nG1 X0 Y30\n"
        "G1 X0 Y0\nG40 G1 X-20 Y5\nM2\n",
        "near_tangent": "G21 G17 G90 F600\nG0 X-10 Y-10\nG41.1 D4 G1 X0 Y0\nG1 X20 Y0\nG1 X40 Y0.5\n"
        "G1 X60 Y1.5\nG1 X60 Y30\nG40 G1 X80 Y40\nM2\n",
        "entry_arc": "G21 G17 G90 F600\nG0 X10 Y-10\nG41.1 D4 G1 X10 Y0\nG1 X40 Y0\nG1 X40 Y20\n"
        "G40 G1 X60 Y30\nM2\n",
    }[case]
    r = _joints_plan(text)
    rng = random.Random(case)
    for near in (0.0, 0.05):
        _same(r.programmed, r.toolpath, r.nc.moves, near, rng, trials=6)
        _same(r.programmed, _jitter(r.toolpath, rng, 0.5), r.nc.moves, near, rng, trials=3)


def test_without_the_part_the_windows_are_verified_at_the_end() -> None:
    r = plan_file(PROBLEMS / "siemens" / "ex02_square_g450.mpf", PlanOptions(timing=False, verify=False))
    ref = verify_plan(r.programmed, r.toolpath, r.nc.moves)
    v, got = _stream(r.programmed, r.toolpath, r.nc.moves, random.Random(3), 0.0, part=False)
    assert v.store is None and got.to_json() == ref.to_json()


def test_programmed_pieces_must_add_up_to_the_part() -> None:
    r = plan_file(PROBLEMS / "siemens" / "ex02_square_g450.mpf", PlanOptions(timing=False, verify=False))
    v = StreamVerifier(part=iter(r.programmed))
    v.add(r.programmed[:-1], r.toolpath, r.nc.moves)
    with pytest.raises(ValueError, match="not the part"):
        v.finish()


def test_long_contour_keeps_little_between_windows() -> None:
    r = plan(_cam_contour(3000), file="cam.ngc", options=PlanOptions(timing=False, verify=False))
    v = StreamVerifier(part=iter(r.programmed), near_tangent_rad=0.05)
    most = 0
    for a in range(0, len(r.toolpath), 200):
        v.add(r.programmed[a : a + 200] if a else r.programmed[:205], r.toolpath[a : a + 200],
              r.nc.moves if a == 0 else [])  # fmt: skip
        if a + 200 < len(r.toolpath):
            v.n_programmed = min(v.n_programmed, len(r.programmed))
        most = max(most, len(v.clear.waiting) + len(v.clear.kept) + len(v.waiting) + len(v.held_arcs))
    assert most < 100  # the windows' segments are not kept: a few around the run's ends and the window edge
    ref = verify_plan(r.programmed, r.toolpath, r.nc.moves, near_tangent_rad=0.05)
    v.n_programmed = len(r.programmed)
    assert v.finish().to_json() == ref.to_json()
