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

Two plans of one polyline without compensation — circular blends at every corner, or run splines
instead where there are runs of CAM chords — follow the same chords within ε, and the model's
errors of the two are much closer: their ratio read −1.1 … +0.7 % from the timing stage's on the
freeform contours of 100–2 000 chords at ε 0.003–0.1 mm, +3.7 % at a feed near the axis speed
limits (``benchmarks/CORNERS.md``), so that choice trusts the model beyond :data:`RUN_SPLINE_MARGIN`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from itertools import chain

import numpy as np

from trcopt.config import Machine
from trcopt.geometry import Arc, Line, Poly
from trcopt.path import Segment

__all__ = ["MODEL_MARGIN", "RUN_SPLINE_MARGIN", "estimate_time", "quicker"]

CURVES_AT_ONCE = 4096  # curves whose samples are gathered in one pass
SECTION_WINDOW = 8192  # segments whose sections are found at once
MODEL_MARGIN = 0.08  # estimates closer than this fraction are decided by the timing stage
RUN_SPLINE_MARGIN = 0.05  # the same for run splines against circular blends on one polyline


def quicker(
    first: Sequence[Segment], second: Sequence[Segment], machine: Machine, margin: float = MODEL_MARGIN
) -> bool:
    """Whether the plan ``first`` is at least as fast as ``second`` on ``machine``: by
    :func:`estimate_time` where the two estimates differ by more than ``margin`` (a fraction),
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
    if abs(t1 - t2) > margin * min(t1, t2):
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
    from trcopt.timing.sections import path_speed_caps, segment_feeds

    segs = list(segments)
    if not segs:
        return 0.0
    feeds = path_speed_caps(segment_feeds(segs, machine), machine)
    ends = _section_ends(segs)
    acc = min(machine.axis("X").amax_mm_s2, machine.axis("Y").amax_mm_s2)
    if machine.path.amax_mm_s2 is not None:
        acc = min(acc, machine.path.amax_mm_s2)
    vmax = np.array([machine.axis(k).vmax_mm_s for k in "XYZ"])
    L, k_ends, first = _intervals(segs)
    v = np.minimum(np.asarray(feeds, dtype=float), _axis_speeds(segs, vmax))
    C = np.minimum(np.repeat(v * v, np.diff(first)), acc / np.maximum(np.maximum(k_ends[0], k_ends[1]), 1e-300))
    # node caps: zero at the start, inside a segment the smaller cap of its two intervals, at a
    # segment's end zero at a stop of the timing stage, else its last interval's cap
    N = np.empty(len(C) + 1)
    N[0] = 0.0
    N[1:-1] = np.minimum(C[:-1], C[1:])
    last = first[1:] - 1
    N[last + 1] = np.where(np.isin(np.arange(len(segs)), list(ends)), 0.0, C[last])
    # a node between two segments is also capped by the next segment's first interval
    N[1:-1] = np.minimum(N[1:-1], C[1:])
    S = np.concatenate(([0.0], np.cumsum(L)))
    two_a = 2.0 * acc
    forward = two_a * S + np.minimum.accumulate(N - two_a * S)
    back = two_a * (S[-1] - S)
    backward = back + np.minimum.accumulate((N - back)[::-1])[::-1]
    b = np.maximum(np.minimum(np.minimum(forward, backward), N), 0.0)
    return float(np.sum(_interval_times(b[:-1], b[1:], L, C, acc)))


def _section_ends(segs: Sequence[Segment]) -> set[int]:
    """The last segment of every section of the timing stage
    (:func:`trcopt.timing.sections.split_sections`), found over windows of SECTION_WINDOW segments
    that share one segment with the next (whether the path stops at a joint depends on its two
    segments only; the path arrays of a whole path of 10⁵ spline pieces hold hundreds of MB).
    Raises the whole path's :class:`~trcopt.errors.TimingError` where a window has one."""
    from trcopt.errors import TimingError
    from trcopt.timing.path import PathArrays
    from trcopt.timing.sections import split_sections

    n = len(segs)
    out: set[int] = set()
    try:
        for a in range(0, max(n - 1, 1), SECTION_WINDOW - 1):
            b = min(a + SECTION_WINDOW, n)
            part = segs[a:b]
            # the window's last segment ends a section where the next window says so
            out.update(a + sec.last for sec in split_sections(part, PathArrays(part)) if a + sec.last < b - 1 or b == n)
    except TimingError:
        return {sec.last for sec in split_sections(segs, PathArrays(segs))}
    return out


