"""The programmed path kept as compact columns, for the streaming verification.

:class:`ProgramStore` reads every programmed segment once (in batches, through
:class:`~trcopt.verify.table.SegmentTable`) and keeps only NumPy columns: source line, kind, role,
end points, plane length, and the arc parameters of the arcs (about 70 bytes an element; the
polynomial curves, rare, are kept as objects). It gives back the table of any rows
(:meth:`ProgramStore.table`, the same floats as ``SegmentTable`` of those segments) and their
geometry objects (:meth:`ProgramStore.geometry`, equal to the programmed ones).

:class:`CompactGrid` is :class:`~trcopt.verify.index.BoxGrid`'s uniform grid over the part
candidates' boxes, stored as ``float32`` boxes rounded outwards and ``int32`` ids (about 30 bytes
an element): a query returns every box within the margin and possibly a few more, which the
exact distances then measure (only elements nearer than R change a residual).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from itertools import islice
from typing import Any

import numpy as np

from trcopt.errors import SourceSpan
from trcopt.geometry import Arc, Line, Plane
from trcopt.path import Role, Segment
from trcopt.verify.table import _ARRAYS, ARC, LINE, ROLE, SegmentTable

__all__ = ["CompactGrid", "ProgramStore"]

BATCH = 1 << 14  # programmed segments read at once
_COLUMNS = ("line", "kind", "role", "sx", "sy", "sz", "ex", "ey", "ez", "plen")
_ARC_COLUMNS = ("cx", "cy", "r", "a0", "sweep")
_ROLES = list(Role)
_PART_ROLES = (ROLE[Role.CONTOUR], ROLE[Role.RAPID])


class ProgramStore:
    """Every programmed segment of a plan, as columns (row j: the j-th segment)."""

    def __init__(self, programmed: Iterable[Segment]) -> None:
        parts: dict[str, list[np.ndarray]] = {c: [] for c in (*_COLUMNS, *_ARC_COLUMNS, "arc_rows")}
        self.others: dict[int, Any] = {}  # row → polynomial curve
        n = 0
        it = iter(programmed)
        while batch := list(islice(it, BATCH)):
            t = SegmentTable(batch)
            for c in _COLUMNS:
                parts[c].append(getattr(t, c))
            arcs = np.nonzero(t.kind == ARC)[0]
            parts["arc_rows"].append(arcs + n)
            for c in _ARC_COLUMNS:
                parts[c].append(getattr(t, c)[arcs])
            for j in np.nonzero(t.kind > ARC)[0].tolist():
                self.others[n + j] = batch[j].geometry
            n += len(batch)
        dtypes = {"line": np.int64, "kind": np.int8, "role": np.int8, "arc_rows": np.int64}
        for c, arrays in parts.items():
            setattr(self, c, np.concatenate(arrays) if arrays else np.zeros(0, dtypes.get(c, float)))
        self.n = n
        #: the part candidates: contour and rapid elements of non-zero plane length
        self.star = np.isin(self.role, _PART_ROLES) & (self.plen > 0.0)
        #: the elements the near-tangent continuations look at (lines and arcs of non-zero length)
        self.sel = (self.plen > 0.0) & (self.kind <= ARC)
        self.monotone = bool(np.all(self.line[1:] >= self.line[:-1])) if n > 1 else True
        self.star_lines = np.unique(self.line[self.star])
        self.sel_lines = np.unique(self.line[self.sel])

    def rows_of(self, lo: int, hi: int) -> tuple[int, int]:
        """The rows of the source lines ``lo`` … ``hi`` (a monotone store: one range)."""
        return int(np.searchsorted(self.line, lo)), int(np.searchsorted(self.line, hi, "right"))

    def first_row(self, line: int, mask: np.ndarray) -> int:
        """The first row of ``line`` where ``mask`` holds, −1 if none."""
        a, b = self.rows_of(line, line)
        hit = np.nonzero(mask[a:b])[0]
        return a + int(hit[0]) if hit.size else -1

    def last_row(self, line: int, mask: np.ndarray) -> int:
        a, b = self.rows_of(line, line)
        hit = np.nonzero(mask[a:b])[0]
        return a + int(hit[-1]) if hit.size else -1

    def next_line(self, lines: np.ndarray, among: np.ndarray) -> np.ndarray:
        """The next source line after each of ``lines`` among the sorted ``among`` (−1: none)."""
        if not len(among):
            return np.full(len(lines), -1, np.int64)
        pos = np.searchsorted(among, lines, "right")
        return np.where(pos < len(among), among[np.minimum(pos, len(among) - 1)], -1)

    def first_row_after(self, line: int) -> int:
        """The first line-or-arc row of the next line with one after ``line`` (−1: none)."""
        nxt = int(self.next_line(np.array([line]), self.sel_lines)[0])
        return self.first_row(nxt, self.sel) if nxt >= 0 else -1

    def table(self, rows: np.ndarray) -> SegmentTable:
        """The :class:`SegmentTable` of the rows ``rows`` (ascending)."""
        rows = np.asarray(rows, np.int64)
        out = object.__new__(SegmentTable)
        out.segments = None
        out.geoms = _Geoms(self, rows)
        for c in _COLUMNS:
            setattr(out, c, getattr(self, c)[rows])
        at = np.searchsorted(self.arc_rows, rows)
        is_arc = out.kind == ARC
        src = at[is_arc]
        for c in _ARC_COLUMNS:
            col = np.full(len(rows), np.nan)
            col[is_arc] = getattr(self, c)[src]
            setattr(out, c, col)
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


def _outward(boxes: np.ndarray) -> np.ndarray:
    """``float32`` boxes containing the ``float64`` ones."""
    f = boxes.astype(np.float32)
    lo = f[:, :2].astype(float) > boxes[:, :2]
    hi = f[:, 2:].astype(float) < boxes[:, 2:]
    f[:, :2] = np.where(lo, np.nextafter(f[:, :2], np.float32(-np.inf)), f[:, :2])
    f[:, 2:] = np.where(hi, np.nextafter(f[:, 2:], np.float32(np.inf)), f[:, 2:])
    return f


class CompactGrid:
    """A uniform grid over boxes (n×4) naming ``ids`` (n), with cells fitted to queries of about
    ``margin``; :meth:`near_many` as :meth:`BoxGrid.near_many <trcopt.verify.index.BoxGrid.near_many>`,
    a superset of its pairs."""

    def __init__(self, boxes: np.ndarray, ids: np.ndarray, margin: float, max_cells: int = 64) -> None:
        self.boxes = _outward(np.asarray(boxes, float).reshape(-1, 4))
        self.ids = np.asarray(ids, np.int64)
        n = len(self.boxes)
        self.nx = self.ny = 0
        self.origin, self.cell = (0.0, 0.0), 1.0
        self._big = self._cells_ids = np.zeros(0, np.int32)
        self._keys, self._starts = np.zeros(0, np.int64), np.zeros(1, np.int64)
        if n == 0:
            return
        b = self.boxes.astype(float)
        u0, v0 = float(b[:, 0].min()), float(b[:, 1].min())
        width, height = float(b[:, 2].max()) - u0, float(b[:, 3].max()) - v0
        size = float(np.median(np.maximum(b[:, 2] - b[:, 0], b[:, 3] - b[:, 1])))
        self.cell = cell = max(2.0 * size + 2.0 * margin, max(width, height) / n, 1e-9)
        self.origin = (u0, v0)
        self.nx, self.ny = int(width / cell) + 1, int(height / cell) + 1
        ix0, ix1 = self._index(b[:, 0], u0, self.nx), self._index(b[:, 2], u0, self.nx)
        iy0, iy1 = self._index(b[:, 1], v0, self.ny), self._index(b[:, 3], v0, self.ny)
        cy = iy1 - iy0 + 1
        counts = (ix1 - ix0 + 1) * cy
        big = counts > max_cells
        self._big = np.nonzero(big)[0].astype(np.int32)
        counts = np.where(big, 0, counts)
        total = int(counts.sum())
        box_of = np.repeat(np.arange(n, dtype=np.int32), counts)
        local = np.arange(total, dtype=np.int64) - np.repeat(np.cumsum(counts) - counts, counts)
        cy_r = np.repeat(cy, counts)
        key = (np.repeat(ix0, counts) + local // cy_r) * self.ny + np.repeat(iy0, counts) + local % cy_r
        del local, cy_r
        order = np.argsort(key, kind="stable")
        self._cells_ids = box_of[order]
        self._keys, first = np.unique(key[order], return_index=True)
        self._starts = np.append(first, total).astype(np.int64)

    def _index(self, x: np.ndarray, origin: float, n: int) -> np.ndarray:
        return np.clip(np.floor((x - origin) / self.cell), 0, n - 1).astype(np.int64)

    def near_many(self, boxes: np.ndarray, margins: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(query, id) of the boxes within each query's margin (by query, ids ascending)."""
        q = np.asarray(boxes, float).reshape(-1, 4)
        margins = np.asarray(margins, float)
        empty = np.zeros(0, np.int64)
        if len(self.boxes) == 0 or len(q) == 0:
            return empty, empty
        lo_u, lo_v, hi_u, hi_v = q[:, 0] - margins, q[:, 1] - margins, q[:, 2] + margins, q[:, 3] + margins
        ox, oy = self.origin
        ix0 = np.maximum(np.floor((lo_u - ox) / self.cell), 0)
        ix1 = np.minimum(np.floor((hi_u - ox) / self.cell), self.nx - 1)
        iy0 = np.maximum(np.floor((lo_v - oy) / self.cell), 0)
        iy1 = np.minimum(np.floor((hi_v - oy) / self.cell), self.ny - 1)
        ncol = np.where((ix1 >= ix0) & (iy1 >= iy0), ix1 - ix0 + 1, 0).astype(np.int64)
        qv = np.repeat(np.arange(len(q)), ncol)
        step = np.arange(int(ncol.sum())) - np.repeat(np.cumsum(ncol) - ncol, ncol)
        col = np.repeat(ix0.astype(np.int64), ncol) + step
        lo = np.searchsorted(self._keys, col * self.ny + np.repeat(iy0.astype(np.int64), ncol))
        hi = np.searchsorted(self._keys, col * self.ny + np.repeat(iy1.astype(np.int64), ncol) + 1)
        a, n_in = self._starts[lo], self._starts[hi] - self._starts[lo]
        within = np.arange(int(n_in.sum())) - np.repeat(np.cumsum(n_in) - n_in, n_in)
        qs = [np.repeat(qv, n_in), np.repeat(np.arange(len(q)), self._big.size)]
        bs = [self._cells_ids[np.repeat(a, n_in) + within], np.tile(self._big, len(q))]
        qq, ii = np.concatenate(qs), np.concatenate(bs).astype(np.int64)
        b = self.boxes[ii]
        keep = (b[:, 0] <= hi_u[qq]) & (b[:, 2] >= lo_u[qq]) & (b[:, 1] <= hi_v[qq]) & (b[:, 3] >= lo_v[qq])
        key = np.unique(qq[keep].astype(np.int64) * len(self.boxes) + ii[keep])
        return key // len(self.boxes), self.ids[key % len(self.boxes)]

    def extent(self) -> float:
        """The diagonal of the grid's boxes, mm (0 when empty)."""
        if len(self.boxes) == 0:
            return 0.0
        b = self.boxes.astype(float)
        return math.hypot(float(b[:, 2].max() - b[:, 0].min()), float(b[:, 3].max() - b[:, 1].min()))
