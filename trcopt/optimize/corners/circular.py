"""The largest circular blend at one corner within the contour tolerance (G1).

:func:`circular_blend` is the baseline transition, the usual controller smoothing: a circle tangent
to both lines of a corner, as large as the cut-part tolerance and the no-gouge condition allow.
The ``arc`` strategy uses it everywhere; the ``optimal`` one where it is faster than the G2 quintic
or the quintic is infeasible.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from trcopt.geometry import Arc, Line
from trcopt.optimize.corners.boundary import element_samples
from trcopt.optimize.corners.sites import CornerSite

__all__ = ["ARC_BLEND_TOL_MM", "circular_blend"]

ARC_BLEND_TOL_MM = 1e-7  # the largest same-ε circular blend is found to this tangent length


def circular_blend(site: CornerSite, eps: float) -> tuple[Arc, float, float] | None:
    """Largest circular blend tangent to both lines of ``site`` with material left ≤ ``eps`` (mm)
    and no gouge: (the circle, its tangent length on ``a``, on ``b``, mm); None when a neighbour
    is an arc or no blend fits."""
    if not (isinstance(site.a, Line) and isinstance(site.b, Line)):
        return None
    phi = abs(site.turn)
    ta, tb = np.array(site.a.direction2()), np.array(site.b.direction2())
    J = site.joint
    sgn = 1.0 if site.turn > 0 else -1.0
    tmax = min(site.avail_a, site.avail_b)

    def build(T: float) -> tuple[Arc, np.ndarray]:
        r = T / math.tan(0.5 * phi)
        A, B = J - T * ta, J + T * tb
        c = A + sgn * r * np.array([-ta[1], ta[0]])
        arc = Arc.from_points((A[0], A[1], site.w), (B[0], B[1], site.w), (c[0], c[1]), sgn > 0, False)
        pts, _ = element_samples(arc, max(arc.plane_length / 200.0, 1e-6))
        return arc, pts

    def margin(T: float) -> float:
        """The smaller slack of the two conditions, mm (≥ 0: the blend of tangent length T fits)."""
        _, pts = build(T)
        dev = float(site.material_left(pts, T, T, eps).max(initial=0.0))
        clear = site.programmed_set.min_distance(pts)
        return min(eps - dev, clear - (site.radius - 1e-9))

    lo, hi = 0.0, tmax
    closed = _closed_form_tangent(site, eps, phi, tmax)
    if closed is not None and margin(closed) >= 0.0:
        # the closed form (vertex distance at an inside corner, the tool radius at an outside one),
        # confirmed by the sampled check; the search below is the fallback
        lo = hi = closed
    else:
        g_hi = margin(hi)
        if g_hi >= 0.0:
            lo = hi
        else:
            lo = _largest_feasible(margin, hi, g_hi)
    if lo <= 1e-9:
        return None
    return build(lo)[0], lo, lo


def _largest_feasible(margin: Callable[[float], float], hi: float, g_hi: float) -> float:
    """The largest T in [0, hi] with ``margin(T) ≥ 0`` to ARC_BLEND_TOL_MM, given ``margin(hi) < 0``
    (the feasible tangent lengths are an interval [0, T*]).

    Regula falsi on the margin with the Illinois modification, each trial kept at least a tenth
    of the bracket from its ends (so the bracket shrinks by ≥ 10 % per step, as bisection's
    worst case), and a trial just beyond every feasible point (so the bracket closes on both
    sides): 5–8 margin evaluations where bisection needs ~20. The lower end is always feasible."""
    lo, g_lo = 0.0, math.nan  # margin(0) is not evaluated (a blend of length 0)
    if hi > ARC_BLEND_TOL_MM:
        # no blend longer than the search tolerance fits: settled by one evaluation
        g_first = margin(ARC_BLEND_TOL_MM)
        if g_first < 0.0:
            return 0.0
        lo, g_lo = ARC_BLEND_TOL_MM, g_first
    side = 0
    while hi - lo > ARC_BLEND_TOL_MM:
        w = hi - lo
        if math.isnan(g_lo) or g_lo <= g_hi:
            x = lo + 0.5 * w
        else:
            x = lo + g_lo * w / (g_lo - g_hi)
            x = min(max(x, lo + 0.1 * w), hi - 0.1 * w)
        g = margin(x)
        if g >= 0.0:
            lo, g_lo = x, g
            if side == 1:
                g_hi *= 0.5
            side = 1
            # close the bracket from above at once when the root is just beyond
            probe = min(lo + 0.5 * ARC_BLEND_TOL_MM, hi)
            if probe < hi:
                g_p = margin(probe)
                if g_p < 0.0:
                    hi, g_hi = probe, g_p
                else:
                    lo, g_lo = probe, g_p
        else:
            hi, g_hi = x, g
            if side == -1 and not math.isnan(g_lo):
                g_lo *= 0.5
            side = -1
    return lo


def _closed_form_tangent(site: CornerSite, eps: float, phi: float, tmax: float) -> float | None:
    """Tangent length of the largest blend within ``eps`` by the closed form of
    :func:`~trcopt.optimize.corners.fillet.cut_contour_spec`, or None when it is not the largest
    (limited by the lines: then the bisection finds it)."""
    if phi <= 0.0 or phi >= math.pi:
        return None
    inside = site.turn * site.material_sign < 0
    half = 0.5 * phi
    one_minus_cos = 2.0 * math.sin(0.5 * half) ** 2
    if inside:
        r = eps * math.cos(half) / one_minus_cos if one_minus_cos > 0 else math.inf
    else:
        r = site.radius
    T = r * math.tan(half)
    if not math.isfinite(T) or T >= tmax:
        return None
    # just inside the bound, so that the sampled check (a bound from above) accepts it
    return T * (1.0 - 1e-9)
