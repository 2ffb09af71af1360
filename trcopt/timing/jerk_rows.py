"""Inequality rows of a :class:`~trcopt.timing.jerk_problem.JerkProblem`, collected and added in one block."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["RowBatch"]


class RowBatch:
    """Collects inequality rows ``lo ≤ g ≤ hi`` (the ``bounded``/``subject_to`` calls of the row
    builders) and hands them to the Opti instance as one block: one ``subject_to`` per section
    instead of one per row group."""

    def __init__(self) -> None:
        self.lo: list[np.ndarray] = []
        self.g: list[Any] = []
        self.hi: list[np.ndarray] = []

    @staticmethod
    def bounded(lo: Any, g: Any, hi: Any) -> tuple[Any, Any, Any]:
        return lo, g, hi

    def subject_to(self, row: tuple[Any, Any, Any]) -> None:
        lo, g, hi = row
        n = int(g.shape[0])
        self.lo.append(np.broadcast_to(np.asarray(lo, dtype=float).ravel(), (n,)) if np.ndim(lo) else np.full(n, lo))
        self.g.append(g)
        self.hi.append(np.broadcast_to(np.asarray(hi, dtype=float).ravel(), (n,)) if np.ndim(hi) else np.full(n, hi))

    def flush(self, opti: Any, ca: Any) -> None:
        if self.g:
            lo, hi = np.concatenate(self.lo), np.concatenate(self.hi)
            opti.subject_to(opti.bounded(ca.DM(lo), ca.vertcat(*self.g), ca.DM(hi)))
