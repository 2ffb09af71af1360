"""The nodes of a jerk-limited section and their speed caps (the grid a :class:`JerkProblem` solves on).

* Nodes ``s_0 < … < s_N`` are fixed in arc length (mm). Every knot between segments is a node, so
  an interval lies on one segment and the closed-form path derivatives ``q′, q″, q‴`` are smooth
  inside it; on a Poly every sample joint is a node as well (its cubic Hermite pieces meet with a
  jump of ``q″``), and intervals over which ``q‴`` changes sharply are split.
* They are placed at equal increments of an estimated time (from the acceleration-limited profile,
  capped by the jerk-limited speed from rest ``v = ½J(6d/J)^{2/3}`` near the section ends and by the
  knot speed caps), plus a share of the estimated speed changes, so intervals are similar in
  duration and the ramps get nodes even on long feed-limited runs; arcs get at least one interval
  per ``DTHETA_JERK``.
* **Curvature jumps** (line↔arc knots, G450 transition circles, arcs of different radius): the
  axis acceleration ``q″_k v²`` steps by ``Δq″_k·v²`` at the knot, which is passed at the speed at
  which that step is absorbed in one interpolation cycle ``T_c``: ``|Δq″_k|·v² ≤ jmax_k·T_c``, and
  with a vector jerk limit J also ``|Δq″|·v² ≤ J·T_c`` (norm of the step vector).

See :mod:`trcopt.timing.jerk_problem` for the NLP on this grid.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from trcopt.codes import Code
from trcopt.errors import TimingError
from trcopt.geometry.poly import Poly
from trcopt.timing.path import PathArrays, path_derivatives
from trcopt.timing.sections import Section

__all__ = ["JerkGrid", "build_jerk_grid", "DTHETA_JERK"]

DTHETA_JERK = 0.05  # rad, largest arc angle per interval
CURVATURE_JUMP_TOL = 1e-6  # 1/mm: smaller q″ differences at a node are interpolation noise (G2 Poly pieces)
RAMP_SHARE = 0.5  # weight of the speed changes against the time when placing nodes
FINE_SAMPLES = 200  # speed estimate samples per segment


@dataclass(frozen=True)
class JerkGrid:
    """Nodes, path derivatives and speed caps of one section; arc lengths are global (mm).

    Attributes
    ----------
    s:
        Nodes, mm (``N + 1``).
    iseg:
        Segment of every interval (``N``).
    delta:
        Interval lengths, mm.
    dl, dr:
        ``(q′, q″, q‴)`` per axis at the left and right end of every interval, taken inside the
        interval (mm⁰, mm⁻¹, mm⁻²; each ``N × 3``).
    tighten:
        ``cos(Δθ/2)`` per interval (1 off arcs): the axis projections rotate inside an arc interval,
        so limits checked at its ends are tightened by it.
    icap:
        Speed cap per interval (feed and axis velocity at both ends), mm/s.
    vcap:
        Speed cap per node (feed, axis velocity, curvature-jump knots; 0 at both section ends), mm/s.
    knot_nodes:
        Nodes with a curvature jump.
    knot_dq2:
        ``Δq″`` per axis at those nodes, mm⁻¹ (rows = knots).
    v_estimate:
        Estimated speed at the nodes (0 at both ends), mm/s; the warm start scales it.
    axes_used:
        Axes (0, 1, 2 = X, Y, Z) the section moves or curves in.
    """

    s: np.ndarray
    iseg: np.ndarray
    delta: np.ndarray
    dl: tuple[np.ndarray, ...]
    dr: tuple[np.ndarray, ...]
    tighten: np.ndarray
    icap: np.ndarray
    vcap: np.ndarray
    knot_nodes: np.ndarray
    knot_dq2: np.ndarray
    v_estimate: np.ndarray
    axes_used: np.ndarray

    @property
    def intervals(self) -> int:
        return int(self.iseg.shape[0])


def _refine_third(g: Poly, loc: np.ndarray, rel: float = 0.1, rounds: int = 8) -> np.ndarray:
    """Split the Poly intervals over which q‴ changes by more than ``rel`` of the larger end value
    (quintic pieces of a sharp transition: q‴ can change tenfold within a few µm), so that the
    jerk varies little between the rows of an interval (both ends and ¼, ½, ¾ of its time).

    ``loc`` are local arc lengths (mm) of the nodes on the curve; returns the refined nodes.
    """
    if g.curvatures is None:
        return loc
    for _ in range(rounds):
        third = np.array([g.third(float(x) + (1e-9 if i == 0 else -1e-9)) for i, x in enumerate(loc)])
        inner = np.array([g.third(float(x) + 1e-9) for x in loc])
        lo_q, hi_q = inner[:-1], third[1:]
        change = np.linalg.norm(hi_q - lo_q, axis=1)
        scale = np.maximum(np.linalg.norm(hi_q, axis=1), np.linalg.norm(lo_q, axis=1))
        split = np.nonzero((change > rel * scale) & (np.diff(loc) > 2e-7))[0]
        if split.shape[0] == 0:
            break
        loc = np.sort(np.concatenate((loc, 0.5 * (loc[split] + loc[split + 1]))))
    return loc


def build_jerk_grid(
    sec: Section,
    ar: PathArrays,
    feeds: np.ndarray,
    vmax: np.ndarray,
    amax: np.ndarray,
    jmax: np.ndarray,
    base_s: np.ndarray,
    base_v: np.ndarray,
    *,
    cycle_s: float,
    points: int,
    label: str = "",
    path_amax: float | None = None,
    path_jmax: float | None = None,
) -> JerkGrid:
    """Place the nodes of section ``sec`` and compute their speed caps.

    Parameters
    ----------
    sec, ar, feeds:
        The section, the evaluator of the whole tool path and the path-speed limit per segment
        (mm/s; the feed capped by the vector speed limit).
    vmax, amax, jmax:
        Per-axis limits X, Y, Z (mm/s, mm/s², mm/s³).
    base_s, base_v:
        The acceleration-limited profile (global arc length mm, path speed mm/s).
    cycle_s:
        Interpolation cycle T_c, s.
    points:
        Target number of intervals (before the per-arc and per-Poly minimums).
    label:
        Appended to the section index in messages.
    path_amax, path_jmax:
        Vector limits on |a| (mm/s²) and |j| (mm/s³), or None; they enter the speed estimate and,
        for |j|, the knot speed caps.

    Raises
    ------
    TimingError
        Two nodes coincide (``TIMING-JERK-GRID``).
    """
    segs = np.arange(sec.first, sec.last + 1)
    jmin, amin = float(jmax.min()), float(amax.min())
    if path_jmax is not None:
        jmin = min(jmin, path_jmax)
    if path_amax is not None:
        amin = min(amin, path_amax)
    # curvature jumps at interior knots → speed caps (|Δq″_k| v² ≤ jmax_k T_c)
    knot_s = ar.start[segs[1:]]
    knot_cap = np.full(segs.shape[0] - 1, np.inf)
    if segs.shape[0] > 1:
        left = path_derivatives(ar, segs[:-1], ar.length[segs[:-1]])[1]
        right = path_derivatives(ar, segs[1:], np.zeros(segs.shape[0] - 1))[1]
        dq2 = right - left
        with np.errstate(divide="ignore"):
            cap2 = (jmax[None, :] * cycle_s / np.where(np.abs(dq2) > CURVATURE_JUMP_TOL, np.abs(dq2), 0.0)).min(
                axis=1
            )
            if path_jmax is not None:
                jump = np.linalg.norm(dq2, axis=1)
                cap2 = np.minimum(cap2, path_jmax * cycle_s / np.where(jump > CURVATURE_JUMP_TOL, jump, 0.0))
        knot_cap = np.sqrt(cap2)
    # estimated speed on a fine sampling of every segment
    fine_n = FINE_SAMPLES
    parts: list[tuple[np.ndarray, np.ndarray]] = []
    fines, vcaps = [], []
    for k in segs:
        loc = (np.arange(fine_n) + 0.5) / fine_n * ar.length[k]
        sg = ar.start[k] + loc
        d1 = ar.eval(np.full(fine_n, k), loc, 1)
        with np.errstate(divide="ignore"):
            vel = (vmax[None, :] / np.abs(d1)).min(axis=1)
        v = np.minimum(np.minimum(vel, feeds[k]), np.interp(sg, base_s, base_v))
        d = np.minimum(sg - sec.s_start, sec.s_start + sec.length - sg)
        v = np.minimum(v, 0.5 * jmin * (6.0 * d / jmin) ** (2.0 / 3.0))
        for ks, cap in zip(knot_s, knot_cap, strict=True):
            if np.isfinite(cap):
                v = np.minimum(v, np.sqrt(cap * cap + 0.5 * amin * np.abs(sg - ks)))
        v = np.maximum(v, 1e-6 * max(float(feeds[k]), 1.0))
        fines.append(loc)
        vcaps.append(v)
        dv = np.abs(np.diff(np.concatenate(([v[0]], v))))
        parts.append((ar.length[k] / fine_n / v, dv))
    # measure = share of the estimated time + RAMP_SHARE × share of the speed changes: the ramps
    # (where the jerk switches) get their nodes even on long feed-limited runs
    t_tot = sum(float(t.sum()) for t, _ in parts)
    r_tot = sum(float(r.sum()) for _, r in parts)
    taus = [t / t_tot + (RAMP_SHARE * r / r_tot if r_tot > 0 else 0.0) for t, r in parts]
    tau_seg = np.array([t.sum() for t in taus])
    total = float(tau_seg.sum())
    s_nodes, iseg_parts = [np.array([sec.s_start])], []
    for q, k in enumerate(segs):
        n_min = 2
        if ar.kind[k] == 1:
            sweep = abs(ar.arc[k, 4]) * ar.length[k]
            n_min = max(n_min, math.ceil(sweep / DTHETA_JERK))
        elif ar.kind[k] == 2:
            n_min = max(n_min, math.ceil(ar.length[k] / 0.2))
        n = max(n_min, round(points * tau_seg[q] / total))
        cum = np.concatenate(([0.0], np.cumsum(taus[q])))
        sfine = np.concatenate(([0.0], fines[q] + 0.5 * ar.length[k] / fine_n))
        sfine[-1] = ar.length[k]
        loc = np.interp(np.linspace(0.0, cum[-1], n + 1), cum, sfine)
        loc[0], loc[-1] = 0.0, ar.length[k]
        if ar.kind[k] == 2:
            # a Poly is a chain of cubic Hermite pieces (q″ jumps, q‴ constant per piece): every
            # sample joint is a node so that each interval lies on one piece
            curve = ar.evals[k].segment.geometry
            assert isinstance(curve, Poly)  # kind 2 is a Poly
            joints = np.asarray(curve.cum, dtype=float)
            loc = np.unique(np.concatenate((loc, joints[(joints > 0) & (joints < ar.length[k])])))
            loc = loc[np.concatenate(([True], np.diff(loc) > 1e-9))]
            loc[-1] = ar.length[k]
            loc = _refine_third(curve, loc)
            n = loc.shape[0] - 1
        s_nodes.append(ar.start[k] + loc[1:])
        iseg_parts.append(np.full(n, k))
    s = np.concatenate(s_nodes)
    iseg = np.concatenate(iseg_parts)
    s[-1] = sec.s_start + sec.length
    n_int = iseg.shape[0]
    lo = s[:-1] - ar.start[iseg]
    hi = s[1:] - ar.start[iseg]
    hi = np.minimum(hi, ar.length[iseg])
    delta = np.diff(s)
    if np.any(delta <= 0):
        raise TimingError(f"section {sec.index}{label}: degenerate jerk grid", code=Code.TIMING_JERK_GRID)
    # derivatives inside the interval (Poly pieces are located by bisection, so nudge inwards)
    nudge = np.where(ar.kind[iseg] == 2, 1e-6 * delta, 0.0)
    dl = path_derivatives(ar, iseg, lo + nudge)
    dr = path_derivatives(ar, iseg, hi - nudge)
    rate = np.where(ar.kind[iseg] == 1, np.abs(ar.arc[iseg, 4]), 0.0)
    tighten = np.cos(0.5 * rate * delta)
    # node speed caps: feed and per-axis velocity on both adjacent intervals, knot caps
    with np.errstate(divide="ignore"):
        vl = (vmax[None, :] * tighten[:, None] / np.abs(dl[0])).min(axis=1)
        vr = (vmax[None, :] * tighten[:, None] / np.abs(dr[0])).min(axis=1)
    f = feeds[iseg]
    icap = np.minimum(np.minimum(vl, vr), f)  # per interval (feed and axis velocity)
    cap = np.full(n_int + 1, np.inf)
    cap[:-1] = np.minimum(cap[:-1], np.minimum(vl, f))
    cap[1:] = np.minimum(cap[1:], np.minimum(vr, f))
    # curvature jumps at interior nodes (segment joints, Poly piece joints): |Δq″_k| v² ≤ jmax_k T_c
    dq2_nodes = dl[1][1:] - dr[1][:-1]
    jump = (np.abs(dq2_nodes) > CURVATURE_JUMP_TOL).any(axis=1)
    knot_nodes = np.nonzero(jump)[0] + 1
    knot_dq2 = dq2_nodes[jump]
    with np.errstate(divide="ignore"):
        kc2 = (jmax[None, :] * cycle_s / np.abs(knot_dq2)).min(axis=1)
        if path_jmax is not None:
            kc2 = np.minimum(kc2, path_jmax * cycle_s / np.linalg.norm(knot_dq2, axis=1))
    cap[knot_nodes] = np.minimum(cap[knot_nodes], np.sqrt(kc2))
    cap[0] = cap[-1] = 0.0
    # estimated speed at the nodes
    v0 = np.minimum(
        np.interp(
            s,
            np.concatenate([sec_f + ar.start[k] for sec_f, k in zip(fines, segs, strict=True)]),
            np.concatenate(vcaps),
        ),
        cap,
    )
    v0[0] = v0[-1] = 0.0
    axes_used = np.nonzero((np.abs(dl[0]) + np.abs(dr[0]) + np.abs(dl[1]) + np.abs(dr[1])).max(axis=0) > 1e-12)[0]
    return JerkGrid(s, iseg, delta, dl, dr, tighten, icap, cap, knot_nodes, knot_dq2, v0, axes_used)
