"""``plan()``: part program → canonical moves → tool-centre path → (timing) → result.

Each stage is also callable on its own (:func:`trcopt.nc.read_program`,
:func:`trcopt.compensation.compensate`, :func:`trcopt.timing.time_parameterize`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from trcopt.codes import Code
from trcopt.compensation import programmed_segment
from trcopt.config import DEFAULT_MACHINE, Machine, TrcSettings
from trcopt.errors import Diagnostic, Severity, SourceSpan, TrcoptError
from trcopt.modes import ApprRadius, CornerObjective, ToleranceKind, ToolUnit, parse_enum
from trcopt.nc.collector import collector_paused, kept_from_collector
from trcopt.nc.model import Move, NcProgram
from trcopt.optimize.corners import strategies as corner_strategies
from trcopt.path import Segment, segments_length
from trcopt.pipeline.summary import summary_text
from trcopt.progress import stage
from trcopt.trajectory import Trajectory

if TYPE_CHECKING:
    from trcopt.controllers.base import Controller

__all__ = ["PlanOptions", "PlanResult", "plan", "plan_file"]

AUTO = "auto"


@dataclass(frozen=True, slots=True)
class PlanOptions:
    """What ``plan`` does.

    Parameters
    ----------
    dialect:
        ``auto`` (from the file name and contents, :func:`trcopt.controllers.detect`) or the
        controller or dialect name whose reader reads the program (``siemens``, ``heidenhain``,
        ``rs274``/``linuxcnc``; :func:`trcopt.controllers.names`).
    profile:
        Compensation semantics: a controller name (``siemens``, ``heidenhain``, ``linuxcnc``);
        ``auto`` is the reading controller's own.
    settings:
        Compensation machine data and tolerances.
    machine:
        Axis limits for the timing stage (the embedded default machine when omitted).
    timing:
        Compute the time-optimal feed profile and cycle time.
    verify:
        Check the tool-centre path against the constraint model (radius, tangency, continuity,
        no reversal of the infeed, clearance) and report the largest residual of each family; a
        family over tolerance is a ``VERIFY-…`` warning at the block of its worst segment.
    strict:
        Treat possible contour violations (CDOF reversed elements) as alarm 10751, and a failed
        verification family as an error (``ok`` False, exit code 1).
    tool_table, tool_unit:
        A tool-table file (LinuxCNC ``.tbl`` for rs274 with its length unit, TOML for
        heidenhain and siemens); by default the readers look beside the program.
    zero_offsets:
        SINUMERIK settable zero offsets G54… (TOML); by default ``<program>.offsets.toml`` beside it.
    appr_radius:
        Heidenhain APPR/DEP CT/LCT: ``R`` is the radius of the tool-centre arc (``centre``, the
        default) or of the contour arc (``contour``); spec heidenhain_trc.md R9.
    corners, tolerance_mm, tolerance_kind:
        The corner strategy by its registry name (:mod:`trcopt.optimize.corners.strategies`):
        ``program`` (the default: what the program's path-control mode makes the controller do —
        rounding within the program's tolerance under LinuxCNC ``G64 P``, SINUMERIK
        ``G641``/``G642``/``CYCLE832``, Heidenhain ``CYCL DEF 32``; exact stops under ``G61.1``,
        ``G60``, ``G9``; the exact path without a mode), ``exact`` (exact stop at every corner), or
        transitions within a tolerance at every corner: ``optimal`` (G2 quintics by SQP) or
        ``arc`` (same-ε circular blends, the usual controller smoothing) — within the program's
        tolerance where it sets one, else ``tolerance_mm`` (ε, mm). On a compensated path ε bounds
        the cut part; on an uncompensated one (G40 CAM output) the distance of the tool-centre
        path from the programmed path, measured as ``tolerance_kind`` says (``contour``: from
        the path, ``vertex``: from the corner point; default: the program's mode's measure, else
        contour). Applied after the verification of the exact path and before timing. An unknown
        name is a usage error.
    jerk:
        Replace the acceleration-limited feed by the jerk-limited one
        (:func:`trcopt.timing.jerk.jerk_limited`, CasADi/IPOPT per section, warm-started from
        TOPP-RA); needs ``jmax_mm_s3`` on every axis of the machine. Slower (tens of segments/s).
    jerk_engine:
        ``"nlp"`` (the time optimum per section, default) or ``"fir"`` (about four times faster,
        1–7 % longer cycle times; every profile checked, the NLP where it cannot be made valid).
    workers:
        Processes for the independent per-corner problems of ``corners="optimal"`` and the
        sections of the jerk-limited feed (``1``: everything in this process).
    """

    dialect: str = "auto"
    profile: str = "auto"
    settings: TrcSettings = field(default_factory=TrcSettings)
    machine: Machine = DEFAULT_MACHINE
    timing: bool = True
    verify: bool = True
    strict: bool = False
    tool_table: str | None = None
    zero_offsets: str | None = None
    tool_unit: ToolUnit = ToolUnit.PROGRAM
    appr_radius: ApprRadius = ApprRadius.CENTRE
    corners: str = corner_strategies.PROGRAM
    tolerance_mm: float = 0.01
    tolerance_kind: ToleranceKind | None = None
    jerk: bool = False
    jerk_engine: str = "nlp"
    workers: int = 1

    def __post_init__(self) -> None:
        if self.jerk_engine not in ("nlp", "fir"):
            raise TrcoptError(f"--jerk-engine: nlp or fir, not {self.jerk_engine!r}", code=Code.USAGE)
        # strings are accepted here, at the boundary, and become modes
        object.__setattr__(self, "tool_unit", parse_enum(ToolUnit, self.tool_unit, "tool unit"))
        object.__setattr__(self, "appr_radius", parse_enum(ApprRadius, self.appr_radius, "APPR/DEP radius reading"))
        if self.tolerance_kind is not None:
            try:
                kind = parse_enum(ToleranceKind, self.tolerance_kind, "--tolerance-kind")
            except ValueError as exc:
                raise TrcoptError(str(exc), code=Code.USAGE) from None
            if kind is ToleranceKind.DISTANCE:
                raise TrcoptError("--tolerance-kind: contour or vertex", code=Code.USAGE)
            object.__setattr__(self, "tolerance_kind", kind)
        try:
            object.__setattr__(self, "corners", corner_strategies.get(self.corners).name)
        except ValueError as exc:
            raise TrcoptError(f"--corners: {exc}", code=Code.USAGE) from None
        if not (math.isfinite(self.tolerance_mm) and self.tolerance_mm > 0.0):
            raise TrcoptError(
                f"--tolerance: the corner tolerance must be a positive finite length in mm, got {self.tolerance_mm!r}",
                code=Code.USAGE,
            )


@dataclass(slots=True)
class PlanResult:
    """Everything a plan produced: the program, both paths, diagnostics and timing."""

    program: str
    dialect: str
    nc: NcProgram
    programmed: list[Segment]
    toolpath: list[Segment]
    diagnostics: list[Diagnostic]
    timing: Trajectory | None = None  # acceleration- or jerk-limited feed, when computed
    extra: dict[str, Any] = field(default_factory=dict)
    verification: Any = None  # trcopt.verify.VerificationReport when computed
    source: str = ""  # the program text (the G-code writer reads its unit words and programmed axes)

    @property
    def ok(self) -> bool:
        """False iff an error-severity diagnostic was raised."""
        return not any(d.severity is Severity.ERROR for d in self.diagnostics)

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity is Severity.ERROR]

    @property
    def warnings(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity is Severity.WARNING]

    @property
    def path_length(self) -> float:
        """Tool-centre path length, mm."""
        return segments_length(self.toolpath)

    @property
    def duration(self) -> float | None:
        """Cycle time, s (None when timing was not computed)."""
        return None if self.timing is None else float(self.timing.duration)

    def to_json(self, samples: str | None = None) -> dict[str, Any]:
        """The plan JSON (design.md §3.1, schema ``trcopt.plan/1``); ``samples`` names the CSV
        feed profile written beside it, if any."""
        from trcopt.io.plan_json import plan_json

        return plan_json(**self._json_arguments(samples, streamed=False))

    def json_chunks(self, samples: str | None = None) -> Iterator[str]:
        """The text of :func:`trcopt.io.plan_json.dumps_plan` of :meth:`to_json` in pieces, one
        ``<segment>`` at a time (never the whole plan dictionary or text in memory); for
        :func:`trcopt.io.atomic.write_chunks_atomic`. Raises ``PlanJsonError`` as ``dumps_plan``."""
        from trcopt.io.plan_json import plan_json_chunks

        return plan_json_chunks(**self._json_arguments(samples, streamed=True))

    def _json_arguments(self, samples: str | None, streamed: bool) -> dict[str, Any]:
        """The arguments of :func:`~trcopt.io.plan_json.plan_json`: the tool path with its times
        (``streamed``: a lazy sequence of the timed segments, not a list of them)."""
        from trcopt.io.plan_json import TimedSegments

        toolpath: Sequence[Segment] = self.toolpath
        timing_json = None
        if self.timing is not None:
            times = getattr(self.timing, "segment_times", None) if streamed else None
            toolpath = TimedSegments(self.timing.segments, *times()) if times else self.timing.segments_with_times()
            timing_json = self.timing.to_json(samples=samples)
        return {
            "program": self.program,
            "dialect": self.dialect,
            "diagnostics": self.diagnostics,
            "programmed": self.programmed,
            "toolpath": toolpath,
            "timing": timing_json,
            "extra": self.extra,
        }

    def write_json(self, path: str | Path, samples: str | None = None) -> Path:
        """Write the plan JSON (:meth:`json_chunks`) to ``path`` atomically, streamed."""
        from trcopt.io.atomic import write_chunks_atomic

        return write_chunks_atomic(path, self.json_chunks(samples))

    def summary(self) -> str:
        """A few lines for the terminal."""
        return summary_text(
            self.program, self.dialect, self.nc.blocks, len(self.toolpath), self.path_length, self.timing,
            self.extra.get("corners"), self.verification, self.diagnostics,
        )


def plan(
    source: str,
    *,
    file: str = "<program>",
    options: PlanOptions | None = None,
) -> PlanResult:
    """Plan a part program given as text.

    Never raises for a problem in the program: alarms are diagnostics and the paths stop there.
    """
    with kept_from_collector() as freeze:
        return _plan(source, file, options, freeze)


def _plan(source: str, file: str, options: PlanOptions | None, freeze: Callable[[], None]) -> PlanResult:
    from trcopt import controllers

    opts = options or PlanOptions()
    settings = opts.settings if not opts.strict else opts.settings.with_(strict=True)
    reader = controllers.detect(file, source) if opts.dialect == AUTO else _controller(opts.dialect, "dialect")
    with stage("reading the program"):
        nc = controllers.read_program(
            source,
            file=file,
            dialect=reader.name,
            tolerances=settings.tolerances,
            max_disc=settings.cutcom_max_disc,
            tool_table=opts.tool_table,
            zero_offsets=opts.zero_offsets,
            tool_unit=opts.tool_unit,
            appr_radius=opts.appr_radius.value,
        )
    diagnostics = list(nc.diagnostics)
    tol = settings.tolerances.coincidence_mm
    front_end_ok = not any(d.severity is Severity.ERROR for d in diagnostics)
    trc_diags: list[Diagnostic] = []
    # the segments of the programmed and the tool-centre path are acyclic: the cyclic collector
    # would only walk them again and again (trcopt.nc.collector)
    with collector_paused():
        moves = list(nc.moves if reader.leads is None else reader.leads(nc.moves, settings, trc_diags))
        programmed = [s for s in (programmed_segment(m, tol) for m in moves) if s is not None]
        front_end_ok = front_end_ok and not any(d.severity is Severity.ERROR for d in trc_diags)
        # the compensation semantics: the reader's controller unless another profile is asked for
        profile = reader if opts.profile == AUTO else _controller(opts.profile, "profile")
        with stage("compensating"):
            toolpath = list(profile.compensate(moves, settings, trc_diags, front_end_ok))
    freeze()  # the moves and segments live as long as the plan: no collection walks them
    diagnostics.extend(trc_diags)
    diagnostics.sort(key=lambda d: (d.span.line, d.span.column))
    result = PlanResult(file, reader.dialect, nc, programmed, toolpath, diagnostics)
    result.source = source
    result.extra["profile"] = profile.name
    _attach_toolholder(result)
    if opts.verify:
        from trcopt.verify.plan import verify_plan

        with stage("verifying"), collector_paused():
            verified = toolpath if profile.verified_path is None else profile.verified_path(toolpath, moves)
            result.verification = verify_plan(
                programmed, verified, moves, settings, near_tangent_rad=profile.near_tangent_rad
            )
        result.extra["verification"] = result.verification.to_json()
        # a failed family is a warning (an error under strict) at its worst block
        result.diagnostics.extend(result.verification.diagnostics(strict=opts.strict))
        result.diagnostics.sort(key=lambda d: (d.span.line, d.span.column))
    exact_toolpath = toolpath
    if toolpath and result.ok:
        with stage(f"corners ({opts.corners})"):
            exact_toolpath, toolpath = _corners(result, moves, opts)
        result.toolpath = toolpath
    if opts.timing and toolpath:
        before_timing = len(result.diagnostics)
        _attach_timing(result, opts.machine, jerk=opts.jerk, workers=opts.workers, engine=opts.jerk_engine)
        if opts.jerk and toolpath is not exact_toolpath and opts.corners != corner_strategies.PROGRAM:
            _keep_the_faster_under_jerk(result, exact_toolpath, opts, before_timing)
    return result


def _corners(result: PlanResult, moves: list[Move], opts: PlanOptions) -> tuple[list[Segment], list[Segment]]:
    """The exact tool path (with the program's exact stops) and the path with the corners the
    options ask for (see :class:`PlanOptions`; the same list when no corner is rounded), and the
    ``corners`` report in ``result.extra`` when a strategy ran
    (:func:`trcopt.optimize.corners.apply.apply_corners`)."""
    from trcopt.optimize.corners.apply import apply_corners

    objective = CornerObjective.JERK if opts.jerk and _has_xy_jerk(opts.machine) else CornerObjective.CURVATURE
    exact, blended, report = apply_corners(
        result.toolpath,
        result.programmed,
        moves,
        mode=opts.corners,
        tolerance_mm=opts.tolerance_mm,
        tolerance_kind=opts.tolerance_kind,
        machine=opts.machine,
        workers=opts.workers,
        select=not opts.jerk,
        objective=objective,
    )
    if report is not None:
        result.extra["corners"] = report
    return exact, blended


def _keep_the_faster_under_jerk(
    result: PlanResult, exact_toolpath: list[Segment], opts: PlanOptions, before_timing: int
) -> None:
    """Under jerk limits, time the controller's exact path as well and keep whichever is faster.

    The transitions are chosen by their curvature (rate) without timing the whole path jerk-limited,
    and on parts with only sharp corners at a small tolerance exact stop can be faster (measured in
    benchmarks/JERK.md); ``corners.kept`` and both cycle times in the JSON say which was kept.
    """
    corners = result.extra["corners"]
    transitions = result.timing
    if transitions is None or not transitions.jerk_limited:
        return  # the jerk-limited feed of the transitions failed: the warning says so
    exact = PlanResult(result.program, result.dialect, result.nc, result.programmed, exact_toolpath, [])
    _attach_timing(exact, opts.machine, jerk=True, workers=opts.workers, engine=opts.jerk_engine)
    if exact.timing is None or not exact.timing.jerk_limited:
        return
    corners["transitions_duration_s"] = transitions.duration
    corners["exact_duration_s"] = exact.timing.duration
    if exact.timing.duration < transitions.duration:
        corners["kept"] = "exact"
        result.toolpath, result.timing = exact.toolpath, exact.timing
        # the timing warnings of the discarded profile go with it (they follow ``before_timing``)
        result.diagnostics[before_timing:] = exact.diagnostics
    else:
        corners["kept"] = "transitions"


def _controller(name: str, what: str) -> Controller:
    """The registered controller called ``name``; an unknown name is a usage error."""
    from trcopt import controllers

    try:
        return controllers.get(name)
    except ValueError as exc:
        raise TrcoptError(f"--{what}: {exc}", code=Code.USAGE) from None


def _has_xy_jerk(machine: Machine) -> bool:
    return all(machine.axis(k).jmax_mm_s3 is not None for k in "XY")


def _attach_toolholder(result: PlanResult) -> None:
    """Toolholder with orientation capability: active holder, angles, $P_TCANG (JSON key
    ``toolholder``) when the program defines or selects one."""
    carriers = result.nc.extras.get("carriers") or {}
    events = result.nc.extras.get("toolholder_events") or []
    if not carriers and not events:
        return
    from trcopt.kinematics import evaluate_toolholder

    report, diags = evaluate_toolholder(carriers, events, result.program)  # type: ignore[arg-type]
    result.extra["toolholder"] = report
    result.diagnostics.extend(diags)
    result.diagnostics.sort(key=lambda d: (d.span.line, d.span.column))


JERK_CHECK_DT_S = 2e-4  # sampling of the limit check of a jerk-limited feed
ACCELERATION_CHECK_DT_S = 1e-3  # sampling of the limit check of the acceleration-limited feed (as the JSON's)


def check_step(duration_s: float, dt_s: float) -> float:
    """The sampling step of a limit check (:func:`trcopt.timing.trajectory.check_step`)."""
    from trcopt.timing.trajectory import check_step as step

    return step(duration_s, dt_s)


def _attach_timing(
    result: PlanResult, machine: Machine, *, jerk: bool = False, workers: int = 1, engine: str = "nlp"
) -> None:
    try:
        from trcopt.timing import time_parameterize
    except ImportError:  # the timing stage is optional at this layer
        return
    try:
        with stage("timing"):
            acceleration_limited = time_parameterize(result.toolpath, machine)
    except TrcoptError as exc:
        _timing_warning(result, exc, "timing not computed")
        return
    result.timing = acceleration_limited
    # never silently wrong: the profile is re-checked against every limit between its grid points
    check_dt = check_step(acceleration_limited.duration, ACCELERATION_CHECK_DT_S)
    rep = acceleration_limited.check_limits(check_dt)
    if not rep.ok:
        _timing_warning(result, limits_error(rep, acceleration_limited, machine, check_dt), "timing check")
    if jerk:
        from trcopt.timing.jerk import jerk_limited

        try:
            with stage("jerk-limited timing"):
                jerk_limited_feed = jerk_limited(
                    result.toolpath, machine, base=acceleration_limited, workers=workers, engine=engine
                )
        except TrcoptError as exc:
            _timing_warning(result, exc, "jerk-limited feed not computed (the acceleration-limited feed is kept)")
            return
        result.timing = jerk_limited_feed
        # never silently wrong: the profile is re-checked against every limit
        rep = jerk_limited_feed.check_limits(dt=check_step(jerk_limited_feed.duration, JERK_CHECK_DT_S))
        if not rep.ok:
            from trcopt.errors import TimingError

            msg = (
                f"the jerk-limited feed exceeds a limit: jerk measure {max(rep.jerk_ratio):.4f}, "
                f"acceleration {max(rep.a_ratio):.4f}, velocity {max(rep.v_ratio):.4f} × the machine limit"
            )
            _timing_warning(result, TimingError(msg), "jerk-limited feed check")


def limits_error(rep: Any, trajectory: Trajectory, machine: Machine, check_dt: float) -> TrcoptError:
    """The ``TIMING-LIMITS`` error of an acceleration-limited feed whose check ``rep`` found a
    limit exceeded between grid points, at the block of its worst sample."""
    from trcopt.errors import TimingError

    msg = (
        f"the acceleration-limited feed exceeds a limit between its grid points: acceleration "
        f"{max(rep.a_ratio):.4f}, velocity {max(rep.v_ratio):.4f}, feed {rep.feed_ratio:.4f} × the limit "
        "(the cycle time is optimistic there; JSON timing.max_ratios)"
    )
    return TimingError(msg, _worst_sample_span(trajectory, machine, check_dt), Code.TIMING_LIMITS)


def _worst_sample_span(trajectory: Trajectory, machine: Machine, dt_s: float) -> SourceSpan | None:
    """The source block of the sample whose acceleration is largest against the axis limits (the
    first such sample; the samples evaluated in pieces, so a long cycle's are never all held)."""
    import numpy as np

    from trcopt.timing.checks import sample_chunks

    amax = np.array([machine.axis(k).amax_mm_s2 for k in "XYZ"])
    best, seg = -np.inf, None
    for ts in sample_chunks(trajectory.duration, dt_s, chunk=1 << 16):
        smp = trajectory.evaluate(ts)
        if not len(smp.segment):
            continue
        ratio = (np.abs(smp.a) / amax).max(axis=1)
        k = int(np.argmax(ratio))
        if ratio[k] > best:  # strictly: an equal value later is not the first
            best, seg = float(ratio[k]), int(smp.segment[k])
    return None if seg is None else trajectory.segments[seg].span


def _timing_warning(result: PlanResult, exc: TrcoptError, what: str) -> None:
    diag = exc.to_diagnostic()
    result.diagnostics.append(
        Diagnostic(Severity.WARNING, diag.code, f"{what}: {diag.message}", diag.span or SourceSpan())
    )


def plan_file(path: str | Path, options: PlanOptions | None = None) -> PlanResult:
    """Plan a part program file; an unreadable file raises :class:`TrcoptError` (code ``IO``), a
    file that is not text (:func:`trcopt.nc.text.decode_program`) one with code ``NC-NOT-TEXT``."""
    from trcopt.nc.text import decode_program

    p = Path(path)
    try:
        raw = p.read_bytes()
    except OSError as exc:
        raise TrcoptError(f"cannot read {p}: {exc.strerror}", code=Code.IO) from None
    return plan(decode_program(raw, str(path)), file=str(path), options=options)
