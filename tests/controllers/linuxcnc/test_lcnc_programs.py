"""Upstream LinuxCNC programs that need only the supported rs274 subset, run through
``trcopt plan --dialect rs274``, against LinuxCNC's own output (``expected.segments.json``), and
the two error programs of ``interp-bad-ccomp``."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

from trcopt.pipeline import PlanOptions, plan_file

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_lcnc_pairs import PEER, TOL, segment_deviation  # noqa: E402

needs_peer = pytest.mark.skipif(
    not PEER.is_dir(), reason=f"LinuxCNC peer data not found at {PEER.resolve()}"
)

# programs within the subset (crazy-paths: O-word subroutines with arguments and if;
# inside-corners: a subroutine run with D0, a negative and a positive diameter; cam-nisley,
# whose inch tool table is not found by name, runs in test_rs274_language; g90g91g92: a G92 offset,
# whose moves LinuxCNC prints in the offset system and trcopt in G54; inverse-time-with-comp: G93
# under cutter compensation; lathe-comp: lathe tools of orientations 2 and 7 in G18, their tips
# programmed) — every program of LinuxCNC's test data with an expected path
SUBSET = [
    "ccomp-lathe-comp/test.ngc",
    "ccomp-mill-g90g91g92/test.ngc",
    "ccomp-mill-line-arc-entry/test.ngc",
    "ccomp-mill-zchanges/test.ngc",
    "interp-crazy-paths/test.ngc",
    "interp-inside-corners/test.ngc",
    "interp-inverse-time-with-comp/inverse.ngc",
]


def _in_g54(expected: list[dict], canon: list[str]) -> list[dict]:
    """LinuxCNC's segments moved from the G92 system they are printed in to G54 (the shift of
    the last SET_G92_OFFSET before each segment's canon line)."""
    shifts: list[tuple[int, list[float]]] = []
    for number, text in enumerate(canon, start=1):
        if "SET_G92_OFFSET(" in text:
            values = [float(v) for v in text.split("(", 1)[1].rstrip(")").split(",")[:3]]
            shifts.append((number, values))
    out = []
    for seg in expected:
        d = [0.0, 0.0, 0.0]
        for number, values in shifts:
            if number < seg["line"]:
                d = values
        moved = dict(seg)
        for key in ("end", "center"):
            if seg.get(key) is not None:
                moved[key] = [None if seg[key][i] is None else seg[key][i] + d[i] for i in range(3)]
        if out:  # a move starts where the previous one ended, in the system that one was printed in
            moved["start"] = out[-1]["end"]
        out.append(moved)
    return out


def _units_mm(expected: list[dict]) -> float:
    return 25.4 if any(s.get("units") == "inch" for s in expected) else 1.0


@needs_peer
@pytest.mark.parametrize("program", SUBSET)
def test_upstream_program_matches_linuxcnc(program: str) -> None:
    path = PEER / program
    expected = json.loads((path.parent / "expected.segments.json").read_text())
    expected = _in_g54(expected, (path.parent / "expected").read_text().splitlines())
    # trcopt's path leaves out a move that goes nowhere (LinuxCNC's canon output keeps it)
    expected = [e for e in expected if e["start"] != e["end"] or e["type"] == "arc"]
    # the interpreter's canonical moves: its G64 blending happens later, in the trajectory planner
    result = plan_file(path, PlanOptions(dialect="rs274", timing=False, corners="exact"))
    assert result.ok, [d.format() for d in result.errors]
    assert result.extra["profile"] == "linuxcnc"
    k = _units_mm(expected)
    ours = result.toolpath
    assert len(ours) == len(expected), [(s.kind, s.span.line) for s in ours]
    for i, (seg, exp) in enumerate(zip(ours, expected, strict=True)):
        dev = segment_deviation(seg, exp, k)
        assert dev <= TOL, (
            f"element {i} (canon line {exp['line']}, program line {seg.span.line}): {dev}"
        )
        assert (seg.kind == "rapid") == (exp["type"] == "rapid"), i


@needs_peer
@pytest.mark.parametrize(
    ("program", "code", "line"),
    [
        ("interp-bad-ccomp/ccomp-arcexit.ngc", "LCNC-ARC-AFTER-G40", 7),
        ("interp-bad-ccomp/ccomp-gouging.ngc", "LCNC-CONCAVE-GOUGE", 7),
    ],
)
def test_bad_ccomp_programs_raise_linuxcnc_errors(program: str, code: str, line: int) -> None:
    path = PEER / program
    first = path.read_text().splitlines()[0]
    assert first.startswith(";")
    result = plan_file(path, PlanOptions(dialect="rs274", timing=False))
    assert not result.ok
    err = result.errors[0]
    assert err.code == code
    assert err.message == first[1:].strip()  # LinuxCNC's exact text
    assert err.span.line == line
