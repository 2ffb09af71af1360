"""Checks both kinds of trajectory share: finite-difference jerk, deviation from the exact path and
the vector (path) limits.

Used by the limit checks of :class:`~trcopt.timing.TimedTrajectory` and
:class:`~trcopt.timing.jerk.JerkTrajectory`, and by the benchmarks; every function takes what it
needs through the :class:`~trcopt.trajectory.Trajectory` protocol or as plain arrays.
:class:`PathLimitReport` is the :class:`~trcopt.trajectory.LimitReport` both return, with the
ratios to the machine's vector limits (``machine.path``) added.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from trcopt.codes import Code
from trcopt.config import PathLimits
from trcopt.errors import TimingError
from trcopt.path import Segment
from trcopt.trajectory import LimitReport, Samples, Trajectory

__all__ = [
    "MAX_SAMPLES",
    "SAMPLE_CHUNK",
    "sample_times",
    "sample_chunks",
    "check_step",
    "max_jerk",
    "path_deviation",
    "axis_triple",
    "path_ratios",
    "worst",
    "PathLimitReport",
    "DEVIATION_PROBES",
]

DEVIATION_PROBES = 64  # states compared with the exact geometry; spread evenly over the profile


#: most samples one profile is sampled at (one hour at 1 ms); longer cycles are sampled coarser
MAX_SAMPLES = 3_600_000


def sample_times(duration: float, dt: float) -> np.ndarray:
    """Times every ``dt`` seconds from 0 to ``duration``, both included, s.

    Raises
    ------
    TimingError
        ``duration`` is not finite, or it needs more than :data:`MAX_SAMPLES` samples at ``dt``.
    """
    if dt <= 0:
        raise ValueError("dt must be positive (s)")
    if not np.isfinite(duration) or duration / dt + 1 > MAX_SAMPLES:
        raise TimingError(
            f"a cycle of {duration:.6g} s sampled every {dt:g} s needs more than {MAX_SAMPLES} samples "
            "(trcopt.timing.trajectory.MAX_SAMPLES)",
            code=Code.TIMING,
        )
    n = int(np.floor(duration / dt)) + 1
    ts = np.arange(n) * dt
    if ts[-1] < duration:
        ts = np.append(ts, duration)
    return ts


SAMPLE_CHUNK = 1 << 18  # samples evaluated at once by the limit checks (bounded memory)


def sample_chunks(duration: float, dt: float, chunk: int = SAMPLE_CHUNK, overlap: int = 0) -> Iterator[np.ndarray]:
    """:func:`sample_times` in consecutive pieces of at most ``chunk`` times (each piece repeating
    the last ``overlap`` times of the one before): the same times, without holding every sample's
    state at once."""
    ts = sample_times(duration, dt)
    step = max(chunk - overlap, 1)
    for a in range(0, max(ts.shape[0] - overlap, 1), step):
        yield ts[a : a + chunk]


def check_step(duration_s: float, dt_s: float) -> float:
    """The sampling step of a limit check of a ``duration_s`` cycle: ``dt_s``, or coarser for a
    cycle so long that ``dt_s`` would need more than :data:`MAX_SAMPLES` samples (every grid point
    is checked exactly whatever the step)."""
    return max(dt_s, duration_s / (MAX_SAMPLES - 8))


def max_jerk(traj: Trajectory, dt: float = 1e-3) -> np.ndarray:
    """Finite-difference per-axis jerk max |Δa|/dt at ``dt`` sampling, mm/s³ (X, Y, Z).

    Of an acceleration-limited profile this is unbounded as ``dt`` → 0 (the acceleration jumps
    between grid intervals); zeros for an empty path or one shorter than ``dt`` (s).
    """
    if not traj.segments or traj.duration <= dt:
        return np.zeros(3)
    # consecutive pieces overlapping by one sample: every difference of the whole sampling once
    out = None
    for ts in sample_chunks(traj.duration, check_step(traj.duration, dt), overlap=1):
        smp = traj.evaluate(ts)
        part = (np.abs(np.diff(smp.a, axis=0)) / np.diff(smp.t)[:, None]).max(axis=0)
        out = part if out is None else np.maximum(out, part)
    assert out is not None
    return out


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


def path_ratios(
    limits: PathLimits, *states: Samples, jerk: np.ndarray | None = None
) -> tuple[float | None, float | None, float | None]:
    """Largest ratios of the states to the vector limits: ``(|v|/vmax, |a|/amax, |j|/jmax)``.

    Each ratio is None where the limit is not given; ``|j|`` is taken from the states' ``j`` (when
    they carry it) and from the extra norms ``jerk`` (mm/s³, e.g. knot steps divided by the cycle);
    it stays None for states without jerk.
    """

    def ratio(limit: float | None, values: list[np.ndarray]) -> float | None:
        if limit is None:
            return None
        return max((float(v.max()) for v in values if v.size), default=0.0) / limit

    speeds = [np.asarray(st.speed) for st in states]
    accs = [np.linalg.norm(st.a, axis=1) for st in states]
    jerks = [np.linalg.norm(st.j, axis=1) for st in states if st.j is not None]
    if jerk is not None:
        jerks.append(np.asarray(jerk))
    pj = ratio(limits.jmax_mm_s3, jerks) if jerks else None
    return ratio(limits.vmax_mm_s, speeds), ratio(limits.amax_mm_s2, accs), pj


def worst(*ratios: float | None) -> float | None:
    """The largest of the given ratios, None when none is given (max over several checks)."""
    given = [r for r in ratios if r is not None]
    return max(given) if given else None


@dataclass(frozen=True)
class PathLimitReport(LimitReport):
    """:class:`~trcopt.trajectory.LimitReport` plus the ratios to the vector (path) limits.

    ``ok`` covers these ratios as well (each ≤ ``tolerance``).

    Attributes
    ----------
    path_v_ratio:
        Largest path speed / ``machine.path.vmax_mm_s``, or None without that limit.
    path_a_ratio:
        Largest |a| / ``machine.path.amax_mm_s2`` (norm of the acceleration vector), or None.
    path_j_ratio:
        Largest |j| / ``machine.path.jmax_mm_s3`` (jerk-limited profiles: the analytic jerk of
        the smooth pieces and the knot steps over the cycle), or None without that limit or for
        a profile that does not bound the jerk.
    """

    path_v_ratio: float | None = None
    path_a_ratio: float | None = None
    path_j_ratio: float | None = None

    @property
    def path_given(self) -> bool:
        """True when any vector-limit ratio was checked."""
        return any(r is not None for r in (self.path_v_ratio, self.path_a_ratio, self.path_j_ratio))

    def path_text(self) -> str:
        """``; path |v|/vmax = …, |a|/amax = …`` for the ratios that were checked (else empty)."""
        named = (("|v|/vmax", self.path_v_ratio), ("|a|/amax", self.path_a_ratio), ("|j|/jmax", self.path_j_ratio))
        parts = [f"{name} = {r:.4f}" for name, r in named if r is not None]
        return f"; path {', '.join(parts)}" if parts else ""

    def path_json(self) -> dict[str, float | None]:
        """The vector-limit ratios by key ``v``, ``a``, ``j`` (None where not checked)."""
        return {"v": self.path_v_ratio, "a": self.path_a_ratio, "j": self.path_j_ratio}

    def __str__(self) -> str:
        return super().__str__() + self.path_text()

    def to_json(self) -> dict[str, Any]:
        out = super().to_json()
        if self.path_given:
            out["path_ratio"] = self.path_json()
        return out
