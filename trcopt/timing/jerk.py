"""Jerk-limited feed along the exact tool-centre path: ``jerk_limited(toolpath, machine, base=…)``.

The acceleration-limited optimum of :func:`trcopt.timing.time_parameterize` has unbounded jerk
(spec timing.md §0.7). Here every section of it (a tangent-continuous run that starts and ends at
rest) is re-solved as a :class:`~trcopt.timing.jerk_problem.JerkProblem`: a CasADi/IPOPT NLP over
the path-speed profile with per-axis velocity, acceleration and jerk limits, warm-started from the
acceleration-limited profile (node placement and speed caps: :mod:`trcopt.timing.jerk_grid`). A
section of collinear lines with one feed is solved in closed form instead: the rest-to-rest
double-S under the line's scalar limits is its exact optimum (:mod:`trcopt.timing.jerk_lines`). With
``engine="fir"`` the other sections get the filtered acceleration-limited profile of
:mod:`trcopt.timing.jerk_fir` instead (checked against every limit; the NLP where it fails). The
result, :class:`JerkTrajectory`, satisfies the :class:`~trcopt.trajectory.Trajectory` protocol like
:class:`~trcopt.timing.TimedTrajectory` (``duration``, ``sample``, ``evaluate``, ``check_limits``,
``segments_with_times``, ``to_json``); its samples carry the jerk, and the report values are in
:mod:`trcopt.timing.jerk_report`.

**Trajectory model.** Between two nodes the path jerk is constant in time, so ``s(t)`` is a cubic
and the tool follows the exact geometry; per-axis velocity, acceleration and jerk are evaluated in
closed form: ``v = q′ṡ``, ``a = q′s̈ + q″ṡ²``, ``j = q‴ṡ³ + 3q″ṡs̈ + q′s⃛``.

**Curvature jumps** (line↔arc knots, G450 transition circles, arcs of different radius inside a
section) are treated by a *jerk-bounded knot speed*: exact path following makes the axis
acceleration step by ``Δq″_k·v²`` at the knot; the knot is passed at a speed where that step, spread
over one interpolation cycle ``T_c`` (``cycle_s``, default 1 ms, what a controller's cycle does
to it), stays within the jerk limit: ``|Δq″_k|·v² ≤ jmax_k·T_c`` on every axis. Tangent
discontinuities are passed at rest with zero acceleration.

**Jerk measure** (``check_limits``, ``jerk_ratio``): per axis, the larger of (1) the analytic jerk of
the smooth pieces, ``max |j_k|/jmax_k`` over samples every ``dt`` and both ends of every interval,
and (2) the knot acceleration steps ``|Δq″_k|·v²/(T_c·jmax_k)``. With a vector jerk limit J
(``machine.path.jmax_mm_s3``) the same measure is taken of the norms, ``|j|/J`` and
``|Δq″|·v²/(T_c·J)`` (``path_j_ratio``); the vector speed and acceleration limits are checked as
``path_v_ratio`` and ``path_a_ratio``. The finite-difference jerk of the
sampled acceleration at 1 kHz and 10 kHz is reported beside it for information: at 1 kHz (= T_c) it
stays close to the measure, at 10 kHz a knot step shows up ten times larger because the step is then
spread over 0.1 ms instead of one cycle.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from trcopt.codes import Code
from trcopt.config import DEFAULT_MACHINE, Machine
from trcopt.errors import TimingError
from trcopt.path import Segment
from trcopt.progress import iterate
from trcopt.solution import Solution
from trcopt.timing.checks import axis_triple, max_jerk, path_deviation, path_ratios, worst
from trcopt.timing.jerk_fir import fir_section
from trcopt.timing.jerk_fir_rows import FirLimits
from trcopt.timing.jerk_lines import line_section_limits, line_section_profile
from trcopt.timing.jerk_problem import JerkProblem, SectionProfile, section_label
from trcopt.timing.jerk_report import JERK_MEASURE, KNOT_RULE, METHOD, JerkLimitReport, JerkSamples, jerk_limits
from trcopt.timing.path import PathArrays, path_derivatives
from trcopt.timing.sections import Section, axis_limits, path_speed_caps, segment_feeds, split_sections
from trcopt.timing.trajectory import TimedTrajectory, check_step, sample_times

__all__ = ["jerk_limited", "JerkTrajectory", "ENGINES"]

ENGINES = ("nlp", "fir")  # jerk_limited(engine=...): the solver of the sections that are not one line


class JerkTrajectory:
    """Jerk-limited feed along a tool path (build with :func:`jerk_limited`).

    Attributes: ``base`` (the acceleration-limited :class:`TimedTrajectory`), ``solutions`` (one
    :class:`~trcopt.solution.Solution` per section: status, cost = section time s,
    iterations, solve time), ``cycle_s``, and per interval ``t0, s0, h, v0, a0, j, iseg``.
    """

    jerk_limited = True  # the Trajectory protocol's flag: samples carry the per-axis jerk

    def __init__(
        self,
        segments: Sequence[Segment],
        machine: Machine,
        feeds: np.ndarray,
        arrays: PathArrays,
        sections: Sequence[Section],
        solutions: Sequence[Solution[SectionProfile]],
        knots: Sequence[tuple[np.ndarray, np.ndarray]],
        base: TimedTrajectory,
        cycle_s: float,
    ) -> None:
        self.segments, self.machine, self.feeds, self.arrays = list(segments), machine, feeds, arrays
        self.sections, self.solutions, self.base, self.cycle_s = list(sections), list(solutions), base, cycle_s
        profs = [sol.geometry for sol in solutions]
        self.s0 = np.concatenate([p.s[:-1] for p in profs])
        self.s1 = np.concatenate([p.s[1:] for p in profs])
        self.v0 = np.concatenate([p.v[:-1] for p in profs])
        self.a0 = np.concatenate([p.a[:-1] for p in profs])
        self.h = np.concatenate([p.h for p in profs])
        self.j = np.concatenate([p.j for p in profs])
        self.iseg = np.concatenate([p.iseg for p in profs]).astype(np.int64)
        self.t0 = np.concatenate(([0.0], np.cumsum(self.h)[:-1]))
        self.section_points = np.concatenate(([0], np.cumsum([p.h.shape[0] for p in profs])))
        self.vmax, self.amax = axis_limits(machine)
        self.jmax = jerk_limits(machine)
        # curvature-jump knots: global s, Δq″ (per axis) and the speed the tool passes them at
        ks, kd, kv = [], [], []
        for (nodes, dq2s), p in zip(knots, profs, strict=True):
            for node, dq2 in zip(nodes, dq2s, strict=True):
                ks.append(p.s[node])
                kd.append(dq2)
                kv.append(p.v[node])
        self.knot_s = np.array(ks)
        self.knot_dq2 = np.array(kd).reshape(-1, 3)
        self.knot_v = np.array(kv)

    # -- queries ----------------------------------------------------------------------------------------
    @property
    def duration(self) -> float:
        """Cycle time, s."""
        return float(self.h.sum())

    @property
    def length(self) -> float:
        return float(self.s1[-1])

    @property
    def iterations(self) -> int:
        return int(sum(max(sol.iterations, 0) for sol in self.solutions))

    @property
    def solve_time_s(self) -> float:
        return float(sum(sol.solve_time_s for sol in self.solutions))

    def _states(self, i: np.ndarray, tau: np.ndarray) -> tuple[np.ndarray, ...]:
        h = self.h[i]
        tau = np.clip(tau, 0.0, h)
        v, a, j = self.v0[i], self.a0[i], self.j[i]
        s = np.clip(self.s0[i] + v * tau + a * tau**2 / 2 + j * tau**3 / 6, self.s0[i], self.s1[i])
        sd = np.maximum(v + a * tau + j * tau**2 / 2, 0.0)
        return s, sd, a + j * tau, j

    def _samples(self, ts: np.ndarray, i: np.ndarray, tau: np.ndarray) -> JerkSamples:
        s, sd, sdd, sddd = self._states(i, tau)
        seg = self.iseg[i]
        # derivatives from inside the interval: a Poly's cubic pieces meet at the nodes with a jump of q″
        pad = np.where(self.arrays.kind[seg] == 2, 1e-6 * (self.s1[i] - self.s0[i]), 0.0)
        local = np.clip(s, self.s0[i] + pad, self.s1[i] - pad) - self.arrays.start[seg]
        local = np.clip(local, 0.0, self.arrays.length[seg])
        p = self.arrays.eval(seg, local, 0)
        d1, d2, d3 = path_derivatives(self.arrays, seg, local)
        v = d1 * sd[:, None]
        a = d1 * sdd[:, None] + d2 * (sd * sd)[:, None]
        jk = d3 * (sd**3)[:, None] + 3 * d2 * (sd * sdd)[:, None] + d1 * sddd[:, None]
        labels = np.array([sg.span.block_label() for sg in self.segments], dtype=object)
        return JerkSamples(ts, s, p, sd, v, a, seg, labels[seg], sdd, jk, sddd)

    def evaluate(self, ts: np.ndarray) -> JerkSamples:
        """State at times ``ts`` (s): position, path speed, per-axis v, a and jerk."""
        ts = np.asarray(ts, dtype=float)
        i = np.clip(np.searchsorted(self.t0, ts, side="right") - 1, 0, self.h.shape[0] - 1)
        return self._samples(ts, i, ts - self.t0[i])

    def sample(self, dt: float = 1e-3) -> JerkSamples:
        """Samples every ``dt`` seconds from 0 to the duration (both included)."""
        return self.evaluate(sample_times(self.duration, dt))

    def grid_states(self) -> JerkSamples:
        """The state at both ends of every interval, evaluated on the interval's own segment."""
        m = self.h.shape[0]
        i = np.concatenate((np.arange(m), np.arange(m)))
        tau = np.concatenate((np.zeros(m), self.h))
        return self._samples(self.t0[i] + tau, i, tau)

    def time_at_segment_starts(self) -> np.ndarray:
        first = np.searchsorted(self.iseg, np.arange(len(self.segments)), side="left")
        return self.t0[np.minimum(first, self.h.shape[0] - 1)]

    def segments_with_times(self) -> list[Segment]:
        """The tool path with ``t_start_s``/``t_end_s`` of the jerk-limited profile."""
        t0 = self.time_at_segment_starts()
        t1 = np.append(t0[1:], self.duration)
        return [seg.with_times(float(a), float(b)) for seg, a, b in zip(self.segments, t0, t1, strict=True)]

    # -- checks and exports -------------------------------------------------------------------------------
    def knot_steps(self) -> np.ndarray:
        """Per-axis acceleration step at every curvature-jump knot, mm/s² (rows = knots)."""
        return np.abs(self.knot_dq2) * (self.knot_v**2)[:, None]

    def check_limits(
        self, dt: float = 1e-4, tolerance: float = 1.001, *, jerk: bool = True, jerk_tolerance: float = 1.01
    ) -> JerkLimitReport:
        """v, a (≤ ``tolerance``) and, with ``jerk``, the jerk measure (≤ ``jerk_tolerance``).

        Sampled every ``dt`` and at both ends of every interval; see the module docstring for the
        jerk measure. Also checks the feed, speed 0 at section ends, the path deviation and the
        machine's vector limits (speed and |a| against ``tolerance``, |j| against
        ``jerk_tolerance``).
        """
        smp, grid = self.sample(dt), self.grid_states()
        vr = np.maximum((np.abs(smp.v) / self.vmax).max(axis=0), (np.abs(grid.v) / self.vmax).max(axis=0))
        ar = np.maximum((np.abs(smp.a) / self.amax).max(axis=0), (np.abs(grid.a) / self.amax).max(axis=0))
        js = np.maximum((np.abs(smp.j) / self.jmax).max(axis=0), (np.abs(grid.j) / self.jmax).max(axis=0))
        fr = max(
            float((smp.speed / self.feeds[smp.segment]).max()), float((grid.speed / self.feeds[grid.segment]).max())
        )
        jk = (self.knot_steps() / (self.cycle_s * self.jmax)).max(axis=0) if self.knot_s.size else np.zeros(3)
        fd = [max_jerk(self, d) / self.jmax for d in (1e-3, 1e-4)]
        corner = float(np.concatenate([[sol.geometry.v[0], sol.geometry.v[-1]] for sol in self.solutions]).max())
        dev = path_deviation(self.segments, self.arrays.start, grid)
        jr = np.maximum(js, jk)
        knot_norm = None
        if self.knot_s.size:
            knot_norm = np.linalg.norm(self.knot_dq2, axis=1) * self.knot_v**2 / self.cycle_s
        pv, pa, pj = path_ratios(self.machine.path, smp, grid, jerk=knot_norm)
        path_va = worst(pv, pa)
        ok = bool(
            vr.max() <= tolerance and ar.max() <= tolerance and fr <= tolerance and corner <= 1e-6 and dev <= 1e-6
            and (path_va is None or path_va <= tolerance)
        )
        if jerk:
            ok = ok and bool(jr.max() <= jerk_tolerance) and (pj is None or pj <= jerk_tolerance)

        return JerkLimitReport(
            ok=ok,
            v_ratio=axis_triple(vr),
            a_ratio=axis_triple(ar),
            feed_ratio=fr,
            corner_speed_mm_s=corner,
            path_deviation_mm=dev,
            tolerance=tolerance,
            samples=int(smp.t.shape[0] + grid.t.shape[0]),
            jerk_ratio=axis_triple(jr),
            jerk_smooth_ratio=axis_triple(js),
            jerk_knot_ratio=axis_triple(jk),
            jerk_fd_1khz_ratio=axis_triple(fd[0]),
            jerk_fd_10khz_ratio=axis_triple(fd[1]),
            jerk_tolerance=jerk_tolerance,
            jerk_checked=jerk,
            path_v_ratio=pv,
            path_a_ratio=pa,
            path_j_ratio=pj,
        )

    def to_json(self, samples: str | None = None) -> dict[str, Any]:
        """The ``timing`` object of the plan JSON with ``jerk_limited: true``."""
        rep = self.check_limits(check_step(self.duration, 1e-3))
        secs = []
        for k, (sec, sol) in enumerate(zip(self.sections, self.solutions, strict=True)):
            a, b = self.section_points[k], self.section_points[k + 1]
            secs.append(
                {
                    "index": sec.index,
                    "first_segment": sec.first,
                    "last_segment": sec.last,
                    "first_block": self.segments[sec.first].span.block,
                    "last_block": self.segments[sec.last].span.block,
                    "s_start_mm": round(sec.s_start, 9),
                    "length_mm": round(sec.length, 9),
                    "t_start_s": float(self.t0[a]),
                    "t_end_s": float(self.t0[b - 1] + self.h[b - 1]),
                    "engine": "casadi-ipopt" if sol.solver == "ipopt" else sol.solver,
                    "status": sol.status.value,
                    "iterations": sol.iterations,
                    # no wall-clock time here: a plan's outputs are byte-identical on every rerun
                    "intervals": int(b - a),
                }
            )
        return {
            "duration_s": self.duration,
            "machine": self.machine.to_json(),
            "samples": samples,
            "length_mm": self.length,
            "jerk_limited": True,
            "method": METHOD,
            "curvature_jumps": KNOT_RULE,
            "cycle_s": self.cycle_s,
            "acceleration_limited_duration_s": self.base.duration,
            "ctr_vs_acceleration_limited": self.duration / self.base.duration if self.base.duration > 0 else None,
            "sections": secs,
            "max_ratios": self._max_ratios(rep),
            "limits_ok": rep.ok,
            "max_jerk_ratio": rep.to_json()["jerk_ratio"],
            "jerk_report": rep.to_json(),
            "jerk_note": JERK_MEASURE,
        }

    @staticmethod
    def _max_ratios(rep: JerkLimitReport) -> dict[str, Any]:
        out: dict[str, Any] = {"v": rep.to_json()["v_ratio"], "a": rep.to_json()["a_ratio"], "feed": rep.feed_ratio}
        if rep.path_given:
            out["path"] = rep.path_json()
        return out

    def __repr__(self) -> str:
        return (
            f"JerkTrajectory(duration={self.duration:.6f} s, acceleration-limited {self.base.duration:.6f} s, "
            f"segments={len(self.segments)}, sections={len(self.sections)}, intervals={self.h.shape[0]})"
        )


