"""SINUMERIK 840D sl dialect: the meaning of each word, block by block.

Modal words (G groups, OFFN, DISC, NORM/KONT…, CDON/CDOF…) change the :class:`ModalState` as
they are read, so they act on the whole block whatever their position in it; words whose effect
needs a check (plane, compensation side, T/D, feed, axes, SAR) are collected in a :class:`_Block`
and applied in :meth:`SiemensReader._finish`. Everything trcopt does not implement is reported
(warning ``NC-UNSUPPORTED-WORD``) and kept in the move's actions; words that would change the
geometry without trcopt knowing (frames, polar coordinates, splines) stop the program.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from ...errors import AlarmError, Diagnostic, Severity, SourceSpan, alarm
from ...geometry.plane import Plane
from ..interpret import (
    DEFAULT_EDGE,
    ModalState,
    ReadOptions,
    arc_centre_from_radius,
    arc_radius_mismatch,
    fail,
)
from ..lexer import Expr, LexedBlock, LexError, Word, lex_line
from ..model import (
    ApproachMode,
    ApproachStrategy,
    CollisionMode,
    CornerMode,
    Move,
    MoveKind,
    NcProgram,
    SarContour,
    SarSegmentation,
    SarSide,
    SarSpec,
    Side,
)
from ..tools import ToolTable

__all__ = ["SiemensReader"]

_AXES = {"X": 0, "Y": 1, "Z": 2}
_CENTRE = {"I": 0, "J": 1, "K": 2}
_MOTION = {0: MoveKind.RAPID, 1: MoveKind.LINE, 2: MoveKind.ARC, 3: MoveKind.ARC}
_PLANES = {17: Plane.G17, 18: Plane.G18, 19: Plane.G19}
_SIDES = {40: Side.OFF, 41: Side.LEFT, 42: Side.RIGHT}
_SAR_CONTOURS = {int(c.value[1:]): c for c in SarContour}
_SAR_SIDES = {int(c.value[1:]): c for c in SarSide}
_SAR_SEGMENTATION = {340: SarSegmentation.G340, 341: SarSegmentation.G341}
_CORNERS = {450: CornerMode.TRANSITION_CIRCLE, 451: CornerMode.INTERSECTION}
_STRATEGIES = {460: ApproachStrategy.G460, 461: ApproachStrategy.G461, 462: ApproachStrategy.G462}
_APPROACH = {m.value: m for m in ApproachMode}
_COLLISION = {m.value: m for m in CollisionMode}
_END_M = {2, 30, 17}
_INCH = 25.4
# words that would change the geometry behind trcopt's back: stop rather than guess
_GEOMETRY_WORDS = {
    "TRANS", "ATRANS", "CTRANS", "ROT", "AROT", "ROTS", "AROTS", "CROTS", "RPL", "SCALE",
    "ASCALE", "MIRROR", "AMIRROR", "AP", "RP", "CIP", "CT", "ASPLINE", "BSPLINE", "CSPLINE",
    "POLY",
}  # fmt: skip
_GEOMETRY_G = {33, 34, 35, 110, 111, 112, 331, 332}
_TOOLHOLDER_WORDS = ("TCOABS", "TCOFR", "TCOFRZ", "TCOFRY", "TCOFRX")


class _Block:
    """Scratch record of one block's words that are applied after the whole block is read."""

    __slots__ = (
        "axes", "centre", "centre_col", "cr", "turn", "motion", "plane", "side", "t", "d",
        "feed", "feed_col", "dwell", "sar", "disr", "discl", "disrp", "fad", "sar_params",
        "actions", "end",
    )  # fmt: skip

    def __init__(self) -> None:
        self.axes: list[tuple[float, bool] | None] = [None, None, None]
        self.centre: list[tuple[float, bool] | None] = [None, None, None]
        self.centre_col = 0
        self.cr: float | None = None
        self.turn = 0
        self.motion: tuple[int, int] | None = None  # (G number, column)
        self.plane: tuple[Plane, int] | None = None
        self.side: tuple[Side, int] | None = None
        self.t: int | None = None
        self.d: int | None = None
        self.feed: float | None = None  # programmed F value (unit per minute)
        self.feed_col = 0
        self.dwell = False
        self.sar: tuple[SarContour, int] | None = None
        self.disr: float | None = None
        self.discl: tuple[float, bool] | None = None
        self.disrp: tuple[float, bool] | None = None
        self.fad: tuple[float, str] | None = None
        self.sar_params: list[Word] = []
        self.actions: list[str] = []
        self.end = False


