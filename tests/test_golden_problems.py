"""The golden suite: every problem under problems/<dialect>/ that has ``<name>.expected.json``.

Expected file format: ``{"source": why these numbers, "ok": bool, "alarms": [[severity,
alarm-number-or-code, block], ...], "tolerance_mm": float, "toolpath": [[kind, block, start,
end, centre-or-null], ...]}`` with 2- or 3-component points (2 = compare x, y only).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from gouge import gouges

from trcopt.pipeline import PlanOptions, plan_file

PROBLEMS = Path(__file__).resolve().parents[1] / "problems"
PROGRAM_SUFFIXES = (".mpf", ".spf", ".h", ".ngc")


def _program(stem: Path) -> Path:
    for suffix in PROGRAM_SUFFIXES:
        if stem.with_suffix(suffix).exists():
            return stem.with_suffix(suffix)
    raise FileNotFoundError(f"no program for {stem}")


CASES = sorted(p.with_suffix("").with_suffix("") for p in PROBLEMS.glob("*/*.expected.json"))
IDS = [f"{c.parent.name}/{c.name}" for c in CASES]


def _xy(v):
    return [float(c) for c in v]


def _close(actual, expected, tol):
    return len(expected) <= len(actual) and all(abs(a - e) <= tol for a, e in zip(actual, expected, strict=False))


def _options(stem: Path) -> PlanOptions:
    """The plan options of a golden problem: its expected file's ``options`` (e.g. a Heidenhain
    APPR radius reading) over the defaults, without timing."""
    expected = json.loads(stem.with_suffix(".expected.json").read_text())
    return PlanOptions(timing=False, **expected.get("options", {}))


@pytest.mark.parametrize("stem", CASES, ids=IDS)
def test_golden_problem(stem: Path) -> None:
    expected = json.loads(stem.with_suffix(".expected.json").read_text())
    result = plan_file(_program(stem), _options(stem))
    tol = expected["tolerance_mm"]
    got = [(s.kind, s.span.block, s.start_xyz, s.end_xyz, s.center_xyz) for s in result.toolpath]
    assert len(got) == len(expected["toolpath"]), "\n".join(map(str, got))
    for k, (g, e) in enumerate(zip(got, expected["toolpath"], strict=True)):
        kind, block, start, end, center = e
        assert g[0] == kind and g[1] == block, (k, g, e)
        assert _close(g[2], _xy(start), tol), (k, g, e)
        assert _close(g[3], _xy(end), tol), (k, g, e)
        if center is None:
            assert g[4] is None
        else:
            assert _close(g[4], _xy(center), tol), (k, g, e)
    alarms = [
        [d.severity.value, d.alarm if d.alarm is not None else d.code, d.span.block]
        for d in result.diagnostics
        if d.severity.value in ("warning", "error")
    ]
    assert alarms == expected["alarms"]
    assert result.ok is expected["ok"]


@pytest.mark.parametrize("stem", CASES, ids=IDS)
def test_golden_problem_does_not_gouge(stem: Path) -> None:
    result = plan_file(_program(stem), _options(stem))
    found = gouges(result.programmed, result.toolpath)
    if any(d.code == "TRC-CONTOUR-VIOLATION" for d in result.diagnostics):
        # CDOF runs the reversed offset as the controller does: the independent check must see it
        assert found, "the contour violation must be visible to the distance check"
    else:
        assert found == []
