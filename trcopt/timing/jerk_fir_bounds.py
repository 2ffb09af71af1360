"""Grid, speed caps and acceleration bounds of one section for the FIR jerk-limited feed.

:mod:`trcopt.timing.jerk_fir` builds a jerk-limited profile by filtering an acceleration-limited one
with moving averages of lengths ``T(s)`` (:class:`FilterLengths`, one per ramp group). This module
states the acceleration-limited problem whose filtered solution keeps every limit:

* **nodes** fixed in arc length: every segment joint, arcs every ``DTHETA_FIR`` of sweep, lines in
  ``LINE_PIECES`` and at ``(1/8 … 2) vT/2`` from their ends (``v`` the feed), and the ends
  ``s_k − c_k T_left/2``, ``s_k + c_k T_right/2`` of every dwell (below);
* **speed caps** per node and at both ends of every interval (inside an interval the profile stays
  below their chord): the path-speed limit (feed), the axis velocities, the steady-state
  acceleration and jerk on curves (``|q″_k| v² ≤ amax_k``, ``|q‴_k| v³ ≤ jmax_k``), the knot speed
  rule at curvature jumps (``|Δq″_k| v² ≤ jmax_k T_c``) and rest at both ends; on arcs the limits
  are taken × ``cos(DTHETA_FIR/2)`` (the axis projections turn inside an interval);
* **acceleration bounds** ``U(s, v)`` (speeding up) and ``L(s, v)`` (slowing down), tabulated per
  interval end on ``LEVELS`` speed levels (:func:`trcopt.timing.jerk_fir_rows.tables`).

**Dwells.** The filtered state at time ``t`` is the mean of the unfiltered one over ``[t − T, t]``.
Where the caps bend upwards (a step down, a dip, a knot; :func:`_kinks`) and the profile reaches
them, the cap ``c`` is held over ``c T/2`` on either side (``T`` of that side): a profile that slows
down into it and speeds up after it then has a filtered speed of exactly ``c`` there, with zero
path acceleration. Along a smooth cap the mean exceeds the cap only by its curvature, which the
check sees. **Window minimum**: the bounds of an interval end are the minimum over the interval ends
the filter window covers around it (:func:`dilate_bounds`, within one piece of constant ``T``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from trcopt.timing.jerk_fir_rows import FirLimits, bound_tables, steady_caps, window_min
from trcopt.timing.path import PathArrays, path_derivatives
from trcopt.timing.sections import Section

__all__ = [
    "FirLimits",
    "FirGrid",
    "FilterLengths",
    "build_fir_grid",
    "with_dwells",
    "dilate_bounds",
    "DTHETA_FIR",
    "LEVELS",
]

DTHETA_FIR = 0.05  # rad, largest arc angle per interval
LEVELS = 32  # speed levels of the U/L tables
LINE_PIECES = 8  # equal pieces of a line (besides the nodes near its ends)
KINK = 2e-3  # relative excess of the filtered speed over a bent cap from which the cap is dilated
CURVATURE_JUMP_TOL = 1e-6  # 1/mm, as in trcopt.timing.jerk_grid
MIN_GAP = 1e-9  # mm, nodes closer than this (relative to the section length) are merged


@dataclass
class FirGrid:
    """Nodes, derivatives, caps and the U/L tables of one section for one filter length ``T``."""

    s: np.ndarray  # nodes, global mm (N + 1)
    iseg: np.ndarray  # segment of every interval (N)
    delta: np.ndarray  # interval lengths, mm
    cap_l: np.ndarray  # cap at the left end of every interval (one-sided), mm/s, dilated
    cap_r: np.ndarray  # cap at the right end of every interval: inside, the profile stays below the chord
    ncap: np.ndarray  # cap per node (both sides, knots, rest at the ends), mm/s, dilated
    levels: np.ndarray  # speed levels of the tables, mm/s (K + 1)
    # largest path acceleration U and deceleration L (magnitude) per interval end (rows 2i, 2i + 1 =
    # left, right end of interval i) and speed level, mm/s²; shape (2N, K + 1)
    U: np.ndarray
    L: np.ndarray
    knot_s: np.ndarray  # curvature-jump joints, global mm
    knot_dq2: np.ndarray  # Δq″ per knot (rows), 1/mm
    t_int: np.ndarray  # filter length per interval, s
    sources: tuple  # dwell sources: node index, window (first node, end node), cap, is a knot
    raw: FirGrid | None = None  # the grid before any dwell (with_dwells works from it)

    @property
    def intervals(self) -> int:
        return int(self.iseg.shape[0])


def _segment_nodes(sec: Section, ar: PathArrays, feeds: np.ndarray, T: float) -> np.ndarray:
    """Geometry nodes (global mm): joints, arc subdivisions, graded line pieces near the ends."""
    pts = [np.array([sec.s_start])]
    for k in range(sec.first, sec.last + 1):
        a, L = float(ar.start[k]), float(ar.length[k])
        if ar.kind[k] == 1:
            n = max(2, math.ceil(abs(float(ar.sweep[k])) / DTHETA_FIR))
            loc = np.linspace(0.0, L, n + 1)[1:]
        else:
            step = max(0.5 * float(feeds[k]) * T, 1e-6)
            ends = step * np.array([0.125, 0.25, 0.5, 1.0, 2.0])
            loc = np.concatenate((ends, L - ends, np.linspace(0.0, L, LINE_PIECES + 1)[1:]))
            loc = loc[(loc > 0) & (loc <= L)]
        pts.append(a + loc)
    s = np.unique(np.concatenate(pts))
    s[-1] = min(s[-1], sec.s_start + sec.length)
    return s


def _dedupe(s: np.ndarray, keep: np.ndarray, tol: float) -> np.ndarray:
    """Sorted unique nodes, dropping a node within ``tol`` of its left neighbour unless it is in ``keep``."""
    s = np.unique(np.concatenate((s, keep)))
    important = np.isin(s, keep)
    out = [s[0]]
    for x, imp in zip(s[1:], important[1:], strict=True):
        if x - out[-1] > tol:
            out.append(x)
        elif imp:
            out[-1] = x
    return np.array(out)


def dilate_bounds(g: FirGrid, reach_lo: np.ndarray, reach_hi: np.ndarray, tf: FilterLengths) -> FirGrid:
    """``g`` with ``U``, ``L`` of every interval end replaced by their minimum over the interval ends
    in ``[reach_lo, reach_hi]`` (per node, mm: the positions the filter window covers around it),
    within the piece of constant ``T`` of ``tf`` (the pieces are filtered apart)."""
    n = g.intervals
    pos = np.repeat(g.s, 2)[1:-1]
    node = np.repeat(np.arange(n + 1), 2)[1:-1]
    piece = np.repeat(np.searchsorted(tf.breaks, 0.5 * (g.s[:-1] + g.s[1:])), 2)
    first = np.searchsorted(piece, piece, side="left")
    end = np.searchsorted(piece, piece, side="right")
    lo = np.maximum(np.searchsorted(pos, reach_lo[node] - 1e-12, side="left"), first)
    hi = np.minimum(np.searchsorted(pos, reach_hi[node] + 1e-12, side="right"), end)
    rows = np.arange(2 * n)
    lo = np.minimum(lo, rows)
    hi = np.maximum(hi, rows + 1)
    return replace(g, U=window_min(g.U, lo, hi), L=window_min(g.L, lo, hi))


def _intervals(s: np.ndarray, sec: Section, ar: PathArrays, lim: FirLimits, margin: float) -> tuple:
    """Segments, lengths, one-sided derivatives, arc tightening and the caps (feed, axis velocity,
    steady state) at both ends of the intervals between nodes ``s``."""
    mid = 0.5 * (s[:-1] + s[1:])
    iseg = np.clip(np.searchsorted(ar.start, mid, side="right") - 1, sec.first, sec.last).astype(np.int64)
    lo = np.maximum(s[:-1] - ar.start[iseg], 0.0)
    hi = np.minimum(s[1:] - ar.start[iseg], ar.length[iseg])
    delta = np.diff(s)
    dl, dr = path_derivatives(ar, iseg, lo), path_derivatives(ar, iseg, hi)
    # the axis projections turn by up to DTHETA_FIR inside an arc interval: limits × cos(Δθ/2) (one
    # factor for every arc interval, so that both sides of a node agree)
    tight = np.where(ar.kind[iseg] == 1, math.cos(0.5 * DTHETA_FIR), 1.0)
    with np.errstate(divide="ignore"):
        vl = (lim.vmax[None, :] * tight[:, None] / np.abs(dl[0])).min(axis=1)
        vr = (lim.vmax[None, :] * tight[:, None] / np.abs(dr[0])).min(axis=1)
    f = lim.feeds[iseg]
    cap_l = np.minimum(np.minimum(vl, f), steady_caps(dl, tight, lim, margin))
    cap_r = np.minimum(np.minimum(vr, f), steady_caps(dr, tight, lim, margin))
    return iseg, delta, dl, dr, tight, cap_l, cap_r


def _node_caps(
    s: np.ndarray, cap_l: np.ndarray, cap_r: np.ndarray, knot_s: np.ndarray, knot_cap: np.ndarray, fcap: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Node caps (both one-sided values, knots, rest at the ends) and interval caps (the larger end
    value: inside an interval the profile stays below the chord of the node caps), with the cap
    factors ``fcap`` (per node) applied."""
    n = cap_l.shape[0]
    ncap = np.full(n + 1, np.inf)
    ncap[:-1] = np.minimum(ncap[:-1], cap_l)
    ncap[1:] = np.minimum(ncap[1:], cap_r)
    if knot_s.shape[0]:
        idx = np.clip(np.searchsorted(s, knot_s - 1e-12), 0, n)
        ncap[idx] = np.minimum(ncap[idx], knot_cap)
    ncap *= fcap
    icap = np.maximum(cap_l, cap_r) * np.minimum(fcap[:-1], fcap[1:])
    ncap[0] = ncap[-1] = 0.0
    return ncap, icap


