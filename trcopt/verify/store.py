"""The programmed path kept as compact columns, for the streaming verification.

:class:`ProgramStore` reads every programmed segment once (in batches, through
:class:`~trcopt.verify.table.SegmentTable`) and keeps only NumPy columns: source line (``int32``
when the lines fit), kind, role, start points, the end points that are not the next element's
start point, the arc parameters of the arcs, two masks (part candidates, near-tangent
continuation elements) and the ``float32`` boxes of the part candidates for
:class:`~trcopt.verify.cellgrid.CompactGrid` (about 48 bytes an element; the polynomial curves,
rare, are kept as objects). It gives back the table of any rows (:meth:`ProgramStore.table`, the
same floats as ``SegmentTable`` of those segments: the plane lengths are computed again, by the
same operations) and their geometry objects (:meth:`ProgramStore.geometry`, equal to the
programmed ones).
"""

from __future__ import annotations

from collections.abc import Iterable
from itertools import islice
from typing import Any

import numpy as np

from trcopt.errors import SourceSpan
from trcopt.geometry import Arc, Line, Plane
from trcopt.path import Role, Segment
from trcopt.verify.cellgrid import outward
from trcopt.verify.table import _ARRAYS, ARC, LINE, ROLE, SegmentTable, hypot

__all__ = ["ProgramStore"]

BATCH = 1 << 12  # programmed segments read at once
_COLUMNS = ("line", "kind", "role", "sx", "sy", "sz", "ex", "ey", "ez")
_KEPT = ("line", "kind", "role", "sx", "sy", "sz")
_ARC_COLUMNS = ("cx", "cy", "r", "a0", "sweep")
_ROLES = list(Role)
_PART_ROLES = (ROLE[Role.CONTOUR], ROLE[Role.RAPID])
_LINES32 = np.iinfo(np.int32).max - 2  # source lines up to this are kept as int32
_EMPTY = {"line": np.zeros(0, np.int32), "kind": np.zeros(0, np.int8), "role": np.zeros(0, np.int8),
          "arc_rows": np.zeros(0, np.int64), "star": np.zeros(0, bool), "sel": np.zeros(0, bool),
          "end_rows": np.zeros(0, np.int64), "boxes": np.zeros((0, 4), np.float32)}  # fmt: skip


