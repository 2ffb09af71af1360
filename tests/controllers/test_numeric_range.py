"""Numbers out of range stop the program at their block (``NC-RANGE``, trcopt.nc.limits), in every
dialect, instead of reaching the later stages (a 1e12 mm line used to exhaust memory in timing)."""

from __future__ import annotations

import dataclasses
import math
import random

import pytest

from trcopt.codes import Code
from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.geometry.plane import Plane
from trcopt.nc.limits import MAX_COORDINATE_MM, MAX_FEED_MM_S, check_moves, out_of_range
from trcopt.nc.model import CompState, Move, MoveKind
from trcopt.pipeline import PlanOptions, plan

SIEMENS = (
    "$TC_DP1[1,1]=120 $TC_DP6[1,1]=5\nN10 G0 X0 Y0 T1 D1\nN20 G1 G41 X{x} Y10 F600\nN30 X50\nN40 G40 X60 Y0\nN50 M30\n"
)
HEIDENHAIN = (
    "0 BEGIN PGM R MM\n1 TOOL DEF 1 L+50 R+5\n2 TOOL CALL 1 Z S3000\n3 L X+0 Y+0 R0 FMAX\n"
    "4 L X{x} Y+10 RL F600\n5 L X+50 Y+10\n6 L X+60 Y+0 R0\n7 END PGM R MM\n"
)
RS274 = "G21 G17 G90\nN10 G0 X0 Y0\nN20 G41.1 D10 G1 X{x} Y10 F600\nN30 G1 X50\nN40 G40 G1 X60 Y0\nM2\n"


@pytest.mark.parametrize(
    ("text", "file", "line", "block"),
    [
        (SIEMENS.format(x="1000000000000"), "p.mpf", 3, "N20"),
        (HEIDENHAIN.format(x="+1000000000000"), "p.h", 5, "4"),
        (RS274.format(x="1000000000000"), "p.ngc", 3, "N20"),
    ],
)
def test_a_coordinate_beyond_the_bound_is_an_error_at_its_block(text: str, file: str, line: int, block: str) -> None:
    result = plan(text, file=file, options=PlanOptions())
    assert not result.ok
    err = result.errors[0]
    assert err.code is Code.NC_RANGE
    assert (err.span.file, err.span.line, err.span.block) == (file, line, block)
    assert err.span.column >= 1
    assert "MAX_COORDINATE_MM" in err.message
    assert result.timing is None or math.isfinite(result.timing.duration)
    assert math.isfinite(result.path_length)


def test_coordinates_within_the_bound_are_planned_as_before() -> None:
    result = plan(SIEMENS.format(x="20"), file="p.mpf", options=PlanOptions(timing=False))
    assert result.ok, [d.format() for d in result.errors]


def _move(**kw: object) -> Move:
    base: dict[str, object] = dict(
        kind=MoveKind.LINE, start=(0.0, 0.0, 0.0), end=(1.0, 0.0, 0.0), plane=Plane.G17,
        span=SourceSpan("p", 1, 1), feed_mm_s=10.0,
    )
    base.update(kw)
    return Move(**base)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("change", "words"),
    [
        (dict(end=(math.nan, 0.0, 0.0)), "not a finite"),
        (dict(end=(0.0, math.inf, 0.0)), "not a finite"),
        (dict(end=(0.0, 0.0, 2 * MAX_COORDINATE_MM)), "MAX_COORDINATE_MM"),
        (dict(kind=MoveKind.ARC, center=(-2 * MAX_COORDINATE_MM, 0.0, 0.0), ccw=True), "arc centre"),
        (dict(feed_mm_s=math.nan), "feed"),
        (dict(feed_mm_s=2 * MAX_FEED_MM_S), "MAX_FEED_MM_S"),
        (dict(comp=CompState(radius=math.inf)), "compensation value"),
        (dict(turns=10**9), "MAX_TURNS"),
    ],
)
def test_out_of_range_names_the_number(change: dict, words: str) -> None:
    problem = out_of_range(_move(**change))
    assert problem is not None and words in problem
    assert out_of_range(_move()) is None


