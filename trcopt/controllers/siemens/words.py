"""SINUMERIK 840D sl words: what each address, G code and keyword does to a block.

:class:`SiemensWords` holds one handler per word (dispatched by :data:`WORD_HANDLERS` and
:data:`G_HANDLERS`). Modal words (G groups, OFFN, DISC, NORM/KONT…, CDON/CDOF…) change the
:class:`~trcopt.nc.modal.ModalState` as they are read, so they act on the whole block whatever
their position in it; words whose effect needs a check (plane, compensation side, T/D, feed, axes,
SAR) are collected in a :class:`~trcopt.controllers.siemens.block.Block` and applied when the block
is complete (:mod:`trcopt.controllers.siemens.reader`); how a word's value reads is
:class:`~trcopt.controllers.siemens.block.WordReader`. Frames, zero offsets, polar coordinates,
CIP/CT act through :mod:`~trcopt.controllers.siemens.motion`, drilling cycles through
:mod:`~trcopt.controllers.siemens.cycles`. Everything trcopt does not implement is reported (warning
``NC-UNSUPPORTED-WORD``) and kept in the move's actions; words that would change the geometry
without trcopt knowing (splines, thread cutting) stop the program.
"""

from __future__ import annotations

from collections.abc import Callable

from trcopt.codes import Code
from trcopt.controllers.siemens.block import Block, WordReader
from trcopt.controllers.siemens.cycles import CYCLES, DrillingCycles
from trcopt.controllers.siemens.feedrate import FEED_TYPE_G, FeedRate
from trcopt.controllers.siemens.frames import SETTABLE_G
from trcopt.controllers.siemens.lexer import Expr, Word
from trcopt.controllers.siemens.path_control import PATH_CONTROL_G, cycle832_arguments
from trcopt.errors import AlarmError, SourceSpan, alarm
from trcopt.geometry.plane import Plane
from trcopt.modes import (
    ApproachMode,
    ApproachStrategy,
    CollisionMode,
    CornerMode,
    LeadSegmentation,
    LeadSide,
    SarContour,
    Side,
)
from trcopt.nc.modal import fail
from trcopt.nc.model import MoveKind

__all__ = ["SiemensWords", "WORD_HANDLERS", "G_HANDLERS", "MOTION_KINDS"]

_AXES = {"X": 0, "Y": 1, "Z": 2}
_CENTRE = {"I": 0, "J": 1, "K": 2}
#: The motion kind of G0…G3.
MOTION_KINDS = {0: MoveKind.RAPID, 1: MoveKind.LINE, 2: MoveKind.ARC, 3: MoveKind.ARC}
_PLANES = {17: Plane.G17, 18: Plane.G18, 19: Plane.G19}
_SIDES = {40: Side.OFF, 41: Side.LEFT, 42: Side.RIGHT}
_SAR_CONTOURS = {int(c.value[1:]): c for c in SarContour}
_SAR_SIDES = {int(c.value[1:]): c for c in LeadSide}
_SAR_SEGMENTATION = {340: LeadSegmentation.SPATIAL, 341: LeadSegmentation.PLANAR}
_CORNERS = {450: CornerMode.TRANSITION_CIRCLE, 451: CornerMode.INTERSECTION}
_STRATEGIES = {460: ApproachStrategy.G460, 461: ApproachStrategy.G461, 462: ApproachStrategy.G462}
_APPROACH = {m.value: m for m in ApproachMode}
_COLLISION = {m.value: m for m in CollisionMode}
_END_M = {2, 30, 17}
_INCH = 25.4
_GEOMETRY_G = {33, 34, 35, 331, 332}
_CIRCLES = {"CIP": -1, "CT": -2}  # motion codes beside G0…G3 (trcopt.controllers.siemens.motion)
_TOOLHOLDER_WORDS = ("TCOABS", "TCOFR", "TCOFRZ", "TCOFRY", "TCOFRX")


def _fmt(value: float) -> str:
    """A number as written in an action string: ``600``, ``0.25`` (no exponent for NC values)."""
    return str(int(value)) if value.is_integer() else repr(value)


Handler = Callable[["SiemensWords", Word, Block, SourceSpan], None]


