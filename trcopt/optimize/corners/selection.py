"""The choice between G2 and circular transitions by cycle time (the ``optimal`` strategy's ``select``).

A per-corner G2 quintic needs zero curvature where it meets a line, so between short chords a
circular blend of the same ε can carry more speed under acceleration limits. :func:`fastest`
compares the G2 plan, the same-ε circular blends everywhere and a per-corner mix (chosen by a local
time estimate) by the cycle-time model of :mod:`~trcopt.optimize.corners.time_model` (by the timing
stage where the model cannot tell them apart) and keeps the fastest.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from trcopt.config import DEFAULT_MACHINE
from trcopt.errors import TimingError
from trcopt.geometry import Arc
from trcopt.modes import TransitionKind
from trcopt.optimize.corners.arc import arc_transitions
from trcopt.optimize.corners.assemble import TransitionPlan, assemble
from trcopt.optimize.corners.curves import quintic_basis
from trcopt.optimize.corners.deviation import cut_deviation
from trcopt.optimize.corners.qp import CornerGeometry
from trcopt.optimize.corners.records import CornerResult
from trcopt.optimize.corners.strategies import CornerJob
from trcopt.optimize.corners.time_model import estimate_time, quicker

__all__ = ["fastest"]


def fastest(
    job: CornerJob, plan: TransitionPlan, optimal: CornerResult, circles: CornerResult | None = None
) -> CornerResult:
    """The fastest on ``job.machine`` of: ``optimal`` (the G2 transitions of ``plan``, with splines
    across runs of CAM chords), same-ε circular blends at every site, and a per-corner choice by
    :func:`_local_time` — compared by :func:`~trcopt.optimize.corners.time_model.quicker`. The records
    keep the G2 solutions, so the report says why a corner is circular. ``circles``: the circular
    blends of ``plan.segments`` where the caller has them (computed otherwise)."""
    m = job.machine or DEFAULT_MACHINE
    segs, eps_of, solved = plan.segments, plan.eps, plan.solved
    arc = circles if circles is not None else arc_transitions(replace(job, strategy="arc", toolpath=segs))
    why_arc = "circular blends everywhere are faster than the G2 transitions (cycle time)"
    best = optimal if quicker(optimal.segments, arc.segments, m) else arc
    if best is arc:
        try:
            estimate_time(optimal.segments, m)
        except TimingError as exc:  # a G2 plan the timing stage cannot parameterise is not chosen
            why_arc = f"the G2 plan could not be timed ({exc.message}): circular blends"
    a_lat = min(m.axis("X").amax_mm_s2, m.axis("Y").amax_mm_s2)
    single = plan.single
    choice = {}
    for k, site in single:
        if site.min_cut > 0.0:  # transition circles: G2 or the circle, nothing to choose here
            continue
        sol = solved.get((k, eps_of[k]))
        if sol is None or not sol.ok:
            continue
        built = plan.circle(k, site)
        if built is None:
            continue
        feed_mm_s = segs[k].feed_mm_s
        feed = m.rapid_mm_s if feed_mm_s is None else float(feed_mm_s)
        shorter = _local_time(sol.geometry, built, feed, a_lat) <= 0.0
        choice[k] = TransitionKind.QUINTIC if shorter else TransitionKind.ARC
    if set(choice.values()) == {TransitionKind.QUINTIC, TransitionKind.ARC}:
        hybrid = assemble(segs, single, eps_of, solved, job.strategy, choice, plan.splines, plan.circles)
        hybrid.max_deviation_mm = cut_deviation(job.programmed, segs, hybrid.segments)[0]
        if hybrid.max_deviation_mm <= job.tolerance_mm and not quicker(best.segments, hybrid.segments, m):
            best = hybrid
    if best is arc:
        # the closed-form circular blends, with the G2 solutions in the records: the report says
        # why each corner is circular
        every = dict(plan.sites or single)
        best.corners = [
            replace(
                c,
                solution=solved.get((c.index, eps_of[c.index])),
                reason=c.reason or why_arc,
            )
            if c.index in every and c.index in eps_of
            else c
            for c in arc.corners
        ]
    best.mode = job.strategy
    return best


def _local_time(q: CornerGeometry, built: tuple[Arc, float, float], feed: float, a_lat: float) -> float:
    """Estimated time of the quintic minus that of the circular blend over the same stretch
    (from the farther start to the farther end of the two), s: each curve at
    ``min(feed, sqrt(a_lat/|κ|))`` (mm/s; ``a_lat`` mm/s²), the uncovered line pieces at the feed."""
    arc, ta, tb = built
    C = np.array([q.p0, q.d0, q.a0, q.a1, q.d1, q.p1])
    H0, H1, H2 = quintic_basis(np.linspace(0.0, 1.0, 129))
    d1, d2 = H1 @ C, H2 @ C
    sp = np.hypot(d1[:, 0], d1[:, 1])
    kappa = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.maximum(sp, 1e-300) ** 3
    inv_v = 1.0 / np.minimum(feed, np.sqrt(a_lat / np.maximum(kappa, 1e-300)))
    f = sp * inv_v
    t_q = float(np.sum(0.5 * (f[1:] + f[:-1])) / 128.0)
    t_a = arc.plane_length / min(feed, math.sqrt(a_lat * arc.radius))
    sa, sb = max(q.sa, ta), max(q.sb, tb)
    t_q += (sa - q.sa + sb - q.sb) / feed
    t_a += (sa - ta + sb - tb) / feed
    return t_q - t_a
