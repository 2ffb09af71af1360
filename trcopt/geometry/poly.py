"""Polynomial and other smooth curves (KONTT/KONTC polynomials, DISC conics, variable-radius spirals).

A :class:`Poly` keeps an adaptive sampling of its defining function (chord error ≤ ``chord_tol``,
1 µm by default) together with the exact unit tangent at each sample; between samples it is
evaluated by cubic Hermite interpolation in arc length, so it is tangent-continuous for timing and
exact at every sample. When the curvature vectors at the samples are known (``curvatures``, the
second derivative in arc length — quintic transitions and lead curves), the pieces are quintic
Hermite polynomials instead: the curve is then curvature-continuous, which the jerk-limited feed
needs (a cubic piece chain has a jump of q″ at every sample).
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from trcopt.geometry import vec
from trcopt.geometry.vec import Vec2, Vec3

__all__ = [
    "MAX_CURVE_SAMPLES", "SamplingError", "Poly", "hermite_at", "hermite_curve", "hermite_pieces", "conic_curve",
    "spiral_curve", "parametric_curve",
]

CHORD_TOL_MM = 1e-3
# Upper bound of the adaptive sampler: a curve that needs more points to its chord tolerance is
# degenerate or extreme (a KONTC curvature of 1e15/mm, a 1e12 mm span); it raises SamplingError
# instead of sampling without end. The sampled curves of real programs stay below a few thousand.
MAX_CURVE_SAMPLES = 100_000


class SamplingError(ValueError):
    """A curve cannot be sampled to its chord tolerance: a non-finite point, or more than
    :data:`MAX_CURVE_SAMPLES` samples needed (geometry knows no source span; the caller that
    built the curve reports it at its block)."""


@dataclass(frozen=True, slots=True)
class Poly:
    """Smooth curve given by samples (points, unit tangents, cumulative 3D arc length)."""

    points: tuple[Vec3, ...]
    tangents: tuple[Vec3, ...]
    cum: tuple[float, ...]
    label: str = "poly"
    curvatures: tuple[Vec3, ...] | None = None  # d²q/ds² at the samples (G2 interpolation when given)

    @property
    def start(self) -> Vec3:
        return self.points[0]

    @property
    def end(self) -> Vec3:
        return self.points[-1]

    @property
    def length(self) -> float:
        return self.cum[-1]

    @property
    def plane_length(self) -> float:
        return sum(
            math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(self.points, self.points[1:], strict=False)
        )

    def _t2(self, t: Vec3) -> Vec2:
        return vec.unit((t[0], t[1]))

    def start_tangent(self) -> Vec2:
        return self._t2(self.tangents[0])

    def end_tangent(self) -> Vec2:
        return self._t2(self.tangents[-1])

    def point2(self, lam: float) -> Vec2:
        p = self.point(lam * self.length)
        return (p[0], p[1])

    def _locate(self, s: float) -> tuple[int, float, float]:
        s = min(max(s, 0.0), self.cum[-1])
        i = min(max(bisect.bisect_right(self.cum, s) - 1, 0), len(self.cum) - 2)
        h = self.cum[i + 1] - self.cum[i]
        return i, h, (s - self.cum[i]) / h if h > 0 else 0.0

    def point(self, s: float) -> Vec3:
        return self.derivatives(s)[0]

    def points_at(self, s: Any) -> Any:
        """Positions at the arc lengths ``s`` (a numpy array, mm), n×3: the interpolation of
        :meth:`derivatives`, evaluated for all of them at once."""
        return self.derivatives_at(s, 0)

    def derivatives_at(self, s: Any, order: int = 1) -> Any:
        """Position (``order`` 0), first (1) or second derivative (2) at the arc lengths ``s`` (a
        numpy array, mm), n×3, as :meth:`derivatives` computes them, for all of them at once."""
        return hermite_at(self.arrays(), s, order)

    def arrays(self) -> tuple[Any, Any, Any, Any]:
        """``(cum, points, tangents, curvatures or None)`` as numpy arrays (for :func:`hermite_at`;
        a caller evaluating the curve many times keeps them)."""
        import numpy as np

        K = None if self.curvatures is None else np.asarray(self.curvatures, dtype=float)
        return np.asarray(self.cum, dtype=float), np.asarray(self.points, dtype=float), np.asarray(
            self.tangents, dtype=float
        ), K

    def derivatives(self, s: float) -> tuple[Vec3, Vec3, Vec3]:
        """Position, first and second derivative in arc length: cubic Hermite interpolation between
        samples, quintic when the sample curvatures are known."""
        i, h, t = self._locate(s)
        p0, p1 = self.points[i], self.points[i + 1]
        m0, m1 = self.tangents[i], self.tangents[i + 1]
        hh = h if h > 0 else 1.0
        if self.curvatures is not None:
            k0, k1 = self.curvatures[i], self.curvatures[i + 1]
            b0, b1, b2 = quintic_hermite_basis(t)
            coef = [(a, h * c, h * h * e, h * h * f, h * d, b) for a, b, c, d, e, f in zip(p0, p1, m0, m1, k0, k1,
                                                                                          strict=True)]
            p = tuple(sum(w * x for w, x in zip(b0, row, strict=True)) for row in coef)
            d1 = tuple(sum(w * x for w, x in zip(b1, row, strict=True)) / hh for row in coef)
            d2 = tuple(sum(w * x for w, x in zip(b2, row, strict=True)) / (hh * hh) for row in coef)
            return (p[0], p[1], p[2]), (d1[0], d1[1], d1[2]), (d2[0], d2[1], d2[2])
        t2, t3 = t * t, t * t * t
        h00, h10, h01, h11 = 2 * t3 - 3 * t2 + 1, t3 - 2 * t2 + t, -2 * t3 + 3 * t2, t3 - t2
        d00, d10, d01, d11 = 6 * t2 - 6 * t, 3 * t2 - 4 * t + 1, -6 * t2 + 6 * t, 3 * t2 - 2 * t
        e00, e10, e01, e11 = 12 * t - 6, 6 * t - 4, -12 * t + 6, 6 * t - 2
        p = tuple(h00 * a + h10 * h * c + h01 * b + h11 * h * d for a, b, c, d in zip(p0, p1, m0, m1, strict=True))
        d1 = tuple(
            (d00 * a + d10 * h * c + d01 * b + d11 * h * d) / hh for a, b, c, d in zip(p0, p1, m0, m1, strict=True)
        )
        d2 = tuple(
            (e00 * a + e10 * h * c + e01 * b + e11 * h * d) / (hh * hh)
            for a, b, c, d in zip(p0, p1, m0, m1, strict=True)
        )
        return (p[0], p[1], p[2]), (d1[0], d1[1], d1[2]), (d2[0], d2[1], d2[2])

    def third(self, s: float) -> Vec3:
        """Third derivative in arc length at ``s`` (constant on a cubic piece, quadratic in s on a
        quintic one); per mm²."""
        i, h, t = self._locate(s)
        if h <= 0:
            return (0.0, 0.0, 0.0)
        # the position weights of every derivative basis are opposite: use the chord p1 − p0, not
        # the coordinates, so a short piece far from the origin keeps its digits
        chord = tuple(b - a for a, b in zip(self.points[i], self.points[i + 1], strict=True))
        m0, m1 = self.tangents[i], self.tangents[i + 1]
        if self.curvatures is None:
            out = tuple((-12 * b + 6 * h * c + 6 * h * d) / h**3 for b, c, d in zip(chord, m0, m1, strict=True))
            return (out[0], out[1], out[2])
        k0, k1 = self.curvatures[i], self.curvatures[i + 1]
        b3 = quintic_hermite_third(t)
        out = tuple(
            (b3[1] * h * c + b3[2] * h * h * e + b3[3] * h * h * f + b3[4] * h * d + b3[5] * b) / h**3
            for b, c, d, e, f in zip(chord, m0, m1, k0, k1, strict=True)
        )
        return (out[0], out[1], out[2])

    def higher(self, s: float) -> tuple[Vec3, Vec3]:
        """Fourth (linear in s) and fifth (constant) derivatives in arc length at ``s`` on the piece
        that holds ``s``; zero on cubic pieces. With :meth:`derivatives` and :meth:`third` they give
        the exact Taylor expansion of a piece; per mm³ and per mm⁴."""
        i, h, t = self._locate(s)
        if h <= 0 or self.curvatures is None:
            return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
        # positions as the chord p1 − p0 (see :meth:`third`)
        rows = [
            (0.0, h * c, h * h * e, h * h * f, h * d, b - a)
            for a, b, c, d, e, f in zip(
                self.points[i],
                self.points[i + 1],
                self.tangents[i],
                self.tangents[i + 1],
                self.curvatures[i],
                self.curvatures[i + 1],
                strict=True,
            )
        ]
        b4, b5 = quintic_hermite_higher(t)
        d4 = tuple(sum(w * x for w, x in zip(b4, row, strict=True)) / h**4 for row in rows)
        d5 = tuple(sum(w * x for w, x in zip(b5, row, strict=True)) / h**5 for row in rows)
        return (d4[0], d4[1], d4[2]), (d5[0], d5[1], d5[2])

    def reversed(self) -> Poly:
        total = self.cum[-1]
        return Poly(
            tuple(reversed(self.points)),
            tuple((-t[0], -t[1], -t[2]) for t in reversed(self.tangents)),
            tuple(total - c for c in reversed(self.cum)),
            self.label,
            None if self.curvatures is None else tuple(reversed(self.curvatures)),
        )

    def distance2(self, p: Vec2) -> float:
        best = math.inf
        for a, b in zip(self.points, self.points[1:], strict=False):
            d = (b[0] - a[0], b[1] - a[1])
            dd = d[0] * d[0] + d[1] * d[1]
            t = 0.0 if dd == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / dd))
            best = min(best, math.hypot(p[0] - a[0] - t * d[0], p[1] - a[1] - t * d[1]))
        return best

    def polyline2(self) -> list[Vec2]:
        return [(p[0], p[1]) for p in self.points]

    def sample_points(self) -> list[Vec3]:
        return list(self.points)

    def sub_s(self, s0: float, s1: float) -> Poly:
        """The piece between arc lengths s0 < s1 (resampled at the stored samples)."""
        keep = [i for i, c in enumerate(self.cum) if s0 < c < s1]
        pts = [self.point(s0)] + [self.points[i] for i in keep] + [self.point(s1)]
        tans = [_unit3(self.derivatives(s0)[1])] + [self.tangents[i] for i in keep] + [
            _unit3(self.derivatives(s1)[1])
        ]
        cum = [0.0] + [self.cum[i] - s0 for i in keep] + [s1 - s0]
        curv = None
        if self.curvatures is not None:
            curv = (self.derivatives(s0)[2], *(self.curvatures[i] for i in keep), self.derivatives(s1)[2])
        return Poly(tuple(pts), tuple(tans), tuple(cum), self.label, curv)


def _unit3(a: Vec3) -> Vec3:
    n = math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
    return (a[0] / n, a[1] / n, a[2] / n) if n > 0 else (0.0, 0.0, 0.0)



def hermite_at(arrays: tuple[Any, Any, Any, Any], s: Any, order: int = 1) -> Any:
    """Position (``order`` 0), first (1) or second derivative (2), n×3, at the arc lengths ``s`` of
    the curve given by :meth:`Poly.arrays` (``cum``, ``points``, ``tangents``, ``curvatures``):
    the quintic Hermite interpolation when the curvatures are known, else the cubic one."""
    import numpy as np

    cum = arrays[0]
    s = np.clip(np.asarray(s, dtype=float), 0.0, cum[-1])
    i = np.clip(np.searchsorted(cum, s, side="right") - 1, 0, cum.shape[0] - 2)
    return hermite_pieces(arrays, i, s, order)


def hermite_pieces(arrays: tuple[Any, Any, Any, Any], i: Any, s: Any, order: int = 1) -> Any:
    """:func:`hermite_at` with the sample interval ``i`` of every arc length ``s`` given (several
    curves concatenated into one set of arrays are evaluated together this way)."""
    import numpy as np

    cum, P, M, K = arrays
    h = cum[i + 1] - cum[i]
    hh = np.where(h > 0, h, 1.0)
    t = np.where(h > 0, (s - cum[i]) / hh, 0.0)
    p0, p1, m0, m1 = P[i], P[i + 1], M[i], M[i + 1]
    hc = h[:, None]
    if K is not None:
        basis = quintic_hermite_basis(t)[order]
        rows = (p0, hc * m0, hc * hc * K[i], hc * hc * K[i + 1], hc * m1, p1)
        out = sum(w[:, None] * r for w, r in zip(basis, rows, strict=True))
        return out / (hh**order)[:, None]
    t2, t3 = t * t, t * t * t
    if order == 0:
        h00, h10, h01, h11 = 2 * t3 - 3 * t2 + 1, t3 - 2 * t2 + t, -2 * t3 + 3 * t2, t3 - t2
    elif order == 1:
        h00, h10, h01, h11 = 6 * t2 - 6 * t, 3 * t2 - 4 * t + 1, -6 * t2 + 6 * t, 3 * t2 - 2 * t
    else:
        h00, h10, h01, h11 = 12 * t - 6, 6 * t - 4, -12 * t + 6, 6 * t - 2
    out = h00[:, None] * p0 + (h10[:, None] * hc) * m0 + h01[:, None] * p1 + (h11[:, None] * hc) * m1
    return out / (hh**order)[:, None]

def _sample(
    f: Callable[[float], Vec3],
    df: Callable[[float], Vec3],
    label: str,
    tol: float = CHORD_TOL_MM / 2,
    d2f: Callable[[float], Vec3] | None = None,
) -> Poly:
    """Adaptive sampling of a parametric curve on u ∈ [0, 1] to a chord error ≤ tol."""
    us = [0.0, 1.0]
    pts = {0.0: f(0.0), 1.0: f(1.0)}
    stack = [(0.0, 1.0, 0)]
    final: list[float] = [0.0]
    while stack:
        a, b, depth = stack.pop()
        m = 0.5 * (a + b)
        pa, pb, pm = pts[a], pts[b], f(m)
        pts[m] = pm
        chord_mid = tuple(0.5 * (x + y) for x, y in zip(pa, pb, strict=True))
        err = math.dist(chord_mid, pm)
        if not math.isfinite(err):
            raise SamplingError(f"{label}: the curve has a non-finite point at u = {m:.6g}")
        if (err > tol or depth < 3) and depth < 24:
            stack.append((m, b, depth + 1))
            stack.append((a, m, depth + 1))
        else:
            final.append(m)
            final.append(b)
        if len(pts) > MAX_CURVE_SAMPLES:
            raise SamplingError(
                f"{label}: the curve needs more than {MAX_CURVE_SAMPLES} samples to a chord error of {tol:g} mm "
                "(trcopt.geometry.poly.MAX_CURVE_SAMPLES)"
            )
    us = sorted(set(final))
    points = [pts[u] if u in pts else f(u) for u in us]
    cum = [0.0]
    if d2f is None:
        for p, q in zip(points, points[1:], strict=False):
            cum.append(cum[-1] + math.dist(p, q))  # chord length
    else:
        # true arc length (5-point Gauss-Legendre of |P′| per piece): the quintic pieces then follow
        # the arc-length parametrisation closely enough for a meaningful third derivative
        for a, b in zip(us, us[1:], strict=False):
            half, mid = 0.5 * (b - a), 0.5 * (a + b)
            piece = sum(w * _norm3(df(mid + half * x)) for x, w in _GAUSS5)
            cum.append(cum[-1] + half * piece)
    tangents = [_unit3(df(u)) for u in us]
    curvatures = None if d2f is None else tuple(_curvature_vector(df(u), d2f(u)) for u in us)
    return Poly(tuple(points), tuple(tangents), tuple(cum), label, curvatures)


_GAUSS5 = (
    (0.0, 128 / 225),
    (-math.sqrt(5 - 2 * math.sqrt(10 / 7)) / 3, (322 + 13 * math.sqrt(70)) / 900),
    (math.sqrt(5 - 2 * math.sqrt(10 / 7)) / 3, (322 + 13 * math.sqrt(70)) / 900),
    (-math.sqrt(5 + 2 * math.sqrt(10 / 7)) / 3, (322 - 13 * math.sqrt(70)) / 900),
    (math.sqrt(5 + 2 * math.sqrt(10 / 7)) / 3, (322 - 13 * math.sqrt(70)) / 900),
)


def _norm3(a: Vec3) -> float:
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


def _curvature_vector(d1: Vec3, d2: Vec3) -> Vec3:
    """d²q/ds² from the parametric derivatives: the part of P″ normal to P′, over |P′|²."""
    n2 = d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2]
    if n2 <= 0:
        return (0.0, 0.0, 0.0)
    along = (d2[0] * d1[0] + d2[1] * d1[1] + d2[2] * d1[2]) / n2
    return ((d2[0] - along * d1[0]) / n2, (d2[1] - along * d1[1]) / n2, (d2[2] - along * d1[2]) / n2)


def quintic_hermite_basis(u: Any) -> Any:
    """Quintic Hermite basis functions and their first and second derivatives at ``u`` (a float
    or a numpy array, elementwise), each a 6-tuple in the coefficient order
    (P0, D0, A0, A1, D1, P1) of :func:`hermite_curve`."""
    u2, u3, u4, u5 = u * u, u**3, u**4, u**5
    h0 = (
        1 - 10 * u3 + 15 * u4 - 6 * u5,
        u - 6 * u3 + 8 * u4 - 3 * u5,
        0.5 * u2 - 1.5 * u3 + 1.5 * u4 - 0.5 * u5,
        0.5 * u3 - u4 + 0.5 * u5,
        -4 * u3 + 7 * u4 - 3 * u5,
        10 * u3 - 15 * u4 + 6 * u5,
    )
    h1 = (
        -30 * u2 + 60 * u3 - 30 * u4,
        1 - 18 * u2 + 32 * u3 - 15 * u4,
        u - 4.5 * u2 + 6 * u3 - 2.5 * u4,
        1.5 * u2 - 4 * u3 + 2.5 * u4,
        -12 * u2 + 28 * u3 - 15 * u4,
        30 * u2 - 60 * u3 + 30 * u4,
    )
    h2 = (
        -60 * u + 180 * u2 - 120 * u3,
        -36 * u + 96 * u2 - 60 * u3,
        1 - 9 * u + 18 * u2 - 10 * u3,
        3 * u - 12 * u2 + 10 * u3,
        -24 * u + 84 * u2 - 60 * u3,
        60 * u - 180 * u2 + 120 * u3,
    )
    return h0, h1, h2


def quintic_hermite_third(u: Any) -> Any:
    """Third derivatives of the quintic Hermite basis functions (order as
    :func:`quintic_hermite_basis`)."""
    u2 = u * u
    return (
        -60 + 360 * u - 360 * u2,
        -36 + 192 * u - 180 * u2,
        -9 + 36 * u - 30 * u2,
        3 - 24 * u + 30 * u2,
        -24 + 168 * u - 180 * u2,
        60 - 360 * u + 360 * u2,
    )


def quintic_hermite_higher(u: Any) -> Any:
    """Fourth and fifth derivatives of the quintic Hermite basis functions (order as
    :func:`quintic_hermite_basis`); the fifth are constants."""
    return (
        (360 - 720 * u, 192 - 360 * u, 36 - 60 * u, -24 + 60 * u, 168 - 360 * u, -360 + 720 * u),
        (-720.0, -360.0, -60.0, 60.0, -360.0, 720.0),
    )


def hermite_curve(
    p0: Vec3, d0: Vec3, p1: Vec3, d1: Vec3, a0: Vec3 | None = None, a1: Vec3 | None = None, label: str = "hermite"
) -> Poly:
    """Cubic (no accelerations given) or quintic Hermite polynomial from p0 to p1, u ∈ [0, 1].

    ``d0``/``d1`` are derivatives dP/du at the ends; ``a0``/``a1`` second derivatives (quintic).
    """
    if a0 is None or a1 is None:

        def f(u: float) -> Vec3:
            h00, h10 = 2 * u**3 - 3 * u**2 + 1, u**3 - 2 * u**2 + u
            h01, h11 = -2 * u**3 + 3 * u**2, u**3 - u**2
            return tuple(h00 * a + h10 * b + h01 * c + h11 * d for a, b, c, d in zip(p0, d0, p1, d1, strict=True))  # type: ignore[return-value]

        def df(u: float) -> Vec3:
            g00, g10 = 6 * u**2 - 6 * u, 3 * u**2 - 4 * u + 1
            g01, g11 = -6 * u**2 + 6 * u, 3 * u**2 - 2 * u
            return tuple(g00 * a + g10 * b + g01 * c + g11 * d for a, b, c, d in zip(p0, d0, p1, d1, strict=True))  # type: ignore[return-value]

        return _sample(f, df, label)

    def combine(b: tuple[float, ...]) -> Vec3:
        return tuple(
            b[0] * P0 + b[1] * D0 + b[2] * A0 + b[3] * A1 + b[4] * D1 + b[5] * P1
            for P0, D0, A0, A1, D1, P1 in zip(p0, d0, a0, a1, d1, p1, strict=True)
        )

    def fq(u: float) -> Vec3:
        return combine(quintic_hermite_basis(u)[0])

    def dfq(u: float) -> Vec3:
        return combine(quintic_hermite_basis(u)[1])

    def d2fq(u: float) -> Vec3:
        return combine(quintic_hermite_basis(u)[2])

    return _sample(fq, dfq, label, d2f=d2fq)


def parametric_curve(
    f: Callable[[float], Vec3],
    df: Callable[[float], Vec3],
    d2f: Callable[[float], Vec3],
    label: str = "curve",
) -> Poly:
    """A twice differentiable parametric curve on u ∈ [0, 1] (value, first and second derivative) as
    a curvature-continuous Poly: samples to a chord error ≤ 0.5 µm on true arc length."""
    return _sample(f, df, label, d2f=d2f)


def conic_curve(q0: Vec2, q1: Vec2, q2: Vec2, weight: float, w: float, label: str = "conic") -> Poly:
    """Rational quadratic Bézier with control points q0, q1, q2 and middle weight ``weight``."""

    def f(u: float) -> Vec3:
        b0, b1, b2 = (1 - u) ** 2, 2 * u * (1 - u) * weight, u * u
        den = b0 + b1 + b2
        return ((b0 * q0[0] + b1 * q1[0] + b2 * q2[0]) / den, (b0 * q0[1] + b1 * q1[1] + b2 * q2[1]) / den, w)

    def df(u: float) -> Vec3:
        h = 1e-7
        a, b = f(max(0.0, u - h)), f(min(1.0, u + h))
        return (b[0] - a[0], b[1] - a[1], 0.0)

    return _sample(f, df, label)


def spiral_curve(
    center: Vec2, r0: float, r1: float, a0: float, sweep: float, w0: float, w1: float, label: str = "spiral"
) -> Poly:
    """Archimedean spiral: radius linear in angle from r0 to r1 over ``sweep``; w linear."""

    def f(u: float) -> Vec3:
        a, r = a0 + u * sweep, r0 + u * (r1 - r0)
        return (center[0] + r * math.cos(a), center[1] + r * math.sin(a), w0 + u * (w1 - w0))

    def df(u: float) -> Vec3:
        a, r = a0 + u * sweep, r0 + u * (r1 - r0)
        dr = r1 - r0
        return (
            dr * math.cos(a) - r * math.sin(a) * sweep,
            dr * math.sin(a) + r * math.cos(a) * sweep,
            w1 - w0,
        )

    return _sample(f, df, label)
