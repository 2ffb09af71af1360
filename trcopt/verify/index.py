"""A uniform-grid spatial index over plane bounding boxes, for the verification's candidate filter.

The verification measures each tool-centre element against the programmed elements whose
bounding boxes come within the tool radius of its own. Filtering all boxes for every element is
quadratic; :class:`BoxGrid` hashes the boxes into a uniform grid once (O(n)) and answers each
query from the cells it overlaps, so a plan costs O(n) overall for programs whose elements are of
similar size (CAM output, generated contours). The candidates it returns are exactly those of the
brute-force filter (the same float comparisons are applied to the cell candidates), so every
residual computed from them is bit-identical.

Boxes spanning many cells (a long line across the part) are kept in a short list that every query
checks, so no box is copied into more than :data:`MAX_CELLS_PER_BOX` cells. Only the occupied
cells are stored (sorted cell numbers), so a grid fitted to the queries (``margin``: cells about
as large as an element and the margin around it) stays small over a thin contour across a large
part; :meth:`BoxGrid.near_many` answers many queries in one batch of array operations.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["BoxGrid", "MAX_CELLS_PER_BOX"]

MAX_CELLS_PER_BOX = 64  # a box over more cells is checked by every query instead


def median(values: np.ndarray, overwrite: bool = False) -> float:
    """``np.median`` of a non-empty 1-D array of finite numbers (the same value), without the import
    of ``numpy.ma`` that ``np.median`` makes on its first call (a few ms of every short run);
    ``overwrite`` partitions ``values`` in place instead of a copy."""
    n = len(values)
    k = n // 2
    kth = k if n % 2 else (k - 1, k)
    if overwrite:
        values.partition(kth)
        part = values
    else:
        part = np.partition(values, kth)
    return float(part[k]) if n % 2 else float((part[k - 1] + part[k]) / 2.0)


class BoxGrid:
    """Uniform grid over ``boxes`` (n×4: umin, vmin, umax, vmax in mm).

    Parameters
    ----------
    boxes:
        Plane bounding boxes, mm (one row per element; the row number is the element's index).
    """

    def __init__(self, boxes: np.ndarray, margin: float | None = None) -> None:
        self.boxes = np.asarray(boxes, float).reshape(-1, 4)
        n = len(self.boxes)
        self._big = np.zeros(0, dtype=np.intp)
        self._ids = np.zeros(0, dtype=np.intp)
        self._keys = np.zeros(0, dtype=np.int64)  # the occupied cells (ix·ny + iy), ascending
        self._starts = np.zeros(1, dtype=np.intp)  # where each occupied cell's ids start in _ids
        self.nx = self.ny = 0
        self.origin = (0.0, 0.0)
        self.cell = 1.0
        if n == 0:
            return
        b = self.boxes
        u0, v0 = float(b[:, 0].min()), float(b[:, 1].min())
        width, height = float(b[:, 2].max()) - u0, float(b[:, 3].max()) - v0
        sizes = np.maximum(b[:, 2] - b[:, 0], b[:, 3] - b[:, 1])
        if margin is None:
            # about one element per cell: the typical element size, or the area shared out
            cell = max(median(sizes), math.sqrt(width * height / n), max(width, height) / n, 1e-9)
        else:
            # the queries' own size (an element and the margin around it): a query sees a few cells
            cell = max(2.0 * median(sizes) + 2.0 * margin, max(width, height) / n, 1e-9)
        self.origin, self.cell = (u0, v0), cell
        self.nx, self.ny = int(width / cell) + 1, int(height / cell) + 1
        ix0, ix1 = self._cells(b[:, 0], self.nx, u0), self._cells(b[:, 2], self.nx, u0)
        iy0, iy1 = self._cells(b[:, 1], self.ny, v0), self._cells(b[:, 3], self.ny, v0)
        cx, cy = ix1 - ix0 + 1, iy1 - iy0 + 1
        counts = cx * cy
        big = counts > MAX_CELLS_PER_BOX
        self._big = np.nonzero(big)[0]
        counts = np.where(big, 0, counts)
        total = int(counts.sum())
        box_of = np.repeat(np.arange(n, dtype=np.intp), counts)
        local = np.arange(total, dtype=np.intp) - np.repeat(np.cumsum(counts) - counts, counts)
        cy_r = np.repeat(cy, counts)
        cell_of = (np.repeat(ix0, counts) + local // cy_r).astype(np.int64) * self.ny
        cell_of += np.repeat(iy0, counts) + local % cy_r
        order = np.argsort(cell_of, kind="stable")
        self._ids = box_of[order]
        # only the occupied cells are stored (a fine grid over a sparse part stays small)
        self._keys, first = np.unique(cell_of[order], return_index=True)
        self._starts = np.append(first, total).astype(np.intp)

    def _cells(self, x: np.ndarray, n: int, origin: float) -> np.ndarray:
        return np.clip(np.floor((x - origin) / self.cell), 0, n - 1).astype(np.intp)

    def _cell(self, x: float, origin: float) -> int:
        return math.floor((x - origin) / self.cell)

    def _gather(self, u0: float, v0: float, u1: float, v1: float) -> np.ndarray:
        """Indices of the boxes hashed into the cells that [u0, u1] × [v0, v1] overlaps (with
        repetitions), and the big boxes."""
        parts = [self._big]
        if self.nx:
            ox, oy = self.origin
            ix0, ix1 = max(self._cell(u0, ox), 0), min(self._cell(u1, ox), self.nx - 1)
            iy0, iy1 = max(self._cell(v0, oy), 0), min(self._cell(v1, oy), self.ny - 1)
            starts, keys = self._starts, self._keys
            if iy1 >= iy0 and ix1 >= ix0:
                # the cells of each column are consecutive keys: one range of _ids per column
                cols = np.arange(ix0, ix1 + 1, dtype=np.int64) * self.ny
                lo = np.searchsorted(keys, cols + iy0)
                hi = np.searchsorted(keys, cols + iy1 + 1)
                for a, b in zip(starts[lo].tolist(), starts[hi].tolist(), strict=True):
                    if b > a:
                        parts.append(self._ids[a:b])
        return parts[0] if len(parts) == 1 else np.concatenate(parts)

    def near(self, box: tuple[float, float, float, float], margin: float) -> np.ndarray:
        """Indices (ascending, unique) of the boxes that come within ``margin`` (mm) of ``box``:
        exactly those of the brute-force filter ``umin <= box.umax + margin``, … ."""
        lo_u, lo_v, hi_u, hi_v = box[0] - margin, box[1] - margin, box[2] + margin, box[3] + margin
        cand = self._gather(lo_u, lo_v, hi_u, hi_v)
        if cand.size == 0:
            return cand
        b = self.boxes[cand]
        keep = (b[:, 0] <= hi_u) & (b[:, 2] >= lo_u) & (b[:, 1] <= hi_v) & (b[:, 3] >= lo_v)
        return np.unique(cand[keep])

    def near_many(self, boxes: np.ndarray, margins: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`near` of many query boxes (m×4) with their margins (m) at once: the pairs
        (query, box index), by query and then by box index ascending — for every query exactly
        the indices :meth:`near` gives (the same float comparisons)."""
        q = np.asarray(boxes, float).reshape(-1, 4)
        margins = np.asarray(margins, float)
        empty = np.zeros(0, dtype=np.intp)
        if len(self.boxes) == 0 or len(q) == 0:
            return empty, empty
        lo_u, lo_v = q[:, 0] - margins, q[:, 1] - margins
        hi_u, hi_v = q[:, 2] + margins, q[:, 3] + margins
        qs, ids = [empty], [empty]
        if self.nx:
            ox, oy = self.origin
            ix0 = np.maximum(np.floor((lo_u - ox) / self.cell), 0)
            ix1 = np.minimum(np.floor((hi_u - ox) / self.cell), self.nx - 1)
            iy0 = np.maximum(np.floor((lo_v - oy) / self.cell), 0)
            iy1 = np.minimum(np.floor((hi_v - oy) / self.cell), self.ny - 1)
            ncol = np.where((ix1 >= ix0) & (iy1 >= iy0), ix1 - ix0 + 1, 0).astype(np.intp)
            # every (query, column) visit: the column's cells are one range of _ids
            qv = np.repeat(np.arange(len(q)), ncol)
            col = np.repeat(ix0.astype(np.int64), ncol) + (
                np.arange(int(ncol.sum())) - np.repeat(np.cumsum(ncol) - ncol, ncol)
            )
            lo = np.searchsorted(self._keys, col * self.ny + np.repeat(iy0.astype(np.int64), ncol))
            hi = np.searchsorted(self._keys, col * self.ny + np.repeat(iy1.astype(np.int64), ncol) + 1)
            a, b = self._starts[lo], self._starts[hi]
            n_in = b - a
            qs.append(np.repeat(qv, n_in))
            within = np.arange(int(n_in.sum())) - np.repeat(np.cumsum(n_in) - n_in, n_in)
            ids.append(self._ids[np.repeat(a, n_in) + within])
        if self._big.size:
            qs.append(np.repeat(np.arange(len(q)), self._big.size))
            ids.append(np.tile(self._big, len(q)))
        qq, ii = np.concatenate(qs), np.concatenate(ids)
        b = self.boxes[ii]
        keep = (b[:, 0] <= hi_u[qq]) & (b[:, 2] >= lo_u[qq]) & (b[:, 1] <= hi_v[qq]) & (b[:, 3] >= lo_v[qq])
        key = np.sort(qq[keep].astype(np.int64) * len(self.boxes) + ii[keep])
        key = key[np.append(True, key[1:] != key[:-1])] if key.size else key  # np.unique's result, by a sort
        return (key // len(self.boxes)).astype(np.intp), (key % len(self.boxes)).astype(np.intp)

    def nearest_many(self, pts: np.ndarray) -> np.ndarray:
        """:meth:`nearest_distance` of many points (m×2) at once, the same values: the corners
        within the first search radius in one batch (:meth:`near_many`), the rest one by one."""
        pts = np.asarray(pts, float).reshape(-1, 2)
        out = np.full(len(pts), math.inf)
        if len(self.boxes) == 0 or len(pts) == 0:
            return out
        r = self.cell
        pad = 1.001 * r + 1e-9
        q, i = self.near_many(np.column_stack((pts, pts)), np.full(len(pts), pad))
        c = self.boxes[i, :2]
        np.minimum.at(out, q, np.hypot(c[:, 0] - pts[q, 0], c[:, 1] - pts[q, 1]))
        # a corner within r of the point is within the padded square: the nearest of all
        for j in np.nonzero(~(out <= r))[0].tolist():
            out[j] = self.nearest_distance((float(pts[j, 0]), float(pts[j, 1])))
        return out

    def nearest_distance(self, p: tuple[float, float]) -> float:
        """Smallest plane distance (mm) from ``p`` to the lower-left corners of the boxes (the
        points of a grid built over degenerate boxes), as ``np.min(np.hypot(*(corners - p).T))``
        computes it; ``inf`` for an empty grid."""
        if len(self.boxes) == 0:
            return math.inf
        corners = self.boxes[:, :2]
        r = self.cell
        while True:
            # cells a little wider than the radius, so float rounding cannot lose a point within r
            pad = 1.001 * r + 1e-9
            whole = self.nx == 0 or (
                self._cell(p[0] - pad, self.origin[0]) <= 0
                and self._cell(p[0] + pad, self.origin[0]) >= self.nx - 1
                and self._cell(p[1] - pad, self.origin[1]) <= 0
                and self._cell(p[1] + pad, self.origin[1]) >= self.ny - 1
            )
            cand = np.arange(len(corners)) if whole else self._gather(p[0] - pad, p[1] - pad, p[0] + pad, p[1] + pad)
            if cand.size:
                c = corners[cand]
                d = float(np.min(np.hypot(c[:, 0] - p[0], c[:, 1] - p[1])))
                if d <= r or whole:
                    return d
            r *= 2.0
