"""FIR jerk-limited profile of one section: a filtered acceleration-limited profile, checked.

Controllers limit jerk by a moving-average (FIR) filter on the commanded speed. Here the filter
acts on the *path speed*, so the tool stays on the exact path:

1. the time-optimal acceleration-limited profile ``ṡ(t)`` of the section is computed under speed
   caps and acceleration bounds derived from the jerk limits (:mod:`trcopt.timing.jerk_fir_bounds`,
   :mod:`trcopt.timing.jerk_fir_rows`): pieces of constant path acceleration ``u``;
2. every ramp group (a run of pieces with acceleration between two flat parts) is averaged over a
   window of its own length ``T`` (:mod:`trcopt.timing.jerk_fir_profile`): the path jerk is the
   change of ``u`` over the window divided by ``T``; length, end speeds and rest at the section ends
   are kept, the group lasts ``T`` longer, and the filtered groups are joined on the flats between
   them (a flat at speed ``c`` between groups of lengths ``T₁``, ``T₂`` must be ``c (T₁ + T₂)/2``
   long: the caps that bend upwards, the knots among them, are held over ``c T/2`` on either
   side). A ramp of speed change ``Δv`` under acceleration ``A`` and jerk ``J`` gets
   ``T = min(A/J, √(Δv/J))``, the length of the jerk-limited optimum of that change: on a line the
   filtered profile is the double-S. The lengths are chosen from a first profile with
   ``T = A/J`` everywhere and the profile is computed again with them (``LENGTH_ROUNDS``);
3. the filtered speed is piecewise quadratic in time, so the result is a
   :class:`~trcopt.timing.jerk_problem.SectionProfile` of constant-path-jerk intervals like the
   NLP's, split at the segment joints;
4. every profile is checked against every limit (:mod:`trcopt.timing.jerk_fir_check`); where a
   limit is exceeded, the speed caps (or, where the path acceleration or jerk term dominates, the
   acceleration bounds) are lowered around the violating positions and the section is computed
   again (``MAX_FIXES`` rounds). The fastest valid profile is kept; :func:`fir_section` returns
   None when none passes the check (or the section has a Poly curve), and the caller solves the
   NLP instead.

Measured against the NLP (benchmarks/JERK.md, "FIR engine"): the same cycle time on lines, within
0.1–1.5 % on large arcs and knots at low speed, 3–7 % on small arcs, helices and corner-dense
programs, about 3–5 times less CPU time.
"""

from __future__ import annotations

import time

import numpy as np

from trcopt.solution import Solution, SolveStatus
from trcopt.timing.jerk_fir_bounds import FilterLengths, FirGrid, FirLimits, build_fir_grid, dilate_bounds, with_dwells
from trcopt.timing.jerk_fir_check import FirCheck, check_profile
from trcopt.timing.jerk_fir_profile import (
    Pieces,
    filter_groups,
    flatten_peaks,
    join_short_flats,
    ramp_groups,
    split_at,
    topp_pieces,
)
from trcopt.timing.jerk_problem import SectionProfile
from trcopt.timing.path import PathArrays
from trcopt.timing.sections import Section

__all__ = ["fir_section", "SOLVER", "LENGTH_ROUNDS", "MAX_FIXES"]

SOLVER = "fir"  # Solution.solver and the plan JSON's section engine
LENGTH_ROUNDS = 1  # profiles computed to settle the filter length of every ramp group
MAX_FIXES = 6  # further rounds of local cap reductions
T_MIN_SHARE = 0.05  # shortest filter length, share of A/J
ACTIVE_TOL = 1e-3  # a bend of the caps is held over its dwell when the profile comes this close to it
MARGIN = 0.999  # share of the limits the bounds are designed for


def _segment_limits(sec: Section, ar: PathArrays, lim: FirLimits) -> tuple[np.ndarray, np.ndarray]:
    """Path acceleration and path jerk limit per segment of ``sec``: on a line the per-axis limits over
    the direction cosines, on a curve the smallest limit of the axes it moves in (and the vector
    limits)."""
    segs = np.arange(sec.first, sec.last + 1)
    with np.errstate(divide="ignore"):
        d = np.abs(ar.d[segs])
        a_line = (lim.amax[None, :] / d).min(axis=1)
        j_line = (lim.jmax[None, :] / d).min(axis=1)
    line = ar.kind[segs] == 0
    # axes of a curve: the plane's two, and the third with a helix pitch
    moving = np.zeros((segs.shape[0], 3), dtype=bool)
    rows = np.arange(segs.shape[0])
    perm = ar.perm[segs]
    moving[rows, perm[:, 0]] = True
    moving[rows, perm[:, 1]] = True
    moving[rows, perm[:, 2]] = np.abs(ar.arc[segs, 6]) > 0
    a_curve = np.where(moving, lim.amax[None, :], np.inf).min(axis=1)
    j_curve = np.where(moving, lim.jmax[None, :], np.inf).min(axis=1)
    A = np.where(line, a_line, a_curve)
    J = np.where(line, j_line, j_curve)
    if lim.path_amax is not None:
        A = np.minimum(A, lim.path_amax)
    if lim.path_jmax is not None:
        J = np.minimum(J, lim.path_jmax)
    return A, J


