"""The acceleration-limited profile on a FIR grid, its moving-average filter and the result intervals.

Steps (see :mod:`trcopt.timing.jerk_fir` for the method):

1. :func:`topp_pieces` — forward and backward passes over the nodes of a
   :class:`~trcopt.timing.jerk_fir_bounds.FirGrid` in ``x = ṡ²`` with the tabulated bounds ``U``, ``L``
   (constant path acceleration per interval; a bound is read at the speed the ramp reaches ``T/2``
   later, where the filtered states holding this acceleration are), then inside every interval the
   exact minimum of the forward ray, the backward ray and the chord of the caps: pieces of constant
   path acceleration ``u`` (``ṡ`` linear in time).
2. :func:`flatten_peaks` — the filter's path jerk is ``(u(t) − u(t − T))/T``; where the acceleration
   turns from positive to negative with too short a flat in between, the jump would be
   ``|u⁺| + |u⁻|``. A peak is cut at the level where the flat lasts ``(T_rise + T_fall)/2``; the
   dwells at the bottom of the dips come from the caps (:mod:`trcopt.timing.jerk_fir_bounds`).
3. :func:`ramp_groups`, :func:`filter_groups` — every ramp group is averaged over its own length
   (:func:`box_filter`: ``ṡ_f(t) = (1/T)∫_{t−T}^{t} ṡ(τ) dτ``, from piecewise-linear ``ṡ`` a
   piecewise-quadratic one with constant path jerk between the breakpoints ``t_m`` and ``t_m + T``,
   ``s_f``, ``ṡ_f``, ``s̈_f`` at every breakpoint in closed form, same length and end speeds, ``T``
   longer), and the groups are joined by constant-speed intervals on the flats between them.
4. :func:`split_at` — intervals split where they cross a segment joint (every interval on one
   segment, as the trajectory model needs).
"""

from __future__ import annotations

import numpy as np

from trcopt.timing.jerk_fir_bounds import FilterLengths, FirGrid

REFINE = 4  # regula falsi steps after the fixed-point step of a speed-dependent bound
FLAT_TOL = 1e-6  # relative shortfall of a flat below its dwell still counted as long enough

__all__ = ["Pieces", "topp_pieces", "flatten_peaks", "ramp_groups", "box_filter", "filter_groups", "split_at"]


class Pieces:
    """Piecewise constant path acceleration: nodes ``s``, speeds ``v`` (``len M + 1``), ``u`` and
    durations ``dt`` (``len M``)."""

    __slots__ = ("s", "v", "u", "dt")

    def __init__(self, s: np.ndarray, v: np.ndarray, u: np.ndarray) -> None:
        self.s, self.v, self.u = s, v, u
        ds = np.diff(s)
        vs = v[:-1] + v[1:]
        self.dt = np.where(ds > 0, 2.0 * ds / np.maximum(vs, 1e-300), 0.0)

    @property
    def duration(self) -> float:
        return float(self.dt.sum())


def _interp_rows(table: list[list[float]], lev: tuple[list[float], float], n: int, v: float) -> float:
    """Linear interpolation of row ``n`` of a table at speed ``v``; the levels ``lev[0]`` are
    ``vtop (k/K)²`` and ``lev[1] = K/√vtop``."""
    levels, kq = lev
    q = kq * v**0.5 if v > 0 else 0.0
    i = int(q)
    row = table[n]
    if i >= len(row) - 1:
        return row[-1]
    a = levels[i]
    f = (v - a) / (levels[i + 1] - a)
    return row[i] * (1.0 - f) + row[i + 1] * f


