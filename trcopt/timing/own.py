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

from trcopt.timing.grid import arc_grid, curve_grids
from trcopt.timing.path import PathArrays
from trcopt.timing.profiles import Profiles, Result, ranges
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
) -> tuple[Profiles, list[int]]:
    """Own reachability solver on line/arc sections; ``feeds`` are the path-speed limits (mm/s).

    With ``path_amax`` (limit on |a|, mm/s²) the passes of
    :func:`~trcopt.timing.reach.solve_lockstep_vector` replace the linear ones. ``window=None``
    solves every section whole (the reference the windows reproduce). Returns the profiles of
    the solved sections (section index → ``(s, x, iseg)``, kept in the flat arrays they were
    computed in) and the sections whose forward pass violates a lower row (they go to toppra).
    """
    pb = _grid(secs, arrays, feeds, vmax, amax, path_amax)
    n_int = np.diff(pb.offsets)
    limit = int(n_int.max()) + 1 if window is None else max(int(window), 8)
    solved = Profiles()
    failed: list[int] = []
    index = np.array([sec.index for sec in secs], dtype=np.int64)
    short = np.nonzero(n_int <= limit)[0]
    for group in _groups(short, n_int, max(group_budget, limit)):
        ms = n_int[group]
        ats = np.cumsum(ms) - ms  # first row of every section
        rows = pb.rows(ranges(pb.offsets[group], ms))
        # node caps: rest at both ends of a section, its inner nodes capped from both sides
        X = np.zeros((group.shape[0], int(ms.max()) + 1))
        inner = np.minimum(rows.cap_l[1:], rows.cap_r[:-1])  # node between row j and j + 1
        rr, cc = _cells(ms)
        mid = cc < ms[rr] - 1
        X[rr[mid], cc[mid] + 1] = inner[(ats[rr] + cc)[mid]]
        F, bad, _ = _lockstep(rows, ats, ms, X)
        ok = ~bad.any(axis=1)
        failed.extend(index[group[~ok]].tolist())
        _expand_many(pb, rows, ats[ok], ms[ok], F[ok], index[group[ok]], solved)
    for q in np.nonzero(n_int > limit)[0].tolist():
        out = _solve_windows(pb, q, limit)
        if out is None:
            failed.append(secs[q].index)
        else:
            solved.add(secs[q].index, *out)
    return solved, failed


