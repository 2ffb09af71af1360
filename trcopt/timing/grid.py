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
* **curves** (Poly): spacing ≤ ``POLY_CAP_MM`` and at most ``DTHETA_ACC`` of the curve's turning
  per interval (measured between its samples), so a short transition's curvature peak is on the grid;
* **lines** need no interior points in the own solver (the exact profile on a line is the min of
  two ramps and the cruise speed, reconstructed in closed form afterwards); for toppra they get
  the ramp-zone rule with a cap of ``LINE_CAP_MM``;
* **toppra**: every knot is a grid point, and so is ``s_k − KNOT_EPS_MM`` just before it
  (toppra evaluates paths right-continuously, so without it an arc's last point would see the
  following line's zero curvature).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from trcopt.modes import TimingEngine
from trcopt.timing.path import SegmentEval

RAMP_POINTS = 16.0
GROWTH = 0.25
DTHETA_ACC = 0.025
DTHETA_FEED = 0.1
LINE_CAP_MM = 5.0
POLY_CAP_MM = 0.2
KNOT_EPS_MM = 1e-6

__all__ = ["segment_grid", "KNOT_EPS_MM"]


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
        rate = abs(sweep) / length  # rad per mm of 3D arc length
        rho = 1.0 / (r * rate * rate)  # radius of curvature (helix: ℓ²/R)
        dtheta = DTHETA_ACC if feed * feed > 0.5 * amin * rho else DTHETA_FEED
        n_min = max(2, math.ceil(abs(sweep) / dtheta))
        hcap = length / n_min
        grid = _graded(length, min(h0, hcap), ramp, hcap)
        return grid, rate
    # a curve turns where its curvature peaks: the same angle cap as on an arc where the
    # centripetal acceleration matters, from the turning between the curve's own samples
    hcap = POLY_CAP_MM
    g = ev.segment.geometry
    tangents = np.asarray(getattr(g, "tangents", ()), dtype=float)
    if tangents.shape[0] >= 2:
        cosines = np.clip(np.einsum("ij,ij->i", tangents[:-1], tangents[1:]), -1.0, 1.0)
        turn = float(np.arccos(cosines).sum())
        hcap = min(hcap, length / max(1, math.ceil(turn / DTHETA_ACC)))
    grid = _graded(length, min(h0, hcap), ramp, hcap)
    if hasattr(g, "derivatives_at"):
        grid = _turn_refined(g, grid)
    return grid, 0.0


def _turn_refined(g: Any, grid: np.ndarray, rounds: int = 24) -> np.ndarray:
    """``grid`` with intervals halved until the curve's tangent turns by at most ``DTHETA_ACC``
    across each: the curvature of a sharp transition peaks within a few µm, where an even spacing
    leaves whole radians between two grid points."""
    for _ in range(rounds):
        t = g.derivatives_at(grid, 1)
        t /= np.maximum(np.linalg.norm(t, axis=1), 1e-300)[:, None]
        turn = np.arccos(np.clip(np.einsum("ij,ij->i", t[:-1], t[1:]), -1.0, 1.0))
        split = np.nonzero((turn > DTHETA_ACC) & (np.diff(grid) > 1e-7))[0]
        if split.shape[0] == 0:
            break
        grid = np.sort(np.concatenate((grid, 0.5 * (grid[split] + grid[split + 1]))))
    return grid