def _step(
    table: list[list[float]], step: tuple[list[float], float], here: int, there: int, x: float, d2: float, half: float
) -> float:
    """Largest ``u`` with ``u ≤ table[here](√x + u·half)`` and ``u ≤ table[there](√(x + d2·u) + u·half)``.

    The bound decreases with the speed; it is read ``half`` (= T/2) ahead in time, at the speed the
    ramp reaches by then: the filtered states whose window holds this acceleration move that fast
    (the fixed-point step from the bound at the current speed, then regula falsi with the Illinois
    rule)."""

    def g(u: float) -> float:
        a = _interp_rows(table, step, here, x**0.5 + u * half)
        b = _interp_rows(table, step, there, (x + d2 * u) ** 0.5 + u * half)
        return (a if a < b else b) - u

    hi = _interp_rows(table, step, here, x**0.5)
    if hi <= 0:
        return 0.0
    ghi = g(hi)
    if ghi >= 0:
        return hi
    # the bound at hi is below hi; since it decreases with u, u = bound(hi) keeps its bound
    lo = hi + ghi
    glo = g(lo) if lo > 0 else -1.0
    iters = REFINE
    if lo <= 0 or glo < 0:
        # no usable fixed-point step (the bound vanishes at the look-ahead speed): bracket from 0
        lo, glo = 0.0, g(0.0)
        if glo <= 0:
            return 0.0
        iters = 8
    side = 0
    for _ in range(iters):
        if hi - lo <= 1e-3 * hi:
            break
        u = lo + (hi - lo) * glo / (glo - ghi)
        gu = g(u)
        if gu >= 0:
            lo, glo = u, gu
            if side == 1:
                ghi *= 0.5
            side = 1
        else:
            hi, ghi = u, gu
            if side == -1:
                glo *= 0.5
            side = -1
    return lo


def topp_pieces(g: FirGrid) -> Pieces:
    """Time-optimal acceleration-limited profile on the grid (forward/backward passes)."""
    n = g.intervals
    U, Lw = g.U.tolist(), g.L.tolist()
    k = g.levels.shape[0] - 1
    step = (g.levels.tolist(), k / max(float(g.levels[-1]), 1e-300) ** 0.5)
    delta = g.delta.tolist()
    ncap2 = (g.ncap**2).tolist()
    half = (0.5 * g.t_int).tolist()
    # intervals whose bounds do not depend on the speed (lines): the step is the smaller end value
    flat_u = (np.ptp(g.U.reshape(n, -1), axis=1) == 0).tolist()
    flat_l = (np.ptp(g.L.reshape(n, -1), axis=1) == 0).tolist()
    xf = [0.0] * (n + 1)
    uf = [0.0] * n
    for i in range(n):
        xi = xf[i]
        d2 = 2.0 * delta[i]
        if flat_u[i]:
            u = min(U[2 * i][0], U[2 * i + 1][0])
        else:
            u = _step(U, step, 2 * i, 2 * i + 1, xi, d2, half[i])
        uf[i] = u
        xf[i + 1] = min(xi + d2 * u, ncap2[i + 1])
    xb = [0.0] * (n + 1)
    ub = [0.0] * n
    for i in range(n - 1, -1, -1):
        xi = xb[i + 1]
        d2 = 2.0 * delta[i]
        if flat_l[i]:
            w = min(Lw[2 * i][0], Lw[2 * i + 1][0])
        else:
            w = _step(Lw, step, 2 * i + 1, 2 * i, xi, d2, half[i])
        ub[i] = w
        xb[i] = min(xi + d2 * w, ncap2[i])
    xf_a, xb_a = np.array(xf), np.array(xb)
    uf_a, ub_a = np.array(uf), np.array(ub)
    # inside interval i: min(F, B, C) of three lines in σ = s − s_i: the forward ray
    # F = xf_i + 2 uf σ, the backward ray B = xb_{i+1} + 2 ub (Δ − σ) and the chord of the caps C
    d = g.delta
    F0, B1 = xf_a[:-1], xb_a[1:]
    c0 = g.cap_l**2
    cs = (g.cap_r**2 - c0) / d
    lines_a = np.stack((F0, B1 + 2 * ub_a * d, c0), axis=1)  # value at σ = 0
    lines_b = np.stack((2 * uf_a, -2 * ub_a, cs), axis=1)  # slope
    cand = [np.zeros(n), d]
    for p, q in ((0, 1), (0, 2), (1, 2)):
        with np.errstate(divide="ignore", invalid="ignore"):
            sig = (lines_a[:, q] - lines_a[:, p]) / (lines_b[:, p] - lines_b[:, q])
        cand.append(np.where(np.isfinite(sig), sig, 0.0))
    cand = np.clip(np.stack(cand, axis=1), 0.0, d[:, None])
    cand.sort(axis=1)
    vals = lines_a[:, None, :] + lines_b[:, None, :] * cand[:, :, None]  # (n, 5, 3)
    xc = np.maximum(vals.min(axis=2), 0.0)
    mids = 0.5 * (cand[:, :-1] + cand[:, 1:])
    which = np.argmin(lines_a[:, None, :] + lines_b[:, None, :] * mids[:, :, None], axis=2)
    u = np.take_along_axis(lines_b / 2, which, axis=1)  # (n, 4)
    # flatten: pieces of positive length
    s_all = g.s[:-1, None] + cand  # (n, 5)
    keep = np.diff(cand, axis=1) > 1e-12 * np.maximum(d[:, None], 1e-12)
    s_nodes = np.concatenate(([g.s[0]], s_all[:, 1:][keep]))
    x_nodes = np.concatenate(([xc[0, 0]], xc[:, 1:][keep]))
    u_p = u[keep]
    x_nodes[0] = 0.0
    x_nodes[-1] = 0.0
    s_nodes[-1] = g.s[-1]
    v = np.sqrt(np.maximum(x_nodes, 0.0))
    # the constant acceleration of a piece from its end speeds (consistent with the times)
    ds = np.diff(s_nodes)
    with np.errstate(divide="ignore", invalid="ignore"):
        u_p = np.where(ds > 0, (x_nodes[1:] - x_nodes[:-1]) / (2 * np.where(ds > 0, ds, 1.0)), 0.0)
    return Pieces(s_nodes, v, u_p)


