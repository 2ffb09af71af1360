"""Tangent-continuous arc splines fitted to smooth curves (biarc approximation of a :class:`Poly`).

A controller moves along circular arcs and lines without stopping where consecutive pieces share
their tangent; a curve written as chords has a kink at every chord joint. :func:`fit_arcs`
replaces a :class:`~trcopt.geometry.poly.Poly` by a chain of arcs (lines where the curve is
straight) that stays within a tolerance of the curve and is tangent-continuous (G1) at every
joint and at both ends.

Method
------
Each span between two curve points with their unit tangents is bridged by one **biarc** (biarc
interpolation, K. M. Bolton, "Biarc curves", 1975): two arcs that meet with a common tangent at a
junction point J. The junctions of all biarcs with the given ends lie on one circle through P0 and
P1 (the *J-circle*); two points of it are used, both in closed form:

* the *incentre biarc*: for C-shaped data (the tangent lines meet at V ahead of P0 and behind P1)
  J is the incentre of the triangle P0 V P1, (|VP1|·P0 + |VP0|·P1 + |P0P1|·V) / perimeter, which
  lies on the J-circle; both arcs turn the same way, so a curve without inflection gets none;
* the *equal-tangent-length biarc* (control legs of equal length d): with chord v = P1 − P0 and
  t = T0 + T1, the control points P0 + d·T0 and P1 − d·T1 are 2d apart, which gives
  (t·t − 4)·d² − 2(v·t)·d + v·v = 0 with the positive root
  d = 2 v·v / (2 v·t + √((2 v·t)² − 4 (t·t − 4) v·v)); J is the middle of the two control points.
  It serves S-shaped data and any span where the incentre biarc misses the tolerance.

Each arc is then given by its start point, start tangent and end point (the tangent-chord angle is
half the sweep); the second is built backwards from P1, so both ends keep their tangents exactly
and the two arcs share the tangent at J because J is on the J-circle.

The spans are chosen greedily: from the current curve sample the farthest sample that one biarc
reaches within the tolerance is searched by doubling and bisection over the samples; a span
between two neighbouring samples that still fails is bisected in arc length. Every candidate is
checked two-sided (Hausdorff-style) by dense sampling: curve points (the samples and points between
them on the curve's own Hermite interpolation) against the pieces in closed form, and points on
the pieces against the densely sampled curve.

Conventions: plane coordinates (u, v, w) as everywhere in :mod:`trcopt.geometry`; a curve of
constant w gives pieces of exactly that w; a curve whose w varies gives helical pieces with w
linear along each piece (from the curve's w at the samples; at a junction in proportion to the
chords of the two arcs), and the check measures the 3D distance. A curve whose plane tangent vanishes
somewhere (a move along w) is returned as chords through its samples.
"""

from __future__ import annotations

import math

import numpy as np

from trcopt.geometry.poly import Poly, quintic_hermite_basis
from trcopt.geometry.primitives import Arc, Line
from trcopt.geometry.vec import Vec2, Vec3

__all__ = ["MIN_PIECE_MM", "SWEEP_EPS", "MAX_RADIUS_MM", "Piece", "arc_to", "biarc", "fit_arcs"]

Piece = Arc | Line

# an arc whose sweep is below this (rad) is a line: the tangent turns by less than half of it
SWEEP_EPS = 1e-9
# an arc of a larger radius (mm) is a line: its centre would be far away and its numbers unwieldy
MAX_RADIUS_MM = 1e6
# pieces shorter than this (mm) are not made: a span this short is a line
MIN_PIECE_MM = 1e-6
# curve check points per sample interval (the samples and sub − 1 points between them): at least
# _SUB_MIN, more when the chords of the check grid would deviate from the curve by more than
# _GRID_SHARE of the tolerance, at most _SUB_MAX
_SUB_MIN, _SUB_MAX = 4, 64
_GRID_SHARE = 0.02
# the fit keeps this fraction of the tolerance (the dense check samples, it does not integrate)
_MARGIN = 0.95
# bisection depth (in arc length) of a span between two samples that one biarc cannot bridge
_MAX_SPLIT = 12
_PLANE_TANGENT_MIN = 1e-6
# C-shaped data whose tangent lines meet farther than this many chords away use equal legs
_C_SHAPE_LIMIT = 1e6
# sample intervals either side of the expected nearest point in the pieces-to-curve check
_WINDOW = 2


