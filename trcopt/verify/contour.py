"""The part contour of a plan, and the lead moves that are not part of it.

The controller compensates every block between G41/G42 and G40 alike; which of them machine the
part is the program's intent. CAM posts write a closed contour between a **lead-in** (an arc, or a
line and an arc, into the contour's start point) and a **lead-out** (the same out of it), all
under compensation:

.. code-block:: text

    N30 G1 G41 X55 Y-5        approach (activation) block
    N40 G3 X50 Y0 CR=5        lead-in arc, tangent to the contour at its start point (50, 0)
    N50 G1 X0 Y0 …            the closed part contour, back to (50, 0) in N90
    N100 G3 X45 Y-5 CR=5      lead-out arc
    N110 G1 G40 X45 Y-15      retraction (deselection) block

The tool-centre path of the contour passes over the programmed lead arcs (they lie in the air
outside the part), so they are not part contour. Within each run of compensated contour blocks,
the **part** is the longest closed loop that starts within the first ``MAX_LEAD_BLOCKS + 1`` blocks
and ends within the last ``MAX_LEAD_BLOCKS + 1`` (the start point of its first block is the end
point of its last, within :data:`CLOSED_MM`); the blocks before and after it are **leads**. A run
that does not close this way (an open profile) is part contour throughout, as before.

Where such a loop closes (the start point of its first block, the end point of its last) the
controller compensates no corner: the tool enters the loop there at the end of the approach (or
lead-in) and leaves it at the start of the retraction. :attr:`ContourBlocks.closings` names the two
blocks of each closing joint; the verification measures the overlap of their tool paths across it
against the entry and exit points (:mod:`trcopt.verify.joints`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Container, Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from trcopt.geometry.vec import Vec3
from trcopt.path import Role, Segment
from trcopt.verify.table import SegmentTable, unique

__all__ = ["CLOSED_MM", "MAX_LEAD_BLOCKS", "Closing", "ContourBlocks", "contour_blocks", "contour_rows", "part_contour"]

MAX_LEAD_BLOCKS = 3  # lead-in (lead-out) blocks at most: a line, an arc, and one more
CLOSED_MM = 1e-5  # a contour closes when its end point is within this of its start point, mm


@dataclass(frozen=True, slots=True)
class Closing:
    """The joint where a closed part contour closes: its last block ends where its first starts.

    Attributes
    ----------
    first_line, last_line:
        Source lines of the loop's first and last block.
    """

    first_line: int
    last_line: int


@dataclass(frozen=True, slots=True)
class ContourBlocks:
    """The programmed elements of the compensated blocks, split into part contour and leads.

    Attributes
    ----------
    compensated:
        Programmed elements of every block whose tool-centre path is a compensated contour, plus
        blocks in between without any tool-centre segment (omitted by collision detection).
    part:
        ``compensated`` without the lead blocks.
    lead_lines:
        Source lines of the lead-in and lead-out blocks.
    closings:
        The closing joint of every closed loop of two or more blocks.
    """

    compensated: list[Segment]
    part: list[Segment]
    lead_lines: frozenset[int]
    closings: tuple[Closing, ...] = ()


def _runs(on: Iterable[bool], lines: Iterable[int], tool_lines: Container[int], has: Container[int]) -> list[list[int]]:
    """Source lines of each run of consecutive compensated contour segments (``on``: a segment of
    radius > 0 and role contour or corner; ``lines``: its source line), in order, with the omitted
    blocks in between; only lines with programmed contour elements (``has``)."""
    runs: list[list[int]] = []
    run: list[int] = []
    last = None
    for flag, line in zip(on, lines, strict=True):
        if not flag:
            if run:
                runs.append(run)
            run, last = [], None
            continue
        if line == last:
            continue
        if last is not None and line > last + 1:
            run.extend(ln for ln in range(last + 1, line) if ln not in tool_lines and ln in has)
        if line in has and line not in run[-1:]:
            run.append(line)
        last = line
    if run:
        runs.append(run)
    return runs


def _loop(blocks: list[int], start_of: Callable[[int], Vec3], end_of: Callable[[int], Vec3]) -> tuple[int, int] | None:
    """Indices (first, last) into ``blocks`` of the closed loop of one run, None for an open run
    (``start_of``, ``end_of``: a block's programmed start and end point)."""
    m = len(blocks)
    starts = [start_of(b) for b in blocks[: MAX_LEAD_BLOCKS + 1]]
    ends = {j: end_of(blocks[j]) for j in range(max(0, m - 1 - MAX_LEAD_BLOCKS), m)}
    for i in range(min(MAX_LEAD_BLOCKS + 1, m)):
        for j in range(m - 1, max(i, m - 1 - MAX_LEAD_BLOCKS) - 1, -1):
            if math.hypot(starts[i][0] - ends[j][0], starts[i][1] - ends[j][1]) <= CLOSED_MM:
                return i, j
    return None


def _split(runs: list[list[int]], start_of: Callable[[int], Vec3], end_of: Callable[[int], Vec3]) -> tuple[
        frozenset[int], tuple[Closing, ...]]:  # fmt: skip
    """The lead lines and the closing joints of the runs."""
    lead_list: list[int] = []
    closings: list[Closing] = []
    for run in runs:
        loop = _loop(run, start_of, end_of)
        if loop is None:
            continue
        i, j = loop
        lead_list += run[:i] + run[j + 1 :]
        if j > i:
            closings.append(Closing(run[i], run[j]))
    return frozenset(lead_list), tuple(closings)


def contour_blocks(programmed: Sequence[Segment], toolpath: Sequence[Segment]) -> ContourBlocks:
    """Split the programmed contour of the compensated blocks into part contour and leads.

    Parameters
    ----------
    programmed, toolpath:
        ``PlanResult.programmed`` and ``PlanResult.toolpath``.

    Returns
    -------
    ContourBlocks
        Approach and retraction (activation, deselection, SAR) blocks are in none of its lists:
        their tool-centre moves are checked by the informational ``lead_clearance``, as are the
        lead blocks'.
    """
    on_lines = {s.span.line for s in toolpath if s.radius > 0.0 and s.role in (Role.CONTOUR, Role.CORNER)}
    lo, hi = (min(on_lines), max(on_lines)) if on_lines else (1, 0)
    tool_lines = {s.span.line for s in toolpath}
    part_lines = on_lines | {ln for ln in range(lo, hi + 1) if ln not in tool_lines}
    compensated = [
        p
        for p in programmed
        if p.span.line in part_lines and p.role in (Role.CONTOUR, Role.RAPID) and p.geometry.plane_length > 0.0
    ]
    by_line: dict[int, list[Segment]] = {}
    for p in compensated:
        by_line.setdefault(p.span.line, []).append(p)
    on = [s.radius > 0.0 and s.role in (Role.CONTOUR, Role.CORNER) for s in toolpath]
    runs = _runs(on, [s.span.line for s in toolpath], tool_lines, by_line)
    leads, closings = _split(runs, lambda b: by_line[b][0].geometry.start, lambda b: by_line[b][-1].geometry.end)
    part = [p for p in compensated if p.span.line not in leads] if leads else compensated
    return ContourBlocks(compensated, part, leads, closings)


def contour_rows(
    programmed: Sequence[Segment], tool: SegmentTable, prog: SegmentTable
) -> tuple[ContourBlocks, np.ndarray, np.ndarray]:
    """:func:`contour_blocks` from the tables of the tool-centre path (``tool``) and of
    ``programmed`` (``prog``), the same blocks, with the rows of ``compensated`` and ``part`` in
    ``prog``."""
    on = (tool.radius > 0.0) & tool.roles(Role.CONTOUR, Role.CORNER)
    on_lines, tool_lines = unique(tool.line[on]), unique(tool.line)
    if on_lines.size:
        span = np.arange(on_lines[0], on_lines[-1] + 1)
        on_lines = unique(np.concatenate((on_lines, span[~np.isin(span, tool_lines)])))
    rows = np.nonzero(np.isin(prog.line, on_lines) & prog.roles(Role.CONTOUR, Role.RAPID) & (prog.plen > 0.0))[0]
    compensated = [programmed[j] for j in rows.tolist()]
    lines = prog.line[rows]
    has, first = np.unique(lines, return_index=True)
    last = len(lines) - 1 - np.unique(lines[::-1], return_index=True)[1]
    where = {ln: j for j, ln in enumerate(has.tolist())}
    runs = _runs(on.tolist(), tool.line.tolist(), set(tool_lines.tolist()), where)

    def start_of(b: int) -> Vec3:
        r = rows[first[where[b]]]
        return (prog.sx[r], prog.sy[r], prog.sz[r])

    def end_of(b: int) -> Vec3:
        r = rows[last[where[b]]]
        return (prog.ex[r], prog.ey[r], prog.ez[r])

    leads, closings = _split(runs, start_of, end_of)
    if leads:
        keep = ~np.isin(lines, np.fromiter(leads, np.int64, len(leads)))
        part_rows = rows[keep]
        part = [p for p, k in zip(compensated, keep.tolist(), strict=True) if k]
    else:
        part_rows, part = rows, compensated
    return ContourBlocks(compensated, part, leads, closings), rows, part_rows


def part_contour(programmed: Sequence[Segment], toolpath: Sequence[Segment]) -> list[Segment]:
    """The part contour: programmed elements of the compensated contour blocks without the
    approach, retraction and lead blocks (:func:`contour_blocks`)."""
    return contour_blocks(programmed, toolpath).part
