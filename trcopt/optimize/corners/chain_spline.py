"""Cubic B-splines of the smoothing splines across runs of CAM chords, as sparse linear maps.

* :func:`basis` — the sparse matrix of a derivative of the cubic B-spline basis at many points (the
  design matrix of the spline, times the sparse difference matrices of its derivatives);
* :func:`rows` — constraint rows ``v·C(s)`` on the control points from rows of a basis;
* :func:`ppoly` / :func:`piece` — the solved spline between two parameters as a
  curvature-continuous :class:`~trcopt.geometry.Poly`, sampled with vectorised evaluation.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from trcopt.geometry import Poly
from trcopt.geometry.poly import CHORD_TOL_MM

if TYPE_CHECKING:
    from scipy.interpolate import BSpline

__all__ = ["basis", "piece", "ppoly", "rows"]


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


def piece(pp: tuple[np.ndarray, np.ndarray, np.ndarray], a: float, b: float, w: float) -> Poly:
    """The spline between its parameters ``a`` and ``b`` as a curvature-continuous Poly: samples
    spaced for a chord error ≤ CHORD_TOL_MM / 2 at the piece's largest curvature (at least 8) and
    at every knot and knot-span middle,
    true arc length by 5-point Gauss–Legendre per interval (``pp``: breakpoints and per-interval
    cubic coefficients of x(s) and y(s), highest power first)."""

    def ev(s: np.ndarray, nu: int) -> np.ndarray:
        brk, cx, cy = pp
        i = np.clip(np.searchsorted(brk, s, side="right") - 1, 0, len(brk) - 2)
        t = s - brk[i]
        out = []
        for c in (cx, cy):
            c3, c2, c1, c0 = c[0, i], c[1, i], c[2, i], c[3, i]
            out.append(
                (((c3 * t + c2) * t + c1) * t + c0, (3.0 * c3 * t + 2.0 * c2) * t + c1, 6.0 * c3 * t + 2.0 * c2)[nu]
            )
        return np.stack(out, axis=1)

    L = b - a
    probe = np.linspace(a, b, 33)
    d1, d2 = ev(probe, 1), ev(probe, 2)
    n2 = np.einsum("ij,ij->i", d1, d1)
    kmax = float(np.max(np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.maximum(n2, 1e-300) ** 1.5))
    k = max(8, int(math.ceil(L * math.sqrt(kmax / (4.0 * CHORD_TOL_MM)))))
    # and every knot of the spline with two points per knot span: the Poly's quintic Hermite pieces
    # then follow the spline's cubic pieces closely, curvature included
    brk = pp[0]
    inner = brk[(brk > a) & (brk < b)]
    spans = np.concatenate(([a], inner, [b]))
    s = np.unique(np.concatenate((np.linspace(a, b, k + 1), spans, 0.5 * (spans[1:] + spans[:-1]))))
    # no two samples closer than 1 nm (a knot next to an end would give an empty Hermite piece)
    s = s[np.concatenate(([True], np.diff(s) > 1e-6 * max(L, 1e-3)))]
    s[-1] = b
    P, d1, d2 = ev(s, 0), ev(s, 1), ev(s, 2)
    n2 = np.maximum(np.einsum("ij,ij->i", d1, d1), 1e-300)
    tan = d1 / np.sqrt(n2)[:, None]
    along = np.einsum("ij,ij->i", d1, d2) / n2
    curv = (d2 - along[:, None] * d1) / n2[:, None]
    half = 0.5 * (s[1:] - s[:-1])
    mid = 0.5 * (s[1:] + s[:-1])
    g = ev((mid[:, None] + half[:, None] * _GL5_X[None, :]).ravel(), 1)
    speed = np.hypot(g[:, 0], g[:, 1]).reshape(len(mid), 5)
    cum = np.concatenate(([0.0], np.cumsum(half * (speed @ _GL5_W))))
    zero = np.zeros((len(s), 1))
    return Poly(
        tuple(map(tuple, np.hstack((P, np.full((len(s), 1), w))).tolist())),
        tuple(map(tuple, np.hstack((tan, zero)).tolist())),
        tuple(cum.tolist()),
        "chain-spline",
        tuple(map(tuple, np.hstack((curv, zero)).tolist())),
    )


def ppoly(cx: BSpline, cy: BSpline) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Breakpoints and per-interval coefficients (highest power first) of the cubic splines x(s)
    and y(s) on the same knots."""
    from scipy.interpolate import PPoly

    px, py = PPoly.from_spline(cx), PPoly.from_spline(cy)
    keep = np.nonzero(np.diff(px.x) > 0.0)[0]  # the repeated end knots bound empty intervals
    brk = np.append(px.x[keep], px.x[keep[-1] + 1])
    return brk, px.c[:, keep], py.c[:, keep]