class ProgramStore:
    """Every programmed segment of a plan, as columns (row j: the j-th segment).

    ``ex``, ``ey``, ``ez`` read as columns (an index or an array of indices); ``boxes`` are the
    ``float32`` boxes, rounded outwards, of the part candidates (the rows where ``star`` holds).
    """

    def __init__(self, programmed: Iterable[Segment]) -> None:
        names = (*_KEPT, *_ARC_COLUMNS, "arc_rows", "star", "sel", "end_rows", "ends", "boxes")
        parts: dict[str, list[np.ndarray]] = {c: [] for c in names}
        self.others: dict[int, Any] = {}  # row → polynomial curve
        self.other_plen: dict[int, float] = {}  # row → its plane length
        n = 0
        last: np.ndarray | None = None  # the end point of the last row read
        it = iter(programmed)
        while batch := list(islice(it, BATCH)):
            t = SegmentTable(batch)
            for c in _KEPT:  # copies: a table's point columns are views of one array
                parts[c].append(np.array(getattr(t, c)))
            if len(batch) and int(t.line.max()) <= _LINES32 and int(t.line.min()) >= 0:
                parts["line"][-1] = t.line.astype(np.int32)
            arcs = np.nonzero(t.kind == ARC)[0]
            parts["arc_rows"].append(arcs + n)
            for c in _ARC_COLUMNS:
                parts[c].append(getattr(t, c)[arcs])
            for j in np.nonzero(t.kind > ARC)[0].tolist():
                self.others[n + j] = batch[j].geometry
                self.other_plen[n + j] = float(t.plen[j])
            # the end points that are not the next start point (bit for bit)
            start, end = np.column_stack((t.sx, t.sy, t.sz)), np.column_stack((t.ex, t.ey, t.ez))
            if last is not None and not _same(last[None], start[:1])[0]:
                parts["end_rows"].append(np.array([n - 1]))
                parts["ends"].append(last[None])
            apart = np.nonzero(~_same(end[:-1], start[1:]))[0]
            parts["end_rows"].append(apart + n)
            parts["ends"].append(end[apart])
            last = end[-1].copy()
            # the part candidates: contour and rapid elements of non-zero plane length
            star = np.isin(t.role, _PART_ROLES) & (t.plen > 0.0)
            parts["star"].append(star)
            parts["boxes"].append(outward(t.bboxes(np.nonzero(star)[0])))
            # the elements the near-tangent continuations look at (lines and arcs of non-zero length)
            parts["sel"].append((t.plen > 0.0) & (t.kind <= ARC))
            n += len(batch)
        if last is not None:
            parts["end_rows"].append(np.array([n - 1]))
            parts["ends"].append(last[None])
        ends = np.concatenate(parts.pop("ends")) if n else np.zeros((0, 3))
        for c in list(parts):  # one column at a time, its pieces freed as it is made
            pieces = parts.pop(c)
            setattr(self, c, np.concatenate(pieces) if pieces else _EMPTY.get(c, np.zeros(0)))
            del pieces
        self.end_rows: np.ndarray
        if n < np.iinfo(np.int32).max:
            self.end_rows = self.end_rows.astype(np.int32)
        self.ex, self.ey, self.ez = (_End(self, col, self.end_rows, ends[:, k].copy())
                                     for k, col in enumerate(("sx", "sy", "sz")))  # fmt: skip
        del ends
        self.n = n
        self.monotone = bool(np.all(self.line[1:] >= self.line[:-1])) if n > 1 else True

    def rows_of(self, lo: int, hi: int) -> tuple[int, int]:
        """The rows of the source lines ``lo`` … ``hi`` (a monotone store: one range)."""
        # searched as the column's own type (a wider value would convert the whole column)
        top = np.iinfo(self.line.dtype)
        a, b = (np.array([min(max(x, top.min), top.max)], self.line.dtype) for x in (lo, hi))
        return int(np.searchsorted(self.line, a)[0]), int(np.searchsorted(self.line, b, side="right")[0])

    def first_row(self, line: int, mask: np.ndarray) -> int:
        """The first row of ``line`` where ``mask`` holds, −1 if none."""
        a, b = self.rows_of(line, line)
        hit = np.nonzero(mask[a:b])[0]
        return a + int(hit[0]) if hit.size else -1

    def last_row(self, line: int, mask: np.ndarray) -> int:
        a, b = self.rows_of(line, line)
        hit = np.nonzero(mask[a:b])[0]
        return a + int(hit[-1]) if hit.size else -1

    def part_rows(self) -> np.ndarray:
        """The rows of the part candidates, ascending (``int32`` when the rows fit)."""
        rows = np.nonzero(self.star)[0]
        return rows.astype(np.int32) if self.n < np.iinfo(np.int32).max else rows

    def star_lines(self, lo: int, hi: int) -> np.ndarray:
        """The source lines ``lo`` … ``hi`` with a part candidate, ascending."""
        a, b = self.rows_of(lo, hi)
        lines = self.line[a:b][self.star[a:b]].astype(np.int64)
        return lines[np.append(True, lines[1:] != lines[:-1])] if lines.size else lines

    def next_line(self, line: int) -> int:
        """The next source line after ``line`` with a line or arc of non-zero length (−1: none)."""
        at, step = self.rows_of(line, line)[1], 1 << 8
        while at < self.n:
            hit = np.nonzero(self.sel[at : at + step])[0]
            if hit.size:
                return int(self.line[at + hit[0]])
            at, step = at + step, 2 * step
        return -1

    def first_row_after(self, line: int) -> int:
        """The first line-or-arc row of the next line with one after ``line`` (−1: none)."""
        nxt = self.next_line(line)
        return self.first_row(nxt, self.sel) if nxt >= 0 else -1

    def table(self, rows: np.ndarray) -> SegmentTable:
        """The :class:`SegmentTable` of the rows ``rows`` (ascending)."""
        rows = np.asarray(rows, np.int64)
        out = object.__new__(SegmentTable)
        out.segments = None
        out.geoms = _Geoms(self, rows)
        for c in _COLUMNS:
            setattr(out, c, getattr(self, c)[rows])
        out.line = out.line.astype(np.int64)
        at = np.searchsorted(self.arc_rows, rows)
        is_arc = out.kind == ARC
        src = at[is_arc]
        for c in _ARC_COLUMNS:
            col = np.full(len(rows), np.nan)
            col[is_arc] = getattr(self, c)[src]
            setattr(out, c, col)
        # the plane lengths, as SegmentTable computes them
        out.plen = plen = np.empty(len(rows))
        lines = np.nonzero(out.kind == LINE)[0]
        plen[lines] = hypot(out.ex[lines] - out.sx[lines], out.ey[lines] - out.sy[lines])
        plen[is_arc] = np.abs(out.sweep[is_arc]) * out.r[is_arc]
        for j in np.nonzero(out.kind > ARC)[0].tolist():
            plen[j] = self.other_plen[int(rows[j])]
        out.radius = np.zeros(len(rows))
        out.side = np.zeros(len(rows))
        out._tangents = out._ends2 = None
        assert all(hasattr(out, c) for c in _ARRAYS)
        return out

    def geometry(self, row: int) -> Any:
        """The geometry object of a row (equal to the programmed segment's)."""
        kind = int(self.kind[row])
        if kind == LINE:
            return Line((float(self.sx[row]), float(self.sy[row]), float(self.sz[row])),
                        (float(self.ex[row]), float(self.ey[row]), float(self.ez[row])))  # fmt: skip
        if kind == ARC:
            a = int(np.searchsorted(self.arc_rows, row))
            return Arc((float(self.cx[a]), float(self.cy[a])), float(self.r[a]), float(self.a0[a]),
                       float(self.sweep[a]), float(self.sz[row]), float(self.ez[row]))  # fmt: skip
        return self.others[row]

    def segment(self, row: int) -> Segment:
        """A segment with the row's geometry, role and source line (what the residuals read)."""
        span = SourceSpan(line=int(self.line[row]))
        return Segment(self.geometry(row), Plane.G17, _ROLES[int(self.role[row])], span, None)


