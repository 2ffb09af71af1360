"""Cubic B-splines of the smoothing splines across runs of CAM chords, as sparse linear maps.

* :func:`breakpoints` — the knot breakpoints of a run: fine where its corners turn sharply, coarser
  away from them;
* :func:`basis` — the sparse matrix of a derivative of the cubic B-spline basis at many points (the
  design matrix of the spline, times the sparse difference matrices of its derivatives);
* :func:`rows` — constraint rows ``v·C(s)`` on the control points from rows of a basis;
* :func:`ppoly` / :func:`pieces` — the solved spline between consecutive parameters as
  curvature-continuous :class:`~trcopt.geometry.Poly` curves, sampled with vectorised evaluation.
"""

from __future__ import annotations

import math
from itertools import accumulate
from typing import TYPE_CHECKING, Any

import numpy as np

from trcopt.geometry import Poly
from trcopt.geometry.poly import CHORD_TOL_MM

if TYPE_CHECKING:
    from scipy.interpolate import BSpline

__all__ = ["KNOT_GROWTH", "SplineBasis", "basis", "breakpoints", "pieces", "ppoly", "rows"]

KNOT_GROWTH = 0.25  # a knot span is at most its need at a corner plus this times its distance from it


def breakpoints(length: float, coarse: float, at: np.ndarray, need: np.ndarray) -> np.ndarray:
    """Breakpoints from 0 to ``length`` (mm) whose spacing h(s) is at most ``coarse`` everywhere
    and at most ``need[j] + KNOT_GROWTH·|s − at[j]|`` around every place ``at[j]`` (sorted, mm):
    ⌈∫ds/h⌉ spans (at least 4) with ∫ds/h even over each; uniform where h is."""
    at, need = np.asarray(at, float), np.minimum(np.asarray(need, float), coarse)
    finest = float(need.min(initial=coarse))
    if finest >= coarse:
        return np.linspace(0.0, length, max(4, int(math.ceil(length / coarse))) + 1)
    grid = np.linspace(0.0, length, int(math.ceil(4.0 * length / finest)) + 2)
    # the lower envelope of the cones need[j] + g·|s − at[j]|: of the places left of every grid
    # point, then of those right of it
    g = KNOT_GROWTH
    left = np.minimum.accumulate(need - g * at)
    right = np.minimum.accumulate((need + g * at)[::-1])[::-1]
    i = np.searchsorted(at, grid, side="right")
    h = np.full(len(grid), coarse)
    h = np.where(i > 0, np.minimum(h, g * grid + left[np.maximum(i - 1, 0)]), h)
    h = np.where(i < len(at), np.minimum(h, right[np.minimum(i, len(at) - 1)] - g * grid), h)
    inv = 1.0 / h
    count = np.concatenate(([0.0], np.cumsum(0.5 * (inv[1:] + inv[:-1]) * np.diff(grid))))
    spans = max(4, int(math.ceil(count[-1] - 1e-9)))
    out = np.interp(np.linspace(0.0, count[-1], spans + 1), count, grid)
    out[0], out[-1] = 0.0, length
    return out


def _derivative(knots: np.ndarray, k: int, n: int) -> Any:
    """The sparse matrix D with ``D @ c`` the coefficients of the derivative of the degree-``k``
    spline with coefficients ``c`` on ``knots`` (degree k−1 on ``knots[1:-1]``)."""
    from scipy import sparse

    w = k / (knots[k + 1 : k + n] - knots[1:n])
    w = np.where(np.isfinite(w), w, 0.0)
    return sparse.diags((-w, w), (0, 1), shape=(n - 1, n), format="csr")


def basis(knots: np.ndarray, x: np.ndarray, nu: int, n: int) -> Any:
    """Sparse matrix of the ``nu``-th derivative of the cubic B-spline basis at ``x``."""
    return SplineBasis(knots, n).at(x, nu)


