"""Distances from many points to a fixed set of plane elements, the lines all at once.

The corner transitions test every candidate curve against the programmed elements near its
corner (tens of elements, hundreds of sample points, thousands of candidates per program).
:class:`ElementSet` keeps the lines of such a set as arrays and measures a point cloud against all
of them in one broadcast (the formula of :func:`~trcopt.verify.model.points_distance`: the
foot on each bounded line, then the distance to it); arcs and polylines are measured one by one.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from trcopt.geometry import Line
from trcopt.verify.model import Element, points_distance

__all__ = ["ElementSet"]

CHUNK = 1 << 18  # points × lines per broadcast block (memory ~ 8 arrays of this many floats)


class ElementSet:
    """A fixed sequence of plane elements (lines, arcs, polylines)."""

    def __init__(self, elements: Sequence[Element]) -> None:
        self.elements = tuple(elements)
        lines = [e for e in self.elements if isinstance(e, Line)]
        self.others = tuple(e for e in self.elements if not isinstance(e, Line))
        if lines:
            self._a = np.array([e.start2 for e in lines], float)
            d = np.array([e.end2 for e in lines], float) - self._a
            self._d = d
            self._dd = np.einsum("ij,ij->i", d, d)
        else:
            self._a = self._d = np.zeros((0, 2))
            self._dd = np.zeros(0)

    def __len__(self) -> int:
        return len(self.elements)

    def distance(self, pts: np.ndarray) -> np.ndarray:
        """Smallest plane distance (mm) from each point of ``pts`` (n×2) to the elements (``inf``
        for an empty set)."""
        pts = np.asarray(pts, float).reshape(-1, 2)
        best = np.full(len(pts), np.inf)
        m = len(self._dd)
        if m and len(pts):
            step = max(1, CHUNK // m)
            for i in range(0, len(pts), step):
                best[i : i + step] = self._lines_min(pts[i : i + step])
        for e in self.others:
            best = np.minimum(best, points_distance(e, pts))
        return best

    def min_distance(self, pts: np.ndarray) -> float:
        """Smallest distance (mm) from any point of ``pts`` to any element (``inf`` when empty)."""
        d = self.distance(pts)
        return float(d.min()) if d.size else float("inf")

    def _lines_min(self, pts: np.ndarray) -> np.ndarray:
        # per line: t = clip(((p − a)·d)/dd, 0, 1), q = a + t·d, |p − q| (degenerate lines: |p − a|)
        pu, pv = pts[:, 0:1], pts[:, 1:2]
        au, av = self._a[None, :, 0], self._a[None, :, 1]
        du, dv = self._d[None, :, 0], self._d[None, :, 1]
        dd = self._dd[None, :]
        safe = np.where(dd == 0.0, 1.0, dd)
        t = np.where(dd == 0.0, 0.0, np.clip(((pu - au) * du + (pv - av) * dv) / safe, 0.0, 1.0))
        return np.hypot(pu - (au + t * du), pv - (av + t * dv)).min(axis=1)
