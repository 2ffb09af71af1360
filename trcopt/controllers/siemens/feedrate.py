"""SINUMERIK feed types (G group 15) and the master spindle: the path feed of a block.

Source: Function Manual Feeds (V1), "Path feedrate F" (revolutional feedrate G95, the deletion of F
on a change of feedrate type, alarm 10860); Programming Manual Fundamentals (feedrate, spindle speed
and direction of rotation).

* ``G94`` (the state after reset): ``F`` in mm/min (inch/min under ``G700``).
* ``G95``: ``F`` in mm (inch under ``G700``) per revolution of the master spindle; the path feed is
  F × S with S the spindle speed [rev/min]. ``S`` and ``S1=`` (spindle 1, the master spindle) are
  modal and act from the start of their block, as do ``M3``/``M4`` (``M1=3``/``M1=4``); ``M5``
  (``M1=5``) stops the spindle at the end of its block. A change of S changes the path feed of the
  following blocks under G95. A feed motion under G95 while there is no spindle speed (no S, or
  S0) or the spindle does not turn (no M3/M4 yet, or stopped by M5) has no path feed — the axes
  would wait for the spindle: ``NC-FEED-MODE`` at its block. ``S`` in a ``G4`` block is the dwell
  in spindle revolutions, not a speed.
* A change of feed type deletes the F value (Feeds V1: the programmed F value is deleted when the
  system switches between the feedrate types G93, G94 and G95): a feed motion after it without a
  new F is alarm **10860** (no feedrate programmed). The type in force programmed again is no
  change.
* ``FAD=`` (the slow infeed of SAR) is in the unit of the feed type in force; ``FAD=PM(…)`` per
  minute and ``FAD=PR(…)`` per revolution whatever the type (× S as above, else ``NC-FEED-MODE``
  at the FAD word).
* The other feed types of group 15 — ``G93`` (inverse time), ``G96``/``G961``/``G962`` (constant
  cutting rate), ``G97``/``G971``, ``G931``, ``G942``, ``G952``, ``G972``, ``G973`` — are
  ``NC-UNSUPPORTED``: the feed they give is not modelled.
* ``SAVE`` restores the feed type with the other G groups (:mod:`.motion`); a restored type other
  than the one in force deletes F as a change does. F and S are not G functions: not restored.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from trcopt.codes import Code
from trcopt.controllers.siemens.block import Block
from trcopt.controllers.siemens.lexer import Word
from trcopt.errors import AlarmError, SourceSpan, alarm
from trcopt.nc.modal import ModalState, fail

__all__ = ["FeedRate", "FEED_TYPE_G"]

#: the feed types of group 15 trcopt does not model, and what they are
_UNMODELLED = {
    93: "inverse-time feed",
    96: "constant cutting rate with feed per revolution",
    97: "constant spindle speed with feed per revolution",
    931: "feed given by the traversing time",
    961: "constant cutting rate with linear feed",
    962: "constant cutting rate with linear or revolutional feed",
    971: "constant spindle speed with linear feed",
    942: "frozen linear feed with constant cutting rate or spindle speed",
    952: "frozen revolutional feed with constant cutting rate or spindle speed",
    972: "frozen linear or revolutional feed with constant spindle speed",
    973: "revolutional feed without spindle speed limitation",
}
#: every G code of group 15 (feed type)
FEED_TYPE_G = (94, 95, *_UNMODELLED)


def _fmt(value: float) -> str:
    return str(int(value)) if value.is_integer() else repr(value)


class FeedRate:
    """The feed part of :class:`~trcopt.controllers.siemens.reader.SiemensReader` (see the module
    docstring); the path feed in force is ``state.feed_mm_s``."""

    state: ModalState
    file: str
    feed_scale: float

    feed_type = 94  # G94 after reset
    feed_value: float | None = None  # F × feed_scale: mm/min (G94) or mm/rev (G95); None: none in force
    deleted: str | None = None  # what deleted the F value (a change of feed type), until a new F
    spindle_speed: float | None = None  # S of the master spindle, rev/min (None: never programmed)
    spindle_turning: bool | None = None  # M3/M4 (True), M5 (False), None: neither yet
    stopped_line = 0  # the line of the M5 that stopped the spindle

    if TYPE_CHECKING:  # provided by the reader

        def _at(self, span: SourceSpan, word: Word) -> SourceSpan: ...

        def _number(self, word: Word, span: SourceSpan) -> float: ...

        def _integer(self, word: Word, span: SourceSpan) -> int: ...

        def _unsupported(self, word: Word, b: Block, span: SourceSpan) -> None: ...

    # ------------------------------------------------------------------ word handlers
    def _g_feed_type(self, g: int, word: Word, b: Block, span: SourceSpan) -> None:
        if g in _UNMODELLED:
            raise fail(
                Code.NC_UNSUPPORTED,
                f"{word.text} ({_UNMODELLED[g]}) is not modelled by trcopt: the path feed would not be the "
                "machine's (G94 and G95 are)",
                self._at(span, word),
            )
        if b.feed_type is not None:
            raise fail(
                Code.NC_SYNTAX, f"G{b.feed_type[0]} and {word.text} in one block (same group)", self._at(span, word)
            )
        b.feed_type = (g, word.column)
        if g == 95:
            b.actions.append("G95")  # the output writes feeds per minute and names it in a comment

    def _speed(self, word: Word, b: Block, span: SourceSpan) -> None:
        """``S`` and ``S1=``: the master spindle speed (the dwell in revolutions in a G4 block)."""
        value = self._number(word, span)
        if b.speed is not None:
            raise fail(Code.NC_SYNTAX, "S programmed twice in one block", self._at(span, word))
        if value < 0.0:
            raise fail(Code.NC_SYNTAX, f"{word.text}: the spindle speed must not be negative", self._at(span, word))
        b.speed = (value, word.column)
        b.actions.append("S" + _fmt(value))

    def _spindle_m(self, word: Word, b: Block, span: SourceSpan) -> None:
        """``M1=3``, ``M1=4``, ``M1=5``: the direction of spindle 1 (the master spindle)."""
        m = self._integer(word, span)
        if m not in (3, 4, 5):
            self._unsupported(word, b, span)
            return
        b.spindle = (m, word.column)
        b.actions.append(f"M{m}")

    # ------------------------------------------------------------------ the block's feed
    def _apply_feed(self, b: Block, span: SourceSpan) -> None:
        """The feed type, F, S and M3/M4 of the block, before its motion; the path feed in force."""
        changed = False
        if b.feed_type is not None and b.feed_type[0] != self.feed_type:
            g = self.feed_type = b.feed_type[0]
            if self.feed_value is not None:
                self.deleted = f"the change to G{g} in line {span.line}"
            self.feed_value = None
            changed = True
        if not b.dwell:  # with G4, F is the dwell time and S the dwell in revolutions
            if b.feed is not None:
                if b.feed <= 0.0:
                    raise fail(
                        Code.NC_SYNTAX,
                        f"feed must be positive, got F{b.feed:g}",
                        SourceSpan(self.file, span.line, b.feed_col, span.block),
                    )
                self.feed_value = b.feed * self.feed_scale
                self.deleted = None
                changed = True
            if b.speed is not None:
                self.spindle_speed = b.speed[0]
                changed = True
        if b.spindle is not None and b.spindle[0] != 5:
            self.spindle_turning = True
            changed = True
        if changed:
            self._set_path_feed()

    def _after_feed(self, b: Block, span: SourceSpan) -> None:
        """M5 stops the spindle at the end of its block."""
        if b.spindle is not None and b.spindle[0] == 5:
            self.spindle_turning = False
            self.stopped_line = span.line
            self._set_path_feed()

    def _set_path_feed(self) -> None:
        f = self.feed_value
        if f is None:
            feed = None
        elif self.feed_type == 94:
            feed = f / 60.0
        else:
            feed = None if self._spindle_problem() else f * self.spindle_speed / 60.0  # type: ignore[operator]
        self.state.feed_mm_s = feed

    def _spindle_problem(self) -> str | None:
        """Why the master spindle gives no feed per revolution (None: it turns at a speed)."""
        if self.spindle_speed is None:
            return "no spindle speed S programmed"
        if self.spindle_speed == 0.0:
            return "the spindle speed is S0"
        if self.spindle_turning is None:
            return "the spindle has not been started (M3/M4)"
        if not self.spindle_turning:
            return f"the spindle was stopped by M5 in line {self.stopped_line}"
        return None

    def _feed_missing(self, span: SourceSpan) -> None:
        """Raise for a feed motion without a path feed: F deleted by a change of feed type or never
        programmed (10860), G95 without a turning spindle (``NC-FEED-MODE``)."""
        if self.deleted is not None:
            raise AlarmError(
                alarm(
                    10860,
                    f"no feedrate programmed: {self.deleted} deleted the F value; program F after changing the "
                    "feed type",
                    span,
                )
            )
        problem = self._spindle_problem()
        if self.feed_type == 95 and self.feed_value is not None and problem is not None:
            raise fail(
                Code.NC_FEED_MODE,
                f"G95 (feed per revolution F{_fmt(self.feed_value / self.feed_scale)}): {problem}, so the path "
                "feed F × S is zero",
                span,
            )
        raise AlarmError(
            alarm(10860, "no feedrate programmed: a G1/G2/G3 block needs a path feed F (none is in force)", span)
        )

    def _fad_feed(self, b: Block, span: SourceSpan) -> tuple[float, str] | None:
        """The SAR infeed feed FAD of the block in mm/s with its mode, or None."""
        if b.fad is None:
            return None
        value, mode = b.fad
        if not (mode == "PR" or (mode == "" and self.feed_type == 95)):
            return value * self.feed_scale / 60.0, mode
        problem = self._spindle_problem()
        if problem is not None:
            raise fail(
                Code.NC_FEED_MODE,
                f"FAD {_fmt(value)} per revolution: {problem}, so the infeed feed FAD × S is zero",
                SourceSpan(self.file, span.line, b.fad_col, span.block),
            )
        return value * self.feed_scale * self.spindle_speed / 60.0, mode  # type: ignore[operator]

    def _restore_feed_type(self, g: int) -> None:
        """The feed type a SAVE subprogram restores on its return."""
        if g == self.feed_type:
            return
        self.feed_type = g
        if self.feed_value is not None:
            self.deleted = f"the return to G{g} from a SAVE subprogram"
        self.feed_value = None
        self._set_path_feed()
