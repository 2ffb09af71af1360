"""The own reachability solver on line/arc sections, in bounded memory.

The passes of :mod:`trcopt.timing.reach` need, per grid interval, a few hundred bytes of row data
(the per-axis rows, their Fourier–Motzkin pairs, the speed caps). Computed for a whole program at
once that is about 6 KB per segment; here it is computed only for the intervals being solved:

* **short sections** (at most ``window`` intervals) are solved in lock-step groups of similar
  interval count, each group holding at most ``group_budget`` padded intervals;
* **long sections** are solved over **windows** of ``window`` intervals. The forward pass carries
  its state from window to window; the backward pass of a window has to start from the unknown
  value at the window's end, so it is run twice, from the largest value there (the speed cap)
  and from the smallest (rest). The backward pass is monotone in its start value, so the exact
  value lies between the two; up to the last node where they are *equal* (the same recursion
  from there on) the exact backward value is known, and the window is committed up to that node —
  all of it but about a braking distance before its end. If that is less than a quarter of the
  window (the profile stays near the speed limit over most of it), the window is doubled and
  solved again, up to the whole rest of the section — the result is always the one the
  whole-section passes give, bit for bit.

Line intervals get their exact ramp/cruise switch points (closed form, spec timing.md §4.2) as
they are committed.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from trcopt.modes import TimingEngine
from trcopt.timing.grid import curve_grids, segment_grid
from trcopt.timing.path import PathArrays
from trcopt.timing.reach import (
    ellipse_terms,
    interval_rows,
    mvc_bound,
    pass_coefficients,
    solve_lockstep,
    solve_lockstep_vector,
)
from trcopt.timing.sections import Section

__all__ = ["solve_own", "WINDOW_INTERVALS", "GROUP_INTERVALS"]

WINDOW_INTERVALS = 4096  # intervals of a long section solved at once (half of them committed)
GROUP_INTERVALS = 32768  # padded intervals of one lock-step group of short sections

Result = tuple[np.ndarray, np.ndarray, np.ndarray]  # s (mm), x = ṡ² (mm²/s²), segment per point


@dataclass
class _Problem:
    """The grid of every section (flat over all intervals) and the limits."""

    arrays: PathArrays
    feeds: np.ndarray
    vmax: np.ndarray
    amax: np.ndarray
    path_amax: float | None
    lo: np.ndarray  # local s at both ends of every interval, mm
    hi: np.ndarray
    iseg: np.ndarray
    rate: np.ndarray  # arc angle per mm (0 off arcs)
    offsets: np.ndarray  # first interval of every section (+ the total)

    def rows(self, idx: np.ndarray) -> _Rows:
        """Row data of the intervals ``idx`` (closed-form derivatives at both ends)."""
        arrays, vmax, path_amax = self.arrays, self.vmax, self.path_amax
        lo, hi, iseg = self.lo[idx], self.hi[idx], self.iseg[idx]
        delta = hi - lo
        d1l, d2l = arrays.eval(iseg, lo, 1), arrays.eval(iseg, lo, 2)
        d1r, d2r = arrays.eval(iseg, hi, 1), arrays.eval(iseg, hi, 2)
        tighten = np.cos(0.5 * self.rate[idx] * delta)  # per-axis |a| inside an arc interval ≤ ends / cos(Δθ/2)
        a_int = self.amax[None, :] * tighten[:, None]
        alpha, beta, gamma = interval_rows(d1l, d2l, d1r, d2r, delta, a_int)
        f2 = self.feeds[iseg] ** 2
        curved = arrays.kind[iseg] != 0

        def cap(d1: np.ndarray, d2: np.ndarray) -> np.ndarray:
            with np.errstate(divide="ignore", over="ignore"):
                vel = ((vmax[None, :] / np.abs(d1)) ** 2).min(axis=1)
            out = np.minimum(np.minimum(vel, f2), mvc_bound(d1, d2, a_int))
            if path_amax is not None:
                with np.errstate(divide="ignore"):
                    out = np.minimum(out, path_amax / np.linalg.norm(d2, axis=1))  # |c|·x ≤ A
            return out

        rows = _Rows(idx, d1l, f2, cap(d1l, d2l), cap(d1r, d2r), curved)
        if path_amax is None:
            rows.linear = pass_coefficients(alpha, beta, gamma, curved)
        else:
            # on a curve the vector rows are tightened like the axis rows (its curvature varies)
            a_vec = np.where(arrays.kind[iseg] == 2, path_amax * tighten, path_amax)
            cl, cr, dd = ellipse_terms(np.linalg.norm(d2l, axis=1), np.linalg.norm(d2r, axis=1), delta, a_vec)
            rows.vector = (alpha, beta, gamma, cl, cr, dd)
        return rows

    def s_nodes(self, idx: np.ndarray) -> np.ndarray:
        """Global arc length at the start of every interval of ``idx`` and at the end of the last."""
        start = self.arrays.start
        return np.append(start[self.iseg[idx]] + self.lo[idx], start[self.iseg[idx[-1]]] + self.hi[idx[-1]])


@dataclass
class _Rows:
    idx: np.ndarray
    d1l: np.ndarray
    f2: np.ndarray
    cap_l: np.ndarray
    cap_r: np.ndarray
    curved: np.ndarray
    linear: tuple[np.ndarray, ...] | None = None
    vector: tuple[np.ndarray, ...] | None = None

    def caps(self, a: int, b: int) -> np.ndarray:
        """Node caps of intervals ``a..b-1`` of these rows (both sides of every inner node)."""
        return np.minimum(np.append(self.cap_l[a:b], np.inf), np.insert(self.cap_r[a:b], 0, np.inf))


def solve_own(
    secs: Sequence[Section],
    arrays: PathArrays,
    feeds: np.ndarray,
    vmax: np.ndarray,
    amax: np.ndarray,
    path_amax: float | None = None,
    *,
    window: int | None = WINDOW_INTERVALS,
    group_budget: int = GROUP_INTERVALS,
) -> tuple[dict[int, Result], list[int]]:
    """Own reachability solver on line/arc sections; ``feeds`` are the path-speed limits (mm/s).

    With ``path_amax`` (limit on |a|, mm/s²) the passes of
    :func:`~trcopt.timing.reach.solve_lockstep_vector` replace the linear ones. ``window=None``
    solves every section whole (the reference the windows reproduce). Returns the profile of
    every solved section by index and the sections whose forward pass violates a lower row (they
    go to toppra).
    """
    pb = _grid(secs, arrays, feeds, vmax, amax, path_amax)
    n_int = np.diff(pb.offsets)
    limit = int(n_int.max()) + 1 if window is None else max(int(window), 8)
    solved: dict[int, Result] = {}
    failed: list[int] = []
    short = [q for q in range(len(secs)) if n_int[q] <= limit]
    for group in _groups(short, n_int, max(group_budget, limit)):
        idx = np.concatenate([np.arange(pb.offsets[q], pb.offsets[q + 1]) for q in group])
        rows = pb.rows(idx)
        ms = n_int[group].astype(np.int64)
        ats = np.concatenate(([0], np.cumsum(ms)[:-1]))
        xs, bad, _ = _lockstep(rows, _short_pieces(rows, ats, ms))
        bad_any = [bool(b.any()) for b in bad] if len(group) < 64 else _any_rows(bad)
        ok = [r for r, b in enumerate(bad_any) if not b]
        failed.extend(secs[group[r]].index for r, b in enumerate(bad_any) if b)
        for r, res in zip(ok, _expand_many(pb, rows, [(int(ats[r]), int(ms[r]), xs[r]) for r in ok]), strict=True):
            solved[secs[group[r]].index] = res
    for q in range(len(secs)):
        if n_int[q] > limit:
            out = _solve_windows(pb, q, limit)
            if out is None:
                failed.append(secs[q].index)
            else:
                solved[secs[q].index] = out
    return solved, failed


def _short_pieces(rows: _Rows, ats: np.ndarray, ms: np.ndarray) -> list[tuple[int, int, np.ndarray]]:
    """The pieces of a group of short sections (consecutive in ``rows``): start, interval count
    and node caps, at rest at both ends (the inner nodes capped from both sides, as
    :meth:`_Rows.caps`)."""
    inner = np.minimum(rows.cap_l[1:], rows.cap_r[:-1])  # node between interval j and j + 1
    zero = np.zeros(1)
    return [
        (a, m, np.concatenate((zero, inner[a : a + m - 1], zero)))
        for a, m in zip(ats.tolist(), ms.tolist(), strict=True)
    ]


def _any_rows(bad: list[np.ndarray]) -> list[bool]:
    """``[b.any() for b in bad]`` in one call."""
    lengths = np.array([b.shape[0] for b in bad])
    flat = np.concatenate(bad) if bad else np.zeros(0, bool)
    cum = np.concatenate(([0], np.cumsum(flat, dtype=np.int64)))
    ends = np.cumsum(lengths)
    return (cum[ends] - cum[ends - lengths] > 0).tolist()


def _grid(
    secs: Sequence[Section], arrays: PathArrays, feeds: np.ndarray, vmax: np.ndarray, amax: np.ndarray,
    path_amax: float | None,
) -> _Problem:
    amin = float(amax.min()) if path_amax is None else min(float(amax.min()), path_amax)
    s_lo, s_hi, seg_of, rate_of = [], [], [], []
    n_int = np.zeros(len(secs), dtype=np.int64)
    # the curves' grids refined together (one evaluation of all their points per round)
    curves = curve_grids(arrays, [k for sec in secs for k in sec.segment_indices if arrays.kind[k] == 2], feeds, amin)
    for q, sec in enumerate(secs):
        for k in sec.segment_indices:
            if k in curves:
                local, turn_rate = curves[k]
            else:
                local, turn_rate = segment_grid(arrays.evals[k], float(feeds[k]), amin, TimingEngine.OWN)
            m = local.shape[0] - 1
            s_lo.append(local[:-1])
            s_hi.append(local[1:])
            seg_of.append(np.full(m, k))
            rate_of.append(np.broadcast_to(turn_rate, (m,)))  # per interval on a curve
            n_int[q] += m
    offsets = np.concatenate(([0], np.cumsum(n_int)))
    return _Problem(
        arrays, feeds, vmax, amax, path_amax,
        np.concatenate(s_lo), np.concatenate(s_hi), np.concatenate(seg_of), np.concatenate(rate_of), offsets,
    )


def _groups(short: list[int], n_int: np.ndarray, budget: int) -> list[list[int]]:
    """Sections of similar interval count (≤ twice the smallest, or +8), ≤ ``budget`` padded intervals."""
    order = sorted(short, key=lambda q: int(n_int[q]))
    out: list[list[int]] = []
    start = 0
    while start < len(order):
        nmax = int(n_int[order[start]])
        limit = max(2 * nmax, nmax + 8)
        stop = start
        while stop < len(order) and n_int[order[stop]] <= limit:
            if (stop - start + 1) * int(n_int[order[stop]]) > budget:
                break
            stop += 1
        stop = max(stop, start + 1)
        out.append(order[start:stop])
        start = stop
    return out


def _lockstep(
    rows: _Rows, pieces: list[tuple[int, int, np.ndarray]], start: float | None = None
) -> tuple[list[np.ndarray], list[np.ndarray], list[np.ndarray]]:
    """Pad the pieces (start in ``rows``, interval count, node caps) and solve them in lock-step;
    returns per piece the forward profile, the lower-row violations per interval and the backward
    pass."""
    G, N = len(pieces), max(m for _, m, _ in pieces)
    ms = [m for _, m, _ in pieces]
    counts = np.array(ms, dtype=np.int64)
    # every interval of every piece: its row in the padded arrays, its column and its source row
    rr = np.repeat(np.arange(G), counts)
    cc = np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)
    src = np.repeat(np.array([a for a, _, _ in pieces], dtype=np.int64), counts) + cc
    X = np.zeros((G, N + 1))
    nodes = counts + 1
    node_col = np.arange(int(nodes.sum())) - np.repeat(np.cumsum(nodes) - nodes, nodes)
    X[np.repeat(np.arange(G), nodes), node_col] = np.concatenate([xm for _, _, xm in pieces])
    first = None if start is None else np.full(G, start)
    if rows.linear is not None:
        qb, wb, zb, wf, zf = rows.linear
        Q = np.full((G, N), np.inf)
        WB = np.zeros((G, N, 12))
        ZB = np.full((G, N, 12), np.inf)
        WF = np.zeros((2, G, N, 12))
        ZF = np.empty((2, G, N, 12))
        ZF[0], ZF[1] = np.inf, -np.inf
        Q[rr, cc], WB[rr, cc], ZB[rr, cc] = qb[src], wb[src], zb[src]
        WF[:, rr, cc], ZF[:, rr, cc] = wf[:, src], zf[:, src]
        F, bad, B = solve_lockstep(Q, WB, ZB, WF, ZF, X, backward=True, start=first)
    else:
        assert rows.vector is not None
        alpha, beta, gamma, cl, cr, dd = rows.vector
        AL = np.zeros((G, N, 12))
        BE = np.zeros((G, N, 12))
        GA = np.ones((G, N, 12))
        CL = np.zeros((G, N))
        CR = np.zeros((G, N))
        DD = np.ones((G, N))
        CU = np.zeros((G, N), dtype=bool)
        AL[rr, cc], BE[rr, cc], GA[rr, cc] = alpha[src], beta[src], gamma[src]
        CL[rr, cc], CR[rr, cc], DD[rr, cc], CU[rr, cc] = cl[src], cr[src], dd[src], rows.curved[src]
        F, bad, B = solve_lockstep_vector(AL, BE, GA, CL, CR, DD, CU, X, backward=True, start=first)
    return [F[r, : m + 1] for r, m in enumerate(ms)], [bad[r, :m] for r, m in enumerate(ms)], [
        B[r, : m + 1] for r, m in enumerate(ms)
    ]


def _solve_windows(pb: _Problem, q: int, window: int) -> Result | None:
    """One long section over windows (module description); None if a lower row is violated."""
    first, total = int(pb.offsets[q]), int(pb.offsets[q + 1] - pb.offsets[q])
    parts: list[Result] = []
    c, carried, w = 0, 0.0, window
    while c < total:
        e = min(total, c + w)
        idx = np.arange(first + c, first + e)
        rows = pb.rows(idx)
        m = e - c
        xm = rows.caps(0, m)
        if c == 0:
            xm[0] = 0.0
        if e == total:
            xm[m] = 0.0
            xs, bad, _ = _lockstep(rows, [(0, m, xm)], carried)
            commit = m
        else:
            low = xm.copy()
            low[m] = 0.0  # the backward pass from rest at the window end: the lower bound
            xs, bad, backs = _lockstep(rows, [(0, m, xm), (0, m, low)], carried)
            settled = np.cumprod(backs[0][:m] == backs[1][:m])  # equal up to here (then equal before)
            commit = int(settled.sum()) - 1
            if commit < m // 4:
                w *= 2  # not settled over most of the window: solve a longer one again
                continue
        if bad[0][:commit].any():
            return None
        x = xs[0][: commit + 1]
        part = _expand(pb, rows, 0, commit, x)
        if e != total or commit != m:
            part = (part[0][:-1], part[1][:-1], part[2])  # the next window starts at this node
        parts.append(part)
        carried = float(x[commit])
        c += commit
        w = window
    return np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts]), np.concatenate(
        [p[2] for p in parts]
    )


def _expand(pb: _Problem, rows: _Rows, at: int, m: int, x: np.ndarray) -> Result:
    """The committed profile of intervals ``at..at+m-1`` of ``rows`` with the exact line ramps."""
    idx = rows.idx[at : at + m]
    sl = slice(at, at + m)
    return _expand_lines(
        pb.s_nodes(idx), x, pb.iseg[idx], pb.arrays, rows.d1l[sl], rows.f2[sl], pb.vmax, pb.amax, pb.path_amax
    )


def _expand_lines(
    s: np.ndarray, x: np.ndarray, iseg: np.ndarray, arrays: PathArrays, d1: np.ndarray, f2: np.ndarray,
    vmax: np.ndarray, amax: np.ndarray, path_amax: float | None = None,
) -> Result:
    """Insert the exact ramp/cruise switch points on line intervals (closed form, spec §4.2).

    The ramps use the per-axis acceleration projected on the line, and at most ``path_amax``.
    """
    S, Xv = _switch_points(s[:-1], s[1:], x[:-1], x[1:], iseg, arrays, d1, f2, vmax, amax, path_amax)
    valid = ~np.isnan(S)
    out_s = np.append(S[valid], s[-1])
    out_x = np.append(Xv[valid], x[-1])
    out_seg = np.repeat(iseg, valid.sum(axis=1))
    return out_s, out_x, out_seg


def _switch_points(
    s0: np.ndarray, s1: np.ndarray, x0: np.ndarray, x1: np.ndarray, iseg: np.ndarray, arrays: PathArrays,
    d1: np.ndarray, f2: np.ndarray, vmax: np.ndarray, amax: np.ndarray, path_amax: float | None,
) -> tuple[np.ndarray, np.ndarray]:
    """Per interval (from ``s0``, ``x0`` to ``s1``, ``x1``): its start and up to two switch points
    (m×3 arc lengths and squared speeds, NaN where there is none)."""
    m = iseg.shape[0]
    is_line = arrays.kind[iseg] == 0
    S = np.full((m, 3), np.nan)
    Xv = np.full((m, 3), np.nan)
    S[:, 0], Xv[:, 0] = s0, x0
    if np.any(is_line):
        with np.errstate(divide="ignore", over="ignore"):
            ad = np.abs(d1)
            acc = (amax[None, :] / ad).min(axis=1)
            if path_amax is not None:
                acc = np.minimum(acc, path_amax)
            xv = np.minimum(((vmax[None, :] / ad) ** 2).min(axis=1), f2)
        L = s1 - s0
        sw1 = (xv - x0) / (2 * acc)
        sw2 = L - (xv - x1) / (2 * acc)
        eps = 1e-12 * (1.0 + L)
        cruise = is_line & (sw1 < sw2 - eps)
        use1 = cruise & (sw1 > eps)
        use2 = cruise & (sw2 < L - eps)
        S[use1, 1], Xv[use1, 1] = s0[use1] + sw1[use1], xv[use1]
        S[use2, 2], Xv[use2, 2] = s0[use2] + sw2[use2], xv[use2]
        peak = is_line & ~cruise
        sp = (x1 - x0 + 2 * acc * L) / (4 * acc)
        usep = peak & (sp > eps) & (sp < L - eps)
        S[usep, 1], Xv[usep, 1] = s0[usep] + sp[usep], np.minimum(x0[usep] + 2 * acc[usep] * sp[usep], xv[usep])
    return S, Xv


def _expand_many(pb: _Problem, rows: _Rows, pieces: list[tuple[int, int, np.ndarray]]) -> list[Result]:
    """:func:`_expand` of several pieces (start in ``rows``, interval count, profile) at once: the
    same values, computed over all their intervals in one pass."""
    if not pieces:
        return []
    ats = np.array([a for a, _, _ in pieces], dtype=np.int64)
    ms = np.array([m for _, m, _ in pieces], dtype=np.int64)
    total = int(ms.sum())
    first = np.cumsum(ms) - ms  # first interval of each piece in the flat arrays
    sel = np.repeat(ats - first, ms) + np.arange(total)  # rows of every interval
    idx = rows.idx[sel]
    iseg = pb.iseg[idx]
    s0 = pb.arrays.start[iseg] + pb.lo[idx]
    last = first + ms - 1
    s1 = np.empty(total)
    s1[:-1] = s0[1:]
    s1[last] = pb.arrays.start[iseg[last]] + pb.hi[idx[last]]
    x0 = np.concatenate([x[:-1] for _, _, x in pieces])
    x1 = np.concatenate([x[1:] for _, _, x in pieces])
    S, Xv = _switch_points(s0, s1, x0, x1, iseg, pb.arrays, rows.d1l[sel], rows.f2[sel], pb.vmax, pb.amax, pb.path_amax)
    end = np.zeros(total, dtype=bool)
    end[last] = True
    S4 = np.column_stack((S, np.where(end, s1, np.nan)))
    X4 = np.column_stack((Xv, np.where(end, x1, np.nan)))
    valid = ~np.isnan(S4)
    valid[:, 3] = end
    flat_s, flat_x = S4[valid], X4[valid]
    per_interval = valid[:, :3].sum(axis=1)
    flat_seg = np.repeat(iseg, per_interval)
    n_seg = np.concatenate(([0], np.cumsum(per_interval)))[np.append(first, total)]
    n_pts = n_seg + np.arange(len(pieces) + 1)  # one end node per piece
    out = []
    for k in range(len(pieces)):
        a, b, c, d = int(n_pts[k]), int(n_pts[k + 1]), int(n_seg[k]), int(n_seg[k + 1])
        out.append((flat_s[a:b], flat_x[a:b], flat_seg[c:d]))
    return out