def arc_to(p: Vec3, t: Vec2, q: Vec3) -> Piece:
    """The arc from ``p`` with unit plane tangent ``t`` through ``q`` (w linear from p to q).

    A line when the sweep is below :data:`SWEEP_EPS`, or below a half turn with a radius above
    :data:`MAX_RADIUS_MM` (a point ``q`` behind ``p`` gives an arc of nearly a full turn).
    """
    ex, ey = q[0] - p[0], q[1] - p[1]
    chord = math.hypot(ex, ey)
    sweep = 2.0 * math.atan2(t[0] * ey - t[1] * ex, t[0] * ex + t[1] * ey)
    half = abs(math.sin(0.5 * sweep))
    if abs(sweep) <= SWEEP_EPS or (abs(sweep) <= math.pi and chord >= 2.0 * MAX_RADIUS_MM * half):
        return Line(p, q)
    radius = chord / (2.0 * half)
    k = 1.0 if sweep > 0.0 else -1.0
    # the centre lies on the normal of t, to the left for a counter-clockwise arc
    center = (p[0] - k * radius * t[1], p[1] + k * radius * t[0])
    a0 = math.atan2(-k * t[0], k * t[1])
    return Arc(center, radius, a0, sweep, p[2], q[2])


def _junction(p0: Vec3, t0: Vec2, p1: Vec3, t1: Vec2, equal_legs: bool = False) -> Vec2 | None:
    """Junction point J of the biarc; None if undefined.

    C-shaped data (the tangent lines meet at V ahead of p0 and behind p1): J is the incentre of
    the triangle p0 V p1, which lies on the circle of possible junctions and gives two arcs that
    turn the same way. Otherwise (S-shaped or parallel data) the equal-tangent-length junction.
    """
    vx, vy = p1[0] - p0[0], p1[1] - p0[1]
    den = t0[0] * t1[1] - t0[1] * t1[0]
    c = math.hypot(vx, vy)
    if den != 0.0 and not equal_legs:
        lam = (vx * t1[1] - vy * t1[0]) / den  # V = p0 + lam·t0 = p1 − mu·t1
        mu = (t0[0] * vy - t0[1] * vx) / den
        if 0.0 < lam < _C_SHAPE_LIMIT * c and 0.0 < mu < _C_SHAPE_LIMIT * c:
            # incentre: the vertices weighted by the lengths of the opposite sides
            a, b = mu, lam
            return (
                (a * p0[0] + b * p1[0] + c * (p0[0] + lam * t0[0])) / (a + b + c),
                (a * p0[1] + b * p1[1] + c * (p0[1] + lam * t0[1])) / (a + b + c),
            )
    sx, sy = t0[0] + t1[0], t0[1] + t1[1]
    cc = vx * vx + vy * vy
    qa = sx * sx + sy * sy - 4.0  # = 2 (t0·t1 − 1) ≤ 0
    qb = 2.0 * (vx * sx + vy * sy)
    root = qb + math.sqrt(max(qb * qb - 4.0 * qa * cc, 0.0))
    if not root > 1e-300:
        return None  # both tangents point back along the chord: no biarc with positive legs
    d = 2.0 * cc / root
    if not math.isfinite(d):
        return None
    return (0.5 * (p0[0] + p1[0] + d * (t0[0] - t1[0])), 0.5 * (p0[1] + p1[1] + d * (t0[1] - t1[1])))


