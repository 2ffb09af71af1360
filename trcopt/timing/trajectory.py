"""``TimedTrajectory``: the acceleration-limited time-parameterised tool-centre path.

The profile is stored as grid points ``s_0 < … < s_M`` (mm) with squared path speeds
``x_i = ṡ²`` and the segment of every interval; between two grid points the path acceleration
``s̈ = (x_{i+1} − x_i)/(2Δ_i)`` is constant (toppra's ``ParametrizeConstAccel`` model), so the tool
follows the exact geometry and ``t_{i+1} − t_i = 2Δ_i/(ṡ_i + ṡ_{i+1})``.

Besides the profile and its queries the class holds its limit check (sampled and at every grid
end; per-axis limits, the feed and the machine's vector limits) and the plan-JSON ``timing`` object
with the binding constraint per section. It satisfies the
:class:`~trcopt.trajectory.Trajectory` protocol; the CSV feed profile and the speed plot are
written by :mod:`trcopt.io.feed_csv` and :func:`trcopt.io.plot.plot_speed`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from trcopt.codes import Code
from trcopt.config import Machine
from trcopt.errors import TimingError
from trcopt.path import Segment
from trcopt.timing.checks import (
    DEVIATION_PROBES,
    MAX_SAMPLES,
    SAMPLE_CHUNK,
    PathLimitReport,
    axis_triple,
    check_step,
    max_jerk,
    path_deviation,
    path_ratios,
    sample_chunks,
    sample_times,
    worst,
)
from trcopt.timing.path import PathArrays
from trcopt.timing.profiles import Profiles
from trcopt.timing.sampled import interval_kinematics, kinematics, sample_pieces, sampled_jerk
from trcopt.timing.sections import Section, axis_limits
from trcopt.trajectory import Samples

__all__ = ["MAX_SAMPLES", "SAMPLE_CHUNK", "TimedTrajectory", "check_step", "sample_chunks", "sample_times"]

# the constraints binding_constraints() names, in the column order of its table of ratios; the
# vector limits of the machine, where given, follow in the order of PATH_BINDING_NAMES
BINDING_NAMES = (
    "feed", "velocity X", "velocity Y", "velocity Z", "acceleration X", "acceleration Y", "acceleration Z",
)
PATH_BINDING_NAMES = ("path velocity", "path acceleration")


# MAX_SAMPLES (trcopt.timing.checks) is the most samples one call of sample_times() returns:
# 3.6·10⁶, one hour of cycle at 1 ms (a feed CSV of ≈ 400 MB, half a minute to write). A longer
# cycle at that rate is refused with a TimingError, not a MemoryError or a write that runs for many
# minutes; the limit checks of the plan sample such a cycle coarser (check_step).


def _max_ratios(rep: PathLimitReport) -> dict[str, Any]:
    """``max_ratios`` of the plan JSON: per axis v and a, feed, and ``path`` where vector limits are given."""
    out: dict[str, Any] = {
        "v": dict(zip("XYZ", rep.v_ratio, strict=True)),
        "a": dict(zip("XYZ", rep.a_ratio, strict=True)),
        "feed": rep.feed_ratio,
    }
    if rep.path_given:
        out["path"] = rep.path_json()
    return out


class TimedTrajectory:
    """Time-optimal feed along a tool path (build with :func:`trcopt.timing.time_parameterize`)."""

    jerk_limited = False  # the Trajectory protocol's flag: constant s̈ per interval, so the jerk is unbounded

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
                Code.TIMING_STUCK,
            )
        with np.errstate(divide="ignore", invalid="ignore"):
            dt = np.where(delta > 0, 2.0 * delta / den, 0.0)
            self.u = np.where(delta > 0, (self.x[1:] - self.x[:-1]) / (2.0 * delta), 0.0)
        self.t = np.concatenate(([0.0], np.cumsum(dt)))
        self._labels: np.ndarray | None = None  # block label of every segment (object array), when needed
        self._checked: dict[tuple[float, float], PathLimitReport] = {}  # check_limits by (dt, tolerance)

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
        results: Mapping[int, tuple[np.ndarray, np.ndarray, np.ndarray]],
    ) -> TimedTrajectory:
        if isinstance(results, Profiles):
            s, x, iseg, starts = results.assembled([sec.index for sec in sections])
            return cls(segments, machine, feeds, arrays, sections, engines, s, x, iseg, starts)
        ss: list[np.ndarray] = []
        xs: list[np.ndarray] = []
        segs: list[np.ndarray] = []
        starts: list[int] = []
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

    def segment_times(self) -> tuple[np.ndarray, np.ndarray]:
        """Start and end time (s) of every segment: the ``t_start_s``/``t_end_s`` of
        :meth:`segments_with_times`."""
        if not self.segments:
            return np.zeros(0), np.zeros(0)
        assert self.arrays is not None
        t0 = self.time_at(self.arrays.start)
        return t0, np.append(t0[1:], self.duration)

    def segments_with_times(self) -> list[Segment]:
        """The tool path with ``t_start_s``/``t_end_s`` set on every segment."""
        if not self.segments:
            return []
        t0, t1 = self.segment_times()
        return [seg.with_times(a, b) for seg, a, b in zip(self.segments, t0.tolist(), t1.tolist(), strict=True)]

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
        p, d1, d2 = self.arrays.eval012(seg, local)
        v = d1 * sd[:, None]
        a = d1 * u[:, None] + d2 * (sd * sd)[:, None]
        if self._labels is None and seg.shape[0] <= DEVIATION_PROBES:  # a few states: only their labels
            labels = np.array([self.segments[k].span.block_label() for k in seg.tolist()] + [None], dtype=object)
            return Samples(ts, s, p, sd, v, a, seg, labels[:-1], u)
        if self._labels is None:
            self._labels = np.array([sg.span.block_label() for sg in self.segments], dtype=object)
        return Samples(ts, s, p, sd, v, a, seg, self._labels[seg], u)

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

    # -- checks and the plan JSON ---------------------------------------------------------------
    def _ratios(self, smp: Samples) -> tuple[np.ndarray, np.ndarray, float]:
        vmax, amax = axis_limits(self.machine)
        if smp.t.shape[0] == 0:
            return np.zeros(3), np.zeros(3), 0.0
        vr = (np.abs(smp.v) / vmax).max(axis=0)
        ar = (np.abs(smp.a) / amax).max(axis=0)
        fr = float((smp.speed / self.feeds[smp.segment]).max()) if self.feeds.size else 0.0
        return vr, ar, fr

    def check_limits(self, dt: float = 1e-4, tolerance: float = 1.001) -> PathLimitReport:
        """Per-axis v and a, feed, vector limits and corner speeds at ``dt`` sampling (s) and at every
        grid end.

        ``tolerance`` is the largest ratio to a limit that passes; the sampled positions must
        also lie on the exact geometry (≤ 1e-6 mm) and the corner speeds be ≤ 1e-6 mm/s. The
        vector limits of ``machine.path`` (path speed, |a|) are checked when given; the jerk of
        this profile is unbounded and not checked.
        """
        if not self.segments:
            return PathLimitReport(True, (0.0,) * 3, (0.0,) * 3, 0.0, 0.0, 0.0, tolerance, 0)
        key = (float(dt), float(tolerance))
        if key not in self._checked:
            self._checked[key] = self._check_limits(dt, tolerance)
        return self._checked[key]

    def _check_limits(self, dt: float, tolerance: float) -> PathLimitReport:
        # the samples that decide the maxima (trcopt.timing.sampled), in pieces (bounded memory):
        # the largest ratios are those of every sample at once
        vr, ar, fr = np.zeros(3), np.zeros(3), 0.0
        pv = pa = None
        if not self._ordered():
            for ts in sample_chunks(self.duration, dt):
                smp = self.evaluate(ts)
                vr1, ar1, fr1 = self._ratios(smp)
                vr, ar, fr = np.maximum(vr, vr1), np.maximum(ar, ar1), max(fr, fr1)
                pv1, pa1, _ = path_ratios(self.machine.path, smp)
                pv, pa = worst(pv, pv1), worst(pa, pa1)
        else:
            for _, ts, i in sample_pieces(self, dt):
                state = interval_kinematics(self, ts, i)
                vr1, ar1, fr1 = self._maxima(*state)
                vr, ar, fr = np.maximum(vr, vr1), np.maximum(ar, ar1), max(fr, fr1)
                pv1, pa1 = self._path_maxima(*state)
                pv, pa = worst(pv, pv1), worst(pa, pa1)
        # every grid end, evaluated inside its interval
        m = len(self.t) - 1
        i = np.concatenate((np.arange(m), np.arange(m)))
        end = np.concatenate((np.zeros(m, bool), np.ones(m, bool)))
        s = np.where(end, self.s[i + 1], self.s[i])
        sd = np.where(end, self.sd[i + 1], self.sd[i])
        u = self.u[i]
        seg, v, a = kinematics(self, i, s, sd, u)
        vr2, ar2, fr2 = self._maxima(seg, sd, v, a)
        vr, ar = np.maximum(vr, vr2), np.maximum(ar, ar2)
        fr = max(fr, fr2)
        pv2, pa2 = self._path_maxima(seg, sd, v, a)
        pv, pa = worst(pv, pv2), worst(pa, pa2)
        corner = float(self.sd[self.section_points].max())
        assert self.arrays is not None
        # a few of the grid states compared with the exact geometry (path_deviation's probes)
        probe = np.linspace(0, 2 * m - 1, min(2 * m, DEVIATION_PROBES)).astype(int)
        ts = np.where(end, self.t[i + 1], self.t[i])[probe]
        states = self._samples_at(ts, i[probe], s[probe], sd[probe], u[probe])
        dev = path_deviation(self.segments, self.arrays.start, states)
        path_worst = worst(pv, pa)
        ok = bool(
            vr.max() <= tolerance and ar.max() <= tolerance and fr <= tolerance and corner <= 1e-6 and dev <= 1e-6
            and (path_worst is None or path_worst <= tolerance)
        )
        return PathLimitReport(
            ok, axis_triple(vr), axis_triple(ar), fr, corner, dev, tolerance, 2 * m,
            path_v_ratio=pv, path_a_ratio=pa,
        )

    def _ordered(self) -> bool:
        """True when the grid times rise (the samples of each interval are consecutive)."""
        return len(self.t) >= 2 and bool(np.all(self.t[1:] >= self.t[:-1]))

    def _maxima(
        self, seg: np.ndarray, speed: np.ndarray, v: np.ndarray, a: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, float]:
        """:meth:`_ratios` of the states: the largest |v|, |a| divided by the limits (the division
        by a positive limit keeps the order: the same as the largest ratio)."""
        vmax, amax = axis_limits(self.machine)
        if speed.shape[0] == 0:
            return np.zeros(3), np.zeros(3), 0.0
        fr = float((speed / self.feeds[seg]).max()) if self.feeds.size else 0.0
        return np.abs(v).max(axis=0) / vmax, np.abs(a).max(axis=0) / amax, fr

    def _path_maxima(
        self, seg: np.ndarray, speed: np.ndarray, v: np.ndarray, a: np.ndarray
    ) -> tuple[float | None, float | None]:
        """The ratios of :func:`~trcopt.timing.checks.path_ratios` (path speed and |a|) of the states."""
        path = self.machine.path
        pv = pa = None
        if path.vmax_mm_s is not None:
            pv = (float(speed.max()) if speed.size else 0.0) / path.vmax_mm_s
        if path.amax_mm_s2 is not None:
            pa = (float(np.linalg.norm(a, axis=1).max()) if a.size else 0.0) / path.amax_mm_s2
        return pv, pa

    def binding_constraints(self) -> list[str]:
        """Per section, the constraint active for the largest share of time.

        At the time midpoint of every grid interval the constraint with the largest ratio to its
        limit (``feed``, ``velocity X``, ``acceleration Y``, …, and where the machine gives them
        ``path velocity``, ``path acceleration``) is active; shares are weighted by duration.
        """
        if not self.segments:
            return []
        vmax, amax = axis_limits(self.machine)
        tm = 0.5 * (self.t[:-1] + self.t[1:])
        i, s, speed, u = self._state_at(tm)
        seg, v, a = kinematics(self, i, s, speed, u)
        columns = [speed / self.feeds[seg], np.abs(v) / vmax, np.abs(a) / amax]
        names = list(BINDING_NAMES)
        path = self.machine.path
        for name, limit in zip(PATH_BINDING_NAMES, (path.vmax_mm_s, path.amax_mm_s2), strict=True):
            if limit is not None:
                value = speed if name == PATH_BINDING_NAMES[0] else np.linalg.norm(a, axis=1)
                columns.append(value / limit)
                names.append(name)
        ratios = np.column_stack(columns)
        which = ratios.argmax(axis=1)
        w = np.diff(self.t)
        # the time per section and constraint: every section's bins in one bincount (each bin sums its
        # intervals' durations in the same order as a bincount per section)
        n_sec, n_names = len(self.sections), len(names)
        sec_of = np.repeat(np.arange(n_sec), np.diff(self.section_points))
        share = np.bincount(sec_of * n_names + which, weights=w, minlength=n_sec * n_names)
        return [names[k] for k in share.reshape(n_sec, n_names).argmax(axis=1).tolist()]

    def to_json(self, samples: str | None = None) -> dict[str, Any]:
        """The ``timing`` object of the plan JSON (design.md §3.1); ``samples`` names the CSV."""
        rep = self.check_limits(check_step(self.duration, 1e-3), 1.001) if self.segments else None
        jerk = self.max_jerk()
        binding = self.binding_constraints()
        sections = []
        t = self.t.tolist()
        points = self.section_points.tolist()
        for k, sec in enumerate(self.sections):
            a, b = points[k], points[k + 1]
            sections.append({
                "index": sec.index,
                "first_segment": sec.first,
                "last_segment": sec.last,
                "first_block": self.segments[sec.first].span.block,
                "last_block": self.segments[sec.last].span.block,
                "s_start_mm": round(sec.s_start, 9),
                "length_mm": round(sec.length, 9),
                "t_start_s": t[a],
                "t_end_s": t[b],
                "engine": self.engines[k],
                "binding": binding[k],
            })
        jmax = [self.machine.axis(n).jmax_mm_s3 for n in "XYZ"]
        return {
            "duration_s": self.duration,
            "machine": self.machine.to_json(),
            "samples": samples,
            "length_mm": self.length,
            "method": (
                "TOPP-RA interpolation scheme on the exact path; const-acceleration output; "
                "speed 0 at tangent discontinuities"
            ),
            "sections": sections,
            "max_ratios": None if rep is None else _max_ratios(rep),
            "limits_ok": None if rep is None else rep.ok,
            "max_jerk_mm_s3": dict(zip("XYZ", (float(j) for j in jerk), strict=True)),
            "max_jerk_ratio": {
                n: (None if jm is None else float(j) / jm) for n, j, jm in zip("XYZ", jerk, jmax, strict=True)
            },
            "jerk_note": "finite difference at 1 kHz; acceleration-limited profiles have unbounded jerk",
        }

    def max_jerk(self, dt: float = 1e-3) -> np.ndarray:
        """:func:`~trcopt.timing.checks.max_jerk` of this profile (the same values, evaluating only
        the samples :mod:`trcopt.timing.sampled` needs)."""
        if not self.segments or self.duration <= dt or not self._ordered():
            return max_jerk(self, dt)
        return sampled_jerk(self, check_step(self.duration, dt))

    def __repr__(self) -> str:
        return (
            f"TimedTrajectory(duration={self.duration:.6f} s, length={self.length:.3f} mm, "
            f"segments={len(self.segments)}, sections={len(self.sections)}, grid={len(self.s)})"
        )

    @property
    def limits(self) -> tuple[np.ndarray, np.ndarray]:
        return axis_limits(self.machine)