class SiemensWords(FeedRate, DrillingCycles, WordReader):
    """Word handlers of the SINUMERIK reader (state lives in :class:`~.block.WordReader`)."""

    # ------------------------------------------------------------------ word handlers
    def _g(self, word: Word, b: Block, span: SourceSpan) -> None:
        value = word.value
        if type(value) is not float:
            value = self._number(word, span)
        g = int(value)
        handler = G_HANDLERS.get(g) if g == value else None
        if handler is None:
            if g == value and g in _GEOMETRY_G:
                raise fail(
                    Code.NC_UNSUPPORTED,
                    f"{word.text} is not supported by trcopt",
                    self._at(span, word),
                )
            self._unsupported(word, b, span)
        else:
            handler(self, g, word, b, span)

    def _g_motion(self, g: int, word: Word, b: Block, span: SourceSpan) -> None:
        if b.motion is not None:
            raise fail(
                Code.NC_SYNTAX,
                f"G{b.motion[0]} and {word.text} in one block (same group)",
                self._at(span, word),
            )
        b.motion = (g, word.column)

    def _circle(self, word: Word, b: Block, span: SourceSpan) -> None:
        """CIP (circle through an intermediate point) and CT (tangential circle): motion group 1."""
        self._keyword(word, span)
        self._g_motion(_CIRCLES[word.name], word, b, span)

    def _g_frames(self, g: int, word: Word, b: Block, span: SourceSpan) -> None:
        """G53/G153 (machine coordinates in this block), G54…G599/G500 (settable zero offsets), G110…G112 (pole)."""
        if g in (53, 153):
            b.machine = b.machine or word.column
        elif g in (110, 111, 112):
            b.pole = (g, word.column)
        else:
            self._settable(g, word.text, b.actions)  # type: ignore[attr-defined]

    def _supa(self, word: Word, b: Block, span: SourceSpan) -> None:
        self._keyword(word, span)
        b.machine = b.machine or word.column

    def _polar(self, word: Word, b: Block, span: SourceSpan) -> None:
        """AP= (polar angle, degrees) and RP= (polar radius), =IC(..) incremental."""
        value, absolute = self._positional(word, span, self.absolute)
        if word.name == "AP":
            b.ap = (value / self.geom_scale, absolute)
        else:
            if absolute and value < 0.0:
                raise fail(Code.NC_SYNTAX, f"{word.text}: the polar radius must not be negative", self._at(span, word))
            b.rp = (value, absolute)

    def _intermediate(self, word: Word, b: Block, span: SourceSpan) -> None:
        """I1=, J1=, K1=: the intermediate point of CIP."""
        if b.inter is None:
            b.inter = [None, None, None]
        b.inter["IJK".index(word.name[0])] = self._positional(word, span, self.absolute)

    def _g_plane(self, g: int, word: Word, b: Block, span: SourceSpan) -> None:
        b.plane = (_PLANES[g], word.column)

    def _g_side(self, g: int, word: Word, b: Block, span: SourceSpan) -> None:
        if b.side is not None:
            raise fail(Code.NC_SYNTAX, "two of G40/G41/G42 in one block", self._at(span, word))
        b.side = (_SIDES[g], word.column)

    def _g_mode(self, g: int, word: Word, b: Block, span: SourceSpan) -> None:
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
        elif g == 4:
            b.dwell = True
            b.actions.append(word.text.upper())

    def _g_path(self, g: int, word: Word, b: Block, span: SourceSpan) -> None:
        """G9 (exact stop in this block) and group 10 (G60, G64, G641–G645)."""
        if g == 9:
            b.exact_stop = True
        else:
            self.path.select(g, word.text)
        b.actions.append(word.text.upper())

    def _rounding(self, word: Word, b: Block, span: SourceSpan) -> None:
        """ADIS=, ADISPOS= (G641 rounding distances) and CTOL= (contour tolerance), mm."""
        value = self._number(word, span) * self.geom_scale
        if value < 0.0:
            raise fail(Code.NC_SYNTAX, f"{word.text}: the value must not be negative", self._at(span, word))
        if word.name == "ADIS":
            self.path.adis = value
        elif word.name == "ADISPOS":
            self.path.adispos = value
        else:
            self.path.ctol = value
        b.actions.append(word.text)

    def _cycle832(self, word: Word, b: Block, span: SourceSpan) -> None:
        """CYCLE832(_TOL, _TOLM, …): high-speed settings; trcopt models their path control."""
        try:
            tol, tolm = cycle832_arguments(word.subscript or "")
        except (ValueError, KeyError) as exc:
            raise fail(
                Code.NC_SYNTAX,
                f"{word.text}: invalid argument ({exc}); expected CYCLE832(tolerance, machining type, …)",
                self._at(span, word),
            ) from None
        self.path.cycle832(tol * self.geom_scale, tolm, word.text)
        b.actions.append(word.text)

    def _g_sar(self, g: int, word: Word, b: Block, span: SourceSpan) -> None:
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

    def _axis(self, word: Word, b: Block, span: SourceSpan) -> None:
        i = _AXES[word.name]
        if b.axes[i] is not None:
            raise fail(
                Code.NC_SYNTAX,
                f"address {word.name} programmed twice in one block",
                self._at(span, word),
            )
        value = word.value
        if type(value) is float:
            b.axes[i] = (value * self.geom_scale, self.absolute)
        else:
            b.axes[i] = self._positional(word, span, self.absolute)

    def _centre(self, word: Word, b: Block, span: SourceSpan) -> None:
        i = _CENTRE[word.name]
        if b.centre[i] is not None:
            raise fail(
                Code.NC_SYNTAX,
                f"address {word.name} programmed twice in one block",
                self._at(span, word),
            )
        b.centre[i] = self._positional(word, span, False)
        b.centre_col = b.centre_col or word.column

    def _cr(self, word: Word, b: Block, span: SourceSpan) -> None:
        b.cr = self._number(word, span) * self.geom_scale
        b.centre_col = b.centre_col or word.column

    def _turn(self, word: Word, b: Block, span: SourceSpan) -> None:
        b.turn = self._integer(word, span)

    def _feed(self, word: Word, b: Block, span: SourceSpan) -> None:
        value = self._number(word, span)
        if b.feed is not None:
            raise fail(Code.NC_SYNTAX, "F programmed twice in one block", self._at(span, word))
        b.actions.append("F" + _fmt(value))
        b.feed = value
        b.feed_col = word.column

    def _tool(self, word: Word, b: Block, span: SourceSpan) -> None:
        if isinstance(word.value, str) and not isinstance(word.value, Expr):
            self._unsupported(word, b, span)  # T="name": tool management not modelled
            return
        b.t = self._integer(word, span)
        b.actions.append(f"T{b.t}")

    def _edge(self, word: Word, b: Block, span: SourceSpan) -> None:
        b.d = self._integer(word, span)
        b.actions.append(f"D{b.d}")

    def _m(self, word: Word, b: Block, span: SourceSpan) -> None:
        m = self._integer(word, span)
        b.actions.append(f"M{m}")
        if m in _END_M:
            b.end = True
        elif m in (3, 4, 5):  # the master spindle (trcopt.controllers.siemens.feedrate)
            b.spindle = (m, word.column)

    def _return(self, word: Word, b: Block, span: SourceSpan) -> None:
        self._keyword(word, span)
        b.actions.append("RET")
        b.end = True

    def _action(self, word: Word, b: Block, span: SourceSpan) -> None:
        """H (auxiliary function): kept as ``"H2"``."""
        b.actions.append(word.name + _fmt(self._number(word, span)))

    def _offn(self, word: Word, b: Block, span: SourceSpan) -> None:
        self.state.offn = self._number(word, span) * self.geom_scale

    def _disc(self, word: Word, b: Block, span: SourceSpan) -> None:
        value = round(self._number(word, span))
        limit = self.options.max_disc
        clamped = min(max(value, 0), limit)
        if clamped != value:
            self._warn(
                Code.NC_DISC_CLAMPED,
                f"DISC={value} clamped to {clamped} (CUTCOM_MAX_DISC {limit})",
                self._at(span, word),
            )
        self.state.disc = clamped

    def _approach(self, word: Word, b: Block, span: SourceSpan) -> None:
        self._keyword(word, span)
        self.state.approach = _APPROACH[word.name]

    def _collision(self, word: Word, b: Block, span: SourceSpan) -> None:
        self._keyword(word, span)
        self.state.collision = _COLLISION[word.name]

    def _cut2d(self, word: Word, b: Block, span: SourceSpan) -> None:
        self._keyword(word, span)
        if word.name == "CUT2DF":
            self._warn(
                Code.NC_UNSUPPORTED_WORD,
                "CUT2DF not supported (frame plane); compensating in the G17-G19 plane",
                self._at(span, word),
            )
            b.actions.append(word.text)

    def _sar_length(self, word: Word, b: Block, span: SourceSpan) -> None:
        if b.sar_param is None:
            b.sar_param = word
        if word.name == "DISR":
            b.disr = self._number(word, span) * self.geom_scale
        else:
            value = self._positional(word, span, False)
            if word.name == "DISCL":
                b.discl = value
            else:
                b.disrp = value

    def _fad(self, word: Word, b: Block, span: SourceSpan) -> None:
        if b.sar_param is None:
            b.sar_param = word
        value = word.value
        mode = ""
        if type(value) is tuple:
            mode, inner = value
            if mode in ("PM", "PR") and isinstance(inner, Expr):
                inner = self.variables.word_value(word, inner, span)
            if mode not in ("PM", "PR") or type(inner) is not float:
                raise fail(
                    Code.NC_SYNTAX,
                    f"invalid value in {word.text!r} (expected PM(..) or PR(..))",
                    self._at(span, word),
                )
            value = inner
        else:
            value = self._number(word, span)
        # in mm/s when the block is complete (the feed type and S of the block act first)
        b.fad = (float(value), mode)
        b.fad_col = word.column

    def _toolholder(self, word: Word, b: Block, span: SourceSpan) -> None:
        if word.name == "TCARR":
            value: int | None = self._integer(word, span)
        else:
            self._keyword(word, span)
            value = None
        self.toolholder_events.append(
            {"line": span.line, "block": span.block, "word": word.name, "value": value}
        )
        b.actions.append(word.text)

    def _msg(self, word: Word, b: Block, span: SourceSpan) -> None:
        b.actions.append(word.text)

    def _block_number(self, word: Word, b: Block, span: SourceSpan) -> None:
        raise fail(Code.NC_SYNTAX, "block number N inside a block", self._at(span, word))

    def _system_variable(self, word: Word, b: Block, span: SourceSpan) -> None:
        name = word.name
        if name.startswith("$TC_DP") and name[6:].isdigit():
            t, d = self._index(word, span, 2)
            value = self._number(word, span)
            if name == "$TC_DP6" and value < 0.0:
                # the geometry radius of a milling tool cannot be negative (a negative wear
                # $TC_DP15 or OFFN may still make R negative, which swaps the side)
                raise fail(
                    Code.NC_TOOL_RADIUS, f"negative tool radius {name}[{t},{d}]={value:g} mm", self._at(span, word)
                )
            if not self.state.tools.assign(int(name[6:]), t, d, value):
                self._unsupported(word, b, span)
                return
        elif name.startswith("$TC_CARR") and name[8:].isdigit():
            (m,) = self._index(word, span, 1)
            data = word.value
            if not isinstance(data, str) or isinstance(data, Expr):
                data = self._number(word, span)
            self.carriers.setdefault(m, {})[int(name[8:])] = data
        else:
            self._unsupported(word, b, span)
            return
        b.actions.append(word.text)

