"""``plan_streamed``: a plan computed window by window in bounded memory, its outputs written as
they are produced.

The program is read once, block by block (:func:`trcopt.controllers.stream_program`); the moves
flow through the lead pass and the compensation (both generators); the tool path is cut into
windows of about :data:`WINDOW_SEGMENTS` segments at the ends of timing sections (where the tool
stops: the timing of one window does not depend on the next), and each window is kept in a
temporary file (:class:`~trcopt.io.spill.SpilledSegments`) while the programmed contour is
gathered as the verification's part (:class:`~trcopt.verify.store.ProgramStore`, compact
columns). Then each window is read back, verified against the whole part
(:class:`~trcopt.verify.stream.StreamVerifier`), timed (:func:`trcopt.timing.time_parameterize`)
and written to the JSON output; the G-code writer reads the same file. Neither the moves nor the
segments of the whole program are ever held as objects; the outputs are put in place atomically
at the end.

The result equals :func:`trcopt.pipeline.plan`'s (the same diagnostics, segments, cycle time and
verification; segment times to rounding in the last digits, since each window's times start at
the sum of the previous windows' durations) for the programs it takes. It does not take (raises
:class:`Unstreamable`, and the caller plans the whole program instead): a corner strategy other
than ``program`` or a path-control mode that rounds corners (transitions span windows), the
jerk-limited feed, a program whose blocks run out of line order (loops, subprograms: the G-code
writer places the program's words by line), and a timing stage that fails (the whole plan then
reports it as :func:`~trcopt.pipeline.plan` does).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from trcopt.codes import Code
from trcopt.compensation import programmed_segment
from trcopt.compensation.engine import makes_segment
from trcopt.errors import Diagnostic, Severity, TrcoptError
from trcopt.modes import PathMode
from trcopt.nc.collector import collector_paused
from trcopt.nc.model import Move, NcProgram
from trcopt.optimize.corners import strategies as corner_strategies
from trcopt.path import Segment, segments_length
from trcopt.pipeline import ACCELERATION_CHECK_DT_S, AUTO, PlanOptions, _controller, check_step
from trcopt.pipeline.summary import summary_text

if TYPE_CHECKING:
    from trcopt.io.plan_json_parts import ArrayText

__all__ = ["WINDOW_SEGMENTS", "Unstreamable", "StreamedPlan", "plan_streamed"]

JERK_DT_S = 1e-3  # the finite-difference step of the timing JSON's max_jerk
WINDOW_SEGMENTS = 4096  # tool-path segments per window, about (a window ends where a timing section does)


class Unstreamable(Exception):
    """The program or the options need the whole-program plan; the message says why."""


@dataclass
class StreamedPlan:
    """What a streamed plan leaves once its outputs are written: the summary's numbers."""

    program: str
    dialect: str
    nc: NcProgram  # without moves
    segments: int = 0
    length_mm: float = 0.0
    diagnostics: list[Diagnostic] = field(default_factory=list)
    timing: _Timing | None = None
    verification: Any = None
    extra: dict[str, Any] = field(default_factory=dict)
    out: Any = None  # the JSON parts (_Outputs) when asked for
    toolpath: Any = ()  # with gcode: the tool path in its file (SpilledSegments)
    source: str = ""  # with gcode: the program text (the G-code writer reads its words)

    @property
    def ok(self) -> bool:
        return not any(d.severity is Severity.ERROR for d in self.diagnostics)

    @property
    def duration(self) -> float | None:
        return None if self.timing is None else self.timing.duration

    def json_chunks(self, samples: str | None = None) -> Iterator[str]:
        """The plan JSON's text in pieces (as :meth:`~trcopt.pipeline.PlanResult.json_chunks`)."""
        from trcopt.io.plan_json_parts import plan_json_parts_chunks

        assert self.out is not None, "plan_streamed(json=True) builds the JSON"
        try:
            yield from plan_json_parts_chunks(
                program=self.program, dialect=self.dialect, diagnostics=self.diagnostics,
                programmed=self.out.programmed, toolpath=self.out.toolpath,
                timing=None if self.timing is None else self.timing.to_json(),
                sections=self.out.sections, extra=self.extra,
            )
        finally:
            self.out.close()

    def summary(self) -> str:
        return summary_text(
            self.program, self.dialect, self.nc.blocks, self.segments, self.length_mm, self.timing, None,
            self.verification, self.diagnostics,
        )


