"""Convex quadratic programs of the corner optimisation, solved by an interior-point method.

The corner problems (one G2 quintic per corner, one smoothing spline per run of CAM chords) are
small sparse QPs, ``min ½xᵀPx + qᵀx`` subject to ``lo ≤ Ax ≤ hi``, solved many times in sequential
convex programming. They are badly scaled (micrometre tolerances beside millimetre lengths) and
often have many nearly active rows (the no-gouge half-planes along a contour): a first-order method
(ADMM) needs thousands of iterations for them and sometimes stops at its iteration limit, while an
interior-point method reaches 1e-8 accuracy in 10–40 Newton steps whatever the scaling. They are
solved with Clarabel (``clarabel``), rows with ``lo == hi`` as equalities.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["QPResult", "conic_form", "solve_conic", "solve_qp"]

SOLVED = ("Solved", "AlmostSolved")


@dataclass
class QPResult:
    """``x`` (None when the solver found no solution), the solver's ``status`` and ``iterations``."""

    x: np.ndarray | None
    status: str
    iterations: int


def solve_qp(
    P: Any, q: np.ndarray, A: Any, lo: np.ndarray, hi: np.ndarray, *, max_iter: int = 200, refine: bool = True
) -> QPResult:
    """The minimiser of ``½xᵀPx + qᵀx`` subject to ``lo ≤ Ax ≤ hi`` (``P`` symmetric positive
    semidefinite, sparse or dense; infinite bounds are absent rows; ``lo == hi`` an equality).
    ``refine=False``: without Clarabel's iterative refinement of each KKT solve."""
    A_c, b, n_eq = conic_form(A, lo, hi)
    return solve_conic(P, q, A_c, b, n_eq, max_iter=max_iter, refine=refine)


def conic_form(A: Any, lo: np.ndarray, hi: np.ndarray) -> tuple[Any, np.ndarray, int]:
    """The rows ``lo ≤ Ax ≤ hi`` in Clarabel's form ``A_c x + s = b``: the equalities first (s in
    the zero cone), then every finite lower bound's row negated, then every finite upper bound's
    row (s ≥ 0), each kind in row order; and the number of equalities."""
    from scipy import sparse

    A = sparse.csr_matrix(A)
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    eq = np.isfinite(lo) & np.isfinite(hi) & (hi - lo <= 1e-12 * np.maximum(1.0, np.abs(hi)))
    below = np.isfinite(lo) & ~eq
    above = np.isfinite(hi) & ~eq
    rows = np.concatenate((np.nonzero(eq)[0], np.nonzero(below)[0], np.nonzero(above)[0]))
    sign = np.concatenate((np.ones(int(eq.sum())), -np.ones(int(below.sum())), np.ones(int(above.sum()))))
    A_c = (sparse.diags(sign) @ A[rows]).tocsc()
    b = np.concatenate((hi[eq], -lo[below], hi[above]))
    return A_c, b, int(eq.sum())


def solve_conic(
    P: Any, q: np.ndarray, A_c: Any, b: np.ndarray, n_eq: int, *, max_iter: int = 200, refine: bool = True
) -> QPResult:
    """:func:`solve_qp` of rows already in Clarabel's form (:func:`conic_form`: ``A_c`` sparse
    CSC without explicit zeros, its first ``n_eq`` rows equalities)."""
    import clarabel
    from scipy import sparse

    cones = []
    if n_eq:
        cones.append(clarabel.ZeroConeT(n_eq))
    if len(b) > n_eq:
        cones.append(clarabel.NonnegativeConeT(len(b) - n_eq))
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.max_iter = max_iter
    settings.iterative_refinement_enable = refine
    solver = clarabel.DefaultSolver(
        sparse.triu(sparse.csc_matrix(P), format="csc"), np.asarray(q, float), A_c, b, cones, settings
    )
    sol = solver.solve()
    status = str(sol.status)
    x = np.asarray(sol.x, float)
    ok = status in SOLVED and x.shape == (np.shape(q)[0],) and bool(np.all(np.isfinite(x)))
    return QPResult(x if ok else None, status, int(sol.iterations))