def _kinks(s: np.ndarray, c: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Nodes where the cap ``c`` bends upwards (a step, a dip) enough that the mean of a profile
    following it over ``± c T/2`` would exceed it by more than ``KINK``: the slope change ``Δm``
    times ``T/8``."""
    n = c.shape[0]
    out = np.zeros(n, dtype=bool)
    if n < 3:
        return out
    cc = np.where(np.isfinite(c), c, 1e300)
    with np.errstate(invalid="ignore", over="ignore"):
        m = np.diff(cc) / np.maximum(np.diff(s), 1e-300)
        bend = np.zeros(n)
        bend[1:-1] = m[1:] - m[:-1]
        bend[0], bend[-1] = m[0], -m[-1]
        out = (bend * T / 8 > KINK) & np.isfinite(c) & (c > 0)
    return out


class FilterLengths:
    """Piecewise-constant filter length ``T(s)``: ``values[k]`` between ``breaks[k-1]`` and ``breaks[k]``."""

    __slots__ = ("breaks", "values")

    def __init__(self, breaks: np.ndarray, values: np.ndarray) -> None:
        self.breaks, self.values = np.asarray(breaks, dtype=float), np.asarray(values, dtype=float)

    @classmethod
    def constant(cls, T: float) -> FilterLengths:
        return cls(np.zeros(0), np.array([T]))

    def at(self, x: np.ndarray, side: str = "right") -> np.ndarray:
        """``T`` just after (``side="right"``) or just before (``"left"``) each position ``x``."""
        return self.values[np.searchsorted(self.breaks, x, side=side)]  # type: ignore[call-overload]

    @property
    def largest(self) -> float:
        return float(self.values.max())


def build_fir_grid(
    sec: Section,
    ar: PathArrays,
    lim: FirLimits,
    tf: FilterLengths,
    *,
    margin: float = 0.995,
    scale: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
) -> FirGrid:
    """The grid, caps and U/L tables of section ``sec`` for the filter lengths ``tf`` (s).

    ``scale`` is ``(positions, cap factors, acceleration factors)``: piecewise-linear multipliers
    (≤ 1) on the speed caps and on ``U``, ``L``, found by the limit check of an earlier attempt.
    """
    s0, s1 = sec.s_start, sec.s_start + sec.length
    tol = MIN_GAP * max(sec.length, 1.0)
    segs = np.arange(sec.first, sec.last + 1)
    joints = ar.start[segs[1:]]
    knot_dq2 = np.zeros((0, 3))
    knot_s = np.zeros(0)
    knot_cap = np.zeros(0)
    if segs.shape[0] > 1:
        left = path_derivatives(ar, segs[:-1], ar.length[segs[:-1]])[1]
        right = path_derivatives(ar, segs[1:], np.zeros(segs.shape[0] - 1))[1]
        dq2 = right - left
        jump = (np.abs(dq2) > CURVATURE_JUMP_TOL).any(axis=1)
        knot_dq2, knot_s = dq2[jump], joints[jump]
        with np.errstate(divide="ignore"):
            c2 = (lim.jmax[None, :] * lim.cycle_s / np.abs(knot_dq2)).min(axis=1)
            if lim.path_jmax is not None:
                c2 = np.minimum(c2, lim.path_jmax * lim.cycle_s / np.linalg.norm(knot_dq2, axis=1))
        knot_cap = np.sqrt(c2) * (1.0 - 1e-9)
    keep = np.concatenate(([s0, s1], joints))

    def factors(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        if scale is None:
            return np.ones(x.shape[0]), np.ones(x.shape[0])
        return np.interp(x, scale[0], scale[1]), np.interp(x, scale[0], scale[2])

    def dwell_points(x: np.ndarray, c: np.ndarray) -> np.ndarray:
        return np.concatenate((x - 0.5 * c * tf.at(x, "left"), x + 0.5 * c * tf.at(x, "right")))

    # first pass: the caps on the geometry nodes give the points where dilated caps end
    nodes = _segment_nodes(sec, ar, lim.feeds, tf.largest)
    nodes = np.concatenate((nodes, tf.breaks) + (() if scale is None else (scale[0],)))
    nodes = _dedupe(nodes[(nodes >= s0) & (nodes <= s1)], keep, tol)
    _, _, _, _, _, cap_l, cap_r = _intervals(nodes, sec, ar, lim, margin)
    ncap, _ = _node_caps(nodes, cap_l, cap_r, knot_s, knot_cap, factors(nodes)[0])
    k = _kinks(nodes, ncap, tf.at(nodes))
    cand = np.concatenate((nodes, dwell_points(nodes[k], ncap[k]), dwell_points(knot_s, knot_cap)))
    s = _dedupe(cand[(cand > s0 + tol) & (cand < s1 - tol)], keep, tol)
    s[0], s[-1] = s0, s1
    # second pass on the final nodes
    n = s.shape[0] - 1
    iseg, delta, dl, dr, tight, cap_l, cap_r = _intervals(s, sec, ar, lim, margin)
    t_int = tf.at(0.5 * (s[:-1] + s[1:]))
    fc, fa = factors(s)
    ncap, icap = _node_caps(s, cap_l, cap_r, knot_s, knot_cap, fc)
    vtop = float(icap.max())
    levels = vtop * (np.arange(LEVELS + 1) / LEVELS) ** 2  # fine at low speeds (small radii)
    line = ar.kind[iseg] == 0
    # rows 2i and 2i + 1: the left and the right end of interval i (an interval's acceleration keeps
    # the rows of its own two ends); a right end is the next left end on the same segment and T
    own = np.ones(n, dtype=bool)
    own[:-1] = (iseg[1:] != iseg[:-1]) | (t_int[1:] != t_int[:-1]) | (tight[1:] != tight[:-1])
    sub = tuple(x[own] for x in dr)
    fa_rows = np.repeat(fa, 2)[1:-1, None]
    tabs: list[np.ndarray] = []
    tab_l = bound_tables(dl, tight, lim, levels, t_int, margin, line)
    tab_r = bound_tables(sub, tight[own], lim, levels, t_int[own], margin, line[own])
    for tl, t_own in zip(tab_l, tab_r, strict=True):
        tr = np.empty_like(tl)
        tr[own] = t_own
        tr[:-1][~own[:-1]] = tl[1:][~own[:-1]]
        t = np.empty((2 * n, levels.shape[0]))
        t[0::2], t[1::2] = tl, tr
        tabs.append(np.maximum(t, 0.0) * fa_rows)
    # dilation of the caps where they bend upwards (steps, dips, knots): the cap c of such a node
    # holds over c T/2 on either side (T of that side; rounded outwards to nodes); along a smooth
    # cap the mean over the window exceeds the cap in the middle only by its curvature, which the
    # check sees
    drop = _kinks(s, ncap, tf.at(s))
    is_knot = np.zeros(n + 1, dtype=bool)
    if knot_s.shape[0]:
        is_knot[np.clip(np.searchsorted(s, knot_s - 1e-12), 0, n)] = True
    drop = (drop | is_knot) & np.isfinite(ncap) & (ncap > 0)
    src = np.nonzero(drop)[0]
    src_s, src_c = s[src], ncap[src]
    eps = 1e-12 * max(sec.length, 1.0)
    lo = src_s - 0.5 * src_c * tf.at(src_s, "left")
    hi = src_s + 0.5 * src_c * tf.at(src_s, "right")
    a_idx = np.clip(np.searchsorted(s, lo + eps, side="right") - 1, 0, n)
    b_idx = np.clip(np.searchsorted(s, hi - eps, side="left") + 1, 0, n + 1)
    sources = (src, a_idx, b_idx, src_c, is_knot[src])
    raw = FirGrid(
        s,
        iseg,
        delta,
        cap_l * fc[:-1],
        cap_r * fc[1:],
        ncap,
        levels,
        tabs[0],
        tabs[1],
        knot_s,
        knot_dq2,
        t_int,
        sources,
    )
    return with_dwells(raw, is_knot[src])


def with_dwells(g: FirGrid, active: np.ndarray) -> FirGrid:
    """The grid with the caps of the ``active`` dwell sources (of ``g.sources``, built from the raw
    caps) held over their windows, the chords and the U/L tables above the caps adjusted."""
    src, a_idx, b_idx, src_c, _ = g.sources
    n = g.intervals
    dil_n = np.full(n + 1, np.inf)
    for a, b, c in zip(a_idx[active].tolist(), b_idx[active].tolist(), src_c[active].tolist(), strict=True):
        seg_n = dil_n[a:b]
        np.minimum(seg_n, c, out=seg_n)
    ncap = np.minimum(g.ncap, dil_n)
    cl = np.minimum(g.cap_l, ncap[:-1])
    cr = np.minimum(g.cap_r, ncap[1:])
    # a node is never passed above its cap: its bounds above the cap are the ones at the cap (they
    # decrease with the speed); the caller takes the minimum over the filter window (dilate_bounds)
    levels = g.levels
    row_cap = np.repeat(ncap, 2)[1:-1]
    above = levels[None, :] > row_cap[:, None]
    U, Lw = g.U, g.L
    if np.any(above):
        at = np.clip(np.searchsorted(levels, row_cap, side="right") - 1, 0, levels.shape[0] - 1)
        rows = np.arange(2 * n)
        U = np.where(above, U[rows, at][:, None], U)
        Lw = np.where(above, Lw[rows, at][:, None], Lw)
    return replace(g, cap_l=cl, cap_r=cr, ncap=ncap, U=U, L=Lw, raw=g if g.raw is None else g.raw)
