"""SINUMERIK 840D sl dialect: reads a program block by block into canonical moves.

The program is scanned into statements (:mod:`trcopt.controllers.siemens.flow`: control structures,
jumps, calls, lexed blocks; read block by block, :meth:`SiemensReader.iter_moves`, the statements
are made as they run, :mod:`trcopt.controllers.siemens.lazyscan`) and run by
:mod:`trcopt.controllers.siemens.runner` (program counter, subprograms), which gives each block's
moves as it has run; each block's words are dispatched to the handlers of
:mod:`trcopt.controllers.siemens.words`, and :meth:`SiemensReader._finish` completes the block:
plane change (alarm 10757), T/D selection, compensation side (tool type check), feed
(:mod:`~trcopt.controllers.siemens.feedrate`: G94/G95, S, M3/M4/M5, alarm 10860), end point,
arc centre (I/J/K, ``=AC``, ``CR=``) with the end radius check, SAR words, and the
:class:`~trcopt.nc.model.Move`. The first error stops reading; warnings are collected.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Iterator

from trcopt.codes import Code
from trcopt.controllers.siemens.block import _GEOMETRY_WORDS, _MOTION_WORDS, _QUIET_CALLS, _QUIET_KEYWORDS, Block
from trcopt.controllers.siemens.flow import scan
from trcopt.controllers.siemens.frames import FRAME_WORDS, IDENTITY, find_zero_offsets, load_zero_offsets
from trcopt.controllers.siemens.lazyscan import scan_lazy
from trcopt.controllers.siemens.lexer import Expr, LexedBlock, Word
from trcopt.controllers.siemens.motion import MotionGeometry
from trcopt.controllers.siemens.path_control import PathControlState
from trcopt.controllers.siemens.runner import ProgramRunner
from trcopt.controllers.siemens.tooldata import find_tool_table, load_tool_table
from trcopt.controllers.siemens.variables import Variables
from trcopt.controllers.siemens.words import MOTION_KINDS, WORD_HANDLERS, SiemensWords
from trcopt.errors import AlarmError, Diagnostic, Severity, SourceSpan, alarm
from trcopt.geometry.plane import Plane
from trcopt.geometry.vec import bisector_foot
from trcopt.modes import Side
from trcopt.nc.collector import collector_paused
from trcopt.nc.modal import (
    DEFAULT_EDGE,
    ModalState,
    ReadOptions,
    arc_centre_from_radius,
    arc_radius_mismatch,
    fail,
)
from trcopt.nc.model import CompState, Move, MoveKind, NcProgram, SarSpec
from trcopt.nc.stream import MoveStream, ReadSummary
from trcopt.nc.tools import ToolEdge, ToolTable

__all__ = ["SiemensReader", "read_siemens", "stream_siemens"]

_RAPID, _ARC, _NONE = MoveKind.RAPID, MoveKind.ARC, MoveKind.NONE
#: names a DEF variable may not take: addresses and keywords trcopt reads or refuses
_RESERVED = frozenset(
    [*WORD_HANDLERS, *_MOTION_WORDS, *_GEOMETRY_WORDS, *_QUIET_KEYWORDS, "PROC", "REAL", "INT", "BOOL", "CHAR",
     "STRING", "AXIS", "FRAME", "SUPA", "CIP", "CT", *FRAME_WORDS, "RPL", "EXTERN", "MCALL", "RET"]
)  # fmt: skip
#: names alone in a block that are words, not subprogram calls
_KNOWN = frozenset([*_RESERVED, *_QUIET_CALLS, "ENDLABEL"])


class SiemensReader(ProgramRunner, MotionGeometry, SiemensWords):
    """Reads one SINUMERIK program (one instance per read)."""

    name = "siemens"

    known_words = _KNOWN

    def __init__(self, options: ReadOptions, tools: dict[tuple[int, int], ToolEdge] | None = None,
                 tool_source: str = "") -> None:  # fmt: skip
        self.options = options
        self.file = self.main_file = options.file
        self.tol = options.tolerances
        self.state = ModalState(ToolTable({**(tools or {}), **(options.tools or {})}))
        self.tool_source = tool_source
        self.frame = IDENTITY  # the programmable frame
        self.settable = 500  # G500 after reset
        self.reference: int | None = None  # the settable zero offset of the plan's coordinates
        self.zero = None
        self.zero_source = "no zero-offset file (--zero-offsets, or <program>.offsets.toml beside the program)"
        self.circle = 1  # motion group 1: G0…G3, CIP (-1), CT (-2)
        self.pole = (0.0, 0.0)
        self.polar = [0.0, 0.0]  # modal AP (degrees), RP (mm)
        self.mcall: tuple[str, str, int] | None = None
        # how often each block ran: a byte a line (ran at all) and the lines that ran again
        self._seen: dict[str, bytearray] = {}
        self._again: dict[tuple[str, int], int] = {}
        self.moves: list[Move] = []  # the moves made and not given yet (trcopt.controllers.siemens.runner)
        self.last_motion: Move | None = None  # the last move that moves (CT)
        self.diagnostics: list[Diagnostic] = []
        self.carriers: dict[int, dict[int, object]] = {}
        self.toolholder_events: list[dict[str, object]] = []
        self.blocks = 0
        self.absolute = True  # G90
        self.path = PathControlState()  # G60/G9/G64/G641…G645, ADIS, CTOL, CYCLE832
        self.geom_scale = 1.0  # G70/G700: inch
        self.feed_scale = 1.0  # G700: inch feeds
        self._plane_uv = Plane.G17.axes[:2]  # indices of the active plane's u and v axes
        self.arc_ccw = False  # G3 (True) or G2 (False), modal with the motion group
        self.variables = Variables(_RESERVED)
        self._executable = False  # a DEF after the first executable block is alarm 14500

    # ------------------------------------------------------------------ driver
    def read(self, text: str) -> NcProgram:
        """Read the whole program; never raises for a problem in the program."""
        with collector_paused():  # the moves are acyclic (trcopt.nc.collector)
            moves = tuple(self.iter_moves(text, lazy=False))
        return NcProgram(
            file=self.main_file,
            dialect=self.name,
            moves=moves,
            diagnostics=tuple(self.diagnostics),
            blocks=self.blocks,
            extras=self.extras(),
        )

    def iter_moves(self, text: str, lazy: bool = True) -> Iterator[Move]:
        """The moves of ``text`` as the blocks run; when it ends, ``diagnostics``, ``blocks`` and
        :meth:`extras` are those :meth:`read` returns. ``lazy``: the statements of the program
        and its subprograms are made as they run (:func:`~.lazyscan.scan_lazy`: the program's
        statements and moves are never all held), else scanned first (:func:`~.flow.scan`)."""
        ended = failed = False
        program = None
        self.scan = scan_lazy if lazy else scan  # of the main program and the subprograms
        try:
            program = self.scan(text, self.file, "", self.known_words)
            ended = yield from self._run(program)
        except AlarmError as exc:
            self.diagnostics.append(exc.diagnostic)
            failed = True
        except (ArithmeticError, LookupError, TypeError, ValueError) as exc:  # a bug must not pass silently
            span = self._current_span()
            message = f"internal error while reading this block: {exc!r}"
            self.diagnostics.append(Diagnostic(Severity.ERROR, Code.NC_INTERNAL, message, span))
            failed = True
        if self.moves:  # those not given yet (of the last blocks, those before an error too)
            yield from self.moves
            self.moves.clear()
        if not ended and not failed:
            lines = len(program.statements) if program is not None else 0
            self._warn(Code.NC_NO_END, "program has no end (M2/M30)", SourceSpan(self.main_file, max(lines, 1), 1))

    def extras(self) -> dict[str, object]:
        """The program's extras: toolholders, toolholder events and tool data."""
        return {
            "carriers": self.carriers,
            "toolholder_events": self.toolholder_events,
            "tools": self.state.tools.as_dict(),
        }

    def _current_span(self) -> SourceSpan:
        levels = getattr(self, "levels", None)
        if not levels:
            return SourceSpan(self.file, 1, 1)
        level = levels[-1]
        st = level.program.statements[max(level.pc - 1, 0)] if level.program.statements else None
        return SourceSpan(self.file, 1, 1) if st is None else st.span(level.program.file)

    def _define(self, line: str, lineno: int, m: re.Match[str]) -> None:
        """A DEF block: only in the definition part, before the first executable block."""
        number = None if m.group("n") is None else "N" + str(int(m.group("n")))
        column = line.upper().index("DEF", m.start("n") if m.group("n") else 0) + 1
        span = SourceSpan(self.file, lineno, column, number)
        if self._executable:
            raise AlarmError(
                alarm(
                    14500, "DEF after the first executable block: definitions belong at the start of the program", span
                )
            )
        self.variables.define(line, m.end(), span)

    def _assign(self, word: Word, b: Block, span: SourceSpan) -> None:
        """``R1=…``, ``R[…]=…``, ``NAME=…``, ``NAME[…]=…``: evaluated and stored in block order."""
        value = word.value
        if type(value) is not float:
            if not isinstance(value, Expr):
                if isinstance(value, str):  # a string into a STRING variable: nothing trcopt uses
                    if word.name in self.variables.user and self.variables.user[word.name].type == "STRING":
                        return
                raise fail(Code.NC_SYNTAX, f"invalid value in {word.text!r}", self._at(span, word))
            value = self.variables.word_value(word, value, span)
        if not self.variables.assign(word, value, span):
            message = f"{word.text}: STRING variables are not modelled (ignored)"
            self._warn(Code.NC_UNSUPPORTED_WORD, message, self._at(span, word))

    def _block(self, lexed: LexedBlock, lineno: int) -> bool:
        seen = self._seen.get(self.file)
        if seen is None:
            seen = self._seen[self.file] = bytearray()
        if lineno >= len(seen):
            seen.extend(bytes(lineno + 1 - len(seen)))
        if seen[lineno]:  # the block runs again: how often it ran is counted from its second run
            key = (self.file, lineno)
            run = self._again.get(key, 0) + 1
            self._again[key] = run
        else:
            seen[lineno] = 1
            run = 0
        span = SourceSpan(self.file, lineno, lexed.first_column, lexed.number, None, None, run)
        self._executable = True
        b = Block()
        if lexed.label is not None:
            b.actions.append(lexed.label + ":")
        handlers = WORD_HANDLERS
        variables = self.variables
        words = lexed.words
        if words and words[0].name in FRAME_WORDS:
            self._frame_block(words, span)
            words = []
        for word in words:
            handler = handlers.get(word.name)
            if handler is None:
                if word.name[0] == "$":
                    self._system_variable(word, b, span)
                elif variables.is_assignment(word):
                    self._assign(word, b, span)
                else:
                    self._unsupported(word, b, span)
            else:
                handler(self, word, b, span)
        self._moved = False
        self._finish(b, span)
        if b.cycle is not None:
            cycle = b.cycle
            column = cycle.column + len(cycle.name) + 1
            self._run_cycle(cycle.name, cycle.subscript or "", column, self._at(span, cycle))
        elif self.mcall is not None and self._moved:
            self._run_cycle(*self.mcall, span)
        return b.end

    # ------------------------------------------------------------------ block completion
    def _finish(self, b: Block, span: SourceSpan) -> None:
        st = self.state
        # plane change: not while TRC is active (alarm 10757)
        if b.plane is not None:
            plane, col = b.plane
            if plane is not st.plane and st.side is not Side.OFF:
                raise AlarmError(
                    alarm(
                        10757,
                        f"plane change {st.plane.value} -> {plane.value} while tool radius compensation is active",
                        SourceSpan(self.file, span.line, col, span.block),
                    )
                )
            st.plane = plane
            self._plane_uv = plane.axes[:2]
        if b.t is not None:
            st.tool = b.t
            st.edge = b.d if b.d is not None else DEFAULT_EDGE
        elif b.d is not None:
            st.edge = b.d
        side_programmed = b.side is not None
        if b.side is not None:
            side, col = b.side
            if side is not Side.OFF:
                edge = st.active_edge()
                if edge is None and st.tool is not None and st.edge:
                    raise AlarmError(alarm(
                        10750,
                        f"G{40 + (side is Side.RIGHT) + 1} with T{st.tool} D{st.edge}: no data for this tool edge "
                        f"($TC_DP… in the program, then {self.tool_source or 'the tools given'})",
                        SourceSpan(self.file, span.line, col, span.block),
                    ))  # fmt: skip
                if edge is not None and not edge.supports_trc:
                    raise fail(
                        Code.NC_TOOL_TYPE,
                        f"unsupported tool type for TRC: tool type {edge.type} ({edge.kind})",
                        SourceSpan(self.file, span.line, col, span.block),
                    )
            st.side = side
        self._apply_feed(b, span)  # feed type, F, S, M3/M4 (trcopt.controllers.siemens.feedrate)
        if b.motion is not None:
            code = b.motion[0]
            st.motion = MOTION_KINDS.get(code, _ARC)
            self.circle = code
            self.arc_ccw = code == 3
        pos = st.position
        kind, end, center, ccw, plane_programmed, span = self._geometry(b, span)
        plane = st.plane
        motion = st.motion
        ax, ay, az = b.axes
        self._moved = kind is not _NONE
        if b.sar is not None and self.frame is not IDENTITY:
            f = self.frame
            wi = plane.axes[2]
            if (
                f.m[wi][wi] != 1.0
                or f.t[wi] != 0.0
                or abs(abs(f.m[plane.axes[0]][plane.axes[0]] ** 2 + f.m[plane.axes[1]][plane.axes[0]] ** 2) - 1.0)
                > 1e-12
            ):
                raise fail(Code.NC_FRAME, "SAR under a frame that scales the plane or moves the applicate is not "
                           "modelled by trcopt", span)  # fmt: skip
        sar = None
        if b.sar is not None:
            sar = SarSpec(
                contour=b.sar[0],
                side=st.sar_side,
                segmentation=st.sar_segmentation,
                disr=b.disr,
                discl=b.discl,
                disrp=b.disrp,
                fad=self._fad_feed(b, span),
                end_programmed=(ax is not None, ay is not None, az is not None),
            )
        elif b.sar_param is not None:
            w = b.sar_param
            self._warn(
                Code.NC_SAR_PARAM,
                f"{w.name} without G147/G148/G247/G248/G347/G348 in the block is ignored",
                self._at(span, w),
            )
        if kind is _RAPID or (kind is _NONE and motion is _RAPID):
            feed = None
        else:
            feed = st.feed_mm_s
            if feed is None and kind is not _NONE:
                self._feed_missing(span)  # alarm 10860 (no F in force), G95 without a turning spindle
        move = Move(
            kind=kind,
            start=pos,
            end=end,
            plane=plane,
            span=span,
            comp=self._comp(side_programmed),
            feed_mm_s=feed,
            center=center,
            ccw=ccw,
            turns=b.turn,
            actions=tuple(b.actions),
            sar=sar,
            plane_programmed=plane_programmed,
            control=self.path.control(kind, b.exact_stop, span, self.diagnostics),
        )
        self.moves.append(move)
        if kind is not _NONE:
            self.last_motion = move
        st.position = end
        self._after_feed(b, span)  # M5 at the block end

    def _comp(self, side_programmed: bool) -> CompState:
        """The compensation snapshot; a frame that mirrors the plane swaps G41 and G42."""
        comp = self.state.comp_state(side_programmed)
        if self.frame is IDENTITY or comp.side is Side.OFF or not self.frame.mirrored(self.state.plane):
            return comp
        return dataclasses.replace(comp, side=Side.RIGHT if comp.side is Side.LEFT else Side.LEFT)

    def _arc_centre(
        self,
        b: Block,
        start: tuple[float, float, float],
        end: tuple[float, float, float],
        ccw: bool,
        span: SourceSpan,
    ) -> tuple[float, float, float]:
        plane = self.state.plane
        su, sv, sw = plane.to_uvw(start)
        eu, ev, _ = plane.to_uvw(end)
        col_span = SourceSpan(self.file, span.line, b.centre_col or span.column, span.block)
        tol = self.tol.arc_end_radius_mm
        if b.cr is not None:
            if any(c is not None for c in b.centre):
                raise fail(Code.NC_SYNTAX, "CR= together with I/J/K in one block", col_span)
            try:
                cu, cv = arc_centre_from_radius((su, sv), (eu, ev), b.cr, ccw, tol, self.tol.coincidence_mm)
            except ValueError as exc:
                raise fail(Code.NC_ARC_RADIUS, str(exc), col_span) from None
        else:
            u, v, w = plane.axes
            if not any(b.centre[i] is not None for i in (u, v)):
                raise fail(Code.NC_ARC_CENTRE, "circle without centre (I/J/K) or radius (CR=)", col_span)
            if b.centre[w] is not None:
                self._warn(
                    Code.NC_UNSUPPORTED_WORD,
                    f"centre word {'IJK'[w]} on the applicate ({plane.value}) ignored",
                    col_span,
                )
            coords = []
            for i, s in ((u, su), (v, sv)):
                c = b.centre[i]
                coords.append(s if c is None else (c[0] if c[1] else s + c[0]))
            cu, cv = coords
        radius_start = math.hypot(su - cu, sv - cv)
        if radius_start <= self.tol.coincidence_mm:
            raise fail(Code.NC_ARC_RADIUS, "circle radius is zero (centre at the start point)", col_span)
        mismatch = arc_radius_mismatch((su, sv), (eu, ev), (cu, cv), tol)
        if mismatch is not None:
            raise fail(
                Code.NC_ARC_RADIUS,
                f"arc end point not on the circle: start radius "
                f"{mismatch[0]:.4f} mm, end radius {mismatch[1]:.4f} mm (difference "
                f"{abs(mismatch[0] - mismatch[1]):.4f} > {tol} mm)",
                col_span,
            )
        # within the tolerance the end point is taken as right and the centre corrected onto the
        # chord's bisector (SINUMERIK circle end point monitoring): the circle runs through both
        cu, cv = bisector_foot((su, sv), (eu, ev), (cu, cv))
        return plane.to_xyz((cu, cv, sw))