class SplineBasis:
    """:func:`basis` of one cubic spline space (``knots``, ``n`` coefficients) at any points, the
    derivative matrices built once (the same products, so the same matrices)."""

    def __init__(self, knots: np.ndarray, n: int) -> None:
        self.knots, self.n = knots, n
        self._D: dict[int, Any] = {0: None}

    def _derivatives(self, nu: int) -> Any:
        if nu not in self._D:
            D = self._derivatives(nu - 1)
            t, k, m = self.knots[nu - 1 : len(self.knots) - nu + 1], 4 - nu, self.n - nu + 1
            step = _derivative(t, k, m)
            self._D[nu] = step if D is None else step @ D
        return self._D[nu]

    def at(self, x: np.ndarray, nu: int) -> Any:
        """Sparse CSR matrix of the ``nu``-th derivative of the basis at ``x``."""
        from scipy.interpolate import BSpline

        D = self._derivatives(nu)
        t, k = self.knots[nu : len(self.knots) - nu], 3 - nu
        B = BSpline.design_matrix(np.clip(x, t[k], t[-k - 1]), t, k).tocsr()
        return B if D is None else (B @ D).tocsr()


def rows(B: Any, m: np.ndarray, vecs: np.ndarray, n: int) -> Any:
    """Rows ``vecs[i]·C(s_m[i])`` of the spline's control points (x block, then y block), from the
    rows ``m`` of the sparse CSR basis ``B`` (built as CSR directly: each row holds its x entries,
    then the same columns shifted by ``n``; indices sorted)."""
    from scipy import sparse

    m = np.asarray(m, np.int64)
    start, counts = B.indptr[m], np.diff(B.indptr)[m]
    r = np.repeat(np.arange(len(m)), counts)
    first = np.cumsum(counts) - counts  # where each row starts among the gathered entries
    src = np.repeat(start - first, counts) + np.arange(int(counts.sum()))  # B's entries of the rows
    data, cols = B.data[src], B.indices[src]
    at = np.repeat(2 * first, counts) + (np.arange(len(src)) - np.repeat(first, counts))  # x entries
    out_data = np.empty(2 * len(src))
    out_cols = np.empty(2 * len(src), dtype=cols.dtype)
    out_data[at], out_cols[at] = data * vecs[r, 0], cols
    at += np.repeat(counts, counts)  # y entries after the row's x entries
    out_data[at], out_cols[at] = data * vecs[r, 1], cols + n
    indptr = np.concatenate(([0], 2 * np.cumsum(counts)))
    out = sparse.csr_matrix((out_data, out_cols, indptr), shape=(len(m), 2 * n))
    if not B.has_sorted_indices:
        out.sort_indices()
    return out


_GL5_X, _GL5_W = np.polynomial.legendre.leggauss(5)


def _ev(pp: tuple[np.ndarray, np.ndarray, np.ndarray], s: np.ndarray, nu: int) -> np.ndarray:
    """The ``nu``-th derivative (0–2) of the spline (x, y) at the parameters ``s`` (n×2)."""
    brk, cx, cy = pp
    i = np.clip(np.searchsorted(brk, s, side="right") - 1, 0, len(brk) - 2)
    t = s - brk[i]
    out = []
    for c in (cx, cy):
        c3, c2, c1, c0 = c[0, i], c[1, i], c[2, i], c[3, i]
        if nu == 0:
            out.append(((c3 * t + c2) * t + c1) * t + c0)
        elif nu == 1:
            out.append((3.0 * c3 * t + 2.0 * c2) * t + c1)
        else:
            out.append(6.0 * c3 * t + 2.0 * c2)
    return np.stack(out, axis=1)