def _profile(
    sec: Section, ar: PathArrays, lim: FirLimits, tf: FilterLengths, scale: tuple | None
) -> tuple[Pieces, list[tuple[int, int]], FirGrid, Pieces]:
    """The acceleration-limited profile for the filter lengths ``tf``, its ramp groups, the grid and
    the profile before its peaks are cut."""
    g = build_fir_grid(sec, ar, lim, tf, margin=MARGIN, scale=scale)
    # the profile with the knot dwells only and without the window minimum: bends of the caps it
    # reaches get their dwells, and it bounds the positions the window covers around a node
    p0 = topp_pieces(g)
    src, _, _, src_c, knot = g.sources
    x0 = np.interp(g.s[src], p0.s, p0.v**2)
    active = knot | (x0 >= (1.0 - ACTIVE_TOL) * src_c**2)
    g = with_dwells(g.raw if g.raw is not None else g, active)
    t = np.concatenate(([0.0], np.cumsum(p0.dt)))
    tn = np.interp(g.s, p0.s, t)
    half = 0.5 * np.maximum(tf.at(g.s, "left"), tf.at(g.s, "right"))
    back = np.interp(tn - half, t, p0.s)
    ahead = np.interp(tn + half, t, p0.s)
    raw = topp_pieces(dilate_bounds(g, back, ahead, tf))
    p = flatten_peaks(raw, tf)
    return p, ramp_groups(p, tf), g, raw


def _lengths(p: Pieces, groups: list[tuple[int, int]], tf: FilterLengths) -> list[float]:
    """The filter length of every group: the largest ``T`` of ``tf`` over it (its bounds hold for
    that length or a shorter one)."""
    out = []
    for a, b in groups:
        inside = (tf.breaks > p.s[a]) & (tf.breaks < p.s[b + 1])
        k0 = int(np.searchsorted(tf.breaks, p.s[a], side="right"))
        vals = [float(tf.values[k0])] + [float(v) for v in tf.values[1:][inside]]
        out.append(max(vals))
    return out


def _largest_change(p: Pieces, a: int, b: int) -> float:
    """The largest speed change of one sign within pieces ``a..b`` (mm/s)."""
    v = p.v[a : b + 2]
    du = np.sign(np.diff(v))
    best, run = 0.0, 0.0
    for k in range(du.shape[0]):
        step = abs(float(v[k + 1] - v[k]))
        if k and du[k] != du[k - 1] and du[k] != 0:
            run = 0.0
        run += step
        best = max(best, run)
    return best