def biarc(p0: Vec3, t0: Vec2, p1: Vec3, t1: Vec2, equal_legs: bool = False) -> list[Piece] | None:
    """The biarc from ``p0`` (unit plane tangent ``t0``) to ``p1`` (``t1``).

    Parameters
    ----------
    p0, p1:
        End points (u, v, w), mm; w at the junction in proportion to the chords of the two arcs.
    t0, t1:
        Unit plane tangents at the ends (direction of travel).
    equal_legs:
        Always the equal-tangent-length junction; by default the incentre junction for C-shaped
        data and the equal-tangent-length one otherwise (see the module notes).

    Returns
    -------
    list of Arc or Line, or None
        One line (a straight span), or two pieces meeting at the junction with a common tangent;
        None when the biarc is undefined or degenerate (a piece shorter than
        :data:`MIN_PIECE_MM`, or an arc over more than a half turn).
    """
    if math.hypot(p1[0] - p0[0], p1[1] - p0[1]) < MIN_PIECE_MM:
        return None
    junction = _junction(p0, t0, p1, t1, equal_legs)
    if junction is None:
        return None
    ju, jv = junction
    l0 = math.hypot(ju - p0[0], jv - p0[1])
    l1 = math.hypot(p1[0] - ju, p1[1] - jv)
    if l0 < MIN_PIECE_MM or l1 < MIN_PIECE_MM:
        return None
    jw = p0[2] + (p1[2] - p0[2]) * (l0 / (l0 + l1)) if p1[2] != p0[2] else p0[2]
    j = (ju, jv, jw)
    first = arc_to(p0, t0, j)
    # the second arc is built backwards from p1 so that both ends meet the given tangents exactly
    second = arc_to(p1, (-t1[0], -t1[1]), j).reversed()
    if isinstance(first, Line) and isinstance(second, Line):
        return [Line(p0, p1)]
    for piece in (first, second):
        if isinstance(piece, Arc) and abs(piece.sweep) > math.pi:
            return None
    return [first, second]


# --------------------------------------------------------------------------------------------
# the curve as arrays: vectorised evaluation of its Hermite pieces
# --------------------------------------------------------------------------------------------


