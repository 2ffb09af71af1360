"""The numeric range trcopt accepts from a part program, checked where numbers become moves.

A reader turns words into canonical :class:`~trcopt.nc.model.Move` values; before any stage uses
them, :func:`check_moves` makes sure every coordinate, centre, feed, compensation value, SAR
distance and turn count is finite and within a sane magnitude. Beyond these bounds no machine
tool exists, and the later stages would sample or allocate without end (a 1e12 mm line timed at
1 ms). A value out of range stops the program at its block with an ``NC-RANGE`` error carrying
the block's place, like any reader error.

Bounds
------
``MAX_COORDINATE_MM``
    1e5 mm (100 m): positions, arc centres, compensation values and SAR distances.
``MAX_FEED_MM_S``
    1e8 mm/min (100 km/min) expressed in mm/s: programmed feeds, far above any machine (the
    timing stage clamps to the machine limits; the bound keeps the numbers finite and sane).
``MAX_TURNS``
    1e4 extra full turns of one helix or circle block.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from trcopt.codes import Code
from trcopt.errors import Diagnostic, Severity
from trcopt.nc.model import Move

__all__ = ["MAX_COORDINATE_MM", "MAX_FEED_MM_S", "MAX_TURNS", "MIN_ARC_RADIUS_MM", "out_of_range", "check_moves"]

MAX_COORDINATE_MM = 1e5
MAX_FEED_MM_S = 1e8 / 60.0
MAX_TURNS = 10_000
MIN_ARC_RADIUS_MM = 1e-9  # an arc's radius in its plane (its centre this near its start: no circle)


def _length_problem(value: float, what: str) -> str | None:
    if not math.isfinite(value):
        return f"{what} is not a finite number ({value!r})"
    if abs(value) > MAX_COORDINATE_MM:
        return f"{what} {value:.6g} mm is beyond ±{MAX_COORDINATE_MM:g} mm (trcopt.nc.limits.MAX_COORDINATE_MM)"
    return None


def _arc_radius(move: Move) -> float:
    """The distance of an arc's start point from its centre in the arc's plane."""
    u, v, _ = move.plane.axes
    p, c = move.start, move.center
    assert c is not None
    return math.hypot(p[u] - c[u], p[v] - c[v])


def out_of_range(move: Move) -> str | None:
    """Why ``move`` holds a number out of range (a sentence), or None when every number is fine."""
    m = MAX_COORDINATE_MM
    p, q, c, feed = move.start, move.end, move.center, move.feed_mm_s
    if (  # the common move: every number plainly in range (NaN fails every comparison)
        len(p) == 3 and len(q) == 3
        and -m <= p[0] <= m and -m <= p[1] <= m and -m <= p[2] <= m
        and -m <= q[0] <= m and -m <= q[1] <= m and -m <= q[2] <= m
        and (c is None or len(c) == 3 and -m <= c[0] <= m and -m <= c[1] <= m and -m <= c[2] <= m
             and _arc_radius(move) >= MIN_ARC_RADIUS_MM)
        and (feed is None or 0.0 <= feed <= MAX_FEED_MM_S)
        and -m <= move.comp.radius <= m
        and 0 <= move.turns <= MAX_TURNS
        and move.sar is None
    ):  # fmt: skip
        return None
    points = [("start point", move.start), ("end point", move.end)]
    if move.center is not None:
        points.append(("arc centre", move.center))
    for what, point in points:
        for axis, value in zip("XYZ", point, strict=False):
            problem = _length_problem(value, f"{what} {axis}")
            if problem:
                return problem
    if move.center is not None and not _arc_radius(move) >= MIN_ARC_RADIUS_MM:
        return (
            f"arc radius {_arc_radius(move):.6g} mm (its centre at its start point) is below "
            f"{MIN_ARC_RADIUS_MM:g} mm (trcopt.nc.limits.MIN_ARC_RADIUS_MM)"
        )
    feed = move.feed_mm_s
    if feed is not None:
        if not math.isfinite(feed) or feed < 0.0:
            return f"feed {feed!r} mm/s is not a finite non-negative number"
        if feed > MAX_FEED_MM_S:
            return (
                f"feed {feed * 60.0:.6g} mm/min is beyond {MAX_FEED_MM_S * 60.0:g} mm/min "
                "(trcopt.nc.limits.MAX_FEED_MM_S)"
            )
    problem = _length_problem(move.comp.radius, "compensation value")
    if problem:
        return problem
    if not 0 <= move.turns <= MAX_TURNS:
        return f"{move.turns} turns are beyond {MAX_TURNS} (trcopt.nc.limits.MAX_TURNS)"
    sar = move.sar
    if sar is not None:
        distances: tuple[tuple[str, float | None], ...] = (
            ("DISR", sar.disr),
            ("DISCL", None if sar.discl is None else sar.discl[0]),
            ("DISRP", None if sar.disrp is None else sar.disrp[0]),
        )
        for what, distance in distances:
            if distance is not None:
                problem = _length_problem(distance, what)
                if problem:
                    return problem
        if sar.fad is not None and not (math.isfinite(sar.fad[0]) and abs(sar.fad[0]) <= MAX_FEED_MM_S):
            return f"FAD {sar.fad[0]!r} mm/s is not a finite feed within {MAX_FEED_MM_S * 60.0:g} mm/min"
    return None


def check_moves(
    moves: Sequence[Move], diagnostics: Sequence[Diagnostic]
) -> tuple[tuple[Move, ...], tuple[Diagnostic, ...]]:
    """The moves up to the first one out of range, and the diagnostics with its ``NC-RANGE`` error.

    Parameters
    ----------
    moves:
        A reader's moves in program order (absolute mm, feeds in mm/s).
    diagnostics:
        The reader's diagnostics; those after the offending block are dropped with its moves
        (they are about blocks that are no longer executed).

    Returns
    -------
    tuple
        ``(moves, diagnostics)``, unchanged when every number is in range.
    """
    m = MAX_COORDINATE_MM
    checked: object = None  # the end point of the move before, found in range (where a move starts)
    for i, move in enumerate(moves):
        p, q = move.start, move.end
        if (  # out_of_range's test of the common move, the start skipped when it was checked as an end
            (p is checked or len(p) == 3 and -m <= p[0] <= m and -m <= p[1] <= m and -m <= p[2] <= m)
            and len(q) == 3 and -m <= q[0] <= m and -m <= q[1] <= m and -m <= q[2] <= m
            and move.center is None
            and (move.feed_mm_s is None or 0.0 <= move.feed_mm_s <= MAX_FEED_MM_S)
            and -m <= move.comp.radius <= m
            and 0 <= move.turns <= MAX_TURNS
            and move.sar is None
        ):  # fmt: skip
            checked = q
            continue
        problem = out_of_range(move)
        if problem is None:
            checked = q
            continue
        span = move.span
        line = max(span.line, 1)
        kept = tuple(d for d in diagnostics if d.span.line < line or not d.span.line)
        error = Diagnostic(Severity.ERROR, Code.NC_RANGE, problem, span)
        return tuple(moves[:i]), (*kept, error)
    return tuple(moves), tuple(diagnostics)
