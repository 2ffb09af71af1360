"""Adaptive grids on the exact path (documented rule; spec timing.md §0.2 and §0.3b).

The error of the TOPP-RA interpolation scheme comes from (1) the switch between an acceleration
ramp and a constant-speed run falling between grid points and (2) limits that vary inside an
interval (the direction of an arc's tangent and normal). Both are controlled here:

* **ramp zones** — within one ramp length ``ℓ = F²/(2·a_min)`` of every segment end the spacing is
  ``h0 = ℓ/RAMP_POINTS`` (ramps start and end at knots or at the slowest points of a section);
  beyond that the spacing grows linearly (``GROWTH`` per mm) up to the cap below;
* **angle cap** on arcs/helices: ``Δθ ≤ DTHETA_ACC`` (0.025 rad, ~250 points per turn) where the
  arc's centripetal acceleration matters (``F² > ½·a_min·ρ``) and ``Δθ ≤ DTHETA_FEED`` (0.1 rad)
  where the feed binds; the acceleration rows of an arc interval are tightened by ``cos(Δθ/2)``
  so the per-axis acceleration inside the interval stays below the limit as well;
* **curves** (Poly): spacing ≤ ``POLY_CAP_MM``, at most ``DTHETA_ACC`` of the curve's turning
  and at most ``DKAPPA_REL`` relative change of its curvature per interval (measured at the grid
  points, halving until it holds), so a short transition's curvature peak and the steep curvature
  ramp of a G2 join into a circle are on the grid;
* **lines** need no interior points in the own solver (the exact profile on a line is the min of
  two ramps and the cruise speed, reconstructed in closed form afterwards); for toppra they get
  the ramp-zone rule with a cap of ``LINE_CAP_MM``;
* **toppra**: every knot is a grid point, and so is ``s_k − KNOT_EPS_MM`` just before it
  (toppra evaluates paths right-continuously, so without it an arc's last point would see the
  following line's zero curvature).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from trcopt.modes import TimingEngine
from trcopt.timing.path import PathArrays, SegmentEval

RAMP_POINTS = 16.0
GROWTH = 0.25
DTHETA_ACC = 0.025
DTHETA_FEED = 0.1
LINE_CAP_MM = 5.0
POLY_CAP_MM = 0.2
DKAPPA_REL = 0.02  # largest relative change of a curve's curvature across one grid interval
KNOT_EPS_MM = 1e-6

__all__ = ["segment_grid", "arc_grid", "curve_grids", "DKAPPA_REL", "KNOT_EPS_MM"]


def _graded(length: float, h0: float, zone: float, hmax: float) -> np.ndarray:
    """Points in [0, length]: spacing h0 within ``zone`` of both ends, growing to ``hmax``."""
    hmax = max(hmax, h0)
    if length <= 2.0 * h0:
        return np.array([0.0, length])
    half = 0.5 * length
    pts = [0.0]
    d = 0.0
    while True:
        h = h0 if d < zone else min(hmax, h0 + GROWTH * (d - zone))
        d += h
        if d >= half:
            break
        pts.append(d)
    left = np.array(pts)
    right = length - left[::-1]
    pts_all = np.concatenate((left, [half], right))
    # drop points closer than h0/4 to their predecessor (the two halves meet in the middle)
    keep = np.concatenate(([True], np.diff(pts_all) > 0.25 * h0))
    keep[-1] = True
    out = pts_all[keep]
    if out.shape[0] > 2 and out[-1] - out[-2] <= 0.25 * h0:
        out = np.delete(out, -2)
    return out


def segment_grid(ev: SegmentEval, feed: float, amin: float, engine: TimingEngine) -> tuple[np.ndarray, float]:
    """Local grid points (0 .. length, mm) of one segment and the arc's angular rate (rad/mm).

    Parameters
    ----------
    ev:
        The segment evaluator.
    feed:
        Path-speed limit on the segment, mm/s.
    amin:
        Smallest axis acceleration limit, mm/s².
    engine:
        ``OWN`` (lines need no interior points) or ``TOPPRA``.
    """
    length = ev.length
    ramp = feed * feed / (2.0 * amin)
    h0 = min(ramp / RAMP_POINTS, length / 4.0)
    if ev.kind == "line":
        if engine is TimingEngine.OWN:
            return np.array([0.0, length]), 0.0
        return _graded(length, h0, ramp, LINE_CAP_MM), 0.0
    if ev.kind == "arc":
        assert ev._arc is not None
        _, _, r, _, sweep, _, _ = ev._arc
        return arc_grid(length, sweep, r, feed, amin)
    grid = _curve_start_grid(ev, h0, ramp)
    floor = np.array([DKAPPA_REL * amin / max(feed, 1e-9) ** 2])
    _, grid, turn, excess = _refined(
        lambda _k, x, order: ev.eval(x, order), np.zeros(len(grid), np.int64), grid, floor
    )
    return grid, _rates(grid, turn, excess)


def arc_grid(length: float, sweep: float, r: float, feed: float, amin: float) -> tuple[np.ndarray, float]:
    """:func:`segment_grid` of an arc/helix of 3D ``length`` (mm), ``sweep`` (rad) and radius ``r`` (mm)."""
    ramp = feed * feed / (2.0 * amin)
    h0 = min(ramp / RAMP_POINTS, length / 4.0)
    rate = abs(sweep) / length  # rad per mm of 3D arc length
    rho = 1.0 / (r * rate * rate)  # radius of curvature (helix: ℓ²/R)
    dtheta = DTHETA_ACC if feed * feed > 0.5 * amin * rho else DTHETA_FEED
    n_min = max(2, math.ceil(abs(sweep) / dtheta))
    hcap = length / n_min
    grid = _graded(length, min(h0, hcap), ramp, hcap)
    return grid, rate


def curve_grids(
    arrays: PathArrays, ks: Sequence[int], feeds: np.ndarray, amin: float
) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """:func:`segment_grid` of the curves (Poly segments) ``ks`` of a path, refined together: one
    evaluation of all their grid points per refinement round instead of one per curve."""
    if not len(ks):
        return {}
    grids = []
    for k in ks:
        ev = arrays.evals[k]
        ramp = float(feeds[k]) ** 2 / (2.0 * amin)
        grids.append(_curve_start_grid(ev, min(ramp / RAMP_POINTS, ev.length / 4.0), ramp))
    seg = np.repeat(np.asarray(ks, dtype=np.int64), [len(g) for g in grids])
    floor = np.zeros(arrays.n)
    floor[list(ks)] = DKAPPA_REL * amin / np.maximum(np.asarray(feeds, float)[list(ks)], 1e-9) ** 2
    seg, s, turn, excess = _refined(arrays.eval, seg, np.concatenate(grids), floor)
    cuts = np.nonzero(seg[1:] != seg[:-1])[0] + 1
    out = {}
    for a, b in zip(np.concatenate(([0], cuts)), np.concatenate((cuts, [len(s)])), strict=True):
        grid = s[a:b]
        out[int(seg[a])] = (grid, _rates(grid, turn[a : b - 1], excess[a : b - 1]))
    return out


def _curve_start_grid(ev: SegmentEval, h0: float, ramp: float) -> np.ndarray:
    """A curve's grid before refinement: graded as a line's, at most POLY_CAP_MM and at most
    DTHETA_ACC of turning between the curve's samples apart, and the samples themselves (the
    curvature is exact there), off the ends."""
    length = ev.length
    hcap = POLY_CAP_MM
    g = ev.segment.geometry
    tangents = np.asarray(getattr(g, "tangents", ()), dtype=float)
    if tangents.shape[0] >= 2:
        cosines = np.clip(np.einsum("ij,ij->i", tangents[:-1], tangents[1:]), -1.0, 1.0)
        turn = float(np.arccos(cosines).sum())
        hcap = min(hcap, length / max(1, math.ceil(turn / DTHETA_ACC)))
    grid = _graded(length, min(h0, hcap), ramp, hcap)
    if ev._poly is not None:
        cum = ev._poly[0]
        inner = cum[(cum > 10.0 * KNOT_EPS_MM) & (cum < length - 10.0 * KNOT_EPS_MM)]
        grid = np.union1d(grid, inner)
        grid = grid[np.concatenate(([True], np.diff(grid) > 1e-7))]
        grid[-1] = length
    return grid


def _rates(grid: np.ndarray, turn: np.ndarray, excess: np.ndarray) -> np.ndarray:
    """Per interval, the tightening of the acceleration rows at its ends that keeps the limits
    inside it, written as an arc's turning rate (the own solver tightens by cos(rate·Δ/2)): the
    tangent turns by ``turn`` and the curvature exceeds its ends' by the factor ``excess`` inside."""
    cos_eff = np.cos(0.5 * turn) / excess
    return 2.0 * np.arccos(np.clip(cos_eff, -1.0, 1.0)) / np.maximum(np.diff(grid), 1e-300)