class _Curve:
    """Samples of a Poly as arrays, with the dense check grid (``sub`` points per interval)."""

    def __init__(self, poly: Poly, tolerance: float) -> None:
        self.p = np.asarray(poly.points, dtype=float)
        self.m = np.asarray(poly.tangents, dtype=float)
        self.k = None if poly.curvatures is None else np.asarray(poly.curvatures, dtype=float)
        self.cum = np.asarray(poly.cum, dtype=float)
        self.h = np.diff(self.cum)
        sub = _SUB_MIN
        dense = self._grid(sub)
        # chord error of each sample interval (at its middle, a point of the grid); a chord of
        # 1/sub of the interval deviates about 1/sub² of it
        sag = float(np.max(np.linalg.norm(dense[sub // 2 :: sub] - 0.5 * (self.p[:-1] + self.p[1:]), axis=1)))
        need = math.ceil(math.sqrt(sag / (_GRID_SHARE * tolerance))) if sag > 0.0 else 0
        if need > sub:
            sub = min(_SUB_MAX, need)
            dense = self._grid(sub)
        self.sub = sub
        self.offsets = np.arange(-_WINDOW * sub, _WINDOW * sub)
        self.dense = dense
        self.dense_cum = _plane_cum(dense)

    def _grid(self, sub: int) -> np.ndarray:
        """The samples and ``sub`` − 1 curve points between each two (even ``sub``: the middle
        of an interval is the point sub/2 after its start)."""
        n = len(self.cum)
        idx = np.repeat(np.arange(n - 1), sub)
        t = np.tile(np.arange(sub) / sub, n - 1)
        return np.vstack([self.eval(idx, t, derivative=False)[0], self.p[-1:]])

    def eval(self, idx: np.ndarray, t: np.ndarray, derivative: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
        """Points and (``derivative``) first derivatives per mm of arc length at parameter t of
        the pieces idx: the Poly's own cubic or quintic Hermite interpolation."""
        p0, p1 = self.p[idx], self.p[idx + 1]
        h = self.h[idx][:, None]
        m0, m1 = self.m[idx] * h, self.m[idx + 1] * h
        u = t[:, None]
        u2 = u * u
        u3 = u2 * u
        der: np.ndarray | None = None
        if self.k is not None:
            u4 = u3 * u
            u5 = u4 * u
            a0, a1 = self.k[idx] * (h * h), self.k[idx + 1] * (h * h)
            pts = (
                (1 - 10 * u3 + 15 * u4 - 6 * u5) * p0
                + (u - 6 * u3 + 8 * u4 - 3 * u5) * m0
                + (0.5 * u2 - 1.5 * u3 + 1.5 * u4 - 0.5 * u5) * a0
                + (0.5 * u3 - u4 + 0.5 * u5) * a1
                + (-4 * u3 + 7 * u4 - 3 * u5) * m1
                + (10 * u3 - 15 * u4 + 6 * u5) * p1
            )
            if derivative:
                _, b1, _ = quintic_hermite_basis(u)
                rows = (p0, m0, a0, a1, m1, p1)
                der = sum(w * r for w, r in zip(b1, rows, strict=True)) / np.where(h > 0.0, h, 1.0)
            return pts, der
        pts = (2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * m0 + (3 * u2 - 2 * u3) * p1 + (u3 - u2) * m1
        if derivative:
            der = ((6 * u2 - 6 * u) * (p0 - p1) + (3 * u2 - 4 * u + 1) * m0 + (3 * u2 - 2 * u) * m1) / np.where(
                h > 0.0, h, 1.0
            )
        return pts, der

    def at(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Points and unit plane tangents at arc lengths ``s``."""
        idx = np.clip(np.searchsorted(self.cum, s, side="right") - 1, 0, len(self.cum) - 2)
        h = self.h[idx]
        t = np.where(h > 0.0, (s - self.cum[idx]) / np.where(h > 0.0, h, 1.0), 0.0)
        pts, der = self.eval(idx, t)
        assert der is not None
        tan = der[:, :2] / np.maximum(np.hypot(der[:, 0], der[:, 1]), 1e-300)[:, None]
        return pts, tan


# --------------------------------------------------------------------------------------------
# two-sided deviation check
# --------------------------------------------------------------------------------------------


def _distance2_to_piece(piece: Piece, q: np.ndarray) -> np.ndarray:
    """Squared distance of points ``q`` (k, 3) to a piece: exact in the plane; with w, an upper
    bound (the w difference at the plane-nearest point of the piece)."""
    if isinstance(piece, Line):
        (au, av, aw), (bu, bv, bw) = piece.start, piece.end
        eu, ev, ew = bu - au, bv - av, bw - aw
        ab2 = eu * eu + ev * ev
        if ab2 > 0.0:
            lam = np.clip(((q[:, 0] - au) * eu + (q[:, 1] - av) * ev) / ab2, 0.0, 1.0)
        else:
            lam = np.zeros(len(q))
        return (q[:, 0] - au - lam * eu) ** 2 + (q[:, 1] - av - lam * ev) ** 2 + (q[:, 2] - aw - lam * ew) ** 2
    cu, cv = piece.center
    r, a0, sweep, w0, w1 = piece.radius, piece.a0, piece.sweep, piece.w0, piece.w1
    du, dv = q[:, 0] - cu, q[:, 1] - cv
    span = abs(sweep)
    phi = np.mod((np.arctan2(dv, du) - a0) * (1.0 if sweep > 0.0 else -1.0), 2.0 * math.pi)
    inside = phi <= span
    radial = (np.sqrt(du * du + dv * dv) - r) ** 2 + (q[:, 2] - w0 - (phi / span) * (w1 - w0)) ** 2
    a1 = a0 + sweep
    ends = np.minimum(
        (du - r * math.cos(a0)) ** 2 + (dv - r * math.sin(a0)) ** 2 + (q[:, 2] - w0) ** 2,
        (du - r * math.cos(a1)) ** 2 + (dv - r * math.sin(a1)) ** 2 + (q[:, 2] - w1) ** 2,
    )
    return np.where(inside, np.minimum(radial, ends), ends)


_LAMS: dict[int, np.ndarray] = {}


def _unit_steps(count: int) -> np.ndarray:
    lam = _LAMS.get(count)
    if lam is None:
        lam = _LAMS[count] = np.linspace(0.0, 1.0, count)
    return lam


def _piece_points(piece: Piece, count: int) -> np.ndarray:
    lam = _unit_steps(count)
    if isinstance(piece, Line):
        a, b = np.asarray(piece.start), np.asarray(piece.end)
        return a[None, :] + lam[:, None] * (b - a)[None, :]
    ang = piece.a0 + lam * piece.sweep
    out = np.empty((count, 3))
    out[:, 0] = piece.center[0] + piece.radius * np.cos(ang)
    out[:, 1] = piece.center[1] + piece.radius * np.sin(ang)
    out[:, 2] = piece.w0 + lam * (piece.w1 - piece.w0)
    return out


def _distance2_to_polyline(x: np.ndarray, c: np.ndarray, where: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """Squared distance of each point of ``x`` (m, 3) to the polyline ``c`` (k, 3), looked for
    among the segments ``where`` (m,) + ``offsets`` (w,) of each point: an upper bound of the
    distance to the whole polyline, equal to it when the nearest segment is in the window."""
    seg = np.clip(where[:, None] + offsets[None, :], 0, len(c) - 2)  # (m, w) segment indices
    a = c[seg]
    ab = c[seg + 1] - a
    ab2 = np.einsum("mwi,mwi->mw", ab, ab)
    ap = x[:, None, :] - a
    lam = np.clip(np.einsum("mwi,mwi->mw", ap, ab) / np.where(ab2 > 0.0, ab2, 1.0), 0.0, 1.0)
    off = ap - lam[:, :, None] * ab
    return np.einsum("mwi,mwi->mw", off, off).min(axis=1)


def _plane_cum(curve: np.ndarray) -> np.ndarray:
    """Cumulative plane length along a point sequence."""
    out = np.zeros(len(curve))
    np.cumsum(np.hypot(np.diff(curve[:, 0]), np.diff(curve[:, 1])), out=out[1:])
    return out


def _within(
    pieces: list[Piece], curve: np.ndarray, limit: float, offsets: np.ndarray, cum: np.ndarray | None = None
) -> bool:
    """Both one-sided distances (curve → pieces, pieces → curve) at most ``limit``.

    ``cum`` is the cumulative plane length along ``curve`` (computed when not given). A point of
    the pieces at the fraction f of their plane length is measured against the curve near the
    fraction f of the curve's plane length (both follow the same path): a window that misses the
    nearest segment only overestimates the distance, so the check stays conservative.
    """
    limit2 = limit * limit
    dist2 = _distance2_to_piece(pieces[0], curve)
    for piece in pieces[1:]:
        dist2 = np.minimum(dist2, _distance2_to_piece(piece, curve))
    if float(dist2.max()) > limit2:
        return False
    if cum is None:
        cum = _plane_cum(curve)
    count = max(5, min(48, len(curve) // len(pieces) + 2))
    lengths = [p.plane_length for p in pieces]
    total = sum(lengths)
    pts = np.vstack([_piece_points(p, count) for p in pieces])
    along = np.concatenate([start + _unit_steps(count) * length for start, length in zip(
        np.cumsum([0.0, *lengths[:-1]]), lengths, strict=True)])
    scale = (cum[-1] - cum[0]) / total if total > 0.0 else 0.0
    where = np.searchsorted(cum, cum[0] + along * scale)
    return float(_distance2_to_polyline(pts, curve, where, offsets).max()) <= limit2


# --------------------------------------------------------------------------------------------
# the fit
# --------------------------------------------------------------------------------------------


def _chords(poly: Poly) -> list[Piece]:
    return [Line(a, b) for a, b in zip(poly.points, poly.points[1:], strict=False) if a != b]


def fit_arcs(curve: Poly, tolerance: float) -> list[Piece]:
    """A tangent-continuous chain of arcs and lines within ``tolerance`` of ``curve``.

    Parameters
    ----------
    curve:
        The smooth curve in plane coordinates (u, v, w).
    tolerance:
        Largest distance (mm) between the chain and the curve, both ways (every point of the
        chain near the curve and every point of the curve near the chain); > 0.

    Returns
    -------
    list of Arc or Line
        Pieces in the direction of travel from ``curve.start`` to ``curve.end``; consecutive pieces
        meet with a common plane tangent, the first starts with the curve's start tangent and the
        last ends with its end tangent. Arcs turn by at most a half turn each. A curve shorter in
        the plane than :data:`MIN_PIECE_MM` is one line; a curve whose plane tangent vanishes
        somewhere is returned as chords through its samples.
    """
    if not (tolerance > 0.0 and math.isfinite(tolerance)):
        raise ValueError(f"the fit tolerance must be a positive finite length in mm, got {tolerance!r}")
    if len(curve.points) < 2:
        return []
    if curve.plane_length < MIN_PIECE_MM:
        return [Line(curve.start, curve.end)]
    tan3 = np.asarray(curve.tangents, dtype=float)
    norms = np.hypot(tan3[:, 0], tan3[:, 1])
    if float(norms.min()) < _PLANE_TANGENT_MIN:
        return _chords(curve)
    limit = _MARGIN * tolerance
    c = _Curve(curve, limit)
    sub = c.sub
    tans = tan3[:, :2] / norms[:, None]
    const_w = bool(np.all(c.p[:, 2] == c.p[0, 2]))
    n = len(c.cum)
    pts: list[Vec3] = [(float(p[0]), float(p[1]), float(p[2])) for p in c.p]
    tan2: list[Vec2] = [(float(t[0]), float(t[1])) for t in tans]

    def attempt(i: int, j: int) -> list[Piece] | None:
        lo, hi = i * sub, j * sub + 1
        return _fitting_biarc(pts[i], tan2[i], pts[j], tan2[j], c.dense[lo:hi], limit, c.offsets, c.dense_cum[lo:hi])

    out: list[Piece] = []
    i, guess = 0, n - 1
    while i < n - 1:
        lo, hi = i, n  # lo: farthest sample known to be reached (or i), hi: first known miss
        best: list[Piece] | None = None
        j = min(n - 1, i + guess)
        while True:
            found = attempt(i, j)
            if found is not None:
                lo, best = j, found
            else:
                hi = j
            if hi - lo <= 1:
                break
            j = min(n - 1, i + 2 * (lo - i)) if hi == n else (lo + hi) // 2
        if best is None:
            lo = i + 1
            best = _split_span(c, float(c.cum[i]), float(c.cum[lo]), pts[i], tan2[i], pts[lo], tan2[lo], limit, 0)
        out.extend(best)
        guess = max(1, lo - i)
        i = lo
    if const_w:
        w = float(c.p[0, 2])
        out = [p.with_w(w, w) for p in out]
    return out


def _fitting_biarc(
    p0: Vec3,
    t0: Vec2,
    p1: Vec3,
    t1: Vec2,
    curve: np.ndarray,
    limit: float,
    offsets: np.ndarray,
    cum: np.ndarray | None = None,
) -> list[Piece] | None:
    """The biarc (incentre junction, else equal legs) within ``limit`` of ``curve``, or None."""
    for equal_legs in (False, True):
        pieces = biarc(p0, t0, p1, t1, equal_legs)
        if pieces is not None and _within(pieces, curve, limit, offsets, cum):
            return pieces
    return None


def _split_span(
    c: _Curve, s0: float, s1: float, p0: Vec3, t0: Vec2, p1: Vec3, t1: Vec2, limit: float, depth: int
) -> list[Piece]:
    """Biarcs for the curve between arc lengths s0 and s1 (ends given), bisected until they fit."""
    s = np.linspace(s0, s1, 2 * c.sub + 1)
    curve, _ = c.at(s)
    curve[0], curve[-1] = p0, p1
    found = _fitting_biarc(p0, t0, p1, t1, curve, limit, c.offsets)
    if found is not None:
        return found
    if depth >= _MAX_SPLIT or math.hypot(p1[0] - p0[0], p1[1] - p0[1]) < 2.0 * MIN_PIECE_MM:
        # nothing shorter can be made (a span 4096 times shorter than the samples' spacing, or
        # shorter than two pieces): the biarc as it is, or a line where there is none
        return biarc(p0, t0, p1, t1) or [Line(p0, p1)]
    mid_pt, mid_tan = c.at(np.array([0.5 * (s0 + s1)]))
    pm: Vec3 = (float(mid_pt[0, 0]), float(mid_pt[0, 1]), float(mid_pt[0, 2]))
    tm: Vec2 = (float(mid_tan[0, 0]), float(mid_tan[0, 1]))
    sm = 0.5 * (s0 + s1)
    return _split_span(c, s0, sm, p0, t0, pm, tm, limit, depth + 1) + _split_span(
        c, sm, s1, pm, tm, p1, t1, limit, depth + 1
    )