def _cells(ms: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Row (piece) and column of every interval of pieces of ``ms`` intervals padded to one width."""
    total = int(ms.sum())
    rr = np.repeat(np.arange(ms.shape[0]), ms)
    return rr, np.arange(total) - np.repeat(np.cumsum(ms) - ms, ms)


def _grid(
    secs: Sequence[Section], arrays: PathArrays, feeds: np.ndarray, vmax: np.ndarray, amax: np.ndarray,
    path_amax: float | None,
) -> _Problem:
    amin = float(amax.min()) if path_amax is None else min(float(amax.min()), path_amax)
    firsts = np.array([sec.first for sec in secs], dtype=np.int64)
    counts = np.array([sec.last - sec.first + 1 for sec in secs], dtype=np.int64)
    ks = ranges(firsts, counts)  # the segments of every section, in order
    kind = arrays.kind[ks]
    # the curves' grids refined together (one evaluation of all their points per round)
    curves = curve_grids(arrays, ks[kind == 2].tolist(), feeds, amin)
    # a line is one interval (0, length); arcs and curves have their own grids
    grids: dict[int, tuple[np.ndarray, np.ndarray | float]] = {}
    m = np.ones(ks.shape[0], dtype=np.int64)  # intervals per segment
    for j in np.nonzero(kind != 0)[0].tolist():
        k = int(ks[j])
        if k in curves:
            grids[j] = curves[k]
        else:
            grids[j] = arc_grid(float(arrays.length[k]), float(arrays.sweep[k]), float(arrays.arc[k, 2]),
                                float(feeds[k]), amin)
        m[j] = grids[j][0].shape[0] - 1
    at = np.cumsum(m) - m  # first interval of every segment
    total = int(m.sum())
    lo = np.zeros(total)
    hi = np.empty(total)
    rate = np.zeros(total)  # per interval on a curve
    lines = kind == 0
    hi[at[lines]] = arrays.length[ks[lines]]
    for j, (local, turn_rate) in grids.items():
        a, b = int(at[j]), int(at[j] + m[j])
        lo[a:b], hi[a:b], rate[a:b] = local[:-1], local[1:], turn_rate
    first_of_section = np.cumsum(counts) - counts
    n_int = np.add.reduceat(m, first_of_section) if len(secs) else np.zeros(0, dtype=np.int64)
    offsets = np.concatenate(([0], np.cumsum(n_int)))
    return _Problem(arrays, feeds, vmax, amax, path_amax, lo, hi, np.repeat(ks, m), rate, offsets)


def _groups(short: np.ndarray, n_int: np.ndarray, budget: int) -> list[np.ndarray]:
    """Sections of similar interval count (≤ twice the smallest, or +8), ≤ ``budget`` padded intervals."""
    order = short[np.argsort(n_int[short], kind="stable")]
    n = n_int[order]
    out: list[np.ndarray] = []
    start = 0
    while start < order.shape[0]:
        nmax = int(n[start])
        limit = max(2 * nmax, nmax + 8)
        # counts rise along ``order``: the group ends at the first count above ``limit`` or the
        # first whose padded size (members × count) exceeds the budget
        end = min(int(np.searchsorted(n, limit, side="right")), start + budget // max(nmax, 1) + 1)
        over = np.nonzero(np.arange(1, end - start + 1) * n[start:end] > budget)[0]
        stop = max(start + (int(over[0]) if over.shape[0] else end - start), start + 1)
        out.append(order[start:stop])
        start = stop
    return out


def _lockstep(
    rows: _Rows, ats: np.ndarray, ms: np.ndarray, X: np.ndarray, start: float | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pad the pieces (first interval ``ats`` in ``rows``, interval counts ``ms``, node caps ``X``
    padded with zeros, one row per piece) and solve them in lock-step; returns the forward profile
    (G, N+1), the lower-row violations per interval (G, N; False on the padding) and the backward
    pass (G, N+1)."""
    G, N = ms.shape[0], X.shape[1] - 1
    # every interval of every piece: its row in the padded arrays, its column and its source row
    rr, cc = _cells(ms)
    src = np.repeat(ats, ms) + cc
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
    real = np.zeros((G, N), dtype=bool)
    real[rr, cc] = True
    return F, bad & real, B


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
            F, bad, _ = _lockstep(rows, np.zeros(1, np.int64), np.array([m]), xm[None, :], carried)
            commit = m
        else:
            low = xm.copy()
            low[m] = 0.0  # the backward pass from rest at the window end: the lower bound
            F, bad, B = _lockstep(rows, np.zeros(2, np.int64), np.array([m, m]), np.stack((xm, low)), carried)
            settled = np.cumprod(B[0, :m] == B[1, :m])  # equal up to here (then equal before)
            commit = int(settled.sum()) - 1
            if commit < m // 4:
                w *= 2  # not settled over most of the window: solve a longer one again
                continue
        if bad[0, :commit].any():
            return None
        x = F[0, : commit + 1]
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


def _expand_many(
    pb: _Problem, rows: _Rows, ats: np.ndarray, ms: np.ndarray, F: np.ndarray, index: np.ndarray, out: Profiles
) -> None:
    """:func:`_expand` of several pieces (first interval ``ats`` in ``rows``, interval counts ``ms``,
    profiles in the rows of ``F``) at once, into ``out`` as the sections ``index``: the same values,
    computed over all their intervals in one pass."""
    if not ms.shape[0]:
        return
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
    rr, cc = _cells(ms)
    x0, x1 = F[rr, cc], F[rr, cc + 1]
    S, Xv = _switch_points(s0, s1, x0, x1, iseg, pb.arrays, rows.d1l[sel], rows.f2[sel], pb.vmax, pb.amax, pb.path_amax)
    end = np.zeros(total, dtype=bool)
    end[last] = True
    S4 = np.column_stack((S, np.where(end, s1, np.nan)))
    X4 = np.column_stack((Xv, np.where(end, x1, np.nan)))
    valid = ~np.isnan(S4)
    valid[:, 3] = end
    per_interval = valid[:, :3].sum(axis=1)
    n_seg = np.concatenate(([0], np.cumsum(per_interval)))[np.append(first, total)]
    n_pts = n_seg + np.arange(ms.shape[0] + 1)  # one end node per piece
    out.add_block(index, S4[valid], X4[valid], np.repeat(iseg, per_interval), n_pts, n_seg)
