"""Arc-spline (biarc) fit of smooth curves: tolerance both ways, tangent continuity, few pieces."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

from trcopt.geometry.arcfit import MAX_RADIUS_MM, arc_to, biarc, fit_arcs
from trcopt.geometry.poly import Poly, conic_curve, hermite_curve, spiral_curve
from trcopt.geometry.primitives import Arc, Line

TOL = 0.001


# --------------------------------------------------------------------------------------------
# an independent two-sided deviation: fine polylines of the curve (Poly.point) and of the pieces
# (their own fields), distances point → polyline through the nearest vertex and its two segments
# --------------------------------------------------------------------------------------------


def curve_polyline(poly: Poly, per: int = 12) -> np.ndarray:
    s = [x for a, b in zip(poly.cum, poly.cum[1:], strict=False) for x in np.linspace(a, b, per, endpoint=False)]
    return np.array([poly.point(x) for x in [*s, poly.cum[-1]]])


def piece_polyline(piece: Arc | Line) -> np.ndarray:
    if isinstance(piece, Line):
        lam = np.linspace(0.0, 1.0, max(2, math.ceil(piece.length / 0.002) + 1))
        a, b = np.array(piece.start), np.array(piece.end)
        return a + lam[:, None] * (b - a)
    # chord error r·δ²/8 ≤ 1e-8 mm, and points at most 2 µm apart
    step = min(math.sqrt(8e-8 / piece.radius), 0.002 / piece.radius)
    lam = np.linspace(0.0, 1.0, max(2, math.ceil(abs(piece.sweep) / step) + 1))
    ang = piece.a0 + lam * piece.sweep
    return np.column_stack(
        (
            piece.center[0] + piece.radius * np.cos(ang),
            piece.center[1] + piece.radius * np.sin(ang),
            piece.w0 + lam * (piece.w1 - piece.w0),
        )
    )


def to_polyline(x: np.ndarray, c: np.ndarray) -> float:
    """Largest distance of the points x to the polyline c."""
    _, i = cKDTree(c).query(x)
    best = np.full(len(x), np.inf)
    for a_idx in (np.clip(i - 1, 0, len(c) - 2), np.clip(i, 0, len(c) - 2)):
        a, b = c[a_idx], c[a_idx + 1]
        ab = b - a
        ab2 = np.maximum(np.sum(ab * ab, axis=1), 1e-300)
        lam = np.clip(np.sum((x - a) * ab, axis=1) / ab2, 0.0, 1.0)
        best = np.minimum(best, np.linalg.norm(x - a - lam[:, None] * ab, axis=1))
    return float(best.max())


def deviation(poly: Poly, pieces: list, per: int = 12) -> tuple[float, float]:
    """(curve → pieces, pieces → curve), mm; ``per`` polyline points per sample interval."""
    cp = curve_polyline(poly, per)
    # consecutive pieces share their joint: one vertex for it (a doubled vertex would hide a segment)
    chain = np.vstack([piece_polyline(p)[(0 if k == 0 else 1) :] for k, p in enumerate(pieces)])
    return to_polyline(cp, chain), to_polyline(chain, cp)


def turn(a: tuple[float, float], b: tuple[float, float]) -> float:
    return abs(math.atan2(a[0] * b[1] - a[1] * b[0], a[0] * b[0] + a[1] * b[1]))


def assert_g1_chain(poly: Poly, pieces: list, tol: float = TOL, per: int = 12) -> None:
    assert pieces, "no pieces"
    joints = [turn(a.end_tangent(), b.start_tangent()) for a, b in zip(pieces, pieces[1:], strict=False)]
    gaps = [math.dist(a.end, b.start) for a, b in zip(pieces, pieces[1:], strict=False)]
    assert max(joints, default=0.0) < 1e-9
    assert max(gaps, default=0.0) < 1e-9
    assert turn(pieces[0].start_tangent(), poly.start_tangent()) < 1e-9
    assert turn(pieces[-1].end_tangent(), poly.end_tangent()) < 1e-9
    assert math.dist(pieces[0].start, poly.start) < 1e-9 and math.dist(pieces[-1].end, poly.end) < 1e-9
    d_curve, d_pieces = deviation(poly, pieces, per)
    assert d_curve <= tol and d_pieces <= tol, (d_curve, d_pieces)
    assert all(abs(p.sweep) <= math.pi + 1e-12 for p in pieces if isinstance(p, Arc))


def random_cubic(seed: int) -> Poly:
    rng = np.random.default_rng(seed)
    p1 = (*rng.uniform(-10.0, 10.0, 2), 0.0)
    d0 = (*rng.uniform(-20.0, 20.0, 2), 0.0)
    d1 = (*rng.uniform(-20.0, 20.0, 2), 0.0)
    start = (*rng.uniform(-500.0, 500.0, 2), -3.0)
    return hermite_curve(start, d0, tuple(s + p for s, p in zip(start, p1, strict=True)), d1)


def quintic_corner(angle_deg: float, leg: float, w: float = 0.0) -> Poly:
    """G2 transition of a corner turning by ``angle_deg``: zero curvature at both ends."""
    th = math.radians(angle_deg)
    u0, u1 = (1.0, 0.0, 0.0), (math.cos(th), math.sin(th), 0.0)
    p0 = (-leg, 0.0, w)
    p1 = (leg * u1[0], leg * u1[1], w)
    d = 1.5 * leg
    return hermite_curve(
        p0, tuple(d * c for c in u0), p1, tuple(d * c for c in u1), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), "corner"
    )


# --------------------------------------------------------------------------------------------
# the fit
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("seed", range(10))
def test_random_cubic_curves_within_tolerance_g1_and_few_pieces(seed: int) -> None:
    poly = random_cubic(seed)
    pieces = fit_arcs(poly, TOL)
    assert_g1_chain(poly, pieces)
    assert len(pieces) * 5 <= len(poly.points), (len(pieces), len(poly.points))
    # constant w is kept exactly
    assert all(p.start[2] == -3.0 and p.end[2] == -3.0 for p in pieces)


@pytest.mark.parametrize("angle", [10.0, 45.0, 90.0, 135.0, -60.0, -170.0])
@pytest.mark.parametrize("leg", [0.05, 0.5, 3.0])
def test_quintic_corner_transitions(angle: float, leg: float) -> None:
    poly = quintic_corner(angle, leg, w=-2.5)
    assert poly.curvatures is not None  # the quintic (curvature-continuous) interpolation
    pieces = fit_arcs(poly, TOL)
    assert_g1_chain(poly, pieces)
    # the smallest curves have 17 samples (the sampler's minimum); a hairpin needs 3 biarcs
    assert len(pieces) <= max(6, len(poly.points) // 4), (len(pieces), len(poly.points))
    # a left turn is all G3, a right turn all G2 (the transition has no inflection)
    senses = {p.sense for p in pieces if isinstance(p, Arc)}
    assert senses == {1 if angle > 0 else -1}


def test_coarser_tolerance_needs_fewer_pieces_and_uses_it() -> None:
    poly = hermite_curve((0.0, 0.0, 0.0), (40.0, 0.0, 0.0), (10.0, 10.0, 0.0), (0.0, 40.0, 0.0))
    fine, coarse = fit_arcs(poly, 0.001), fit_arcs(poly, 0.05)
    assert_g1_chain(poly, coarse, 0.05)
    assert len(coarse) < len(fine) / 2
    # the coarse fit is not needlessly exact: it uses a good part of its tolerance
    assert max(deviation(poly, coarse)) > 0.01


def test_conic_and_s_curve() -> None:
    conic = conic_curve((0.0, 0.0), (10.0, 0.0), (10.0, 10.0), 0.7, 0.5)
    assert_g1_chain(conic, fit_arcs(conic, TOL))
    s_curve = hermite_curve((0.0, 0.0, 1.0), (10.0, 0.0, 0.0), (10.0, 3.0, 1.0), (10.0, 0.0, 0.0))
    pieces = fit_arcs(s_curve, TOL)
    assert_g1_chain(s_curve, pieces)
    # an inflection: both senses
    assert {p.sense for p in pieces if isinstance(p, Arc)} == {1, -1}


def test_straight_curve_is_one_line() -> None:
    poly = hermite_curve((1.0, 2.0, 3.0), (10.0, 5.0, 0.0), (11.0, 7.0, 3.0), (10.0, 5.0, 0.0))
    assert len(poly.points) > 2
    pieces = fit_arcs(poly, TOL)
    assert pieces == [Line(poly.start, poly.end)]


def test_helical_curve_gives_helical_arcs_within_tolerance_in_3d() -> None:
    poly = spiral_curve((0.0, 0.0), 5.0, 8.0, 0.3, 4.0, 0.0, -3.0)
    pieces = fit_arcs(poly, TOL)
    assert_g1_chain(poly, pieces)
    assert all(isinstance(p, Arc) and p.w1 < p.w0 for p in pieces)  # descending helices
    assert pieces[0].w0 == 0.0 and pieces[-1].w1 == -3.0
    assert len(pieces) * 8 <= len(poly.points)


def test_curve_with_a_vertical_tangent_falls_back_to_chords() -> None:
    poly = Poly(
        ((0.0, 0.0, 0.0), (0.0, 0.0, -1.0), (1.0, 0.0, -1.0)),
        ((0.0, 0.0, -1.0), (math.sqrt(0.5), 0.0, -math.sqrt(0.5)), (1.0, 0.0, 0.0)),
        (0.0, 1.0, 2.0),
    )
    assert fit_arcs(poly, TOL) == [Line(poly.points[0], poly.points[1]), Line(poly.points[1], poly.points[2])]


def test_tiny_curve() -> None:
    poly = hermite_curve((0.0, 0.0, 0.0), (0.001, 0.0, 0.0), (0.001, 0.001, 0.0), (0.0, 0.001, 0.0))
    assert_g1_chain(poly, fit_arcs(poly, TOL))
    dot = Poly(((1.0, 1.0, 0.0), (1.0 + 1e-8, 1.0, 0.0)), ((1.0, 0.0, 0.0), (1.0, 0.0, 0.0)), (0.0, 1e-8))
    assert fit_arcs(dot, TOL) == [Line(dot.start, dot.end)]


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf])
def test_invalid_tolerance(bad: float) -> None:
    with pytest.raises(ValueError, match="tolerance"):
        fit_arcs(quintic_corner(90.0, 1.0), bad)


# --------------------------------------------------------------------------------------------
# the biarc construction
# --------------------------------------------------------------------------------------------


def test_biarc_reproduces_a_circle() -> None:
    # two points of a circle with its tangents: both arcs lie on that circle
    r, c = 7.0, (3.0, -2.0)
    a0, a1 = 0.2, 1.9
    p0 = (c[0] + r * math.cos(a0), c[1] + r * math.sin(a0), 0.0)
    p1 = (c[0] + r * math.cos(a1), c[1] + r * math.sin(a1), 0.0)
    pieces = biarc(p0, (-math.sin(a0), math.cos(a0)), p1, (-math.sin(a1), math.cos(a1)))
    assert pieces is not None and len(pieces) == 2
    for p in pieces:
        assert isinstance(p, Arc) and p.radius == pytest.approx(r, abs=1e-9)
        assert math.dist(p.center, c) < 1e-9
    assert sum(p.sweep for p in pieces) == pytest.approx(a1 - a0, abs=1e-12)


def test_equal_tangent_length_biarc() -> None:
    p0, t0 = (0.0, 0.0, 0.0), (1.0, 0.0)
    p1, t1 = (4.0, 3.0, 0.0), (0.0, 1.0)
    first, second = biarc(p0, t0, p1, t1, equal_legs=True)  # type: ignore[misc]
    assert turn(first.end_tangent(), second.start_tangent()) < 1e-12
    assert turn(first.start_tangent(), t0) < 1e-12 and turn(second.end_tangent(), t1) < 1e-12
    assert math.dist(first.end, second.start) < 1e-12
    # the junction is the middle of the control points p0 + d·t0 and p1 − d·t1, which are 2d apart
    vx, vy = p1[0] - p0[0], p1[1] - p0[1]
    sx, sy = t0[0] + t1[0], t0[1] + t1[1]
    roots = np.roots([sx * sx + sy * sy - 4.0, -2.0 * (vx * sx + vy * sy), vx * vx + vy * vy])
    leg = float(max(roots.real))
    q0 = (p0[0] + leg * t0[0], p0[1] + leg * t0[1])
    q1 = (p1[0] - leg * t1[0], p1[1] - leg * t1[1])
    assert math.dist(q0, q1) == pytest.approx(2 * leg)
    assert math.dist(first.end[:2], ((q0[0] + q1[0]) / 2, (q0[1] + q1[1]) / 2)) < 1e-12


def test_incentre_biarc_of_c_shaped_data() -> None:
    # the tangent lines meet at V = (6, 0): the junction is the incentre of p0 V p1 and both arcs
    # turn left, where the equal-leg biarc of the same data has an inflection
    p0, t0 = (0.0, 0.0, 1.0), (1.0, 0.0)
    p1, t1 = (6.0, 1.0, 1.0), (0.0, 1.0)
    first, second = biarc(p0, t0, p1, t1)  # type: ignore[misc]
    a, b, c = 1.0, 6.0, math.hypot(6.0, 1.0)  # sides opposite p0, p1 and V
    incentre = ((a * 0.0 + b * 6.0 + c * 6.0) / (a + b + c), (a * 0.0 + b * 1.0 + c * 0.0) / (a + b + c))
    assert math.dist(first.end[:2], incentre) < 1e-12
    assert turn(first.end_tangent(), second.start_tangent()) < 1e-12
    assert isinstance(first, Arc) and isinstance(second, Arc) and first.sweep > 0.0 and second.sweep > 0.0
    assert first.w0 == first.w1 == second.w1 == 1.0
    legs = biarc(p0, t0, p1, t1, equal_legs=True)
    assert legs is not None and {p.sense for p in legs if isinstance(p, Arc)} == {1, -1}


def test_biarc_degenerate_cases() -> None:
    # collinear: one line
    assert biarc((0.0, 0.0, 0.0), (1.0, 0.0), (5.0, 0.0, 0.0), (1.0, 0.0)) == [Line((0.0, 0.0, 0.0), (5.0, 0.0, 0.0))]
    # both tangents back along the chord: undefined
    assert biarc((0.0, 0.0, 0.0), (-1.0, 0.0), (5.0, 0.0, 0.0), (-1.0, 0.0)) is None
    # shorter than the smallest piece
    assert biarc((0.0, 0.0, 0.0), (1.0, 0.0), (1e-7, 0.0, 0.0), (0.0, 1.0)) is None


def test_arc_to_lines_and_arcs() -> None:
    assert arc_to((0.0, 0.0, 0.0), (1.0, 0.0), (3.0, 0.0, 1.0)) == Line((0.0, 0.0, 0.0), (3.0, 0.0, 1.0))
    # an almost straight arc with a radius over MAX_RADIUS_MM is a line
    far = arc_to((0.0, 0.0, 0.0), (1.0, 0.0), (1.0, 1.0 / (2.0 * MAX_RADIUS_MM) * 0.5, 0.0))
    assert isinstance(far, Line)
    quarter = arc_to((1.0, 0.0, 0.0), (0.0, 1.0), (0.0, 1.0, 2.0))
    assert isinstance(quarter, Arc)
    assert quarter.radius == pytest.approx(1.0) and quarter.sweep == pytest.approx(math.pi / 2)
    assert math.dist(quarter.center, (0.0, 0.0)) < 1e-12 and (quarter.w0, quarter.w1) == (0.0, 2.0)
    cw = arc_to((1.0, 0.0, 0.0), (0.0, -1.0), (0.0, -1.0, 0.0))
    assert isinstance(cw, Arc) and cw.sweep == pytest.approx(-math.pi / 2)


def test_coarse_samples_are_bisected_between_samples() -> None:
    # two samples only (a half turn as one quintic Hermite piece): no single biarc fits, so the
    # span between the samples is bisected in arc length
    poly = Poly(
        ((1.0, 0.0, 0.0), (-1.0, 0.0, 0.0)),
        ((0.0, 1.0, 0.0), (0.0, -1.0, 0.0)),
        (0.0, math.pi),
        "half turn",
        ((-1.0, 0.0, 0.0), (1.0, 0.0, 0.0)),
    )
    pieces = fit_arcs(poly, 1e-4)
    assert len(pieces) > 2
    assert_g1_chain(poly, pieces, 1e-4, per=20_000)


def test_tight_tolerance() -> None:
    poly = quintic_corner(90.0, 2.0)
    pieces = fit_arcs(poly, 1e-5)
    # the check polyline must be much finer than the tolerance here
    assert max(deviation(poly, pieces, per=60)) <= 1e-5
    assert len(fit_arcs(poly, 1e-3)) < len(pieces) < len(poly.points) / 2
