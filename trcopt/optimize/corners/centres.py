"""The disc centres of a new tool path for the cut-deviation measurement, sampled on demand.

:func:`~trcopt.optimize.corners.deviation.cut_deviation` sweeps discs around the new path's centre
samples, every ``step`` mm of each element (:func:`~trcopt.optimize.corners.samples.path_samples`).
Most probes of the exact cut boundary are settled by a bound from a few of those samples, so
:class:`CentreSamples` computes them only where they are needed:

* :meth:`CentreSamples.coarse` — every few samples of every element, in path order (the samples
  bound the material left from above: fewer discs leave at least as much);
* :meth:`CentreSamples.near` — every sample of the elements that come within a distance of some
  points (what an exact value needs).

Each sample is the very point :func:`~trcopt.optimize.corners.samples.path_samples` gives for the
same elements (the same expressions, element by element; the curves of one call concatenated the
same way), so a value measured from them is the same to the last bit.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from trcopt.geometry import Arc, Line, Poly
from trcopt.geometry.poly import hermite_pieces
from trcopt.optimize.corners.samples import boxes, joined_curves
from trcopt.path import Segment

__all__ = ["CentreSamples"]

LINE, ARC, POINT, CURVE = 0, 1, 2, 3


class CentreSamples:
    """The centre samples of ``segments`` every ``step`` mm (as :func:`path_samples` takes them),
    evaluated on demand; ``arrays`` keeps the curves' :meth:`~trcopt.geometry.Poly.arrays` by
    ``id`` from one instance to the next (those of this instance's curves only)."""

    def __init__(self, segments: Sequence[Segment], step: float, arrays: dict[int, Any] | None = None) -> None:
        geoms = [s.geometry for s in segments]
        n = len(geoms)
        self.step = step
        self.region: np.ndarray | None = None  # where the caller needs samples (xmin, ymin, xmax, ymax), if known
        self.box = boxes(geoms) if n else np.zeros((0, 4))
        self.kind = np.empty(n, np.int64)
        self.count = np.empty(n, np.int64)
        self.place = np.zeros(n, np.int64)  # a curve's place in its group
        self.group = np.zeros(n, np.int64)  # a curve's group: 0 with sample curvatures, 1 without
        length = np.zeros(n)
        ends = np.zeros((n, 4))  # a line's ends, or an arc's centre, radius and start angle
        sweep = np.zeros(n)
        curves: list[list[tuple[int, Poly]]] = [[], []]
        for i, g in enumerate(geoms):
            if isinstance(g, Line | Arc):
                L = g.plane_length
                if L > 0:
                    length[i] = L
                    if isinstance(g, Line):
                        self.kind[i] = LINE
                        ends[i] = (*g.start2, *g.end2)
                    else:
                        self.kind[i] = ARC
                        ends[i] = (g.center[0], g.center[1], g.radius, g.a0)
                        sweep[i] = g.sweep
                else:
                    self.kind[i] = POINT
                    ends[i, :2] = g.point2(0.0)
            else:
                self.kind[i] = CURVE
                k = 0 if g.curvatures is not None else 1
                self.group[i], self.place[i] = k, len(curves[k])
                curves[k].append((i, g))
        flat = self.kind <= ARC
        self.count[flat] = np.maximum(2, np.ceil(length[flat] / step).astype(int) + 1)
        self.count[self.kind == POINT] = 1
        self.length, self.ends, self.sweep = length, ends, sweep
        known = {} if arrays is None else arrays
        self.groups = [self._group(group, step, known) for group in curves]
        for i, _ in [x for group in curves for x in group]:
            self.count[i] = self.groups[self.group[i]][4][self.place[i]]
        if arrays:
            mine = {id(g) for group in curves for _, g in group}
            for key in [key for key in arrays if key not in mine]:
                del arrays[key]

    @staticmethod
    def _group(group: list[tuple[int, Poly]], step: float, known: dict[int, Any]) -> tuple[Any, ...]:
        """The curves of one group as :func:`~trcopt.optimize.corners.samples.curve_samples`
        joins them: their arrays, each curve's offset, length, first sample and sample count."""
        if not group:
            return ((), np.zeros(0), np.zeros(0), np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, np.int64))
        return joined_curves([g for _, g in group], step, known)

    def __len__(self) -> int:
        return len(self.kind)

    def coarse(self, every: int, box: np.ndarray | None = None) -> np.ndarray:
        """Every ``every``-th sample of every element and its last one, element by element in
        path order (m×2); with ``box`` (xmin, ymin, xmax, ymax) only those of a line that lie in
        it (a lead-in line can be metres long)."""
        return self._points(np.arange(len(self.kind)), every, box)

    def near(self, points: np.ndarray, within: float) -> np.ndarray:
        """Every sample of the elements whose boxes come within ``within`` mm of one of ``points``
        (m×2, in no particular order); of a line, those in the box of the points grown by
        ``within`` (the others are farther from every point)."""
        if not len(self.kind) or not len(points):
            return np.zeros((0, 2))
        from scipy.spatial import cKDTree

        centre = 0.5 * (self.box[:, :2] + self.box[:, 2:])
        half = 0.5 * np.hypot(self.box[:, 2] - self.box[:, 0], self.box[:, 3] - self.box[:, 1])
        hits = cKDTree(points).query_ball_point(centre, half + within, return_length=True)
        box = np.concatenate((points.min(axis=0) - within, points.max(axis=0) + within))
        return self._points(np.nonzero(np.asarray(hits) > 0)[0], 1, box)

    def _line_range(self, which: np.ndarray, box: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The first and last sample (with one more on either side) of the lines ``which`` in
        ``box`` (a last below the first: none)."""
        a, b = self.ends[which, :2], self.ends[which, 2:]
        d = b - a
        lo, hi = np.full(len(which), -np.inf), np.full(len(which), np.inf)
        for k in (0, 1):
            with np.errstate(divide="ignore", invalid="ignore"):
                t0, t1 = (box[k] - a[:, k]) / d[:, k], (box[k + 2] - a[:, k]) / d[:, k]
            flat = d[:, k] == 0.0
            inside = (a[:, k] >= box[k]) & (a[:, k] <= box[k + 2])
            lo = np.maximum(lo, np.where(flat, np.where(inside, -np.inf, np.inf), np.minimum(t0, t1)))
            hi = np.minimum(hi, np.where(flat, np.where(inside, np.inf, -np.inf), np.maximum(t0, t1)))
        last = self.count[which] - 1
        empty = lo > hi
        first = np.clip(np.floor(np.clip(lo, -1.0, 2.0) * last) - 1, 0, last).astype(np.int64)
        end = np.clip(np.ceil(np.clip(hi, -1.0, 2.0) * last) + 1, 0, last).astype(np.int64)
        return np.where(empty, 1, first), np.where(empty, 0, end)

    def _points(self, which: np.ndarray, every: int, box: np.ndarray | None = None) -> np.ndarray:
        """Samples of the elements ``which`` (sorted): every ``every``-th and the last of each (of
        a line, from its first to its last sample in ``box``)."""
        first = np.zeros(len(which), np.int64)
        last = self.count[which] - 1
        if box is not None:
            line = self.kind[which] == LINE
            first[line], last[line] = self._line_range(which[line], box)
        span = np.maximum(last - first, -1)
        per = np.where(span < 0, 0, span // every + 1 + (span % every > 0))
        member = np.repeat(which, per)
        k = np.arange(int(per.sum())) - np.repeat(np.cumsum(per) - per, per)
        j = np.minimum(np.repeat(first, per) + k * every, np.repeat(last, per))
        out = np.empty((len(j), 2))
        kind = self.kind[member]
        flat = kind <= ARC
        if flat.any():
            m, jj = member[flat], j[flat]
            L, n = self.length[m], self.count[m]
            # np.linspace(0, L, n) / L (element_samples)
            y = jj * (L / (n - 1))
            last = jj == n - 1
            y[last] = L[last]
            lam = y / L
            e = self.ends[m]
            line = kind[flat] == LINE
            pts = np.empty((len(m), 2))
            a, b = e[line, :2], e[line, 2:]
            pts[line] = a + lam[line][:, None] * (b - a)
            arc = ~line
            ang = e[arc, 3] + lam[arc] * self.sweep[m[arc]]
            pts[arc] = np.stack((e[arc, 0] + e[arc, 2] * np.cos(ang), e[arc, 1] + e[arc, 2] * np.sin(ang)), axis=1)
            out[flat] = pts
        point = kind == POINT
        if point.any():
            out[point] = self.ends[member[point], :2]
        for k, (joined, offset, lengths, first, counts, sizes) in enumerate(self.groups):
            sel = (kind == CURVE) & (self.group[member] == k)
            if not sel.any():
                continue
            c, jj = self.place[member[sel]], j[sel]
            # curve_samples: the arc lengths and sample intervals on the joined arrays
            s = offset[c] + lengths[c] * (jj / (counts - 1)[c])
            i = np.searchsorted(joined[0], s, side="right") - 1
            i = np.clip(i, first[c], (first + sizes - 2)[c])
            out[sel] = hermite_pieces(joined, i, s, 0)[:, :2]
        return out