@dataclass
class _Timing:
    """The acceleration-limited feed of the windows so far: the ``timing`` JSON object merged."""

    machine: Any
    duration: float = 0.0
    length: float = 0.0
    segments: int = 0
    sections: int = 0
    json: dict[str, Any] | None = None
    worst: tuple[float, TrcoptError] | None = None  # the largest ratio past a limit and its warning
    jerk_limited: bool = False
    end_a: Any = None  # per-axis acceleration at the end of the last window, mm/s²

    def add(self, window: list[Segment], sections_out: ArrayText | None, samples: str | None) -> list[Any]:
        """Time one window; returns the segments with their times. Raises ``TrcoptError`` as
        :func:`~trcopt.timing.time_parameterize` does."""
        from trcopt.pipeline import limits_error
        from trcopt.timing import time_parameterize

        traj = time_parameterize(window, self.machine)
        rep = traj.check_limits(check_step(traj.duration, ACCELERATION_CHECK_DT_S))
        if not rep.ok:
            ratio = max(max(rep.a_ratio), max(rep.v_ratio), rep.feed_ratio)
            if self.worst is None or ratio > self.worst[0]:
                check_dt = check_step(traj.duration, ACCELERATION_CHECK_DT_S)
                self.worst = (ratio, limits_error(rep, traj, self.machine, check_dt))
        part = traj.to_json(samples=samples)
        self._boundary_jerk(traj, part)
        t0, t1 = traj.segment_times()
        t = self.duration
        timed = [s.with_times(t + a, t + b) for s, a, b in zip(window, t0.tolist(), t1.tolist(), strict=True)]
        if sections_out is not None:
            sections_out.add(_shifted(sec, self.sections, self.segments, t, self.length) for sec in part["sections"])
        self.sections += len(part["sections"])
        self.segments += len(window)
        self.duration += traj.duration
        self.length += part["length_mm"]
        part["sections"] = None  # written to its part (plan_json_parts), in its place
        self.json = part if self.json is None else _merged(self.json, part)
        return timed

    def _boundary_jerk(self, traj: Any, part: dict[str, Any]) -> None:
        """The finite-difference jerk across the window's start (the whole plan's samples straddle
        it): the jump from the previous window's last acceleration to this one's first."""
        import numpy as np

        end = traj.duration
        a = traj.evaluate(np.array([min(1e-9, 0.5 * end), max(end - 1e-9, 0.5 * end)])).a
        if self.end_a is not None:
            jump = np.abs(a[0] - self.end_a) / JERK_DT_S
            for k, axis in enumerate("XYZ"):
                part["max_jerk_mm_s3"][axis] = max(part["max_jerk_mm_s3"][axis], float(jump[k]))
                jm = self.machine.axis(axis).jmax_mm_s3
                if jm is not None:
                    part["max_jerk_ratio"][axis] = part["max_jerk_mm_s3"][axis] / jm
        self.end_a = a[1]

    def to_json(self) -> dict[str, Any]:
        assert self.json is not None
        return {**self.json, "duration_s": self.duration, "length_mm": self.length}


def _shifted(sec: dict[str, Any], sections: int, segments: int, t: float, s: float) -> dict[str, Any]:
    return {
        **sec,
        "s_start_mm": round(sec["s_start_mm"] + s, 9),
        "index": sec["index"] + sections,
        "first_segment": sec["first_segment"] + segments,
        "last_segment": sec["last_segment"] + segments,
        "t_start_s": sec["t_start_s"] + t,
        "t_end_s": sec["t_end_s"] + t,
    }


