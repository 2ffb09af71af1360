"""The solved profiles of a path's sections, held as a few flat arrays.

A program of short sections (a stop at every vertex of a CAM polyline) has as many sections as
segments; :class:`Profiles` keeps the profiles of many sections solved together in the arrays they
were computed in (one *block*: the points of every section one after the other) and strings them
together in path order with index arithmetic (:meth:`Profiles.assembled`), with no Python object
per section. It is a read-only mapping from section index to ``(s, x, iseg)`` (arc lengths mm,
squared path speeds mm²/s², the segment of every interval) as well.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence

import numpy as np

__all__ = ["Profiles", "Result", "ranges"]

Result = tuple[np.ndarray, np.ndarray, np.ndarray]  # s (mm), x = ṡ² (mm²/s²), segment per interval


def ranges(starts: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """``np.concatenate([np.arange(a, a + c) for a, c in zip(starts, counts)])`` in one pass."""
    counts = np.asarray(counts, dtype=np.int64)
    total = int(counts.sum())
    return np.repeat(np.asarray(starts, dtype=np.int64) - (np.cumsum(counts) - counts), counts) + np.arange(
        total, dtype=np.int64
    )


class Profiles(Mapping[int, Result]):
    """Section index → ``(s, x, iseg)``, stored as blocks of flat arrays."""

    def __init__(self) -> None:
        self._blocks: list[Result] = []
        self._index: list[np.ndarray] = []  # per block: the section indices
        self._points: list[np.ndarray] = []  # per block: first point of every section, and the end
        self._intervals: list[np.ndarray] = []  # per block: first interval of every section, and the end
        self._where: dict[int, tuple[int, int]] | None = None

    def add_block(
        self, index: np.ndarray, s: np.ndarray, x: np.ndarray, iseg: np.ndarray, points: np.ndarray,
        intervals: np.ndarray,
    ) -> None:
        """The profiles of the sections ``index``: section ``index[j]`` has the points
        ``points[j]..points[j+1]-1`` of ``s``, ``x`` and the intervals ``intervals[j]..intervals[j+1]-1``
        of ``iseg``."""
        if not len(index):
            return
        self._blocks.append((s, x, iseg))
        self._index.append(np.asarray(index, dtype=np.int64))
        self._points.append(np.asarray(points, dtype=np.int64))
        self._intervals.append(np.asarray(intervals, dtype=np.int64))
        self._where = None

    def add(self, index: int, s: np.ndarray, x: np.ndarray, iseg: np.ndarray) -> None:
        """The profile of one section."""
        self.add_block(np.array([index]), s, x, iseg, np.array([0, s.shape[0]]), np.array([0, iseg.shape[0]]))

    def _lookup(self) -> dict[int, tuple[int, int]]:
        if self._where is None:
            self._where = {
                k: (b, j) for b, index in enumerate(self._index) for j, k in enumerate(index.tolist())
            }
        return self._where

    def __getitem__(self, k: int) -> Result:
        b, j = self._lookup()[k]
        s, x, iseg = self._blocks[b]
        p, i = self._points[b], self._intervals[b]
        return s[p[j] : p[j + 1]], x[p[j] : p[j + 1]], iseg[i[j] : i[j + 1]]

    def __iter__(self) -> Iterator[int]:
        return iter(self._lookup())

    def __len__(self) -> int:
        return sum(index.shape[0] for index in self._index)

    def assembled(self, order: Sequence[int]) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The profiles of the sections ``order`` one after the other: ``(s, x, iseg, starts)`` with
        every section's first point left out but the first section's (it is the previous section's
        last, at rest), and ``starts`` the point of every section start and the last point."""
        index = np.concatenate(self._index)
        pos = np.full(int(index.max()) + 1, -1, dtype=np.int64)
        pos[index] = np.arange(index.shape[0])
        sel = pos[np.asarray(order, dtype=np.int64)]
        if np.any(sel < 0):
            missing = np.asarray(order)[sel < 0]
            raise KeyError(int(missing[0]))
        p_off = np.cumsum([0] + [b[0].shape[0] for b in self._blocks])[:-1]
        i_off = np.cumsum([0] + [b[2].shape[0] for b in self._blocks])[:-1]
        p_first = np.concatenate([p[:-1] + o for p, o in zip(self._points, p_off, strict=True)])[sel]
        p_count = np.concatenate([np.diff(p) for p in self._points])[sel]
        i_first = np.concatenate([i[:-1] + o for i, o in zip(self._intervals, i_off, strict=True)])[sel]
        i_count = np.concatenate([np.diff(i) for i in self._intervals])[sel]
        p_first[1:] += 1  # a section starts where the one before ends
        p_count[1:] -= 1
        pts = ranges(p_first, p_count)
        s = np.concatenate([b[0] for b in self._blocks])[pts]
        x = np.concatenate([b[1] for b in self._blocks])[pts]
        iseg = np.concatenate([b[2] for b in self._blocks])[ranges(i_first, i_count)].astype(np.int64)
        before = np.cumsum(p_count) - p_count  # points of the sections before each
        starts = np.append(np.maximum(before - 1, 0), before[-1] + p_count[-1] - 1)
        starts[0] = 0
        return s, x, iseg, starts
