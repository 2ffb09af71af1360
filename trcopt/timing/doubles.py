"""Closed-form jerk-limited ("double-S") rest-to-rest motion on a straight line (spec timing.md §4.2).

Reference for the jerk-limited feed (:mod:`trcopt.timing.jerk`): on a line the time-optimal
rest-to-rest motion under path limits ``v``, ``a``, ``J`` is the symmetric double-S profile, and on a
polyline with sharp corners (speed 0 at every corner) the optimum is the sum of these times.
Per-axis box limits project onto a line of unit direction ``t`` as ``v = min(F, min_i vmax_i/|t_i|)``,
``a = min_i amax_i/|t_i|``, ``J = min_i jmax_i/|t_i|``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from trcopt.config import Machine

__all__ = ["double_s_time", "double_s_phases", "line_limits", "double_s_line_time", "double_s_polyline_time"]


def double_s_time(length: float, v: float, a: float, j: float) -> float:
    """Time-optimal rest-to-rest duration (s) over ``length`` mm under v (mm/s), a (mm/s²), J (mm/s³).

    ``Ta = v/a + a/J`` if ``vJ ≥ a²`` else ``2·sqrt(v/J)``; if ``L ≥ v·Ta`` then ``T = L/v + Ta``,
    otherwise the peak speed ``vp`` solves ``vp·Ta(vp) = L`` and ``T = 2·Ta(vp)``: the sum of the
    phases of :func:`double_s_phases`.
    """
    if length <= 0:
        return 0.0
    return float(double_s_phases(length, v, a, j)[0].sum())


def double_s_phases(length: float, v: float, a: float, j: float) -> tuple[np.ndarray, np.ndarray]:
    """Durations (s) and path jerks (mm/s³) of the rest-to-rest double-S phases over ``length`` mm.

    ``Tj`` (jerk phase) and ``Ta`` (acceleration phase) for the peak speed ``vp``: ``Tj = a/J``,
    ``Ta = vp/a + a/J`` when ``vp·J ≥ a²``, else ``Tj = sqrt(vp/J)``, ``Ta = 2·Tj``; the peak speed is
    ``v`` when ``L ≥ v·Ta(v)`` (cruise ``L/v − Ta``), else the root of ``vp·Ta(vp) = L`` in closed
    form. Phases of zero duration are left out.
    """
    if length <= 0:
        raise ValueError("double_s_phases needs a positive length")
    if min(v, a, j) <= 0:
        raise ValueError("double_s_time needs positive v, a and J")

    def ramp(vp: float) -> tuple[float, float]:
        if vp * j >= a * a:
            return a / j, vp / a + a / j
        tj = math.sqrt(vp / j)
        return tj, 2.0 * tj

    tj, ta = ramp(v)
    vp = v
    if length < v * ta:
        # vp² /a + vp·a/J = L (acceleration reaches a) or 2·vp·sqrt(vp/J) = L (it does not)
        vp = 0.5 * a * (math.sqrt((a / j) ** 2 + 4.0 * length / a) - a / j)
        if vp * j < a * a:
            vp = (length * length * j / 4.0) ** (1.0 / 3.0)
        vp = min(vp, v)
        tj, ta = ramp(vp)
    tv = max(length / vp - ta, 0.0)
    tc = max(ta - 2.0 * tj, 0.0)
    h = np.array([tj, tc, tj, tv, tj, tc, tj])
    jj = np.array([j, 0.0, -j, 0.0, -j, 0.0, j])
    keep = h > 0.0
    return h[keep], jj[keep]


def line_limits(direction: Sequence[float], machine: Machine, feed: float) -> tuple[float, float, float]:
    """Path limits (v mm/s, a mm/s², J mm/s³) on a line of unit ``direction`` (x, y, z)."""
    t = np.abs(np.asarray(direction, dtype=float))
    names = "XYZ"
    vmax = np.array([machine.axis(k).vmax_mm_s for k in names])
    amax = np.array([machine.axis(k).amax_mm_s2 for k in names])
    jm = [machine.axis(k).jmax_mm_s3 for k in names]
    if any(x is None for x in jm):
        raise ValueError(f"machine {machine.name!r} has no jerk limit on every axis")
    jmax = np.array(jm, dtype=float)
    with np.errstate(divide="ignore"):
        v = min(feed, float((vmax / t).min()))
        a = float((amax / t).min())
        j = float((jmax / t).min())
    return v, a, j


def double_s_line_time(start: Sequence[float], end: Sequence[float], machine: Machine, feed: float) -> float:
    """Rest-to-rest double-S time (s) of one line from ``start`` to ``end`` (mm) at ``feed`` (mm/s)."""
    d = np.asarray(end, dtype=float) - np.asarray(start, dtype=float)
    length = float(np.linalg.norm(d))
    if length == 0.0:
        return 0.0
    return double_s_time(length, *line_limits(d / length, machine, feed))


def double_s_polyline_time(points: Sequence[Sequence[float]], machine: Machine, feed: float) -> float:
    """Σ double-S over a polyline whose every vertex is a sharp corner (stop), s."""
    return sum(double_s_line_time(a, b, machine, feed) for a, b in zip(points, points[1:], strict=False))