def _merged(a: Any, b: Any) -> Any:
    """Two windows' timing values as one: sums of lengths, largest ratios, all limits kept."""
    if isinstance(a, dict) and isinstance(b, dict):
        return {k: (_merged(v, b[k]) if k in b else v) for k, v in a.items()}
    if isinstance(a, bool) or isinstance(b, bool):
        return bool(a) and bool(b)
    if a is None or b is None:
        return a if b is None else b
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return max(a, b)
    return a


def plan_streamed(
    path: str,
    options: PlanOptions | None = None,
    *,
    json: bool = False,
    gcode: bool = False,
    samples: str | None = None,
    window: int = WINDOW_SEGMENTS,
) -> StreamedPlan:
    """Plan the program file ``path`` window by window (module description); with ``json`` the
    plan JSON is built in parts as the windows pass (:meth:`StreamedPlan.json_chunks` at the end;
    ``samples`` as :meth:`~trcopt.pipeline.PlanResult.to_json`'s); with ``gcode`` the tool path is
    kept in a temporary file (:class:`~trcopt.io.spill.SpilledSegments`) with the moves that carry
    words, so that :func:`trcopt.io.gcode_program.plan_to_gcode_chunks` can write it from the result.

    Raises
    ------
    Unstreamable
        The program or the options need :func:`~trcopt.pipeline.plan` (nothing has been written).
    TrcoptError
        The file cannot be read or is not text (as :func:`~trcopt.pipeline.plan_file`).
    """
    from trcopt import controllers
    from trcopt.io.plan_json_parts import ArrayText
    from trcopt.nc.text import decode_program

    opts = options or PlanOptions()
    _check_options(opts)
    settings = opts.settings if not opts.strict else opts.settings.with_(strict=True)
    try:
        with open(path, "rb") as fh:
            raw = fh.read()
    except OSError as exc:
        raise TrcoptError(f"cannot read {path}: {exc.strerror}", code=Code.IO) from None
    text = decode_program(raw, str(path))
    del raw
    reader = controllers.detect(path, text) if opts.dialect == AUTO else _controller(opts.dialect, "dialect")
    profile = reader if opts.profile == AUTO else _controller(opts.profile, "profile")

    def read() -> Any:
        return controllers.stream_program(
            text, file=path, dialect=reader.name, tolerances=settings.tolerances,
            max_disc=settings.cutcom_max_disc, tool_table=opts.tool_table, zero_offsets=opts.zero_offsets,
            tool_unit=opts.tool_unit, appr_radius=opts.appr_radius.value,
        )

    def leads(moves: Iterator[Move], lead_diags: list[Diagnostic]) -> Iterator[Move]:
        return moves if reader.leads is None else reader.leads(moves, settings, lead_diags)

    def tapped(stream: Iterator[Move]) -> Iterator[Move]:
        """The reader's moves, keeping those whose words the G-code writer writes (it reads the
        program's moves as read, before the lead pass)."""
        from trcopt.io.gcode_program import carries_words

        for m in stream:
            if m.actions and carries_words(m.actions):
                run.word_moves.append(m)
            yield m

    lead_diags: list[Diagnostic] = []
    comp_diags: list[Diagnostic] = []
    stream = read()
    tap = tapped(stream) if gcode else stream  # the lead pass reads the moves through the tap
    moves = leads(tap, lead_diags)
    tee = _Moves(iter(moves), path, settings.tolerances.coincidence_mm)
    # the programmed segments feed the verification's part and the JSON; else they are counted
    tee.keep = json or opts.verify
    out = _Outputs(ArrayText(1, True), ArrayText(1, True), ArrayText(2, False)) if json else None
    run = _Run(opts, out, samples, profile.name)
    run.keep = opts.verify or opts.timing or json or gcode  # a later stage reads the windows

    def first_pass() -> Iterator[Segment]:
        """Read, compensate and cut the windows (kept in ``run.windows``); the programmed
        segments as they are read (the verification's part, known before any window is verified)."""
        buf: list[Segment] = []
        limit = window
        for seg in profile.compensate(iter(tee), settings, comp_diags, _Complete(stream, lead_diags)):
            buf.append(seg)
            if len(buf) >= limit:
                buf, programmed = run.cut(buf, tee, final=False)
                yield from programmed
                # a stretch without a stop grows the window: look for its end again at twice
                # the length (not at every segment: that would split it quadratically often)
                limit = window if len(buf) < window else 2 * len(buf)
        for _ in tee:  # the programmed contour after an alarm, as the whole plan reads it
            pass
        _, programmed = run.cut(buf, tee, final=True)
        yield from programmed
        for _ in tap:  # the blocks after a lead-pass alarm (their words; the reader's diagnostics)
            pass

    try:
        with collector_paused():  # the moves and segments hold no cycles
            if opts.verify:
                from trcopt.verify.store import ProgramStore
                from trcopt.verify.stream import StreamVerifier

                part = ProgramStore(first_pass())
                run.verifier = StreamVerifier(settings, near_tangent_rad=profile.near_tangent_rad, part=part)
                if not run.verifier.streaming:
                    raise Unstreamable("its blocks run out of line order (loops, subprograms)")
            else:
                for _ in first_pass():
                    pass
            run.second_pass()
    except BaseException:
        run.close()
        raise
    return run.finish(stream.program, reader.dialect, path, text, lead_diags + comp_diags, gcode)