def read_siemens(text: str, options: ReadOptions) -> NcProgram:
    """Read a SINUMERIK program. Tool data: the TOML tool table ``options.tool_table`` (default: the
    one beside the program, :func:`~trcopt.controllers.siemens.tooldata.find_tool_table`), then
    ``options.tools``, then the program's ``$TC_DP`` assignments; zero offsets: ``options.zero_offsets``
    (default: the one beside the program). An invalid file raises :class:`~trcopt.errors.ConfigError`."""
    return _reader(options).read(text)


def stream_siemens(text: str, options: ReadOptions) -> MoveStream:
    """:func:`read_siemens` block by block (:meth:`SiemensReader.iter_moves`)."""
    reader = _reader(options)
    return MoveStream(
        options.file,
        reader.name,
        reader.iter_moves(text),
        lambda: ReadSummary(list(reader.diagnostics), reader.blocks, reader.extras()),
    )


def _reader(options: ReadOptions) -> SiemensReader:
    path = options.tool_table if options.tool_table is not None else find_tool_table(options.file)
    if path is not None:
        tools = load_tool_table(path)
        source = f"the tool table {path}"
    else:
        tools = {}
        source = "no tool table (--tool-table; none beside the program: <program>.tools.toml, tools.toml)"
    reader = SiemensReader(options, tools, source)
    if options.zero_offsets is not None or find_zero_offsets(options.file) is not None:
        reader.zero = load_zero_offsets(options.zero_offsets or find_zero_offsets(options.file))  # type: ignore[arg-type]
    return reader