def _choose_lengths(
    sec: Section,
    ar: PathArrays,
    lim: FirLimits,
    p: Pieces,
    groups: list[tuple[int, int]],
    g: FirGrid,
    *,
    split: bool = True,
) -> FilterLengths:
    """Filter lengths from the ramp groups of ``p``: per group ``min(A/J, √(Δv/J))`` (the jerk-limited
    optimum of a speed change Δv under acceleration A and jerk J), changing at a knot inside the flat
    between two groups (its dwell is ``c T_left/2`` before and ``c T_right/2`` after it), else in
    the middle of the flat. A flat over several knots (their dwells overlap: a short curve between
    curvature jumps) changes at each of them; between two knots the length is the one of a speed
    change up to the largest cap there. With ``split``, a group that passes a knot at its cap is
    split there as well (the next profile dwells at the knot)."""
    A, J = _segment_limits(sec, ar, lim)
    starts = ar.start[sec.first : sec.last + 1]
    raw = g.raw if g.raw is not None else g
    knots = g.knot_s

    def length(s0: float, s1: float, dv: float) -> float:
        segs = np.clip(np.searchsorted(starts, [s0, s1], side="right") - 1, 0, starts.shape[0] - 1)
        Jg, Ag = float(J[segs[0] : segs[1] + 1].min()), float(A[segs[0] : segs[1] + 1].min())
        return max(min(Ag / Jg, (dv / Jg) ** 0.5), T_MIN_SHARE * Ag / Jg)

    vals, breaks = [], []
    for k, (a, b) in enumerate(groups):
        if k:
            f0, f1 = float(p.s[groups[k - 1][1] + 1]), float(p.s[a])
            inside = knots[(knots >= f0) & (knots <= f1)]
            if inside.shape[0] == 0:
                breaks.append(0.5 * (f0 + f1))
            for q, kn in enumerate(inside):
                breaks.append(float(kn))
                if q + 1 < inside.shape[0]:
                    m = (raw.s > kn) & (raw.s < inside[q + 1])
                    top = float(raw.ncap[m].max()) if np.any(m) else 0.0
                    vals.append(length(float(kn), float(inside[q + 1]), max(top - float(p.v[a]), 0.0)))
        # a knot inside a group that the profile passes at its cap (its dwell was merged away) splits
        # the group: each part its own length
        cuts = knots[(knots > p.s[a]) & (knots < p.s[b + 1])]
        at_cap = np.interp(cuts, p.s, p.v) >= (1.0 - ACTIVE_TOL) * np.interp(cuts, raw.s, raw.ncap)
        cuts = cuts[at_cap] if split else cuts[:0]
        first = a
        for kn in cuts:
            last = int(np.searchsorted(p.s, kn, side="right")) - 1
            if first <= last - 1:
                vals.append(length(float(p.s[first]), float(kn), _largest_change(p, first, last - 1)))
                breaks.append(float(kn))
                first = last
        vals.append(length(float(p.s[first]), float(p.s[b + 1]), _largest_change(p, first, b)))
    return FilterLengths(np.array(breaks), np.array(vals if vals else [float((A / J).max())]))


def _attempt(
    sec: Section, ar: PathArrays, lim: FirLimits, tf: FilterLengths, scale: tuple | None
) -> tuple[SectionProfile, FirCheck, Pieces, list[tuple[int, int]], bool, FirGrid]:
    p, groups, g, raw = _profile(sec, ar, lim, tf, scale)
    lengths = _lengths(p, groups, tf)
    joined, _ = join_short_flats(p, groups, lengths)
    # every filtered group within one piece of constant T (else its bounds or its flats were made
    # for another length)
    consistent = len(joined) == len(groups) and all(
        not np.any((tf.breaks > p.s[a] + 1e-9) & (tf.breaks < p.s[b + 1] - 1e-9)) for a, b in groups
    )
    t0, s0, v0, a0, j, h = filter_groups(p, groups, lengths)
    joints = ar.start[sec.first + 1 : sec.last + 1]
    t0, s0, v0, a0, j, h = split_at(t0, s0, v0, a0, j, h, joints)
    s = np.append(s0, sec.s_start + sec.length)
    s = np.minimum(np.maximum.accumulate(s), s[-1])
    if joints.shape[0]:
        near = _nearest(s, joints)
        close = np.abs(s[near] - joints) <= 1e-9 * max(sec.length, 1.0)
        s[near[close]] = joints[close]
    v = np.maximum(np.append(v0, 0.0), 0.0)
    a = np.append(a0, 0.0)
    v[0] = a[0] = 0.0
    mid = 0.5 * (s[:-1] + s[1:])
    iseg = np.clip(np.searchsorted(ar.start, mid, side="right") - 1, sec.first, sec.last).astype(np.int64)
    prof = SectionProfile(s, v, a, h, j, iseg)
    chk = check_profile(s[:-1], v[:-1], a[:-1], j, h, iseg, ar, lim, g.knot_s, g.knot_dq2)
    return prof, chk, raw, ramp_groups(raw, tf), consistent, g


