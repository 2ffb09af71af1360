"""``time_parameterize``: the time-optimal feed along the tool-centre path.

Pipeline: split at tangent discontinuities (:mod:`.sections`) → adaptive grid on the exact
geometry (:mod:`.grid`) → per section either the own vectorised reachability solver
(:mod:`.reach`, sections made of lines and arcs/helices) or toppra (:mod:`.toppra_engine`,
sections with Poly curves, sections where the own solver reports an infeasible step, or every
section with ``engine="toppra"``) → exact closed-form profile on lines → :class:`TimedTrajectory`.

The machine's vector limits (``machine.path``) join the per-axis ones: the path speed limit caps
the feed of every segment, and the limit on |a| adds the rows of
:func:`~trcopt.timing.reach.solve_lockstep_vector` to the own solver (exact on lines and arcs) and
an inscribed polygon of the (s̈, κṡ²) disc to toppra.
"""

from __future__ import annotations

from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from trcopt.config import DEFAULT_MACHINE, Machine
from trcopt.modes import TimingEngine, parse_enum
from trcopt.path import Segment
from trcopt.timing.grid import segment_grid
from trcopt.timing.path import PathArrays
from trcopt.timing.reach import (
    ellipse_terms,
    interval_rows,
    mvc_bound,
    pass_coefficients,
    solve_lockstep,
    solve_lockstep_vector,
)
from trcopt.timing.sections import Section, axis_limits, path_speed_caps, segment_feeds, split_sections
from trcopt.timing.toppra_engine import solve_section_toppra
from trcopt.timing.trajectory import TimedTrajectory

__all__ = ["time_parameterize"]


def time_parameterize(
    toolpath: Sequence[Segment],
    machine: Machine = DEFAULT_MACHINE,
    *,
    engine: TimingEngine | str = TimingEngine.AUTO,
    workers: int = 1,
    tangent_tol_rad: float = 1e-6,
) -> TimedTrajectory:
    """Time-optimal feed profile of a tool-centre path under the machine's limits.

    Parameters
    ----------
    toolpath:
        Tool-centre segments in path order (lines, arcs/helices, Poly curves).
    machine:
        Per-axis ``vmax`` (mm/s) and ``amax`` (mm/s²), the optional vector limits
        ``machine.path`` (path speed, |a|), rapid feed and feed reference.
    engine:
        ``AUTO`` (own reachability solver on line/arc sections, toppra on sections with Poly
        curves), ``OWN`` (same, spelled out) or ``TOPPRA`` (toppra on every section); the value
        strings are accepted.
    workers:
        Processes for the toppra sections (independent sections run in parallel).
    tangent_tol_rad:
        Joints turning more than this are tangent discontinuities (speed 0 there), rad.

    Returns
    -------
    TimedTrajectory
        ``duration``, ``sample(dt)``, ``check_limits()``, ``segments_with_times()``, ``to_json()``.

    Raises
    ------
    TimingError
        A section cannot be parameterised; names section, s, source block and a remedy.
    """
    engine = parse_enum(TimingEngine, engine, "timing engine")
    segments = list(toolpath)
    vmax, amax = axis_limits(machine)
    if not segments:
        return TimedTrajectory.empty(machine)
    arrays = PathArrays(segments)
    feeds = segment_feeds(segments, machine)
    speed = path_speed_caps(feeds, machine)
    path_amax = machine.path.amax_mm_s2
    sections = split_sections(segments, arrays, tangent_tol_rad)
    use_toppra = [
        engine is TimingEngine.TOPPRA or bool(np.any(arrays.kind[sec.first : sec.last + 1] == 2)) for sec in sections
    ]
    results: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
    own = [sec for sec, t in zip(sections, use_toppra, strict=True) if not t]
    if own:
        solved, failed = _solve_own(own, arrays, speed, vmax, amax, path_amax)
        results.update(solved)
        for k in failed:
            use_toppra[k] = True
    tsecs = [sec for sec, t in zip(sections, use_toppra, strict=True) if t]
    toppra_results = _solve_toppra_all(tsecs, segments, speed, vmax, amax, path_amax, workers)
    for sec, (grid, x) in zip(tsecs, toppra_results, strict=True):
        local_start = arrays.start[sec.first : sec.last + 1] - sec.s_start
        iseg = sec.first + np.searchsorted(local_start, grid[:-1], side="right") - 1
        results[sec.index] = (grid + sec.s_start, x, iseg)
    engines = ["toppra" if t else "own" for t in use_toppra]
    return TimedTrajectory.assemble(segments, machine, feeds, arrays, sections, engines, results)