Handler = Callable[["SiemensReader", Word, _Block, SourceSpan], None]


class SiemensReader:
    """Reads one SINUMERIK program (one instance per read)."""

    name = "siemens"

    def __init__(self, options: ReadOptions) -> None:
        self.options = options
        self.file = options.file
        self.tol = options.tolerances
        self.state = ModalState(ToolTable(options.tools))
        self.moves: list[Move] = []
        self.diagnostics: list[Diagnostic] = []
        self.carriers: dict[int, dict[int, object]] = {}
        self.toolholder_events: list[dict[str, object]] = []
        self.blocks = 0
        self.absolute = True  # G90
        self.geom_scale = 1.0  # G70/G700: inch
        self.feed_scale = 1.0  # G700: inch feeds
        self.arc_ccw = False  # G3 (True) or G2 (False), modal with the motion group
        self._warned_no_feed = False

    # ------------------------------------------------------------------ driver
    def read(self, text: str) -> NcProgram:
        lines = text.splitlines()
        ended = failed = False
        for lineno, line in enumerate(lines, 1):
            try:
                lexed = lex_line(line)
            except LexError as exc:
                span = SourceSpan(self.file, lineno, exc.column, exc.block)
                self.diagnostics.append(Diagnostic(Severity.ERROR, "NC-SYNTAX", exc.message, span))
                self.blocks += 1
                failed = True
                break
            if not lexed.words and lexed.label is None:
                continue
            self.blocks += 1
            try:
                ended = self._block(lexed, lineno)
            except AlarmError as exc:
                self.diagnostics.append(exc.diagnostic)
                failed = True
                break
            if ended:
                break
        if not ended and not failed:
            span = SourceSpan(self.file, max(len(lines), 1), 1)
            self._warn("NC-NO-END", "program has no end (M2/M30)", span)
        extras: dict[str, object] = {
            "carriers": self.carriers,
            "toolholder_events": self.toolholder_events,
            "tools": self.state.tools.as_dict(),
        }
        return NcProgram(
            file=self.file,
            dialect=self.name,
            moves=tuple(self.moves),
            diagnostics=tuple(self.diagnostics),
            blocks=self.blocks,
            extras=extras,
        )

    def _warn(self, code: str, message: str, span: SourceSpan) -> None:
        self.diagnostics.append(Diagnostic(Severity.WARNING, code, message, span))

    def _at(self, span: SourceSpan, word: Word) -> SourceSpan:
        return SourceSpan(span.file, span.line, word.column, span.block)

    def _block(self, lexed: LexedBlock, lineno: int) -> bool:
        span = SourceSpan(self.file, lineno, lexed.first_column, lexed.number)
        b = _Block()
        if lexed.label is not None:
            b.actions.append(lexed.label + ":")
        handlers = _HANDLERS
        for word in lexed.words:
            handler = handlers.get(word.name)
            if handler is None:
                if word.name[0] == "$":
                    self._system_variable(word, b, span)
                else:
                    self._unsupported(word, b, span)
            else:
                handler(self, word, b, span)
        self._finish(b, span)
        return b.end

    # ------------------------------------------------------------------ value helpers
    def _number(self, word: Word, span: SourceSpan) -> float:
        value = word.value
        if type(value) is float:
            return value
        if value is None:
            raise fail("NC-SYNTAX", f"{word.name} without a value", self._at(span, word))
        if isinstance(value, Expr):
            raise fail(
                "NC-UNSUPPORTED-EXPR",
                f"expression {word.text!r} uses variables, which trcopt does not evaluate",
                self._at(span, word),
            )
        raise fail("NC-SYNTAX", f"invalid value in {word.text!r}", self._at(span, word))

    def _integer(self, word: Word, span: SourceSpan) -> int:
        value = self._number(word, span)
        if value != int(value) or value < 0:
            raise fail(
                "NC-SYNTAX",
                f"{word.name} needs a whole number, got {word.text!r}",
                self._at(span, word),
            )
        return int(value)

    def _positional(
        self, word: Word, span: SourceSpan, default_absolute: bool
    ) -> tuple[float, bool]:
        """A coordinate word: (value in mm, absolute?) honouring ``=AC(..)`` / ``=IC(..)``."""
        value = word.value
        if type(value) is tuple:
            mode, inner = value
            if mode in ("AC", "IC") and type(inner) is float:
                return inner * self.geom_scale, mode == "AC"
            if isinstance(inner, Expr):
                self._number(Word(word.name, inner, word.column, word.text), span)
            raise fail(
                "NC-SYNTAX",
                f"invalid value in {word.text!r} (expected AC(..) or IC(..))",
                self._at(span, word),
            )
        return self._number(word, span) * self.geom_scale, default_absolute

    def _keyword(self, word: Word, span: SourceSpan) -> None:
        if word.value is not None:
            raise fail("NC-SYNTAX", f"{word.name} takes no value", self._at(span, word))

    # ------------------------------------------------------------------ word handlers
    def _g(self, word: Word, b: _Block, span: SourceSpan) -> None:
        value = self._number(word, span)
        g = int(value)
        handler = _G_HANDLERS.get(g) if g == value else None
        if handler is None:
            if g == value and g in _GEOMETRY_G:
                raise fail(
                    "NC-UNSUPPORTED",
                    f"{word.text} is not supported by trcopt",
                    self._at(span, word),
                )
            self._unsupported(word, b, span)
        else:
            handler(self, g, word, b, span)

    def _g_motion(self, g: int, word: Word, b: _Block, span: SourceSpan) -> None:
        if b.motion is not None:
            raise fail(
                "NC-SYNTAX",
                f"G{b.motion[0]} and {word.text} in one block (same group)",
                self._at(span, word),
            )
        b.motion = (g, word.column)

    def _g_plane(self, g: int, word: Word, b: _Block, span: SourceSpan) -> None:
        b.plane = (_PLANES[g], word.column)

    def _g_side(self, g: int, word: Word, b: _Block, span: SourceSpan) -> None:
        if b.side is not None:
            raise fail("NC-SYNTAX", "two of G40/G41/G42 in one block", self._at(span, word))
        b.side = (_SIDES[g], word.column)

    def _g_mode(self, g: int, word: Word, b: _Block, span: SourceSpan) -> None:
        st = self.state
        if g in _CORNERS:
            st.corner = _CORNERS[g]
        elif g in _STRATEGIES:
            st.strategy = _STRATEGIES[g]
        elif g in _SAR_SIDES:
            st.sar_side = _SAR_SIDES[g]
        elif g in _SAR_SEGMENTATION:
            st.sar_segmentation = _SAR_SEGMENTATION[g]
        elif g == 90 or g == 91:
            self.absolute = g == 90
        elif g in (70, 71, 700, 710):
            self.geom_scale = _INCH if g in (70, 700) else 1.0
            if g in (700, 710):
                self.feed_scale = _INCH if g == 700 else 1.0
        elif g == 94:
            pass
        elif g == 95:
            self._warn(
                "NC-G95", "feed per revolution not supported, treated as G94", self._at(span, word)
            )
        elif g == 4:
            b.dwell = True
            b.actions.append(word.text.upper())

    def _g_sar(self, g: int, word: Word, b: _Block, span: SourceSpan) -> None:
        if b.sar is not None:
            raise AlarmError(
                alarm(
                    10743,
                    f"SAR programmed twice in one block (G{b.sar[0].value[1:]}"
                    f" and {word.text.upper()})",
                    self._at(span, word),
                )
            )
        b.sar = (_SAR_CONTOURS[g], word.column)

    def _axis(self, word: Word, b: _Block, span: SourceSpan) -> None:
        i = _AXES[word.name]
        if b.axes[i] is not None:
            raise fail(
                "NC-SYNTAX",
                f"address {word.name} programmed twice in one block",
                self._at(span, word),
            )
        b.axes[i] = self._positional(word, span, self.absolute)

    def _centre(self, word: Word, b: _Block, span: SourceSpan) -> None:
        i = _CENTRE[word.name]
        if b.centre[i] is not None:
            raise fail(
                "NC-SYNTAX",
                f"address {word.name} programmed twice in one block",
                self._at(span, word),
            )
        b.centre[i] = self._positional(word, span, False)
        b.centre_col = b.centre_col or word.column

    def _cr(self, word: Word, b: _Block, span: SourceSpan) -> None:
        b.cr = self._number(word, span) * self.geom_scale
        b.centre_col = b.centre_col or word.column

    def _turn(self, word: Word, b: _Block, span: SourceSpan) -> None:
        b.turn = self._integer(word, span)

    def _feed(self, word: Word, b: _Block, span: SourceSpan) -> None:
        value = self._number(word, span)
        b.actions.append(word.text.upper().replace(" ", ""))
        b.feed = value
        b.feed_col = word.column

    def _tool(self, word: Word, b: _Block, span: SourceSpan) -> None:
        if isinstance(word.value, str) and not isinstance(word.value, Expr):
            self._unsupported(word, b, span)  # T="name": tool management not modelled
            return
        b.t = self._integer(word, span)
        b.actions.append(f"T{b.t}")

    def _edge(self, word: Word, b: _Block, span: SourceSpan) -> None:
        b.d = self._integer(word, span)
        b.actions.append(f"D{b.d}")

    def _m(self, word: Word, b: _Block, span: SourceSpan) -> None:
        m = self._integer(word, span)
        b.actions.append(f"M{m}")
        if m in _END_M:
            b.end = True

    def _action(self, word: Word, b: _Block, span: SourceSpan) -> None:
        if word.name in ("S", "H"):
            self._number(word, span)
        b.actions.append(word.text)

    def _offn(self, word: Word, b: _Block, span: SourceSpan) -> None:
        self.state.offn = self._number(word, span) * self.geom_scale

    def _disc(self, word: Word, b: _Block, span: SourceSpan) -> None:
        value = round(self._number(word, span))
        limit = self.options.max_disc
        clamped = min(max(value, 0), limit)
        if clamped != value:
            self._warn(
                "NC-DISC-CLAMPED",
                f"DISC={value} clamped to {clamped} (CUTCOM_MAX_DISC {limit})",
                self._at(span, word),
            )
        self.state.disc = clamped

    def _approach(self, word: Word, b: _Block, span: SourceSpan) -> None:
        self._keyword(word, span)
        self.state.approach = _APPROACH[word.name]

    def _collision(self, word: Word, b: _Block, span: SourceSpan) -> None:
        self._keyword(word, span)
        self.state.collision = _COLLISION[word.name]

    def _cut2d(self, word: Word, b: _Block, span: SourceSpan) -> None:
        self._keyword(word, span)
        if word.name == "CUT2DF":
            self._warn(
                "NC-UNSUPPORTED-WORD",
                "CUT2DF not supported (frame plane); compensating in the G17-G19 plane",
                self._at(span, word),
            )
            b.actions.append(word.text)

    def _sar_length(self, word: Word, b: _Block, span: SourceSpan) -> None:
        b.sar_params.append(word)
        if word.name == "DISR":
            b.disr = self._number(word, span) * self.geom_scale
        else:
            value = self._positional(word, span, False)
            if word.name == "DISCL":
                b.discl = value
            else:
                b.disrp = value

    def _fad(self, word: Word, b: _Block, span: SourceSpan) -> None:
        b.sar_params.append(word)
        value = word.value
        mode = ""
        if type(value) is tuple:
            mode, inner = value
            if mode not in ("PM", "PR") or type(inner) is not float:
                raise fail(
                    "NC-SYNTAX",
                    f"invalid value in {word.text!r} (expected PM(..) or PR(..))",
                    self._at(span, word),
                )
            value = inner
        else:
            value = self._number(word, span)
        if mode == "PR":
            self._warn(
                "NC-G95",
                "FAD=PR (feed per revolution) not supported; value kept in mm/rev",
                self._at(span, word),
            )
            b.fad = (float(value), mode)
        else:
            b.fad = (float(value) * self.feed_scale / 60.0, mode)

    def _toolholder(self, word: Word, b: _Block, span: SourceSpan) -> None:
        if word.name == "TCARR":
            value: int | None = self._integer(word, span)
        else:
            self._keyword(word, span)
            value = None
        self.toolholder_events.append(
            {"line": span.line, "block": span.block, "word": word.name, "value": value}
        )
        b.actions.append(word.text)

    def _msg(self, word: Word, b: _Block, span: SourceSpan) -> None:
        b.actions.append(word.text)

    def _block_number(self, word: Word, b: _Block, span: SourceSpan) -> None:
        raise fail("NC-SYNTAX", "block number N inside a block", self._at(span, word))

    def _unsupported(self, word: Word, b: _Block, span: SourceSpan) -> None:
        if word.name in _GEOMETRY_WORDS:
            raise fail(
                "NC-UNSUPPORTED",
                f"{word.name} is not supported by trcopt (it would change the geometry)",
                self._at(span, word),
            )
        if word.value is None and word.index is None and len(word.name) == 1:
            raise fail("NC-SYNTAX", f"{word.name} without a value", self._at(span, word))
        self._warn(
            "NC-UNSUPPORTED-WORD",
            f"{word.text} is not supported by trcopt (ignored)",
            self._at(span, word),
        )
        b.actions.append(word.text)

    def _system_variable(self, word: Word, b: _Block, span: SourceSpan) -> None:
        name = word.name
        if name.startswith("$TC_DP") and name[6:].isdigit():
            t, d = self._index(word, span, 2)
            value = self._number(word, span)
            if not self.state.tools.assign(int(name[6:]), t, d, value):
                self._unsupported(word, b, span)
                return
        elif name.startswith("$TC_CARR") and name[8:].isdigit():
            (m,) = self._index(word, span, 1)
            value = word.value
            if not isinstance(value, str) or isinstance(value, Expr):
                value = self._number(word, span)
            self.carriers.setdefault(m, {})[int(name[8:])] = value
        else:
            self._unsupported(word, b, span)
            return
        b.actions.append(word.text)

    def _index(self, word: Word, span: SourceSpan, count: int) -> tuple[int, ...]:
        parts = (word.index or "").split(",")
        try:
            values = tuple(int(p) for p in parts)
        except ValueError:
            values = ()
        if len(values) != count or min(values) < 0:
            raise fail(
                "NC-SYNTAX",
                f"{word.name} needs {count} whole-number index"
                f"{'es' if count > 1 else ''}, got [{word.index}]",
                self._at(span, word),
            )
        return values

    # ------------------------------------------------------------------ block completion
    def _finish(self, b: _Block, span: SourceSpan) -> None:
        st = self.state
        # plane change: not while TRC is active (alarm 10757)
        if b.plane is not None:
            plane, col = b.plane
            if plane is not st.plane and st.side is not Side.OFF:
                raise AlarmError(
                    alarm(
                        10757,
                        f"plane change {st.plane.value} -> {plane.value} "
                        "while tool radius compensation is active",
                        SourceSpan(self.file, span.line, col, span.block),
                    )
                )
            st.plane = plane
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
                if edge is not None and not edge.supports_trc:
                    raise fail(
                        "NC-TOOL-TYPE",
                        f"unsupported tool type for TRC: tool type {edge.type} ({edge.kind})",
                        SourceSpan(self.file, span.line, col, span.block),
                    )
            st.side = side
        if b.feed is not None and not b.dwell:  # with G4, F is the dwell time
            if b.feed <= 0.0:
                raise fail(
                    "NC-SYNTAX",
                    f"feed must be positive, got F{b.feed:g}",
                    SourceSpan(self.file, span.line, b.feed_col, span.block),
                )
            st.feed_mm_s = b.feed * self.feed_scale / 60.0
        if b.motion is not None:
            st.motion = _MOTION[b.motion[0]]
            self.arc_ccw = b.motion[0] == 3
        # end point
        pos = st.position
        start = (pos[0], pos[1], pos[2])
        end = list(start)
        written = [a is not None for a in b.axes]
        for i in range(3):
            a = b.axes[i]
            if a is not None:
                end[i] = a[0] if a[1] else pos[i] + a[0]
        endt = (end[0], end[1], end[2])
        plane = st.plane
        u, v, _w = plane.axes
        plane_programmed = written[u] or written[v]
        has_centre = b.cr is not None or any(c is not None for c in b.centre)
        motion = st.motion
        center = None
        ccw = None
        if motion is MoveKind.ARC and (any(written) or has_centre):
            kind = MoveKind.ARC
            ccw = self.arc_ccw
            center = self._arc_centre(b, start, endt, ccw, span)
        elif any(written):
            kind = motion
            if has_centre:
                self._warn(
                    "NC-UNSUPPORTED-WORD",
                    "circle centre/radius outside G2/G3 ignored",
                    SourceSpan(self.file, span.line, b.centre_col, span.block),
                )
        else:
            kind = MoveKind.NONE
        sar = None
        if b.sar is not None:
            sar = SarSpec(
                contour=b.sar[0],
                side=st.sar_side,
                segmentation=st.sar_segmentation,
                disr=b.disr,
                discl=b.discl,
                disrp=b.disrp,
                fad=b.fad,
                end_programmed=(written[0], written[1], written[2]),
            )
        elif b.sar_params:
            w = b.sar_params[0]
            self._warn(
                "NC-SAR-PARAM",
                f"{w.name} without G147/G148/G247/G248/G347/G348 in the block is ignored",
                self._at(span, w),
            )
        if kind is MoveKind.RAPID or (kind is MoveKind.NONE and motion is MoveKind.RAPID):
            feed = None
        else:
            feed = st.feed_mm_s
            if feed is None and kind is not MoveKind.NONE and not self._warned_no_feed:
                self._warned_no_feed = True
                self._warn("NC-NO-FEED", "no feed programmed (F) for a G1/G2/G3 block", span)
        self.moves.append(
            Move(
                kind=kind,
                start=start,
                end=endt,
                plane=plane,
                span=span,
                comp=st.comp_state(side_programmed),
                feed_mm_s=feed,
                center=center,
                ccw=ccw,
                turns=b.turn,
                actions=tuple(b.actions),
                sar=sar,
                plane_programmed=plane_programmed,
            )
        )
        st.position = end

    def _arc_centre(
        self,
        b: _Block,
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
                raise fail("NC-SYNTAX", "CR= together with I/J/K in one block", col_span)
            try:
                cu, cv = arc_centre_from_radius(
                    (su, sv), (eu, ev), b.cr, ccw, tol, self.tol.coincidence_mm
                )
            except ValueError as exc:
                raise fail("NC-ARC-RADIUS", str(exc), col_span) from None
        else:
            u, v, w = plane.axes
            if not any(b.centre[i] is not None for i in (u, v)):
                raise fail(
                    "NC-ARC-CENTRE", "circle without centre (I/J/K) or radius (CR=)", col_span
                )
            if b.centre[w] is not None:
                self._warn(
                    "NC-UNSUPPORTED-WORD",
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
            raise fail(
                "NC-ARC-RADIUS", "circle radius is zero (centre at the start point)", col_span
            )
        mismatch = arc_radius_mismatch((su, sv), (eu, ev), (cu, cv), tol)
        if mismatch is not None:
            raise fail(
                "NC-ARC-RADIUS",
                f"arc end point not on the circle: start radius "
                f"{mismatch[0]:.4f} mm, end radius {mismatch[1]:.4f} mm (difference "
                f"{abs(mismatch[0] - mismatch[1]):.4f} > {tol} mm)",
                col_span,
            )
        return plane.to_xyz((cu, cv, sw))


def _g_table() -> dict[int, Callable[[SiemensReader, int, Word, _Block, SourceSpan], None]]:
    table: dict[int, Callable[[SiemensReader, int, Word, _Block, SourceSpan], None]] = {}
    for g in _MOTION:
        table[g] = SiemensReader._g_motion
    for g in _PLANES:
        table[g] = SiemensReader._g_plane
    for g in _SIDES:
        table[g] = SiemensReader._g_side
    for g in _SAR_CONTOURS:
        table[g] = SiemensReader._g_sar
    modes = [*_CORNERS, *_STRATEGIES, *_SAR_SIDES, *_SAR_SEGMENTATION, 90, 91, 70, 71, 700, 710]
    for g in [*modes, 94, 95, 4]:
        table[g] = SiemensReader._g_mode
    return table


_G_HANDLERS = _g_table()

_HANDLERS: dict[str, Handler] = {
    "G": SiemensReader._g,
    "X": SiemensReader._axis,
    "Y": SiemensReader._axis,
    "Z": SiemensReader._axis,
    "I": SiemensReader._centre,
    "J": SiemensReader._centre,
    "K": SiemensReader._centre,
    "CR": SiemensReader._cr,
    "TURN": SiemensReader._turn,
    "F": SiemensReader._feed,
    "T": SiemensReader._tool,
    "D": SiemensReader._edge,
    "M": SiemensReader._m,
    "S": SiemensReader._action,
    "H": SiemensReader._action,
    "N": SiemensReader._block_number,
    "OFFN": SiemensReader._offn,
    "DISC": SiemensReader._disc,
    "DISR": SiemensReader._sar_length,
    "DISCL": SiemensReader._sar_length,
    "DISRP": SiemensReader._sar_length,
    "FAD": SiemensReader._fad,
    "CUT2D": SiemensReader._cut2d,
    "CUT2DF": SiemensReader._cut2d,
    "TCARR": SiemensReader._toolholder,
    "MSG": SiemensReader._msg,
    **{name: SiemensReader._approach for name in _APPROACH},
    **{name: SiemensReader._collision for name in _COLLISION},
    **{name: SiemensReader._toolholder for name in _TOOLHOLDER_WORDS},
}