def _intervals(segs: Sequence[Segment]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The intervals of the path: their lengths (mm), the curvature at their two ends (2×m,
    1/mm) and the index of every segment's first interval (one more at the end): a line or an arc
    is one interval, a ``Poly`` one per sample interval. The curves' samples are gathered into one
    set of arrays (their curvatures as recorded, else from the interpolation)."""
    count = np.ones(len(segs), dtype=np.int64)
    single: list[tuple[int, float, float]] = []  # lines and arcs: segment, length, curvature
    curves: list[tuple[int, Poly]] = []
    for i, seg in enumerate(segs):
        g = seg.geometry
        if isinstance(g, Line):
            single.append((i, g.length, 0.0))
        elif isinstance(g, Arc):
            # a helix: the curvature of the plane circle times (plane length / length)²
            single.append((i, g.length, (g.plane_length / g.length) ** 2 / g.radius if g.length > 0 else 0.0))
        else:
            count[i] = len(g.cum) - 1
            curves.append((i, g))
    first = np.concatenate(([0], np.cumsum(count)))
    L = np.empty(int(first[-1]))
    k_ends = np.empty((2, len(L)))
    if single:
        at, length, kappa = (np.array(x) for x in zip(*single, strict=True))
        L[first[at]], k_ends[0, first[at]], k_ends[1, first[at]] = length, kappa, kappa
    if curves:
        # (the samples a few thousand curves at a time: a path of 10⁵ spline pieces has millions)
        parts = [curves[i : i + CURVES_AT_ONCE] for i in range(0, len(curves), CURVES_AT_ONCE)]
        cum = np.concatenate([np.fromiter(chain.from_iterable(g.cum for _, g in part), float) for part in parts])
        kappa = np.concatenate([_norms(part) for part in parts])
        n = np.array([len(g.cum) for _, g in curves])
        start = np.concatenate(([0], np.cumsum(n)))[:-1]  # each curve's first sample
        inner = np.ones(len(cum), bool)
        inner[start] = False
        j = np.nonzero(inner)[0]  # the interval from sample j − 1 to sample j
        c = np.repeat(np.arange(len(curves)), n)[j]
        at = first[np.array([i for i, _ in curves])][c] + (j - start[c]) - 1
        L[at], k_ends[0, at], k_ends[1, at] = cum[j] - cum[j - 1], kappa[j - 1], kappa[j]
    return L, k_ends, first


def _norms(curves: Sequence[tuple[int, Poly]]) -> np.ndarray:
    """The curvature (1/mm) at every sample of ``curves``, one curve after the other."""
    K = np.array(list(chain.from_iterable(_curvatures(g) for _, g in curves)), dtype=float)
    K = K.reshape(sum(len(g.cum) for _, g in curves), -1)
    return np.sqrt(np.einsum("ij,ij->i", K, K))


def _curvatures(g: Poly) -> Sequence[Sequence[float]]:
    """The curvature vectors at the samples of ``g`` (as recorded, else from the interpolation)."""
    if g.curvatures is not None:
        return g.curvatures
    from trcopt.geometry.poly import hermite_at

    return hermite_at(g.arrays(), np.asarray(g.cum, dtype=float), 2).tolist()


def _axis_speeds(segs: Sequence[Segment], vmax: np.ndarray) -> np.ndarray:
    """The per-axis speed limits as a path speed per segment: along a line's direction; the
    smallest otherwise."""
    out = np.full(len(segs), float(vmax.min()))
    lines = [(i, s) for i, s in enumerate(segs) if isinstance(s.geometry, Line) and s.geometry.length > 0]
    if lines:
        at = np.array([i for i, _ in lines])
        g = [s.geometry for _, s in lines]
        d = (
            np.abs(np.array([e.end for e in g]) - np.array([e.start for e in g]))
            / np.array([e.length for e in g])[:, None]
        )
        limit = vmax[np.array([s.plane.axes for _, s in lines])]  # the limit of the axis each coordinate moves
        out[at] = np.min(np.where(d > 0, limit / np.maximum(d, 1e-300), math.inf), axis=1)
    return out


def _interval_times(b0: np.ndarray, b1: np.ndarray, L: np.ndarray, cap: np.ndarray, acc: float) -> np.ndarray:
    """Time over intervals of length ``L`` entered at squared speed ``b0``, left at ``b1``, with
    the squared speed rising at most 2·acc per mm from either end and at most ``cap``."""
    peak = np.minimum(0.5 * (b0 + b1) + acc * L, cap)
    x_up = np.maximum(peak - b0, 0.0) / (2.0 * acc)
    x_down = np.maximum(peak - b1, 0.0) / (2.0 * acc)
    cruise = np.maximum(L - x_up - x_down, 0.0)
    rp, r0, r1 = np.sqrt(peak), np.sqrt(b0), np.sqrt(b1)
    return (2.0 * rp - r0 - r1) / acc + cruise / np.maximum(rp, 1e-300)
