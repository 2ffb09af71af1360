"""The step QPs of the smoothing splines across runs of CAM chords (:mod:`.chain`).

Each step of a run spline is a sparse QP ``min ½xᵀPx + qᵀx`` subject to ``lo ≤ Ax ≤ hi`` on the
B-spline control points (banded, a few hundred to a few thousand variables). Clarabel's iterative
refinement of every KKT solve takes about half of its solve time there and changes the solution
by less than 1e-8 mm, so :func:`solve_step` solves without it first and solves again with it
(:func:`trcopt.optimize.convex.solve_qp`'s default) where that does not end ``Solved``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from trcopt.optimize.convex import QPResult, solve_qp

__all__ = ["solve_step"]


def solve_step(P: Any, q: np.ndarray, A: Any, lo: np.ndarray, hi: np.ndarray) -> QPResult:
    """:func:`~trcopt.optimize.convex.solve_qp` of the step QP, without refinement when that
    is solved."""
    fast = solve_qp(P, q, A, lo, hi, refine=False)
    if fast.status == "Solved" and fast.x is not None:
        return fast
    return solve_qp(P, q, A, lo, hi)
