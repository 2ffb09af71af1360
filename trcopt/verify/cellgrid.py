"""A compact uniform grid over the part candidates' boxes, for the streaming verification.

:class:`CompactGrid` is :class:`~trcopt.verify.index.BoxGrid`'s uniform grid, stored as
``float32`` boxes rounded outwards and ``int32`` ids (about 30 bytes an element): a query returns
every box within the margin and possibly a few more, which the exact distances then measure (only
elements nearer than R change a residual).

The grid is built a chunk of boxes at a time, so that building it takes little more memory than
the grid itself: the cell numbers of each chunk's boxes are written into one array (``int32``
when the grid has fewer than 2³¹ cells), sorted once, and only the occupied cells are kept.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np

from trcopt.verify.index import median as median_of

__all__ = ["CompactGrid", "outward"]

CHUNK = 1 << 14  # boxes handled at once while building
_I32 = np.iinfo(np.int32).max


def outward(boxes: np.ndarray) -> np.ndarray:
    """``float32`` boxes containing the ``float64`` ones."""
    f = boxes.astype(np.float32)
    lo = f[:, :2].astype(float) > boxes[:, :2]
    hi = f[:, 2:].astype(float) < boxes[:, 2:]
    f[:, :2] = np.where(lo, np.nextafter(f[:, :2], np.float32(-np.inf)), f[:, :2])
    f[:, 2:] = np.where(hi, np.nextafter(f[:, 2:], np.float32(np.inf)), f[:, 2:])
    return f


def _index_type(top: int) -> type:
    """The smaller integer type that holds 0 … ``top``."""
    return np.int32 if top <= _I32 else np.int64


class CompactGrid:
    """A uniform grid over boxes (n×4) naming ``ids`` (n), with cells fitted to queries of about
    ``margin``; :meth:`near_many` as :meth:`BoxGrid.near_many <trcopt.verify.index.BoxGrid.near_many>`,
    a superset of its pairs.

    ``boxes`` of ``float32`` are taken as they are (already rounded outwards, not copied); others
    are rounded outwards ``chunk`` boxes at a time.
    """

    def __init__(self, boxes: np.ndarray, ids: np.ndarray, margin: float, max_cells: int = 64,
                 chunk: int = CHUNK) -> None:  # fmt: skip
        boxes = np.asarray(boxes).reshape(-1, 4)
        n = len(boxes)
        if boxes.dtype == np.float32:
            self.boxes = boxes
        else:
            self.boxes = np.empty((n, 4), np.float32)
            for a in range(0, n, chunk):
                self.boxes[a : a + chunk] = outward(np.asarray(boxes[a : a + chunk], float))
        ids = np.asarray(ids)
        self.ids: np.ndarray = ids.astype(_index_type(int(ids.max()) if ids.size else 0), copy=False)
        self.nx = self.ny = 0
        self.origin, self.cell = (0.0, 0.0), 1.0
        self._big = self._cells_ids = np.zeros(0, np.int32)
        self._keys, self._starts = np.zeros(0, np.int64), np.zeros(1, np.int64)
        self._chunk, self._size = chunk, (0.0, 0.0)
        if n == 0:
            return
        # the extent and the median element size, of the float32 boxes (in float64)
        lo, hi = np.full(2, np.inf), np.full(2, -np.inf)
        size = np.empty(n)
        for a, b in self._chunks():
            lo, hi = np.minimum(lo, b[:, :2].min(axis=0)), np.maximum(hi, b[:, 2:].max(axis=0))
            size[a : a + len(b)] = np.maximum(b[:, 2] - b[:, 0], b[:, 3] - b[:, 1])
        u0, v0 = float(lo[0]), float(lo[1])
        width, height = float(hi[0]) - u0, float(hi[1]) - v0
        self._size = (width, height)
        median = median_of(size, overwrite=True)
        del size
        self.cell = cell = max(2.0 * median + 2.0 * margin, max(width, height) / n, 1e-9)
        self.origin = (u0, v0)
        self.nx, self.ny = int(width / cell) + 1, int(height / cell) + 1
        self._build(max_cells)

    def _chunks(self) -> Iterator[tuple[int, np.ndarray]]:
        """(first index, ``float64`` boxes) of each chunk of boxes."""
        for a in range(0, len(self.boxes), self._chunk):
            yield a, self.boxes[a : a + self._chunk].astype(float)

    def _ranges(self, b: np.ndarray, max_cells: int) -> tuple[np.ndarray, ...]:
        """The first column and row of each box, its rows, and its cells (0 if over ``max_cells``)."""
        ox, oy = self.origin
        ix0, ix1 = self._index(b[:, 0], ox, self.nx), self._index(b[:, 2], ox, self.nx)
        iy0, iy1 = self._index(b[:, 1], oy, self.ny), self._index(b[:, 3], oy, self.ny)
        cy = iy1 - iy0 + 1
        counts = (ix1 - ix0 + 1) * cy
        return ix0, iy0, cy, np.where(counts > max_cells, 0, counts), counts > max_cells

    def _build(self, max_cells: int) -> None:
        """The cells of every box, sorted by cell (the boxes of a cell ascending): a counting sort
        by column (each chunk's cells written at their column's place), then each group of
        columns sorted by row, then the occupied cells numbered."""
        nx, ny, piece = self.nx, self.ny, 4 * self._chunk
        big, start = [], np.zeros(nx + 2, np.int64)
        for a, b in self._chunks():
            ix0, _, cy, counts, over = self._ranges(b, max_cells)
            big.append(np.nonzero(over)[0] + a)
            keep = ~over
            np.add.at(start, ix0[keep] + 1, cy[keep])  # a box's rows in each of its columns
            np.add.at(start, ix0[keep] + 1 + counts[keep] // cy[keep], -cy[keep])
        self._big = np.concatenate(big).astype(np.int32)
        np.cumsum(start, out=start)  # the cells of each column
        start = np.cumsum(start[:-1])  # where each column starts
        total = int(start[-1])
        rows, boxes = np.empty(total, np.int32), np.empty(total, np.int32)
        cursor = start[:-1].copy()
        for a, b in self._chunks():
            ix0, iy0, cy, counts, _ = self._ranges(b, max_cells)
            ends = np.cumsum(counts)
            cuts = np.searchsorted(ends, np.arange(piece, int(ends[-1]), piece)).tolist()
            for s, e in zip((0, *cuts), (*cuts, len(b)), strict=True):
                c = counts[s:e]
                local = np.arange(int(c.sum())) - np.repeat(np.cumsum(c) - c, c)
                cy_r = np.repeat(cy[s:e], c)
                column = np.repeat(ix0[s:e], c) + local // cy_r
                order = np.argsort(column, kind="stable")
                column = column[order]
                first = np.nonzero(_new(column))[0]
                size = np.diff(np.append(first, len(column)))
                at = cursor[column] + np.arange(len(column)) - np.repeat(first, size)
                rows[at] = (np.repeat(iy0[s:e], c) + local % cy_r)[order]
                boxes[at] = np.repeat(np.arange(a + s, a + e, dtype=np.int32), c)[order]
                cursor[column[first]] += size
        del cursor
        groups = list(_groups(start, piece))
        cells = 0
        for c0, c1 in groups:  # each column by row (its boxes stay ascending), and its occupied cells
            p, q = int(start[c0]), int(start[c1])
            key = _group_keys(start, c0, c1, ny, rows[p:q])
            order = np.argsort(key, kind="stable")
            rows[p:q], boxes[p:q] = rows[p:q][order], boxes[p:q][order]
            cells += int(np.count_nonzero(_new(key[order])))
        self._cells_ids = boxes
        self._keys = np.empty(cells, _index_type(nx * ny))
        self._starts = np.empty(cells + 1, _index_type(total))
        self._starts[-1] = total
        k = 0
        for c0, c1 in groups:
            p, q = int(start[c0]), int(start[c1])
            key = _group_keys(start, c0, c1, ny, rows[p:q])
            first = np.nonzero(_new(key))[0]
            self._keys[k : k + len(first)] = key[first] + c0 * ny
            self._starts[k : k + len(first)] = first + p
            k += len(first)

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
        col = (np.repeat(ix0.astype(np.int64), ncol) + step) * self.ny
        kt = self._keys.dtype  # every cell number and the one past the last fit the keys' type
        lo = np.searchsorted(self._keys, (col + np.repeat(iy0.astype(np.int64), ncol)).astype(kt))
        hi = np.searchsorted(self._keys, (col + np.repeat(iy1.astype(np.int64), ncol) + 1).astype(kt))
        a, n_in = self._starts[lo], self._starts[hi] - self._starts[lo]
        within = np.arange(int(n_in.sum())) - np.repeat(np.cumsum(n_in) - n_in, n_in)
        qs = [np.repeat(qv, n_in), np.repeat(np.arange(len(q)), self._big.size)]
        bs = [self._cells_ids[np.repeat(a, n_in) + within], np.tile(self._big, len(q))]
        qq, ii = np.concatenate(qs), np.concatenate(bs).astype(np.int64)
        b = self.boxes[ii]
        keep = (b[:, 0] <= hi_u[qq]) & (b[:, 2] >= lo_u[qq]) & (b[:, 1] <= hi_v[qq]) & (b[:, 3] >= lo_v[qq])
        key = np.unique(qq[keep].astype(np.int64) * len(self.boxes) + ii[keep])
        return key // len(self.boxes), self.ids[key % len(self.boxes)].astype(np.int64)

    def extent(self) -> float:
        """The diagonal of the grid's boxes, mm (0 when empty)."""
        return math.hypot(*self._size)


def _groups(start: np.ndarray, size: int) -> Iterator[tuple[int, int]]:
    """Consecutive columns ``c0 … c1 - 1`` of about ``size`` cells together (or one column)."""
    c, nx = 0, len(start) - 1
    while c < nx:
        e = min(max(int(np.searchsorted(start, start[c] + size, "right")) - 1, c + 1), nx)
        yield c, e
        c = e


def _group_keys(start: np.ndarray, c0: int, c1: int, ny: int, rows: np.ndarray) -> np.ndarray:
    """The cell numbers, less ``c0 · ny``, of the cells of the columns ``c0 … c1 - 1``."""
    column = np.repeat(np.arange(c1 - c0, dtype=np.int64), np.diff(start[c0 : c1 + 1]))
    return column * ny + rows


def _new(key: np.ndarray) -> np.ndarray:
    """Where a sorted array's value changes (its first element included)."""
    return np.append(True, key[1:] != key[:-1]) if key.size else np.zeros(0, bool)
