"""The SAR golden problems (spec §C examples 7–12), run read_program → expand_sar → compensate.

The same files are picked up by tests/test_golden_problems.py through the pipeline; this module
checks them end to end through the stage functions directly.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from trcopt.compensation import compensate
from trcopt.config import TrcSettings
from trcopt.controllers import read_program
from trcopt.controllers.siemens.sar import expand_sar
from trcopt.errors import Diagnostic
from trcopt.path import Role, Segment

SIEMENS = Path(__file__).resolve().parents[3] / "problems" / "siemens"
CASES = sorted(
    p
    for p in SIEMENS.glob("ex*.mpf")
    if p.name[:4] in ("ex07", "ex08", "ex09", "ex10", "ex11", "ex12")
)


def plan_sar(
    path: Path, settings: TrcSettings | None = None
) -> tuple[list[Segment], list[Diagnostic]]:
    settings = settings or TrcSettings()
    nc = read_program(path.read_text(), file=str(path), dialect="siemens")
    diagnostics = list(nc.diagnostics)
    moves = list(expand_sar(nc.moves, settings, diagnostics))
    complete = not any(d.severity.value == "error" for d in diagnostics)
    toolpath = list(compensate(moves, settings, diagnostics, complete=complete))
    diagnostics.sort(key=lambda d: (d.span.line, d.span.column))
    return toolpath, diagnostics


def _close(actual, expected, tol: float) -> bool:
    return len(expected) <= len(actual) and all(
        abs(a - e) <= tol for a, e in zip(actual, expected, strict=False)
    )


def test_every_sar_example_has_a_golden_problem() -> None:
    stems = {p.stem[:4] for p in CASES if p.with_suffix(".expected.json").exists()}
    assert stems == {"ex07", "ex08", "ex09", "ex10", "ex11", "ex12"}
    assert len(CASES) >= 15


@pytest.mark.parametrize("program", CASES, ids=[p.stem for p in CASES])
def test_sar_golden(program: Path) -> None:
    expected = json.loads(program.with_suffix(".expected.json").read_text())
    toolpath, diagnostics = plan_sar(program)
    tol = expected["tolerance_mm"]
    got = [(s.kind, s.span.block, s.start_xyz, s.end_xyz, s.center_xyz) for s in toolpath]
    assert len(got) == len(expected["toolpath"]), "\n".join(map(str, got))
    for k, (g, e) in enumerate(zip(got, expected["toolpath"], strict=True)):
        kind, block, start, end, center = e
        assert g[0] == kind and g[1] == block, (k, g, e)
        assert _close(g[2], start, tol), (k, g, e)
        assert _close(g[3], end, tol), (k, g, e)
        assert (g[4] is None) if center is None else _close(g[4], center, tol), (k, g, e)
    alarms = [
        [d.severity.value, d.alarm if d.alarm is not None else d.code, d.span.block]
        for d in diagnostics
        if d.severity.value in ("warning", "error")
    ]
    assert alarms == expected["alarms"]
    assert (not any(d.severity.value == "error" for d in diagnostics)) is expected["ok"]


def test_example9_roles_feeds_and_radii() -> None:
    """R43/R44: rapid infeed, FAD 200 on P2→P3, F1500 on the quadrant, old feed on the helix."""
    toolpath, _ = plan_sar(SIEMENS / "ex09_sar_offn_contour_example2.mpf")
    per_min = [None if s.feed_mm_s is None else round(s.feed_mm_s * 60.0, 6) for s in toolpath]
    assert per_min == [
        None,
        None,
        None,
        200.0,
        1500.0,
        1500.0,
        1500.0,
        1500.0,
        10000.0,
        10000.0,
        10000.0,
    ]
    roles = [s.role for s in toolpath]
    assert roles[1] is Role.APPROACH and roles[4] is Role.APPROACH
    assert roles[7] is Role.RETRACT and roles[9] is Role.RETRACT
    arc_in, helix_out = toolpath[4].geometry, toolpath[7].geometry
    assert arc_in.radius == pytest.approx(10.0)  # tool-centre radius = DISR on approach
    assert helix_out.radius == pytest.approx(5.0)  # ... and on retraction
    assert toolpath[4].radius == pytest.approx(15.0)  # R_eff = 10 + OFFN 5


def test_example10_helix_lengths() -> None:
    toolpath, _ = plan_sar(SIEMENS / "ex10_sar_semicircle_helix_g143.mpf")
    helix = toolpath[3].geometry
    assert helix.plane_length == pytest.approx(18.850, abs=5e-4)
    assert helix.length == pytest.approx(18.955, abs=5e-4)
    assert toolpath[3].feed_mm_s * 60.0 == pytest.approx(300.0)
