"""The pieces of the run-spline steps: the knot breakpoints graded from the sharp corners of a run
(``chain_spline.breakpoints``), the constraint rows on the control points (``chain_spline.rows``)
and the step QP without iterative refinement (``chain_qp.solve_step``), which must give what the
refined solve gives."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import sparse

from trcopt.optimize.convex import solve_qp
from trcopt.optimize.corners.chain_qp import solve_step
from trcopt.optimize.corners.chain_spline import KNOT_GROWTH, basis, breakpoints, rows


def test_breakpoints_are_uniform_where_no_place_needs_finer_spans():
    out = breakpoints(10.0, 0.3, np.array([2.0, 7.0]), np.array([0.5, 0.4]))
    assert np.allclose(out, np.linspace(0.0, 10.0, math.ceil(10.0 / 0.3) + 1))
    assert len(breakpoints(0.5, 0.3, np.zeros(0), np.zeros(0))) == 5  # at least four spans


def test_breakpoints_grow_from_the_places_that_need_fine_spans():
    length, coarse = 20.0, 0.5
    at, need = np.array([0.0, 6.0, 13.0, 20.0]), np.array([0.05, 0.03, 0.2, 0.05])
    out = breakpoints(length, coarse, at, need)
    assert out[0] == 0.0 and out[-1] == length and np.all(np.diff(out) > 0)
    mid = 0.5 * (out[1:] + out[:-1])
    allowed = np.minimum(coarse, np.min(need[None, :] + KNOT_GROWTH * np.abs(mid[:, None] - at[None, :]), axis=1))
    # every span is about as long as the spacing allowed at its middle (the spacing varies along it)
    assert np.all(np.diff(out) <= 1.25 * allowed)
    assert np.diff(out)[np.argmin(np.abs(mid - 6.0))] <= 1.25 * 0.03  # finest at the sharpest place
    assert np.diff(out).max() >= 0.9 * coarse  # coarse far from the places
    # far fewer spans than one spacing of the finest need everywhere
    assert len(out) - 1 < 0.25 * length / need.min()


@pytest.mark.parametrize("nu", [0, 1, 2])
def test_constraint_rows_are_the_basis_rows_times_the_directions(nu):
    length, n = 6.0, 23
    knots = np.concatenate(([0.0] * 3, np.linspace(0.0, length, n - 2), [length] * 3))
    rng = np.random.default_rng(nu)
    B = basis(knots, np.sort(rng.uniform(0.0, length, 80)), nu, n)
    m = rng.integers(0, 80, 120)  # repeated and unordered rows
    v = rng.normal(size=(120, 2))
    out = rows(B, m, v, n)
    dense = B.toarray()[m]
    assert out.shape == (120, 2 * n) and out.has_sorted_indices
    assert np.allclose(out.toarray(), np.hstack((dense * v[:, :1], dense * v[:, 1:])), rtol=0.0, atol=1e-12)
    assert rows(B, np.zeros(0, int), np.zeros((0, 2)), n).shape == (0, 2 * n)  # no rows (no element near)


def _qp(seed: int) -> tuple:
    """A small strictly convex QP with equalities, two-sided and one-sided rows."""
    rng = np.random.default_rng(seed)
    n = 30
    M = rng.normal(size=(n, n))
    P = sparse.csc_matrix(M @ M.T + n * np.eye(n))
    q = rng.normal(size=n)
    A = sparse.csr_matrix(rng.normal(size=(40, n)))
    x0 = rng.normal(size=n)
    ax = A @ x0
    lo = ax - rng.uniform(0.0, 0.5, 40)
    hi = ax + rng.uniform(0.0, 0.5, 40)
    lo[:3] = hi[:3] = ax[:3]  # equalities
    lo[3:10] = -np.inf
    hi[10:15] = np.inf
    return P, q, A, lo, hi


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_step_qp_gives_the_refined_solution(seed):
    P, q, A, lo, hi = _qp(seed)
    fast, ref = solve_step(P, q, A, lo, hi), solve_qp(P, q, A, lo, hi)
    assert fast.status == "Solved" and fast.x is not None and ref.x is not None
    # both within the solver's tolerance of the optimum (on the run splines' steps: < 1e-8 mm apart)
    assert np.max(np.abs(fast.x - ref.x)) <= 1e-5
    f = lambda x: 0.5 * x @ (P @ x) + q @ x  # noqa: E731
    assert f(fast.x) == pytest.approx(f(ref.x), rel=1e-7, abs=1e-9)
    ax = A @ fast.x
    assert np.all(ax >= lo - 1e-7) and np.all(ax <= hi + 1e-7)


def test_step_qp_reports_an_infeasible_problem_as_the_refined_solve_does():
    P, q, A, lo, hi = _qp(3)
    lo[20], hi[20] = 1.0, 0.5  # lo > hi: no x satisfies the row
    fast, ref = solve_step(P, q, A, lo, hi), solve_qp(P, q, A, lo, hi)
    assert fast.x is None and ref.x is None
    assert fast.status == ref.status
