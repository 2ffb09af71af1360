"""Cubic B-splines of the smoothing splines across runs of CAM chords, as sparse linear maps.

* :func:`basis` — the sparse matrix of a derivative of the cubic B-spline basis at many points (the
  design matrix of the spline, times the sparse difference matrices of its derivatives);
* :func:`rows` — constraint rows ``v·C(s)`` on the control points from rows of a basis;
* :func:`ppoly` / :func:`pieces` — the solved spline between consecutive parameters as
  curvature-continuous :class:`~trcopt.geometry.Poly` curves, sampled with vectorised evaluation.
"""

from __future__ import annotations

from itertools import accumulate
from typing import TYPE_CHECKING, Any

import numpy as np

from trcopt.geometry import Poly
from trcopt.geometry.poly import CHORD_TOL_MM

if TYPE_CHECKING:
    from scipy.interpolate import BSpline

__all__ = ["basis", "pieces", "ppoly", "rows"]


def _derivative(knots: np.ndarray, k: int, n: int) -> Any:
    """The sparse matrix D with ``D @ c`` the coefficients of the derivative of the degree-``k``
    spline with coefficients ``c`` on ``knots`` (degree k−1 on ``knots[1:-1]``)."""
    from scipy import sparse

    w = k / (knots[k + 1 : k + n] - knots[1:n])
    w = np.where(np.isfinite(w), w, 0.0)
    return sparse.diags((-w, w), (0, 1), shape=(n - 1, n), format="csr")


def basis(knots: np.ndarray, x: np.ndarray, nu: int, n: int) -> Any:
    """Sparse matrix of the ``nu``-th derivative of the cubic B-spline basis at ``x``."""
    from scipy.interpolate import BSpline

    D = None
    t, k, m = knots, 3, n
    for _ in range(nu):
        step = _derivative(t, k, m)
        D = step if D is None else step @ D
        t, k, m = t[1:-1], k - 1, m - 1
    B = BSpline.design_matrix(np.clip(x, t[k], t[-k - 1]), t, k).tocsr()
    return B if D is None else (B @ D).tocsr()


def rows(B: Any, m: np.ndarray, vecs: np.ndarray, n: int) -> Any:
    """Rows ``vecs[i]·C(s_m[i])`` of the spline's control points (x block, then y block), from the
    rows ``m`` of the sparse basis ``B``."""
    from scipy import sparse

    sub = B[m]
    counts = np.diff(sub.indptr)
    r = np.repeat(np.arange(len(m)), counts)
    vx = np.repeat(vecs[:, 0], counts)
    vy = np.repeat(vecs[:, 1], counts)
    data = np.concatenate((sub.data * vx, sub.data * vy))
    cols = np.concatenate((sub.indices, sub.indices + n))
    return sparse.csr_matrix((data, (np.concatenate((r, r)), cols)), shape=(len(m), 2 * n))


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
    pts = list(map(tuple, np.hstack((P, np.full((len(s), 1), w))).tolist()))
    tans = list(map(tuple, np.hstack((tan, np.zeros((len(s), 1)))).tolist()))
    curvs = list(map(tuple, np.hstack((curv, np.zeros((len(s), 1)))).tolist()))
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
