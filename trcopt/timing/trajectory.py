"""``TimedTrajectory``: the time-parameterised tool-centre path.

The profile is stored as grid points ``s_0 < … < s_M`` (mm) with squared path speeds
``x_i = ṡ²`` and the segment of every interval; between two grid points the path acceleration
``s̈ = (x_{i+1} − x_i)/(2Δ_i)`` is constant (toppra's ``ParametrizeConstAccel`` model), so the tool
follows the exact geometry and ``t_{i+1} − t_i = 2Δ_i/(ṡ_i + ṡ_{i+1})``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from trcopt.config import Machine
from trcopt.errors import TimingError
from trcopt.path import Segment
from trcopt.timing.path import PathArrays
from trcopt.timing.sections import Section, axis_limits

__all__ = ["TimedTrajectory", "Samples", "LimitReport", "sample_times"]


def sample_times(duration: float, dt: float) -> np.ndarray:
    """Times every ``dt`` seconds from 0 to ``duration``, both included, s."""
    if dt <= 0:
        raise ValueError("dt must be positive (s)")
    n = int(np.floor(duration / dt)) + 1
    ts = np.arange(n) * dt
    if ts[-1] < duration:
        ts = np.append(ts, duration)
    return ts


@dataclass(frozen=True)
class Samples:
    """A sampling of the trajectory (arrays of equal length; xyz, v, a have 3 columns X, Y, Z)."""

    t: np.ndarray  # s
    s: np.ndarray  # mm along the whole path
    xyz: np.ndarray  # mm
    speed: np.ndarray  # mm/s
    v: np.ndarray  # mm/s per axis
    a: np.ndarray  # mm/s² per axis
    segment: np.ndarray  # index into the tool path
    block: np.ndarray  # source block label (str)
    sdd: np.ndarray  # path acceleration, mm/s²


@dataclass(frozen=True)
class LimitReport:
    """Result of :meth:`TimedTrajectory.check_limits` (ratios are max over samples and grid ends)."""

    ok: bool
    v_ratio: tuple[float, float, float]
    a_ratio: tuple[float, float, float]
    feed_ratio: float
    corner_speed_mm_s: float
    path_deviation_mm: float
    tolerance: float
    samples: int

    def __str__(self) -> str:
        v = ", ".join(f"{r:.4f}" for r in self.v_ratio)
        a = ", ".join(f"{r:.4f}" for r in self.a_ratio)
        return (
            f"{'PASS' if self.ok else 'FAIL'}: v/vmax (X,Y,Z) = {v}; a/amax = {a}; feed {self.feed_ratio:.4f}; "
            f"corner speed {self.corner_speed_mm_s:.2e} mm/s; deviation {self.path_deviation_mm:.1e} mm"
        )

    def to_json(self) -> dict[str, Any]:
        return {
            "ok": self.ok,
            "v_ratio": dict(zip("XYZ", self.v_ratio, strict=True)),
            "a_ratio": dict(zip("XYZ", self.a_ratio, strict=True)),
            "feed_ratio": self.feed_ratio,
            "corner_speed_mm_s": self.corner_speed_mm_s,
            "path_deviation_mm": self.path_deviation_mm,
        }


class TimedTrajectory:
    """Time-optimal feed along a tool path (build with :func:`trcopt.timing.time_parameterize`)."""

    def __init__(
        self,
        segments: Sequence[Segment],
        machine: Machine,
        feeds: np.ndarray,
        arrays: PathArrays | None,
        sections: Sequence[Section],
        engines: Sequence[str],
        s: np.ndarray,
        x: np.ndarray,
        iseg: np.ndarray,
        section_points: np.ndarray,
    ) -> None:
        self.segments = list(segments)
        self.machine = machine
        self.feeds = feeds
        self.arrays = arrays
        self.sections = list(sections)
        self.engines = list(engines)
        self.s = s
        self.x = np.maximum(x, 0.0)
        self.iseg = iseg
        self.section_points = section_points  # grid index of each section start (+ final index)
        self.sd = np.sqrt(self.x)
        delta = np.diff(s)
        den = self.sd[:-1] + self.sd[1:]
        if np.any((den <= 0) & (delta > 0)):
            i = int(np.nonzero((den <= 0) & (delta > 0))[0][0])
            seg = self.segments[int(iseg[i])]
            raise TimingError(
                f"zero speed over a whole interval at s={s[i]:.6f} mm (block {seg.span.block_label()}); "
                "remedy: check the limits of the machine and the feed of the block",
                seg.span,
                "TIMING-STUCK",
            )
        with np.errstate(divide="ignore", invalid="ignore"):
            dt = np.where(delta > 0, 2.0 * delta / den, 0.0)
            self.u = np.where(delta > 0, (self.x[1:] - self.x[:-1]) / (2.0 * delta), 0.0)
        self.t = np.concatenate(([0.0], np.cumsum(dt)))

    # -- construction ---------------------------------------------------------------------------
    @classmethod
    def empty(cls, machine: Machine) -> TimedTrajectory:
        z = np.zeros(1)
        return cls(
            [], machine, np.zeros(0), None, [], [], z, z, np.zeros(0, dtype=np.int64), np.zeros(1, dtype=np.int64)
        )

    @classmethod
    def assemble(
        cls,
        segments: Sequence[Segment],
        machine: Machine,
        feeds: np.ndarray,
        arrays: PathArrays,
        sections: Sequence[Section],
        engines: Sequence[str],
        results: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]],
    ) -> TimedTrajectory:
        ss, xs, segs, starts = [], [], [], []
        n = 0
        for sec in sections:
            s, x, iseg = results[sec.index]
            if ss:
                s, x = s[1:], x[1:]  # the section start coincides with the previous end (speed 0)
            starts.append(max(n - 1, 0) if ss else 0)
            ss.append(s)
            xs.append(x)
            segs.append(iseg)
            n += s.shape[0]
        starts.append(n - 1)
        return cls(
            segments, machine, feeds, arrays, sections, engines,
            np.concatenate(ss), np.concatenate(xs), np.concatenate(segs).astype(np.int64), np.array(starts),
        )

    # -- basic queries --------------------------------------------------------------------------
    @property
    def duration(self) -> float:
        """Cycle time, s."""
        return float(self.t[-1])

    @property
    def length(self) -> float:
        """Path length, mm."""
        return float(self.s[-1])

    def time_at(self, s_query: np.ndarray) -> np.ndarray:
        """Time (s) at which the tool passes arc lengths ``s_query`` (mm)."""
        s_query = np.asarray(s_query, dtype=float)
        i = np.clip(np.searchsorted(self.s, s_query, side="right") - 1, 0, max(len(self.s) - 2, 0))
        if len(self.s) < 2:
            return np.zeros_like(s_query)
        ds = np.clip(s_query - self.s[i], 0.0, None)
        u = self.u[i]
        sd0 = self.sd[i]
        sd1 = np.sqrt(np.maximum(self.x[i] + 2.0 * u * ds, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            tau = np.where(np.abs(u) > 1e-12, (sd1 - sd0) / np.where(u == 0, 1.0, u), ds / np.where(sd0 > 0, sd0, 1.0))
        tau = np.where(ds > 0, tau, 0.0)
        return self.t[i] + tau

    def segments_with_times(self) -> list[Segment]:
        """The tool path with ``t_start_s``/``t_end_s`` set on every segment."""
        if not self.segments:
            return []
        assert self.arrays is not None
        starts = self.arrays.start
        t0 = self.time_at(starts)
        t1 = np.append(t0[1:], self.duration)
        return [seg.with_times(float(a), float(b)) for seg, a, b in zip(self.segments, t0, t1, strict=True)]

    # -- sampling -------------------------------------------------------------------------------
    def _state_at(self, ts: np.ndarray) -> tuple[np.ndarray, ...]:
        i = np.clip(np.searchsorted(self.t, ts, side="right") - 1, 0, len(self.t) - 2)
        tau = ts - self.t[i]
        u = self.u[i]
        sd = np.maximum(self.sd[i] + u * tau, 0.0)
        s = np.minimum(self.s[i] + self.sd[i] * tau + 0.5 * u * tau * tau, self.s[i + 1])
        return i, s, sd, u

    def evaluate(self, ts: np.ndarray) -> Samples:
        """State at the times ``ts`` (s)."""
        ts = np.asarray(ts, dtype=float)
        if self.arrays is None or len(self.t) < 2:
            z = np.zeros((ts.shape[0], 3))
            e = np.zeros(ts.shape[0])
            return Samples(ts, e, z, e, z, z, e.astype(int), np.array([""] * ts.shape[0]), e)
        i, s, sd, u = self._state_at(ts)
        return self._samples_at(ts, i, s, sd, u)

    def _samples_at(self, ts: np.ndarray, i: np.ndarray, s: np.ndarray, sd: np.ndarray, u: np.ndarray) -> Samples:
        assert self.arrays is not None
        seg = self.iseg[i]
        local = np.clip(s - self.arrays.start[seg], 0.0, self.arrays.length[seg])
        p = self.arrays.eval(seg, local, 0)
        d1 = self.arrays.eval(seg, local, 1)
        d2 = self.arrays.eval(seg, local, 2)
        v = d1 * sd[:, None]
        a = d1 * u[:, None] + d2 * (sd * sd)[:, None]
        labels = np.array([sg.span.block_label() for sg in self.segments], dtype=object)
        return Samples(ts, s, p, sd, v, a, seg, labels[seg], u)

    def sample(self, dt: float = 1e-3) -> Samples:
        """Samples every ``dt`` seconds from 0 to the duration (both included)."""
        return self.evaluate(sample_times(self.duration, dt))

    def grid_states(self) -> Samples:
        """The state at both ends of every grid interval, evaluated inside the interval."""
        if self.arrays is None or len(self.t) < 2:
            return self.evaluate(np.zeros(1))
        m = len(self.t) - 1
        i = np.concatenate((np.arange(m), np.arange(m)))
        end = np.concatenate((np.zeros(m, bool), np.ones(m, bool)))
        s = np.where(end, self.s[i + 1], self.s[i])
        sd = np.where(end, self.sd[i + 1], self.sd[i])
        ts = np.where(end, self.t[i + 1], self.t[i])
        return self._samples_at(ts, i, s, sd, self.u[i])

    # -- reports (see report.py) ----------------------------------------------------------------
    def check_limits(self, dt: float = 1e-4, tolerance: float = 1.001) -> LimitReport:
        """Per-axis v and a, feed and corner speeds at ``dt`` sampling and at every grid end."""
        from trcopt.timing.report import check_limits

        return check_limits(self, dt, tolerance)

    def to_json(self, samples: str | None = None) -> dict[str, Any]:
        """The ``timing`` object of the plan JSON (design.md §3.1)."""
        from trcopt.timing.report import timing_json

        return timing_json(self, samples)

    def write_csv(self, path: str | Path, dt: float = 1e-3) -> Path:
        """Write the feed profile (t, s, x, y, z, speed, v and a per axis, block) as CSV."""
        from trcopt.timing.report import write_csv

        return write_csv(self, Path(path), dt)

    def plot_speed(self, path: str | Path | None = None, ax: Any = None) -> Any:
        """Speed over s and over the path (matplotlib, imported here); saves to ``path`` if given."""
        from trcopt.timing.report import plot_speed

        return plot_speed(self, path, ax)

    def __repr__(self) -> str:
        return (
            f"TimedTrajectory(duration={self.duration:.6f} s, length={self.length:.3f} mm, "
            f"segments={len(self.segments)}, sections={len(self.sections)}, grid={len(self.s)})"
        )

    @property
    def limits(self) -> tuple[np.ndarray, np.ndarray]:
        return axis_limits(self.machine)