def _check_moves_one_by_one(moves: list[Move], diagnostics: tuple) -> tuple:  # type: ignore[type-arg]
    """:func:`~trcopt.nc.limits.check_moves` asking :func:`out_of_range` about every move."""
    for i, move in enumerate(moves):
        problem = out_of_range(move)
        if problem is not None:
            line = max(move.span.line, 1)
            kept = tuple(d for d in diagnostics if d.span.line < line or not d.span.line)
            return tuple(moves[:i]), (*kept, Diagnostic(Severity.ERROR, Code.NC_RANGE, problem, move.span))
    return tuple(moves), tuple(diagnostics)


def test_check_moves_finds_what_out_of_range_finds_move_by_move() -> None:
    # chains of moves (each starting at the end before it, the same tuple or an equal one) with now
    # and then a number out of range in any field the common test looks at
    r = random.Random(11)
    bad = [math.inf, -math.inf, math.nan, 2 * MAX_COORDINATE_MM, -2 * MAX_COORDINATE_MM]
    notes = tuple(Diagnostic(Severity.INFO, Code.LCNC_MESSAGE, "note", SourceSpan("p", k, 1)) for k in range(0, 60, 7))
    found = 0
    for _ in range(400):
        moves, pos = [], (0.0, 0.0, 0.0)
        for k in range(r.randrange(1, 40)):
            end = tuple(r.uniform(-100, 100) for _ in range(3))
            if r.random() < 0.03:
                end = tuple(r.choice(bad) if r.random() < 0.5 else v for v in end)
            start = pos if r.random() < 0.8 else tuple(pos)
            change: dict = {}  # type: ignore[type-arg]
            x = r.random()
            if x < 0.01:
                change["feed_mm_s"] = r.choice([-1.0, 2 * MAX_FEED_MM_S, math.nan])
            elif x < 0.02:
                change["comp"] = CompState(radius=r.choice(bad))
            elif x < 0.03:
                change["turns"] = r.choice([-1, 10**6])
            elif x < 0.05:
                change.update(kind=MoveKind.ARC, center=(0.0, r.choice([0.0, *bad]), 0.0), ccw=True)
            elif x < 0.06:
                start = start[:2]  # a malformed point
            m = Move(MoveKind.LINE, start, end, Plane.G17, SourceSpan("p", k + 1, 1), feed_mm_s=10.0)  # type: ignore[arg-type]
            moves.append(dataclasses.replace(m, **change))
            pos = end
        expected = _check_moves_one_by_one(moves, notes)
        assert check_moves(moves, notes) == expected
        found += len(expected[0]) < len(moves)
    assert 50 < found < 350


@pytest.mark.parametrize("streamed", [False, True])
def test_an_arc_of_radius_zero_is_an_error_at_its_block(tmp_path: object, streamed: bool) -> None:
    """A polar circle around a pole at the tool (SINUMERIK ``AP=… G3`` from the pole) has its
    centre at its start point: no circle, and a zero-length arc the timing stage cannot divide by."""
    text = "N10 G17 G90 G0 X0 Y0 Z0\nN20 AP=459 F476 G3\nN30 G1 X10\nN40 M30\n"
    if streamed:
        from pathlib import Path

        from trcopt.pipeline.stream import plan_streamed

        prog = Path(str(tmp_path)) / "p.mpf"
        prog.write_text(text)
        res: object = plan_streamed(str(prog), PlanOptions())
    else:
        res = plan(text, file="p.mpf", options=PlanOptions())
    errors = [d for d in res.diagnostics if d.severity is Severity.ERROR]  # type: ignore[attr-defined]
    assert [(d.code, d.span.line, d.span.block) for d in errors] == [(Code.NC_RANGE, 2, "N20")]
    assert "arc radius 0 mm" in errors[0].message


def test_an_arc_with_its_radius_in_its_plane_is_in_range() -> None:
    """The radius is measured in the arc's plane: a G18 arc whose centre differs only in Y from
    its start has no radius; one whose centre differs in Z has."""
    span = SourceSpan("p.ngc", 1, 1)
    comp = CompState()
    arc = Move(MoveKind.ARC, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), Plane.G18, span, comp, 1.0, (0.0, 5.0, 0.0), True)
    assert out_of_range(arc) is not None and "arc radius" in (out_of_range(arc) or "")
    arc = dataclasses.replace(arc, center=(0.0, 5.0, 2.0))
    assert out_of_range(arc) is None
