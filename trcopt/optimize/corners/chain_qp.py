"""The step QPs of the smoothing splines across runs of CAM chords (:mod:`.chain`).

Each step of a run spline is a sparse QP ``min ½xᵀPx + qᵀx`` subject to ``lo ≤ Ax ≤ hi`` on the
B-spline control points (banded, a few hundred to a few thousand variables). Clarabel's iterative
refinement of every KKT solve takes about half of its solve time there and changes the solution
by less than 1e-8 mm, so :func:`solve_step` solves without it first and solves again with it
(:func:`trcopt.optimize.convex.solve_qp`'s default) where that does not end ``Solved``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from trcopt.optimize.convex import QPResult, conic_form, solve_conic

__all__ = ["solve_rows", "solve_step"]


def solve_step(P: Any, q: np.ndarray, A: Any, lo: np.ndarray, hi: np.ndarray) -> QPResult:
    """:func:`~trcopt.optimize.convex.solve_qp` of the step QP, without refinement when that
    is solved."""
    A_c, b, n_eq = conic_form(A, lo, hi)
    return _solve(P, q, A_c, b, n_eq)


def solve_rows(
    P: Any,
    q: np.ndarray,
    equal: tuple[Any, np.ndarray],
    lower: Sequence[tuple[Any, np.ndarray]],
    upper: Sequence[tuple[Any, np.ndarray]],
) -> QPResult:
    """:func:`solve_step` of rows given by kind, each a sparse CSR block and its bounds: the
    equalities ``A x = b``, the lower bounds ``A x ≥ lo`` and the upper bounds ``A x ≤ hi`` (all
    finite) — the QP :func:`solve_step` solves for the rows stacked in this order (the same
    matrices for the solver, built without selecting rows)."""
    from scipy import sparse

    A_c = sparse.vstack([equal[0], *(-A for A, _ in lower), *(A for A, _ in upper)], format="csr")
    A_c.eliminate_zeros()  # (what conic_form's row signs leave out)
    b = np.concatenate([equal[1], *(-lo for _, lo in lower), *(hi for _, hi in upper)])
    return _solve(P, q, A_c.tocsc(), b, equal[0].shape[0])


def _solve(P: Any, q: np.ndarray, A_c: Any, b: np.ndarray, n_eq: int) -> QPResult:
    fast = solve_conic(P, q, A_c, b, n_eq, refine=False)
    if fast.status == "Solved" and fast.x is not None:
        return fast
    return solve_conic(P, q, A_c, b, n_eq)