def _solve_toppra_all(
    secs: list[Section], segments: list[Segment], feeds: np.ndarray, vmax: np.ndarray, amax: np.ndarray,
    path_amax: float | None, workers: int,
) -> list[tuple[np.ndarray, np.ndarray]]:
    jobs = [
        (sec, segments[sec.first : sec.last + 1], feeds[sec.first : sec.last + 1], vmax, amax, path_amax)
        for sec in secs
    ]
    if workers > 1 and len(jobs) > 1:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            return list(pool.map(_toppra_job, jobs))
    return [_toppra_job(j) for j in jobs]


def _toppra_job(job: tuple) -> tuple[np.ndarray, np.ndarray]:
    sec, segs, feeds, vmax, amax, path_amax = job
    return solve_section_toppra(sec, segs, feeds, vmax, amax, path_amax=path_amax)


def _solve_own(
    secs: list[Section], arrays: PathArrays, feeds: np.ndarray, vmax: np.ndarray, amax: np.ndarray,
    path_amax: float | None = None,
) -> tuple[dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]], list[int]]:
    """Own reachability solver on line/arc sections; ``feeds`` are the path-speed limits (mm/s).

    With ``path_amax`` (limit on |a|, mm/s²) the passes of
    :func:`~trcopt.timing.reach.solve_lockstep_vector` replace the linear ones.
    """
    amin = float(amax.min()) if path_amax is None else min(float(amax.min()), path_amax)
    # 1. grids: flat list of intervals (segment, local s at both ends) over all sections
    s_lo, s_hi, seg_of, rate_of = [], [], [], []
    n_int = np.zeros(len(secs), dtype=np.int64)
    for q, sec in enumerate(secs):
        for k in sec.segment_indices:
            local, turn_rate = segment_grid(arrays.evals[k], float(feeds[k]), amin, TimingEngine.OWN)
            m = local.shape[0] - 1
            s_lo.append(local[:-1])
            s_hi.append(local[1:])
            seg_of.append(np.full(m, k))
            rate_of.append(np.full(m, turn_rate))
            n_int[q] += m
    lo = np.concatenate(s_lo)
    hi = np.concatenate(s_hi)
    iseg = np.concatenate(seg_of)
    rate = np.concatenate(rate_of)
    delta = hi - lo
    # 2. one-sided derivatives at both ends of every interval (closed form, all at once)
    d1l, d2l = arrays.eval(iseg, lo, 1), arrays.eval(iseg, lo, 2)
    d1r, d2r = arrays.eval(iseg, hi, 1), arrays.eval(iseg, hi, 2)
    tighten = np.cos(0.5 * rate * delta)  # per-axis |a| inside an arc interval ≤ ends / cos(Δθ/2)
    a_int = amax[None, :] * tighten[:, None]
    alpha, beta, gamma = interval_rows(d1l, d2l, d1r, d2r, delta, a_int)
    f2 = feeds[iseg] ** 2
    curved = arrays.kind[iseg] != 0

    def cap(d1: np.ndarray, d2: np.ndarray) -> np.ndarray:
        with np.errstate(divide="ignore", over="ignore"):
            vel = ((vmax[None, :] / np.abs(d1)) ** 2).min(axis=1)
        out = np.minimum(np.minimum(vel, f2), mvc_bound(d1, d2, a_int))
        if path_amax is not None:
            with np.errstate(divide="ignore"):
                out = np.minimum(out, path_amax / np.linalg.norm(d2, axis=1))  # |c|·x ≤ A
        return out

    cap_l, cap_r = cap(d1l, d2l), cap(d1r, d2r)
    if path_amax is None:
        qb, wb, zb, wf, zf = pass_coefficients(alpha, beta, gamma, curved)
    else:
        cl, cr, dd = ellipse_terms(np.linalg.norm(d2l, axis=1), np.linalg.norm(d2r, axis=1), delta, path_amax)
    # 3. lock-step solve, grouping sections of similar interval count
    offsets = np.concatenate(([0], np.cumsum(n_int)))
    order = np.argsort(n_int, kind="stable")
    solved: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
    failed: list[int] = []
    start = 0
    while start < len(order):
        nmax = int(n_int[order[start]])
        limit = max(2 * nmax, nmax + 8)
        stop = start
        while stop < len(order) and n_int[order[stop]] <= limit:
            stop += 1
        group = order[start:stop]
        N = int(n_int[group].max())
        G = len(group)
        X = np.zeros((G, N + 1))
        for r, q in enumerate(group):
            a, b = offsets[q], offsets[q + 1]
            m = b - a
            xm = np.minimum(np.append(cap_l[a:b], np.inf), np.insert(cap_r[a:b], 0, np.inf))
            xm[0] = xm[m] = 0.0
            X[r, : m + 1] = xm
        if path_amax is None:
            Q = np.full((G, N), np.inf)
            WB = np.zeros((G, N, 12))
            ZB = np.full((G, N, 12), np.inf)
            WF = np.zeros((2, G, N, 12))
            ZF = np.empty((2, G, N, 12))
            ZF[0], ZF[1] = np.inf, -np.inf
            for r, q in enumerate(group):
                a, b = offsets[q], offsets[q + 1]
                m = b - a
                Q[r, :m], WB[r, :m], ZB[r, :m] = qb[a:b], wb[a:b], zb[a:b]
                WF[:, r, :m], ZF[:, r, :m] = wf[:, a:b], zf[:, a:b]
            x, bad = solve_lockstep(Q, WB, ZB, WF, ZF, X)
        else:
            x, bad = _lockstep_vector(group, offsets, alpha, beta, gamma, cl, cr, dd, curved, X)
        for r, q in enumerate(group):
            sec = secs[q]
            if bad[r]:
                failed.append(sec.index)
                continue
            a, b = offsets[q], offsets[q + 1]
            m = b - a
            s_grid = np.append(arrays.start[iseg[a:b]] + lo[a:b], arrays.start[iseg[b - 1]] + hi[b - 1])
            solved[sec.index] = _expand_lines(
                s_grid, x[r, : m + 1], iseg[a:b], arrays, d1l[a:b], f2[a:b], vmax, amax, path_amax
            )
        start = stop
    return solved, failed


