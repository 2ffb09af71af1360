"""The runs of compensated contour blocks of a tool-centre path read piece by piece, and what the
streaming verification knows so far about each source line.

:class:`LineFacts` follows :func:`trcopt.verify.contour.contour_rows` over a path whose source
lines never decrease: the lines with compensated contour segments, the lines with any segment,
and the runs of compensated blocks (:func:`~trcopt.verify.contour._runs`) with their lead blocks
and closing joints (:func:`~trcopt.verify.contour._split`), each run settled when it ends. For a
line it tells whether its programmed elements are compensated, whether it is a lead block, and
whether that can still change (a line not passed yet, a block among the first or last
``MAX_LEAD_BLOCKS + 1`` of the open run).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

import numpy as np

from trcopt.verify.contour import MAX_LEAD_BLOCKS, _split
from trcopt.verify.store import ProgramStore

__all__ = ["EndedRun", "LineFacts"]

_EDGE = MAX_LEAD_BLOCKS + 1  # blocks at each end of a run that may be leads or closing blocks


@dataclass(slots=True)
class EndedRun:
    """A run of compensated blocks that has ended: its edge blocks, its closing (first and last
    line, or None) and the index of the segment that ended it (the path's length at the end)."""

    lines: frozenset[int]
    closing: tuple[int, int] | None
    end: int
    start: int
    segments: dict[int, object] = field(default_factory=dict)  # index → segment, around the edges


class LineFacts:
    """What is known about the source lines after the segments read so far."""

    def __init__(self, store: ProgramStore) -> None:
        self.store = store
        size = int(store.line.max()) + 2 if store.n else 2
        self.on = np.zeros(size, bool)  # lines with a compensated contour (or corner) segment
        self.tool = np.zeros(size, bool)  # lines with any segment
        self.cur = -(1 << 62)  # the last line read
        self.lo: int | None = None
        self.hi: int | None = None
        self.finished = False
        self.lead_lines: set[int] = set()
        self.closings: dict[int, int] = {}  # last line → first line
        self.closing_firsts: set[int] = set()
        # the open run: its blocks at both ends, how many, the last compensated line
        self.head: list[int] = []
        self.tail: deque[int] = deque(maxlen=_EDGE)
        self.blocks = 0
        self.last: int | None = None
        self.run_start = -1  # index of the open run's first segment
        self.ended: list[EndedRun] = []  # ended runs not yet settled by the verifier

    def _grow(self, top: int) -> None:
        if top >= len(self.on):
            size = max(top + 2, 2 * len(self.on))
            self.on, self.tool = (np.concatenate((a, np.zeros(size - len(a), bool))) for a in (self.on, self.tool))

    def read(self, on: np.ndarray, lines: np.ndarray, k0: int) -> None:
        """Take the segments ``k0`` … (their on flag: radius > 0 and contour or corner role;
        their source lines)."""
        if not len(lines):
            return
        if lines[0] < self.cur or np.any(lines[1:] < lines[:-1]):
            raise ValueError("the source lines of the tool path decrease: not a streamable plan")
        self._grow(int(lines[-1]))
        self.tool[lines] = True
        self.on[lines[on]] = True
        if on.any():
            self.lo = int(lines[on][0]) if self.lo is None else self.lo
            self.hi = int(lines[on][-1])
        self.cur = int(lines[-1])
        # one step per change of (on, line): the runs of contour.py's _runs
        change = np.ones(len(lines), bool)
        change[1:] = (on[1:] != on[:-1]) | (lines[1:] != lines[:-1])
        star = self.store.star_lines(int(lines[0]) if self.last is None else min(self.last, int(lines[0])),
                                     int(lines[-1]))  # fmt: skip
        idx = np.nonzero(change)[0]
        at = np.minimum(np.searchsorted(star, lines[idx]), max(len(star) - 1, 0))
        has = star[at] == lines[idx] if len(star) else np.zeros(len(idx), bool)
        for k, flag, line, is_block in zip(idx.tolist(), on[idx].tolist(), lines[idx].tolist(), has.tolist(),
                                           strict=True):  # fmt: skip
            if not flag:
                if self.blocks:
                    self._end(k0 + k)
                self.blocks, self.last, self.run_start = 0, None, -1
                self.head, self.tail = [], deque(maxlen=_EDGE)
                continue
            if self.run_start < 0:
                self.run_start = k0 + k
            if line == self.last:
                continue
            if self.last is not None and line > self.last + 1:
                gap = star[np.searchsorted(star, self.last, "right") : np.searchsorted(star, line)]
                for g in gap[~self.tool[gap]].tolist():
                    self._block(g)
            if is_block and (not self.tail or self.tail[-1] != line):
                self._block(line)
            self.last = line

    def _block(self, line: int) -> None:
        self.blocks += 1
        if len(self.head) < _EDGE:
            self.head.append(line)
        self.tail.append(line)

    def _end(self, end: int) -> None:
        m = self.blocks
        # _split on a run of which only the edges are kept: the indices into it are the same
        run = {i: b for i, b in enumerate(self.head)}
        run.update({m - len(self.tail) + i: b for i, b in enumerate(self.tail)})
        store = self.store

        def start_of(b: int) -> tuple[float, float, float]:
            r = store.first_row(b, store.star)
            return (store.sx[r], store.sy[r], store.sz[r])

        def end_of(b: int) -> tuple[float, float, float]:
            r = store.last_row(b, store.star)
            return (store.ex[r], store.ey[r], store.ez[r])

        leads, closings = _split([_Edges(run, m)], start_of, end_of)  # type: ignore[list-item]
        self.lead_lines |= leads
        closing = None
        for c in closings:
            self.closings[c.last_line] = c.first_line
            self.closing_firsts.add(c.first_line)
            closing = (c.first_line, c.last_line)
        self.ended.append(EndedRun(frozenset(run.values()), closing, end, self.run_start))

    def finish(self, n: int) -> None:
        """The path has ended after ``n`` segments: every fact is final."""
        if self.blocks:
            self._end(n)
        self.blocks, self.head, self.tail = 0, [], deque(maxlen=_EDGE)
        self.finished = True

    def open_lines(self) -> set[int]:
        """The open run's edge blocks: lead or closing blocks perhaps."""
        return set(self.head) | set(self.tail)

    def compensated(self, lines: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(compensated, final) for programmed elements of these lines (part candidates)."""
        inside = lines < len(self.on)
        safe = np.where(inside, lines, 0)
        on = self.on[safe] & inside
        tool = self.tool[safe] & inside
        if self.lo is None or self.hi is None:
            omitted = np.zeros(len(lines), bool)
            known = np.ones(len(lines), bool)
        else:
            omitted = ~tool & (lines >= self.lo) & (lines <= self.hi)
            known = tool | (lines < self.lo) | (lines <= self.hi)
        if self.finished:
            return on | omitted, np.ones(len(lines), bool)
        below = lines < self.cur
        return on | (below & omitted), on | (below & known)

    def lead(self, lines: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(lead block, final) of these lines."""
        value = np.isin(lines, np.fromiter(self.lead_lines, np.int64, len(self.lead_lines)))
        if self.finished:
            return value, np.ones(len(lines), bool)
        edges = self.open_lines()
        unsure = np.isin(lines, np.fromiter(edges, np.int64, len(edges))) | (lines >= self.cur)
        return value, value | ~unsure

    def part(self, lines: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(part contour element, final) for part candidates of these lines."""
        cv, cd = self.compensated(lines)
        lv, ld = self.lead(lines)
        return cv & ~lv, (cd & ~cv) | (ld & lv) | (cd & ld)


class _Edges:
    """A run of which only the blocks at both ends are known, as :func:`_split` reads it."""

    def __init__(self, blocks: dict[int, int], m: int) -> None:
        self.blocks, self.m = blocks, m

    def __len__(self) -> int:
        return self.m

    def __getitem__(self, i: int | slice) -> int | list[int]:
        if isinstance(i, slice):
            return [self.blocks[j] for j in range(*i.indices(self.m))]
        return self.blocks[i if i >= 0 else self.m + i]