def _spaced(a: np.ndarray, b: np.ndarray, counts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``np.linspace(a[i], b[i], counts[i])`` for every i, concatenated, and the i of each value."""
    pid = np.repeat(np.arange(len(a)), counts)
    first = np.concatenate(([0], np.cumsum(counts)[:-1]))
    j = np.arange(int(counts.sum())) - first[pid]
    x = j * ((b - a) / (counts - 1))[pid] + a[pid]
    last = first + counts - 1
    x[last] = b
    return x, pid


def pieces(pp: tuple[np.ndarray, np.ndarray, np.ndarray], cuts: np.ndarray, w: float) -> list[Poly]:
    """The spline between consecutive parameters of ``cuts`` as curvature-continuous Polys: each
    sampled for a chord error ≤ CHORD_TOL_MM / 2 at its largest curvature (at least 8 intervals)
    and at every knot and knot-span middle, true arc length by 5-point Gauss–Legendre per interval
    (``pp``: breakpoints and per-interval cubic coefficients of x(s) and y(s), highest power
    first); every piece of the run is evaluated in one pass."""
    cuts = np.asarray(cuts, float)
    a, b = cuts[:-1], cuts[1:]
    n = len(a)
    L = b - a
    probe, _ = _spaced(a, b, np.full(n, 33))
    d1, d2 = _ev(pp, probe, 1), _ev(pp, probe, 2)
    n2 = np.einsum("ij,ij->i", d1, d1)
    kap = (np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.maximum(n2, 1e-300) ** 1.5).reshape(n, 33)
    k = np.maximum(8, np.ceil(L * np.sqrt(kap.max(axis=1) / (4.0 * CHORD_TOL_MM))).astype(int))
    uniform, upid = _spaced(a, b, k + 1)
    # every knot of the spline with two points per knot span: the Poly's quintic Hermite pieces
    # then follow the spline's cubic pieces closely, curvature included
    brk = pp[0]
    spans = np.unique(np.concatenate((cuts, brk[(brk > cuts[0]) & (brk < cuts[-1])])))
    mids = 0.5 * (spans[1:] + spans[:-1])
    inner = spans[(spans > cuts[0]) & (spans < cuts[-1])]
    at = np.clip(np.searchsorted(cuts, inner, side="right") - 1, 0, n - 1)
    on_cut = np.isin(inner, cuts)  # a cut ends one piece and starts the next
    s = np.concatenate((uniform, mids, inner, inner[on_cut]))
    pid = np.concatenate((upid, np.clip(np.searchsorted(cuts, mids, side="right") - 1, 0, n - 1), at, at[on_cut] - 1))
    order = np.lexsort((s, pid))
    s, pid = s[order], pid[order]
    # no two samples closer than 1 nm (a knot next to an end would give an empty Hermite piece)
    keep = np.ones(len(s), bool)
    same = pid[1:] == pid[:-1]
    keep[1:] = ~same | (np.diff(s) > 1e-6 * np.maximum(L, 1e-3)[pid[1:]])
    s, pid = s[keep], pid[keep]
    ends = np.concatenate((np.nonzero(pid[1:] != pid[:-1])[0], [len(s) - 1]))
    s[ends] = b
    P, d1, d2 = _ev(pp, s, 0), _ev(pp, s, 1), _ev(pp, s, 2)
    n2 = np.maximum(np.einsum("ij,ij->i", d1, d1), 1e-300)
    tan = d1 / np.sqrt(n2)[:, None]
    along = np.einsum("ij,ij->i", d1, d2) / n2
    curv = (d2 - along[:, None] * d1) / n2[:, None]
    half = 0.5 * (s[1:] - s[:-1])
    mid = 0.5 * (s[1:] + s[:-1])
    g = _ev(pp, (mid[:, None] + half[:, None] * _GL5_X[None, :]).ravel(), 1)
    seg_len = half * (np.hypot(g[:, 0], g[:, 1]).reshape(len(mid), 5) @ _GL5_W)
    starts = np.concatenate(([0], ends[:-1] + 1))
    # (every point shares one float for its applicate, every vector one zero: a run of thousands
    # of chords holds its samples as Python tuples)
    wf, zero = float(w), 0.0
    pts = [(x, y, wf) for x, y in P.tolist()]
    tans = [(x, y, zero) for x, y in tan.tolist()]
    curvs = [(x, y, zero) for x, y in curv.tolist()]
    lengths = seg_len.tolist()
    out = []
    for i0, i1 in zip(starts.tolist(), ends.tolist(), strict=True):
        # (the running sum is np.cumsum's: sequential additions)
        cum = tuple(accumulate(lengths[i0:i1], initial=0.0))
        out.append(
            Poly(tuple(pts[i0 : i1 + 1]), tuple(tans[i0 : i1 + 1]), cum, "chain-spline", tuple(curvs[i0 : i1 + 1]))
        )
    return out


def ppoly(cx: BSpline, cy: BSpline) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Breakpoints and per-interval coefficients (highest power first) of the cubic splines x(s)
    and y(s) on the same knots."""
    from scipy.interpolate import PPoly

    px, py = PPoly.from_spline(cx), PPoly.from_spline(cy)
    keep = np.nonzero(np.diff(px.x) > 0.0)[0]  # the repeated end knots bound empty intervals
    brk = np.append(px.x[keep], px.x[keep[-1] + 1])
    return brk, px.c[:, keep], py.c[:, keep]