@dataclass
class _Outputs:
    programmed: ArrayText
    toolpath: ArrayText
    sections: ArrayText

    def close(self) -> None:
        for part in (self.programmed, self.toolpath, self.sections):
            part.close()


class _Complete:
    """The compensation's ``complete`` flag, known when the moves end: no reader or lead error."""

    def __init__(self, stream: Any, lead_diags: list[Diagnostic]) -> None:
        self.stream, self.lead_diags = stream, lead_diags

    def __bool__(self) -> bool:
        return not self.stream.failed and not any(d.severity is Severity.ERROR for d in self.lead_diags)


class _Run:
    """The windows: cut and kept in a temporary file as the program is read and compensated
    (:meth:`cut`), then verified, timed and written one at a time (:meth:`second_pass`)."""

    def __init__(self, opts: PlanOptions, out: _Outputs | None, samples: str | None, profile: str) -> None:
        from trcopt.io.spill import SpilledSegments

        self.opts, self.out, self.samples, self.profile = opts, out, samples, profile
        self.verifier: Any = None
        self.timing = _Timing(opts.machine) if opts.timing else None
        self.segments, self.length = 0, 0.0
        self.windows = SpilledSegments()  # every window's tool path (the G-code writer's too)
        self.keep = True  # False: no later stage reads the windows (they are only counted)
        # per window: its number of segments, of programmed segments, and its SAR moves
        self.cuts: list[tuple[int, int, list[Move]]] = []
        self.word_moves: list[Move] = []  # the reader's moves that carry words (the G-code writer's)

    def cut(self, buf: list[Segment], tee: _Moves, final: bool) -> tuple[list[Segment], list[Segment]]:
        """Keep the segments of ``buf`` up to the last section end (all when ``final``) as a
        window; (the rest, the window's programmed segments)."""
        keep: list[Segment] = []
        if not final and self.timing is not None:
            from trcopt.timing.path import PathArrays
            from trcopt.timing.sections import split_sections

            try:
                sections = split_sections(buf, PathArrays(buf))
            except TrcoptError as exc:
                raise Unstreamable(f"the timing stage fails: {exc}") from None
            if len(sections) < 2:
                return buf, []  # one section so far: the window grows until it ends
            cut = sections[-1].first
            buf, keep = buf[:cut], buf[cut:]
        programmed, moves = tee.take()
        count = programmed if isinstance(programmed, int) else len(programmed)
        if self.out is not None:
            assert not isinstance(programmed, int)
            self.out.programmed.add(programmed)
        if self.keep:
            self.windows.append(buf)
        self.cuts.append((len(buf), count, [m for m in moves if m.sar is not None]))
        self.segments += len(buf)
        self.length += segments_length(buf)
        return keep, [] if isinstance(programmed, int) else programmed

    def second_pass(self) -> None:
        """Verify, time and write the windows in order."""
        chunks = self.windows.chunks()
        for n, programmed, sar_moves in self.cuts:
            buf: list[Segment] = next(chunks) if n and self.keep else []
            if self.verifier is not None:
                self.verifier.add(programmed, buf, sar_moves)
            if not buf:
                continue
            timed: list[Any] = buf
            if self.timing is not None:
                try:
                    timed = self.timing.add(buf, None if self.out is None else self.out.sections, self.samples)
                except TrcoptError as exc:
                    raise Unstreamable(f"the timing stage fails: {exc}") from None
            if self.out is not None:
                self.out.toolpath.add(timed)

    def close(self) -> None:
        if self.out is not None:
            self.out.close()
        self.windows.close()

    def finish(
        self, nc: NcProgram, dialect: str, file: str, text: str, trc_diags: list[Diagnostic], gcode: bool
    ) -> StreamedPlan:
        from trcopt.pipeline import _attach_toolholder, _timing_warning

        diagnostics = [*nc.diagnostics, *trc_diags]
        diagnostics.sort(key=lambda d: (d.span.line, d.span.column))
        plan = StreamedPlan(file, dialect, nc, self.segments, self.length, diagnostics)
        plan.out = self.out
        if gcode:
            plan.toolpath, plan.source = self.windows, text
            plan.nc = dataclasses.replace(nc, moves=tuple(self.word_moves))
        else:
            self.windows.close()
        plan.extra["profile"] = self.profile
        _attach_toolholder(plan)  # type: ignore[arg-type]
        if self.verifier is not None:
            plan.verification = self.verifier.finish()
            plan.extra["verification"] = plan.verification.to_json()
            plan.diagnostics.extend(plan.verification.diagnostics(strict=self.opts.strict))
            plan.diagnostics.sort(key=lambda d: (d.span.line, d.span.column))
        if self.timing is not None and self.segments:
            plan.timing = self.timing
            if self.timing.worst is not None:
                _timing_warning(plan, self.timing.worst[1], "timing check")  # type: ignore[arg-type]
        return plan


