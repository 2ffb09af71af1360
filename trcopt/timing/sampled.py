"""The sampled limit check and jerk measure of an acceleration-limited profile, by interval.

Sampling every ``dt`` puts the samples of one grid interval of :class:`~trcopt.timing.TimedTrajectory`
at consecutive indices: sample ``k`` lies in the interval ``i`` with ``t_i ≤ t_k < t_{i+1}`` (the
last interval also takes the samples at its end). On a **line** the direction ``p′`` is constant
and ``p″ = 0``, so over one interval

* the axis velocities ``p′·ṡ`` and the feed ratio ``ṡ/F`` are monotone in the sample time (the
  computed ``ṡ = max(ṡ_i + s̈·τ, 0)`` is monotone in ``τ``: every floating-point operation in it is),
  so their largest values over the interval's samples are those at its first or its last sample;
* the axis accelerations ``p′·s̈ + p″·ṡ²`` are the same at every sample (up to the sign of a zero),
  so consecutive samples inside the interval differ by exactly zero.

The check and the jerk measure therefore evaluate the first and the last sample of every line
interval and every sample of the other intervals (arcs, curves), with the formulas of
:meth:`TimedTrajectory.evaluate`, and give the maxima of sampling every state, bit for bit.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Protocol

import numpy as np

from trcopt.timing.checks import SAMPLE_CHUNK, sample_times
from trcopt.timing.path import PathArrays


class TimedTrajectory(Protocol):
    """What these functions read of a :class:`trcopt.timing.TimedTrajectory`."""

    arrays: PathArrays | None
    t: np.ndarray  # time at every grid point, s
    s: np.ndarray  # arc length, mm
    sd: np.ndarray  # path speed, mm/s
    u: np.ndarray  # path acceleration per interval, mm/s²
    iseg: np.ndarray  # segment per interval

    @property
    def duration(self) -> float: ...

__all__ = ["kinematics", "sample_pieces", "sampled_jerk", "interval_kinematics"]


def kinematics(
    traj: TimedTrajectory, i: np.ndarray, s: np.ndarray, sd: np.ndarray, u: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Segment, axis velocity and axis acceleration of the states at arc length ``s`` with path
    speed ``sd`` and path acceleration ``u`` in the intervals ``i`` (as ``_samples_at``, without
    the positions)."""
    arrays = traj.arrays
    assert arrays is not None
    seg = traj.iseg[i]
    local = np.clip(s - arrays.start[seg], 0.0, arrays.length[seg])
    d1, d2 = arrays.eval_orders(seg, local, (1, 2))
    v = d1 * sd[:, None]
    a = d1 * u[:, None] + d2 * (sd * sd)[:, None]
    return seg, v, a


def interval_kinematics(
    traj: TimedTrajectory, ts: np.ndarray, i: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(segment, speed, v, a)`` at the times ``ts`` in the intervals ``i`` (as ``evaluate``)."""
    tau = ts - traj.t[i]
    u = traj.u[i]
    sd = np.maximum(traj.sd[i] + u * tau, 0.0)
    s = np.minimum(traj.s[i] + traj.sd[i] * tau + 0.5 * u * tau * tau, traj.s[i + 1])
    seg, v, a = kinematics(traj, i, s, sd, u)
    return seg, sd, v, a


def sample_pieces(traj: TimedTrajectory, dt: float, chunk: int = SAMPLE_CHUNK) -> Iterator[tuple[np.ndarray, ...]]:
    """The samples every ``dt`` s that decide the sampled maxima (module description), in time
    order and in pieces of at most ``chunk``: ``(k, ts, i)`` — sample index, time and interval.
    Consecutive pieces share one sample (the last of a piece is the first of the next)."""
    ts = sample_times(traj.duration, dt)
    t = traj.t
    m = t.shape[0] - 1  # intervals
    # the samples of interval i: first[i] .. end[i]-1 (the index arithmetic of searchsorted(t, ts, "right") - 1,
    # clipped to the intervals, inverted)
    inner = np.searchsorted(ts, t[1:m], side="left")
    first = np.concatenate(([0], inner))
    end = np.append(inner, ts.shape[0])
    count = end - first
    assert traj.arrays is not None
    line = traj.arrays.kind[traj.iseg] == 0
    n_eval = np.where(line, np.minimum(count, 2), count)
    cum = np.cumsum(n_eval)
    total = int(cum[-1])
    step = max(chunk - 1, 1)
    for a in range(0, max(total - 1, 1), step):
        pos = np.arange(a, min(a + chunk, total))
        i = np.searchsorted(cum, pos, side="right")
        j = pos - (cum[i] - n_eval[i])  # the j-th evaluated sample of interval i
        k = first[i] + np.where(line[i] & (j == 1), count[i] - 1, j)
        yield k, ts[k], i


def sampled_jerk(traj: TimedTrajectory, dt: float) -> np.ndarray:
    """:func:`~trcopt.timing.checks.max_jerk` of an acceleration-limited profile at the sampling
    ``dt`` (s): the largest ``|Δa|/Δt`` of consecutive samples, those inside one line interval
    differing by zero."""
    out = np.zeros(3)
    for k, ts, i in sample_pieces(traj, dt):
        _, _, _, a = interval_kinematics(traj, ts, i)
        next_ = k[1:] == k[:-1] + 1  # consecutive samples (the others lie inside one line interval)
        if np.any(next_):
            part = (np.abs(np.diff(a, axis=0))[next_] / np.diff(ts)[next_][:, None]).max(axis=0)
            out = np.maximum(out, part)
    return out