def _lockstep_vector(
    group: np.ndarray, offsets: np.ndarray, alpha: np.ndarray, beta: np.ndarray, gamma: np.ndarray,
    cl: np.ndarray, cr: np.ndarray, dd: np.ndarray, curved: np.ndarray, X: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Pad one group of sections and solve it with the vector-acceleration rows."""
    G, N = X.shape[0], X.shape[1] - 1
    AL = np.zeros((G, N, 12))
    BE = np.zeros((G, N, 12))
    GA = np.ones((G, N, 12))
    CL = np.zeros((G, N))
    CR = np.zeros((G, N))
    DD = np.ones((G, N))
    CU = np.zeros((G, N), dtype=bool)
    for r, q in enumerate(group):
        a, b = offsets[q], offsets[q + 1]
        m = b - a
        AL[r, :m], BE[r, :m], GA[r, :m] = alpha[a:b], beta[a:b], gamma[a:b]
        CL[r, :m], CR[r, :m], DD[r, :m], CU[r, :m] = cl[a:b], cr[a:b], dd[a:b], curved[a:b]
    return solve_lockstep_vector(AL, BE, GA, CL, CR, DD, CU, X)


def _expand_lines(
    s: np.ndarray, x: np.ndarray, iseg: np.ndarray, arrays: PathArrays, d1: np.ndarray, f2: np.ndarray,
    vmax: np.ndarray, amax: np.ndarray, path_amax: float | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Insert the exact ramp/cruise switch points on line intervals (closed form, spec §4.2).

    The ramps use the per-axis acceleration projected on the line, and at most ``path_amax``.
    """
    m = iseg.shape[0]
    is_line = arrays.kind[iseg] == 0
    S = np.full((m, 3), np.nan)
    Xv = np.full((m, 3), np.nan)
    S[:, 0], Xv[:, 0] = s[:-1], x[:-1]
    if np.any(is_line):
        with np.errstate(divide="ignore", over="ignore"):
            ad = np.abs(d1)
            acc = (amax[None, :] / ad).min(axis=1)
            if path_amax is not None:
                acc = np.minimum(acc, path_amax)
            xv = np.minimum(((vmax[None, :] / ad) ** 2).min(axis=1), f2)
        L = s[1:] - s[:-1]
        x0, x1 = x[:-1], x[1:]
        s1 = (xv - x0) / (2 * acc)
        s2 = L - (xv - x1) / (2 * acc)
        eps = 1e-12 * (1.0 + L)
        cruise = is_line & (s1 < s2 - eps)
        use1 = cruise & (s1 > eps)
        use2 = cruise & (s2 < L - eps)
        S[use1, 1], Xv[use1, 1] = s[:-1][use1] + s1[use1], xv[use1]
        S[use2, 2], Xv[use2, 2] = s[:-1][use2] + s2[use2], xv[use2]
        peak = is_line & ~cruise
        sp = (x1 - x0 + 2 * acc * L) / (4 * acc)
        usep = peak & (sp > eps) & (sp < L - eps)
        S[usep, 1], Xv[usep, 1] = s[:-1][usep] + sp[usep], np.minimum(x0[usep] + 2 * acc[usep] * sp[usep], xv[usep])
    valid = ~np.isnan(S)
    out_s = np.append(S[valid], s[-1])
    out_x = np.append(Xv[valid], x[-1])
    out_seg = np.repeat(iseg, valid.sum(axis=1))
    return out_s, out_x, out_seg
