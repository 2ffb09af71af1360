"""The largest circular blend at one corner within the contour tolerance (G1).

:func:`circular_blend` is the baseline transition, the usual controller smoothing: a circle tangent
to both lines of a corner, as large as the cut-part tolerance and the no-gouge condition allow.
The ``arc`` strategy uses it everywhere; the ``optimal`` one where it is faster than the G2 quintic
or the quintic is infeasible.
"""

from __future__ import annotations

import math

import numpy as np

from trcopt.geometry import Arc, Line
from trcopt.optimize.corners.boundary import element_samples
from trcopt.optimize.corners.sites import CornerSite
from trcopt.verify.model import points_distance

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

    def ok(T: float) -> bool:
        _, pts = build(T)
        dev = site.material_left(pts, T, T, eps)
        clear = min((points_distance(e, pts).min() for e in site.programmed), default=math.inf)
        return float(dev.max(initial=0.0)) <= eps and clear >= site.radius - 1e-9

    lo, hi = 0.0, tmax
    closed = _closed_form_tangent(site, eps, phi, tmax)
    if closed is not None and ok(closed):
        # the closed form (vertex distance at an inside corner, the tool radius at an outside one),
        # confirmed by the sampled check; the bisection below is the fallback
        lo = hi = closed
    elif ok(hi):
        lo = hi
    else:
        # the feasible tangent lengths are an interval [0, T*]: bisect T* to ARC_BLEND_TOL_MM
        while hi - lo > ARC_BLEND_TOL_MM:
            mid = 0.5 * (lo + hi)
            if ok(mid):
                lo = mid
            else:
                hi = mid
    if lo <= 1e-9:
        return None
    return build(lo)[0], lo, lo


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