def _g_table() -> dict[int, Callable[[SiemensWords, int, Word, Block, SourceSpan], None]]:
    table: dict[int, Callable[[SiemensWords, int, Word, Block, SourceSpan], None]] = {}
    for g in MOTION_KINDS:
        table[g] = SiemensWords._g_motion
    for g in _PLANES:
        table[g] = SiemensWords._g_plane
    for g in _SIDES:
        table[g] = SiemensWords._g_side
    for g in _SAR_CONTOURS:
        table[g] = SiemensWords._g_sar
    modes = [*_CORNERS, *_STRATEGIES, *_SAR_SIDES, *_SAR_SEGMENTATION, 90, 91, 70, 71, 700, 710]
    for g in [*modes, 4]:
        table[g] = SiemensWords._g_mode
    for g in FEED_TYPE_G:
        table[g] = SiemensWords._g_feed_type
    for g in [9, *PATH_CONTROL_G]:
        table[g] = SiemensWords._g_path
    for g in [53, 153, 110, 111, 112, *SETTABLE_G]:
        table[g] = SiemensWords._g_frames
    return table


G_HANDLERS = _g_table()

WORD_HANDLERS: dict[str, Handler] = {
    "G": SiemensWords._g,
    "X": SiemensWords._axis,
    "Y": SiemensWords._axis,
    "Z": SiemensWords._axis,
    "I": SiemensWords._centre,
    "J": SiemensWords._centre,
    "K": SiemensWords._centre,
    "CR": SiemensWords._cr,
    "TURN": SiemensWords._turn,
    "F": SiemensWords._feed,
    "T": SiemensWords._tool,
    "D": SiemensWords._edge,
    "M": SiemensWords._m,
    "S": SiemensWords._speed,
    "S1": SiemensWords._speed,
    "M1": SiemensWords._spindle_m,
    "H": SiemensWords._action,
    "N": SiemensWords._block_number,
    "OFFN": SiemensWords._offn,
    "DISC": SiemensWords._disc,
    "DISR": SiemensWords._sar_length,
    "DISCL": SiemensWords._sar_length,
    "DISRP": SiemensWords._sar_length,
    "FAD": SiemensWords._fad,
    "CUT2D": SiemensWords._cut2d,
    "CUT2DF": SiemensWords._cut2d,
    "TCARR": SiemensWords._toolholder,
    "MSG": SiemensWords._msg,
    "RET": SiemensWords._return,
    "ADIS": SiemensWords._rounding,
    "ADISPOS": SiemensWords._rounding,
    "CTOL": SiemensWords._rounding,
    "CYCLE832": SiemensWords._cycle832,
    "CIP": SiemensWords._circle,
    "CT": SiemensWords._circle,
    "SUPA": SiemensWords._supa,
    "AP": SiemensWords._polar,
    "RP": SiemensWords._polar,
    "I1": SiemensWords._intermediate,
    "J1": SiemensWords._intermediate,
    "K1": SiemensWords._intermediate,
    **{name: SiemensWords._cycle_word for name in CYCLES},
    **{name: SiemensWords._approach for name in _APPROACH},
    **{name: SiemensWords._collision for name in _COLLISION},
    **{name: SiemensWords._toolholder for name in _TOOLHOLDER_WORDS},
}