def jerk_limited(
    toolpath: Sequence[Segment],
    machine: Machine = DEFAULT_MACHINE,
    *,
    base: TimedTrajectory | None = None,
    cycle_s: float = 1e-3,
    points: int | None = None,
    tangent_tol_rad: float = 1e-6,
    workers: int = 1,
    closed_form: bool = True,
    engine: str = "nlp",
) -> JerkTrajectory:
    """Jerk-limited time-optimal feed along a tool-centre path.

    Parameters
    ----------
    toolpath:
        Tool-centre segments in path order.
    machine:
        Per-axis ``vmax`` (mm/s), ``amax`` (mm/s²) and ``jmax`` (mm/s³, required on X, Y, Z), and
        the optional vector limits ``machine.path`` (path speed, |a|, |j|).
    base:
        The acceleration-limited trajectory of the same path (computed when omitted); it places
        the nodes and warm-starts IPOPT.
    cycle_s:
        Interpolation cycle T_c, s: a curvature jump is passed at a speed whose acceleration step
        fits in one cycle at the jerk limit.
    points:
        Target intervals per section (default ``min(60 + 30·segments, 600)``).
    tangent_tol_rad:
        Tangent discontinuity threshold, rad (same meaning as in ``time_parameterize``).
    workers:
        Processes for the sections (independent problems; ``1`` solves in this process).
    closed_form:
        Solve the sections that are one straight line (collinear lines with one speed cap) by the
        closed-form double-S of :mod:`trcopt.timing.jerk_lines` instead of the NLP (``False``: the
        NLP on every section).
    engine:
        ``"nlp"`` (default): the other sections by the NLP. ``"fir"``: by the filtered
        acceleration-limited profile of :mod:`trcopt.timing.jerk_fir` (several times faster, cycle
        times a few per cent longer on curves, see benchmarks/JERK.md); a section it cannot make
        valid under every limit (or with a Poly curve) falls back to the NLP.

    Raises
    ------
    TimingError
        IPOPT did not converge on a section (names the section, its blocks and the worst
        constraint group).
    ConfigError
        The machine has no jerk limit on some axis.
    """
    from trcopt.timing.solve import time_parameterize

    segments = list(toolpath)
    if not segments:
        raise TimingError("jerk_limited: empty tool path", code=Code.TIMING_EMPTY)
    if engine not in ENGINES:
        raise ValueError(f"engine must be one of {', '.join(ENGINES)} (got {engine!r})")
    jmax = jerk_limits(machine)
    if cycle_s <= 0:
        raise ValueError("cycle_s must be positive (s)")
    if base is None:
        base = time_parameterize(segments, machine, tangent_tol_rad=tangent_tol_rad)
    vmax, amax = axis_limits(machine)
    arrays = PathArrays(segments)
    feeds = segment_feeds(segments, machine)
    sections = split_sections(segments, arrays, tangent_tol_rad)
    vector = (machine.path.amax_mm_s2, machine.path.jmax_mm_s3)
    caps = path_speed_caps(feeds, machine)
    ctx = (arrays, caps, vmax, amax, jmax, base.s, base.sd, cycle_s, points, vector, closed_form, engine)
    if workers > 1 and len(sections) > 1:
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(max_workers=workers, initializer=_init_worker, initargs=(ctx,)) as pool:
            chunks = max(1, len(sections) // (4 * workers))
            results = list(iterate(pool.map(_solve_section, sections, chunksize=chunks), "sections", len(sections)))
    else:
        _init_worker(ctx)
        try:
            results = [_solve_section(sec) for sec in iterate(sections, "sections")]
        finally:
            _init_worker(None)
    solutions, knots = [], []
    for sec, (sol, knot) in zip(sections, results, strict=True):
        if not sol.ok:
            label = section_label(segments, sec)
            worst = sol.binding or "dynamics_mm"
            amount = sol.constraint_violation.get(worst, float("nan"))
            raise TimingError(
                f"jerk-limited feed: IPOPT failed on section {sec.index} ({label}, s={sec.s_start:.6f} mm): "
                f"{sol.message}; worst constraint group '{worst}' violated by {amount:.3g}; "
                "remedy: check the jerk limits of the machine or pass points= for a finer grid",
                segments[sec.first].span,
                Code.TIMING_JERK_SOLVER,
            )
        solutions.append(sol)
        knots.append(knot)
    return JerkTrajectory(segments, machine, feeds, arrays, sections, solutions, knots, base, cycle_s)


_CTX: tuple | None = None


def _init_worker(ctx: tuple | None) -> None:
    global _CTX
    _CTX = ctx


def _solve_section(sec: Section) -> tuple[Solution[SectionProfile], tuple[np.ndarray, np.ndarray]]:
    """Solve one section: a line section in closed form (``closed``), else with ``engine="fir"`` the
    FIR profile when it passes its limit check, else the NLP — first with the fast IPOPT options;
    IPOPT may stop at a local infeasibility from a poor start, so retry with the
    adaptive barrier, from a slower warm start, then on a doubled grid. Returns the solution and
    (knot nodes, Δq″ per knot)."""
    assert _CTX is not None
    arrays, feeds, vmax, amax, jmax, base_s, base_sd, cycle_s, points, (path_amax, path_jmax), closed, engine = _CTX
    if closed:
        limits = line_section_limits(sec, arrays, feeds, vmax, amax, jmax, path_amax, path_jmax)
        if limits is not None:
            return line_section_profile(sec, arrays, limits), (np.zeros(0, dtype=np.int64), np.zeros((0, 3)))
    if engine == "fir":
        fir = fir_section(sec, arrays, FirLimits(feeds, vmax, amax, jmax, path_amax, path_jmax, cycle_s))
        if fir is not None:
            sol_fir, nodes, dq2 = fir
            return sol_fir, (nodes, dq2)
    nseg = sec.last - sec.first + 1
    n0 = points if points is not None else min(60 + 30 * nseg, 600)
    spent = 0.0
    for n_pts, scale, fast in ((n0, 0.95, True), (n0, 0.95, False), (n0, 0.5, False), (2 * n0, 0.7, False)):
        pb = JerkProblem(
            sec, arrays, feeds, vmax, amax, jmax, base_s, base_sd, cycle_s=cycle_s, points=n_pts, init_scale=scale,
            path_amax=path_amax, path_jmax=path_jmax, fast=fast,
        )
        sol = pb.solve()
        spent += sol.solve_time_s
        if sol.ok:
            break
    return replace(sol, solve_time_s=spent), (pb.grid.knot_nodes, pb.grid.knot_dq2)
