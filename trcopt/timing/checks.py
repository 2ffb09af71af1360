"""Checks both kinds of trajectory share: finite-difference jerk and deviation from the exact path.

Used by the limit checks of :class:`~trcopt.timing.TimedTrajectory` and
:class:`~trcopt.timing.jerk.JerkTrajectory`, and by the benchmarks; every function takes what it
needs through the :class:`~trcopt.trajectory.Trajectory` protocol or as plain arrays.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from trcopt.path import Segment
from trcopt.trajectory import Samples, Trajectory

__all__ = ["max_jerk", "path_deviation", "axis_triple", "DEVIATION_PROBES"]

DEVIATION_PROBES = 64  # states compared with the exact geometry; spread evenly over the profile


def max_jerk(traj: Trajectory, dt: float = 1e-3) -> np.ndarray:
    """Finite-difference per-axis jerk max |Δa|/dt at ``dt`` sampling, mm/s³ (X, Y, Z).

    Of an acceleration-limited profile this is unbounded as ``dt`` → 0 (the acceleration jumps
    between grid intervals); zeros for an empty path or one shorter than ``dt`` (s).
    """
    if not traj.segments or traj.duration <= dt:
        return np.zeros(3)
    smp = traj.sample(dt)
    return (np.abs(np.diff(smp.a, axis=0)) / np.diff(smp.t)[:, None]).max(axis=0)


def path_deviation(segments: Sequence[Segment], starts: np.ndarray, states: Samples) -> float:
    """Largest distance (mm) of sampled positions from the segments' own geometry.

    The trajectories evaluate positions with the vectorised closed forms of
    :class:`~trcopt.timing.path.PathArrays`; comparing a few states with ``geometry.point`` is an
    independent check of that evaluator.

    Parameters
    ----------
    segments:
        The tool path.
    starts:
        Arc length at the start of every segment, mm.
    states:
        States to probe (``DEVIATION_PROBES`` of them, evenly spread, are compared).
    """
    n = states.t.shape[0]
    dev = 0.0
    for j in np.linspace(0, n - 1, min(n, DEVIATION_PROBES)).astype(int):
        k = int(states.segment[j])
        seg = segments[k]
        local = float(states.s[j] - starts[k])
        ref = np.array(seg.plane.to_xyz(seg.geometry.point(min(max(local, 0.0), seg.geometry.length))))
        dev = max(dev, float(np.linalg.norm(ref - states.xyz[j])))
    return dev


def axis_triple(values: np.ndarray) -> tuple[float, float, float]:
    """The X, Y, Z entries of a per-axis array as plain floats (for reports and JSON)."""
    return (float(values[0]), float(values[1]), float(values[2]))