def _signs(p: Pieces, tol: float = 1e-9) -> np.ndarray:
    umax = float(np.abs(p.u).max()) if p.u.shape[0] else 0.0
    return np.where(p.u > tol * umax, 1, np.where(p.u < -tol * umax, -1, 0))


def flatten_peaks(p: Pieces, tf: FilterLengths) -> Pieces:
    """Cut every peak where the acceleration turns from positive to negative with less than
    ``(T_rise + T_fall)/2`` of zero acceleration between (``T`` from ``tf`` at the two sides), at the
    level where the cut lasts that long."""
    for _ in range(256):
        sg = _signs(p)
        nz = np.nonzero(sg)[0]
        if nz.shape[0] < 2:
            return p
        change = np.nonzero((sg[nz[:-1]] > 0) & (sg[nz[1:]] < 0))[0]
        bad = None
        for c in change:
            a, b = int(nz[c]), int(nz[c + 1])
            need = 0.5 * float(tf.at(p.s[a + 1 : a + 2], "left")[0] + tf.at(p.s[b : b + 1], "right")[0])
            if p.dt[a + 1 : b].sum() < need * (1 - 1e-9):
                bad = (a, b, need)
                break
        if bad is None:
            return p
        p = _cut_peak(p, bad[0], bad[1], bad[2])
    return p


def _cut_peak(p: Pieces, a: int, b: int, need: float) -> Pieces:
    """Cut the peak between the rising piece ``a`` and the falling piece ``b`` to a flat of ``need`` s."""
    x = p.v**2
    peak = a + 1 + int(np.argmax(x[a + 1 : b + 1]))
    lo = peak
    while lo > 0 and x[lo - 1] <= x[lo] + 1e-12:
        lo -= 1
    hi = peak
    while hi < x.shape[0] - 1 and x[hi + 1] <= x[hi] + 1e-12:
        hi += 1
    ls, lx = p.s[lo : peak + 1], x[lo : peak + 1]  # increasing x
    rs, rx = p.s[peak : hi + 1][::-1], x[peak : hi + 1][::-1]  # increasing x

    def span(y: float) -> tuple[float, float]:
        return float(np.interp(y, lx, ls)), float(np.interp(y, rx, rs))

    def dwell(y: float) -> float:
        left, right = span(y)
        return (right - left) / max(y**0.5, 1e-300)

    y_lo, y_hi = max(float(lx[0]), float(rx[0])), float(x[peak])
    if dwell(y_lo) < need:
        y = y_lo
    else:
        for _ in range(60):
            y = 0.5 * (y_lo + y_hi)
            if dwell(y) >= need:
                y_lo = y
            else:
                y_hi = y
        y = y_lo
    left, right = span(y)
    s_new = np.concatenate((p.s[p.s < left], [left, right], p.s[p.s > right]))
    x_new = np.concatenate((x[p.s < left], [y, y], x[p.s > right]))
    ok = np.concatenate(([True], np.diff(s_new) > 0))
    s_new, x_new = s_new[ok], x_new[ok]
    u = (x_new[1:] - x_new[:-1]) / (2 * np.diff(s_new))
    return Pieces(s_new, np.sqrt(np.maximum(x_new, 0.0)), u)