class _Geoms:
    """``SegmentTable.geoms`` of a store table: the geometry objects, made when asked for."""

    def __init__(self, store: ProgramStore, rows: np.ndarray) -> None:
        self.store, self.rows = store, rows

    def __getitem__(self, j: int) -> Any:
        return self.store.geometry(int(self.rows[j]))

    def __len__(self) -> int:
        return len(self.rows)


class _End:
    """An end-point coordinate as a column: the next row's start, or the value kept for the rows
    where they differ (``rows`` ascending, the last row always among them)."""

    def __init__(self, store: ProgramStore, start: str, rows: np.ndarray, values: np.ndarray) -> None:
        self.store, self.start, self.rows, self.values = store, start, rows, values

    def __getitem__(self, rows: Any) -> Any:
        start = getattr(self.store, self.start)
        if np.ndim(rows) == 0:
            j = int(rows)
            at = int(np.searchsorted(self.rows, np.array([j], self.rows.dtype))[0])
            return self.values[at] if at < len(self.rows) and self.rows[at] == j else start[j + 1]
        r = np.asarray(rows, self.rows.dtype)  # row numbers fit the type of ``self.rows``
        if not r.size:
            return np.zeros(0)
        pos = np.minimum(np.searchsorted(self.rows, r), len(self.rows) - 1)
        own = self.rows[pos] == r
        out = start[np.where(own, 0, r + 1)]
        out[own] = self.values[pos[own]]
        return out


def _same(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Which rows of two k×3 ``float64`` arrays are equal bit for bit."""
    return np.all(np.ascontiguousarray(a).view(np.int64) == np.ascontiguousarray(b).view(np.int64), axis=1)