Evaluate = Callable[[np.ndarray, np.ndarray, int], np.ndarray]


def _refined(
    evaluate: Evaluate, seg: np.ndarray, s: np.ndarray, floor: np.ndarray, rounds: int = 24
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The grid points ``(seg, s)`` (curve index and local arc length, sorted by curve then s) with
    intervals halved until the curve's tangent turns by at most ``DTHETA_ACC`` across each (the
    curvature of a sharp transition peaks within a few µm, where an even spacing leaves whole
    radians between two grid points) and its curvature changes by at most ``DKAPPA_REL`` of its value
    or ``floor[curve]`` (1/mm: ``DKAPPA_REL·a/F²``, a change of the centripetal acceleration at the
    feed F of DKAPPA_REL of the acceleration limit a — near zero curvature a relative change means
    nothing); with, per
    interval (between consecutive points, also across two curves: unused there), the turn (rad) and
    the factor by which the curvature inside it may exceed the larger at its ends."""
    for round_ in range(rounds + 1):
        same = seg[1:] == seg[:-1]
        t = evaluate(seg, s, 1)
        t /= np.maximum(np.linalg.norm(t, axis=1), 1e-300)[:, None]
        turn = np.arccos(np.clip(np.einsum("ij,ij->i", t[:-1], t[1:]), -1.0, 1.0))
        k = np.linalg.norm(evaluate(seg, s, 2), axis=1)
        k_mid = np.linalg.norm(evaluate(seg[:-1], 0.5 * (s[1:] + s[:-1]), 2), axis=1)
        hi = np.maximum(np.maximum(k[:-1], k[1:]), k_mid)
        lo = np.minimum(np.minimum(k[:-1], k[1:]), k_mid)
        # where the curvature changes by more than DKAPPA_REL of its value across an interval, the
        # acceleration q″·ṡ² between two grid points is not bounded by the ends
        split = np.nonzero(
            same & ((turn > DTHETA_ACC) | (hi - lo > DKAPPA_REL * hi + floor[seg[:-1]])) & (np.diff(s) > 1e-7)
        )[0]
        if not len(split) or round_ == rounds:
            break
        s = np.insert(s, split + 1, 0.5 * (s[split] + s[split + 1]))
        seg = np.insert(seg, split + 1, seg[split])
    ends = np.maximum(np.maximum(k[:-1], k[1:]), 1e-9)
    # the midpoint's excess, and a quarter of the allowed change for a peak off the midpoint
    excess = np.minimum(np.maximum(k_mid / ends, 1.0) + 0.25 * DKAPPA_REL, 1.0 + DKAPPA_REL)
    return seg, s, turn, excess
