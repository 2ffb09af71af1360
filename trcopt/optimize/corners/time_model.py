"""A fast cycle-time estimate for choosing between transition plans (``estimate_time``).

The ``optimal`` strategy chooses between whole transition plans (G2 transitions, same-ε circular
blends, a per-corner mix) by cycle time. Timing each candidate with the timing stage costs as much
as timing the final plan; this model ranks them in one vectorised pass instead, and the timing
stage times the chosen plan once.

**Model.** The path is a chain of intervals (a line or an arc is one interval, a ``Poly`` curve one
per sample interval) with a speed cap each: the feed (the machine's vector speed limit, and on a
line the per-axis speed limits along its direction) and, on a curve, ``sqrt(A/κ)`` with the larger
curvature of the interval's ends, where ``A`` is the smallest X/Y acceleration limit (and the
vector limit). The speed is zero at the start, at the end and at every stop of the timing stage
(tangent discontinuities, rapid↔feed changes, exact stops: :func:`trcopt.timing.sections.split_sections`).
Between nodes the squared speed changes at the rate ``2A`` per mm — the fastest profile under one
scalar acceleration limit, found by a forward and a backward scan (running minima, no loop) — and
the time of each interval is exact for that profile (accelerate, cruise at the cap, decelerate).

It is an estimate — the same one for every candidate: the timing stage's per-axis limits couple
the tangential and the centripetal acceleration, which the model leaves apart. On the CAM contours
of ``benchmarks/bench_cam_scale.py`` it reads 1–5 % from the timing stage, and the errors of two
candidates differ by up to 5 %: :func:`quicker` trusts it where two plans differ by more than
:data:`MODEL_MARGIN` and times both with the timing stage otherwise.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from trcopt.config import Machine
from trcopt.geometry import Arc, Line, Poly
from trcopt.path import Segment

__all__ = ["MODEL_MARGIN", "estimate_time", "quicker"]

MODEL_MARGIN = 0.08  # estimates closer than this fraction are decided by the timing stage


def quicker(first: Sequence[Segment], second: Sequence[Segment], machine: Machine) -> bool:
    """Whether the plan ``first`` is at least as fast as ``second`` on ``machine``: by
    :func:`estimate_time` where the two estimates differ by more than :data:`MODEL_MARGIN`,
    else by the timing stage's cycle times. A plan that cannot be timed
    (:class:`~trcopt.errors.TimingError`) is not the quicker."""
    from trcopt.errors import TimingError
    from trcopt.timing import time_parameterize

    try:
        t1 = estimate_time(first, machine)
    except TimingError:
        return False
    try:
        t2 = estimate_time(second, machine)
    except TimingError:
        return True
    if abs(t1 - t2) > MODEL_MARGIN * min(t1, t2):
        return t1 < t2
    try:
        t1 = time_parameterize(first, machine).duration
    except TimingError:
        return False
    try:
        return t1 <= time_parameterize(second, machine).duration
    except TimingError:
        return True


def estimate_time(segments: Sequence[Segment], machine: Machine) -> float:
    """Estimated cycle time of ``segments`` on ``machine``, s (see the module description).

    Raises :class:`~trcopt.errors.TimingError` where the timing stage would (a zero-length
    element, a segment without a feed)."""
    from trcopt.timing.path import PathArrays
    from trcopt.timing.sections import path_speed_caps, segment_feeds, split_sections

    segs = list(segments)
    if not segs:
        return 0.0
    feeds = path_speed_caps(segment_feeds(segs, machine), machine)
    ends = {sec.last for sec in split_sections(segs, PathArrays(segs))}
    acc = min(machine.axis("X").amax_mm_s2, machine.axis("Y").amax_mm_s2)
    if machine.path.amax_mm_s2 is not None:
        acc = min(acc, machine.path.amax_mm_s2)
    vmax = np.array([machine.axis(k).vmax_mm_s for k in "XYZ"])
    lengths, caps, node_caps = [], [], [np.zeros(1)]
    for i, seg in enumerate(segs):
        ds, kappa = _intervals(seg.geometry)
        v = min(float(feeds[i]), _axis_speed(seg, vmax))
        cap = np.minimum(v * v, acc / np.maximum(np.maximum(kappa[:-1], kappa[1:]), 1e-300))
        lengths.append(ds)
        caps.append(cap)
        inner = np.minimum(cap[:-1], cap[1:])  # the nodes inside the segment
        node_caps.append(inner)
        node_caps.append(np.zeros(1) if i in ends else cap[-1:])
    L = np.concatenate(lengths)
    C = np.concatenate(caps)
    N = np.concatenate(node_caps)
    # a node between two segments is also capped by the next segment's first interval
    N[1:-1] = np.minimum(N[1:-1], C[1:])
    S = np.concatenate(([0.0], np.cumsum(L)))
    two_a = 2.0 * acc
    forward = two_a * S + np.minimum.accumulate(N - two_a * S)
    back = two_a * (S[-1] - S)
    backward = back + np.minimum.accumulate((N - back)[::-1])[::-1]
    b = np.maximum(np.minimum(np.minimum(forward, backward), N), 0.0)
    return float(np.sum(_interval_times(b[:-1], b[1:], L, C, acc)))


def _intervals(g: Line | Arc | Poly) -> tuple[np.ndarray, np.ndarray]:
    """Interval lengths (mm) and the curvature at the interval ends (1/mm) of one element."""
    if isinstance(g, Line):
        return np.array([g.length]), np.zeros(2)
    if isinstance(g, Arc):
        # a helix: the curvature of the plane circle times (plane length / length)²
        k = (g.plane_length / g.length) ** 2 / g.radius if g.length > 0 else 0.0
        return np.array([g.length]), np.full(2, k)
    cum = np.asarray(g.cum, dtype=float)
    if g.curvatures is not None:
        K = np.asarray(g.curvatures, dtype=float)
    else:
        from trcopt.geometry.poly import hermite_at

        K = hermite_at(g.arrays(), cum, 2)
    return np.diff(cum), np.sqrt(np.einsum("ij,ij->i", K, K))


def _axis_speed(seg: Segment, vmax: np.ndarray) -> float:
    """The per-axis speed limits as a path speed: along a line's direction; the smallest otherwise."""
    g = seg.geometry
    if isinstance(g, Line) and g.length > 0:
        d = np.abs(np.array(g.end) - np.array(g.start)) / g.length  # plane coordinates (u, v, w)
        limit = vmax[list(seg.plane.axes)]  # the limit of the axis each plane coordinate moves
        return float(np.min(np.where(d > 0, limit / np.maximum(d, 1e-300), math.inf)))
    return float(vmax.min())


def _interval_times(b0: np.ndarray, b1: np.ndarray, L: np.ndarray, cap: np.ndarray, acc: float) -> np.ndarray:
    """Time over intervals of length ``L`` entered at squared speed ``b0``, left at ``b1``, with
    the squared speed rising at most 2·acc per mm from either end and at most ``cap``."""
    peak = np.minimum(0.5 * (b0 + b1) + acc * L, cap)
    x_up = np.maximum(peak - b0, 0.0) / (2.0 * acc)
    x_down = np.maximum(peak - b1, 0.0) / (2.0 * acc)
    cruise = np.maximum(L - x_up - x_down, 0.0)
    rp, r0, r1 = np.sqrt(peak), np.sqrt(b0), np.sqrt(b1)
    return (2.0 * rp - r0 - r1) / acc + cruise / np.maximum(rp, 1e-300)