def _nearest(s: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Index of the node of ``s`` (sorted) nearest to each ``x``."""
    i = np.clip(np.searchsorted(s, x), 1, s.shape[0] - 1)
    return np.where(np.abs(s[i - 1] - x) <= np.abs(s[i] - x), i - 1, i)


def _lower(scale: tuple | None, s0: float, s1: float, chk: FirCheck, width: float) -> tuple:
    """Lower the factors around the violations: the acceleration factor where the path
    acceleration/jerk term dominates, else the cap factor (by the root of the ratio that the
    exceeded term grows with: speed 1, acceleration 2, jerk 3, knot step 2). Violations closer than
    ``width`` form one window; the factor is lowered over the window ± ``width`` with linear ramps
    of ``width`` on both sides."""
    if scale is None:
        pos, fc, fa = np.array([s0, s1]), np.ones(2), np.ones(2)
    else:
        pos, fc, fa = scale
    power = np.array([1.0, 0.5, 1.0 / 3.0, 0.5])[chk.bad_kind]
    need_c = np.where(chk.bad_tangential, 1.0, np.minimum(0.995, chk.bad_ratio**-power))
    need_a = np.where(chk.bad_tangential, np.minimum(0.98, 1.0 / chk.bad_ratio), 1.0)
    order = np.argsort(chk.bad_s)
    bs, nc, na = chk.bad_s[order], need_c[order], need_a[order]
    cut = np.nonzero(np.diff(bs) > width)[0] + 1
    windows = []
    for grp in np.split(np.arange(bs.shape[0]), cut):
        lo, hi = float(bs[grp[0]]) - width, float(bs[grp[-1]]) + width
        windows.append((lo, hi, float(nc[grp].min()), float(na[grp].min())))
    pts = [pos]
    for lo, hi, _, _ in windows:
        pts.append(np.array([lo - width, lo, hi, hi + width]))
    new = np.unique(np.clip(np.concatenate(pts), s0, s1))
    nfc, nfa = np.interp(new, pos, fc), np.interp(new, pos, fa)
    for lo, hi, c, a in windows:
        # 1 outside, the factor inside [lo, hi], linear in between
        ramp = np.clip(np.minimum(new - (lo - width), (hi + width) - new) / width, 0.0, 1.0)
        nfc = np.minimum(nfc, nfc * (1.0 - ramp * (1.0 - c)))
        nfa = np.minimum(nfa, nfa * (1.0 - ramp * (1.0 - a)))
    return new, nfc, nfa


def fir_section(
    sec: Section, ar: PathArrays, lim: FirLimits, *, rounds: int = LENGTH_ROUNDS
) -> tuple[Solution[SectionProfile], np.ndarray, np.ndarray] | None:
    """FIR profile of ``sec`` (see the module docstring), or None when no candidate is valid.

    Returns the :class:`Solution` (``solver = "fir"``, cost = section time s, iterations = profiles
    computed), the knot node indices and ``Δq″`` per knot.
    """
    t_start = time.perf_counter()
    if np.any(ar.kind[sec.first : sec.last + 1] == 2):
        return None
    A, J = _segment_limits(sec, ar, lim)
    tf = FilterLengths.constant(float((A / J).max()))
    best: tuple[float, SectionProfile, FirCheck] | None = None
    count = fixes = choices = 0
    scale = None
    plain: FilterLengths | None = None  # the lengths without splits at knots, tried second
    while True:
        prof, chk, raw, groups, consistent, grid = _attempt(sec, ar, lim, tf, scale)
        count += 1
        if consistent and chk.ok and (best is None or prof.duration < best[0]):
            best = (prof.duration, prof, chk)
        if not consistent and plain is not None:
            tf, plain = plain, None
            continue
        if not consistent or chk.ok:
            # new filter lengths from the ramp groups of this profile
            new = _choose_lengths(sec, ar, lim, raw, groups, grid)
            if choices >= rounds or _same(new, tf):
                break
            plain = _choose_lengths(sec, ar, lim, raw, groups, grid, split=False)
            plain = None if _same(plain, new) else plain
            tf = new
            choices += 1
            continue
        if fixes >= MAX_FIXES:
            break
        fixes += 1
        width = max(float(prof.v.max()) * tf.largest, 1e-3)
        scale = _lower(scale, sec.s_start, sec.s_start + sec.length, chk, width)
    if best is None:
        return None
    _, prof, _ = best
    g_knots = build_fir_grid(sec, ar, lim, FilterLengths.constant(tf.largest), margin=MARGIN)
    nodes = _nearest(prof.s, g_knots.knot_s)
    wall = time.perf_counter() - t_start
    sol = Solution(SolveStatus.OPTIMAL, prof.duration, count, wall, prof, {}, "fir", SOLVER)
    return sol, nodes.astype(np.int64), g_knots.knot_dq2


def _same(a: FilterLengths, b: FilterLengths) -> bool:
    return (
        a.breaks.shape == b.breaks.shape
        and bool(np.allclose(a.breaks, b.breaks, rtol=0, atol=1e-6))
        and bool(np.allclose(a.values, b.values, rtol=1e-3))
    )