class _Moves:
    """The stream of moves the compensation reads, keeping what the other stages need of them:
    the programmed segments and the moves since the last window."""

    def __init__(self, moves: Iterator[Move], file: str, tol: float) -> None:
        self._moves, self.file, self.tol = moves, file, tol
        self.programmed: list[Segment] = []
        self.counted = 0  # the programmed segments since the last window when they are not kept
        self.keep = True  # False: the programmed segments are counted, not made
        self.pending: list[Move] = []
        self._line = 0

    def checked(self) -> Iterator[Move]:
        """The moves, refused (``Unstreamable``) where the program needs the whole plan."""
        for m in self._moves:
            span = m.span
            if span.file != self.file or span.line < self._line:
                raise Unstreamable("its blocks run out of line order (loops, subprograms)")
            if m.control.mode is PathMode.BLEND:
                raise Unstreamable(f"its path-control mode rounds corners ({m.control.word or 'blend'})")
            if m.comp.orientation not in (0, 9):
                raise Unstreamable("a lathe tool's tip is verified on the whole program")
            self._line = span.line
            yield m

    def __iter__(self) -> Iterator[Move]:
        if not self.keep:
            for m in self.checked():
                self.pending.append(m)
                self.counted += makes_segment(m)
                yield m
            return
        for m in self.checked():
            self.pending.append(m)
            seg = programmed_segment(m, self.tol)
            if seg is not None:
                self.programmed.append(seg)
            yield m

    def take(self) -> tuple[list[Segment] | int, list[Move]]:
        """The programmed segments since the last window (their number when they are not kept)
        and the moves."""
        out = (self.programmed if self.keep else self.counted), self.pending
        self.programmed, self.counted, self.pending = [], 0, []
        return out


def _check_options(opts: PlanOptions) -> None:
    if opts.jerk:
        raise Unstreamable("the jerk-limited feed is planned on the whole program")
    if opts.corners != corner_strategies.PROGRAM:
        raise Unstreamable(f"--corners {opts.corners} is planned on the whole program")