def ramp_groups(p: Pieces, tf: FilterLengths) -> list[tuple[int, int]]:
    """Pieces ``(first, last)`` of every ramp group: runs of pieces with acceleration, joined across
    every flat shorter than the mean of the two sides' ``T`` (each group is filtered with its own
    length; the flats between groups are where the filtered profiles are joined)."""
    sg = _signs(p)
    nz = np.nonzero(sg)[0]
    if nz.shape[0] == 0:
        return []
    groups = [[int(nz[0]), int(nz[0])]]
    for i in nz[1:]:
        i = int(i)
        g = groups[-1]
        if i == g[1] + 1:
            g[1] = i
            continue
        gap = float(p.dt[g[1] + 1 : i].sum())
        need = 0.5 * float(tf.at(p.s[g[1] : g[1] + 1])[0] + tf.at(p.s[i : i + 1])[0])
        if gap < need * (1 - FLAT_TOL):
            g[1] = i
        else:
            groups.append([i, i])
    return [(a, b) for a, b in groups]


def box_filter(p: Pieces, T: float, first: int = 0, last: int | None = None) -> tuple[np.ndarray, ...]:
    """Moving average of length ``T`` of the speed of pieces ``first..last`` of ``p``, with the speed
    before (after) them held at its value at their start (end).

    Returns ``(t0, s0, v0, a0, j, h)`` of the filtered intervals (constant path jerk each) from the
    time the output leaves the first speed to the time it settles at the last one (``T`` longer
    than the pieces); ``t0`` starts at 0, ``s0`` at ``p.s[first] − c₀T/2``.
    """
    last = p.u.shape[0] - 1 if last is None else last
    dt = p.dt[first : last + 1]
    u = p.u[first : last + 1]
    V = p.v[first : last + 2]
    S = p.s[first : last + 2] - p.s[first]
    t = np.concatenate(([0.0], np.cumsum(dt)))
    te = float(t[-1])
    c0, c1 = float(V[0]), float(V[-1])
    Q = np.concatenate(([0.0], np.cumsum(S[:-1] * dt + V[:-1] * dt**2 / 2 + u * dt**3 / 6)))
    Ltot = float(S[-1])

    def state(tt: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        i = np.clip(np.searchsorted(t, tt, side="right") - 1, 0, len(dt) - 1)
        tau = np.clip(tt - t[i], 0.0, dt[i])
        ss = S[i] + V[i] * tau + u[i] * tau**2 / 2
        vv = V[i] + u[i] * tau
        qq = Q[i] + S[i] * tau + V[i] * tau**2 / 2 + u[i] * tau**3 / 6
        uu = u[i].copy()
        before, after = tt < 0, tt > te
        ta = tt - te
        ss = np.where(before, c0 * tt, np.where(after, Ltot + c1 * ta, ss))
        vv = np.where(before, c0, np.where(after, c1, vv))
        qq = np.where(before, c0 * tt**2 / 2, np.where(after, Q[-1] + Ltot * ta + c1 * ta**2 / 2, qq))
        uu = np.where(before | after, 0.0, uu)
        return ss, vv, qq, uu

    b = np.unique(np.concatenate((t, t + T)))
    keep = np.concatenate(([True], np.diff(b) > 1e-13 * max(te + T, 1e-9)))
    b = b[keep]
    b[-1] = te + T
    h = np.diff(b)
    s_a, v_a, q_a, _ = state(b)
    s_b, v_b, q_b, _ = state(b - T)
    s0 = (q_a - q_b) / T + p.s[first]
    v0 = (s_a - s_b) / T
    a0 = (v_a - v_b) / T
    mid = 0.5 * (b[:-1] + b[1:])
    j = (state(mid)[3] - state(mid - T)[3]) / T
    return b[:-1], s0[:-1], v0[:-1], a0[:-1], j, h


def join_short_flats(p: Pieces, groups: list[tuple[int, int]], lengths: list[float]) -> tuple[list, list]:
    """Merge neighbouring groups whose flat is shorter than ``c (T_left + T_right)/2`` (the merged
    group is filtered with the larger length)."""
    gs, ls = list(groups), list(lengths)
    k = 0
    while k + 1 < len(gs):
        (a0, b0), (a1, b1) = gs[k], gs[k + 1]
        flat = float(p.s[a1] - p.s[b0 + 1])
        if flat < 0.5 * float(p.v[a1]) * (ls[k] + ls[k + 1]) * (1 - FLAT_TOL):
            gs[k : k + 2] = [(a0, b1)]
            ls[k : k + 2] = [max(ls[k], ls[k + 1])]
        else:
            k += 1
    return gs, ls


def filter_groups(p: Pieces, groups: list[tuple[int, int]], lengths: list[float]) -> tuple[np.ndarray, ...]:
    """Every ramp group filtered with its own length, joined by constant-speed intervals on the flats
    between them (see :func:`join_short_flats`). Returns ``(t0, s0, v0, a0, j, h)``."""
    groups, lengths = join_short_flats(p, groups, lengths)
    parts: list[tuple[np.ndarray, ...]] = []
    t_now = 0.0
    s_prev_end: float | None = None
    for (a, b), T in zip(groups, lengths, strict=True):
        t0, s0, v0, a0, j, h = box_filter(p, T, a, b)
        c0 = float(p.v[a])
        if s_prev_end is not None:
            gap = float(s0[0]) - s_prev_end
            if gap > 0 and c0 > 0:
                dt = gap / c0
                parts.append(
                    (
                        np.array([t_now]),
                        np.array([s_prev_end]),
                        np.array([c0]),
                        np.zeros(1),
                        np.zeros(1),
                        np.array([dt]),
                    )
                )
                t_now += dt
        parts.append((t0 + t_now, s0, v0, a0, j, h))
        t_now += float(h.sum())
        c1 = float(p.v[b + 1])
        s_prev_end = float(p.s[b + 1]) + 0.5 * c1 * T
    if not parts:  # no ramp at all (a section the bounds keep at rest): one interval at rest
        return np.zeros(1), np.array([p.s[0]]), np.zeros(1), np.zeros(1), np.zeros(1), np.zeros(1)
    return tuple(np.concatenate([q[k] for q in parts]) for k in range(6))


def _pos(s0: np.ndarray, v0: np.ndarray, a0: np.ndarray, j: np.ndarray, tau: np.ndarray) -> np.ndarray:
    return s0 + v0 * tau + a0 * tau**2 / 2 + j * tau**3 / 6


def split_at(
    t0: np.ndarray, s0: np.ndarray, v0: np.ndarray, a0: np.ndarray, j: np.ndarray, h: np.ndarray, cuts: np.ndarray
) -> tuple[np.ndarray, ...]:
    """Split the intervals where ``s`` crosses one of ``cuts`` (mm); returns the new ``(t0, s0, v0, a0, j, h)``."""
    if cuts.shape[0] == 0:
        return t0, s0, v0, a0, j, h
    s_end = _pos(s0, v0, a0, j, h)
    iv = np.searchsorted(s_end, cuts, side="left")
    iv = np.clip(iv, 0, h.shape[0] - 1)
    inside = (cuts > s0[iv] + 1e-12) & (cuts < s_end[iv] - 1e-12)
    iv, cuts = iv[inside], cuts[inside]
    if iv.shape[0] == 0:
        return t0, s0, v0, a0, j, h
    lo, hi = np.zeros(iv.shape[0]), h[iv].copy()
    for _ in range(64):
        mid = 0.5 * (lo + hi)
        below = _pos(s0[iv], v0[iv], a0[iv], j[iv], mid) < cuts
        lo = np.where(below, mid, lo)
        hi = np.where(below, hi, mid)
    tc = t0[iv] + 0.5 * (lo + hi)
    tb = np.unique(np.concatenate((t0, tc)))
    te = float(t0[-1] + h[-1])
    k = np.clip(np.searchsorted(t0, tb, side="right") - 1, 0, h.shape[0] - 1)
    tau = tb - t0[k]
    ns = _pos(s0[k], v0[k], a0[k], j[k], tau)
    nv = v0[k] + a0[k] * tau + j[k] * tau**2 / 2
    na = a0[k] + j[k] * tau
    nh = np.diff(np.append(tb, te))
    return tb, ns, nv, na, j[k], nh
