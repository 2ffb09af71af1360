"""One SINUMERIK block's words before they act, and how a word's value reads.

* :class:`Block` — the scratch record the word handlers fill with what is applied once the whole
  block is read (plane, side, T/D, feed, axes, centre, SAR words, actions);
* :class:`WordReader` — the base of :class:`~trcopt.controllers.siemens.words.SiemensWords`: the
  reader state the handlers use, and the value readers (a number, a whole number, an ``=AC``/``=IC``
  position in mm, a keyword without value, an ``[t,d]`` index), the warning of an unsupported
  word and the stop of a word that would change the geometry behind trcopt's back.

Lengths in mm (``geom_scale`` turns inch programs into mm).
"""

from __future__ import annotations

from trcopt.codes import Code
from trcopt.controllers.siemens.lexer import Expr, Word
from trcopt.controllers.siemens.path_control import PathControlState
from trcopt.controllers.siemens.variables import Variables
from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.geometry.plane import Plane
from trcopt.modes import SarContour, Side
from trcopt.nc.modal import ModalState, ReadOptions, fail

__all__ = ["Block", "WordReader"]

# words that would change the geometry behind trcopt's back: stop rather than guess
_GEOMETRY_WORDS = {
    "CTRANS", "ROTS", "AROTS", "CROTS", "ASPLINE", "BSPLINE", "CSPLINE", "POLY",
}  # fmt: skip
#: words that decide which blocks run or where the tool goes and that trcopt does not model: an
#: error, never an ignored word (the program would be planned along a path the machine does not run)
_MOTION_WORDS = {
    # program flow
    "GOTOF": "a jump", "GOTOB": "a jump", "GOTO": "a jump", "GOTOC": "a jump", "IF": "a condition",
    "ELSE": "a condition", "ENDIF": "a condition", "WHILE": "a loop", "ENDWHILE": "a loop", "FOR": "a loop",
    "ENDFOR": "a loop", "REPEAT": "a repetition", "REPEATB": "a repetition", "UNTIL": "a loop",
    "LOOP": "a loop", "ENDLOOP": "a loop", "CASE": "a branch",
    # subprograms and cycles
    "CALL": "a subprogram call", "PCALL": "a subprogram call", "MCALL": "a modal cycle call",
    "EXTCALL": "a subprogram call", "L": "a subprogram call",
    # kinematic transformations
    "TRAORI": "a kinematic transformation",
    "TRANSMIT": "a kinematic transformation", "TRACYL": "a kinematic transformation",
    "TRAANG": "a kinematic transformation",
    # procedures (DEF is read by trcopt.controllers.siemens.variables)
    "PROC": "a subprogram definition", "SAVE": "a subprogram attribute",
}  # fmt: skip
_MOTION_G: dict[int, str] = {}
#: program-flow words: read by trcopt.controllers.siemens.flow where they stand right; elsewhere a syntax error
_FLOW_WORDS = frozenset(
    ["GOTOF", "GOTOB", "GOTO", "GOTOC", "IF", "ELSE", "ENDIF", "WHILE", "ENDWHILE", "FOR", "ENDFOR", "REPEAT",
     "REPEATB", "UNTIL", "LOOP", "ENDLOOP", "PROC", "EXTERN", "MCALL"]
)  # fmt: skip
#: keywords without a value that are known not to move the tool (reported and ignored); any other
#: unknown name on its own may be a subprogram call and stops the program
_QUIET_KEYWORDS = {
    "FFWON", "FFWOF", "SOFT", "SOFTA", "BRISK", "BRISKA", "DRIVE", "DRIVEA", "STOPRE", "WAITM", "WAITS",
    "CFC", "CFTCP", "CFIN", "COMPOF", "COMPON", "COMPCURV", "COMPCAD", "COMPSURF", "UPATH", "SPATH",
    "FNORM", "FLIN", "FCUB", "DIAMOF", "DIAMON", "DIAM90", "ACN", "ACP", "DC", "G60", "G9",
    "TRAFOOF", "STOPFIFO", "STARTFIFO", "FIFOCTRL",
}  # fmt: skip
#: calls known not to move the tool (the blank of the controller's simulation, feed grouping)
_QUIET_CALLS = {"WORKPIECE", "FGROUP"}


class Block:
    """Scratch record of one block's words that are applied after the whole block is read.

    Class attributes hold the defaults so that creating a record per block stays cheap.
    """

    centre_col = 0  # column of the first I/J/K/CR word (0: none)
    cr: float | None = None
    turn = 0
    motion: tuple[int, int] | None = None  # (G number, column)
    plane: tuple[Plane, int] | None = None
    side: tuple[Side, int] | None = None
    t: int | None = None
    d: int | None = None
    feed: float | None = None  # programmed F value (unit per minute)
    feed_col = 0
    dwell = False
    exact_stop = False  # G9
    sar: tuple[SarContour, int] | None = None
    disr: float | None = None
    discl: tuple[float, bool] | None = None
    disrp: tuple[float, bool] | None = None
    fad: tuple[float, str] | None = None  # FAD value as written and its mode ("", "PM", "PR")
    fad_col = 0
    feed_type: tuple[int, int] | None = None  # G94/G95 (group 15): (G number, column)
    speed: tuple[float, int] | None = None  # S / S1= of the master spindle: (value, column)
    spindle: tuple[int, int] | None = None  # M3/M4/M5 (M1=…) of the master spindle: (M number, column)
    sar_param: Word | None = None  # first SAR parameter word (for the warning without SAR)
    end = False
    machine = 0  # column of G53/G153/SUPA (0: none): the axis values are machine positions
    pole: tuple[int, int] | None = None  # (G110/G111/G112, column)
    ap: tuple[float, bool] | None = None  # AP= (degrees, absolute?)
    rp: tuple[float, bool] | None = None  # RP= (mm, absolute?)
    inter: list[tuple[float, bool] | None] | None = None  # CIP intermediate point I1, J1, K1
    cycle: Word | None = None  # CYCLE81…83 called in this block

    def __init__(self) -> None:
        self.axes: list[tuple[float, bool] | None] = [None, None, None]
        self.centre: list[tuple[float, bool] | None] = [None, None, None]
        self.actions: list[str] = []



class WordReader:
    """The base of the word handlers: the reader state they use (set by
    :class:`~trcopt.controllers.siemens.reader.SiemensReader`) and how they read a word's value."""

    options: ReadOptions
    file: str
    state: ModalState
    diagnostics: list[Diagnostic]
    carriers: dict[int, dict[int, object]]
    toolholder_events: list[dict[str, object]]
    absolute: bool
    path: PathControlState
    geom_scale: float
    feed_scale: float
    variables: Variables

    def _warn(self, code: Code, message: str, span: SourceSpan) -> None:
        self.diagnostics.append(Diagnostic(Severity.WARNING, code, message, span))

    def _at(self, span: SourceSpan, word: Word) -> SourceSpan:
        return SourceSpan(span.file, span.line, word.column, span.block)

    # ------------------------------------------------------------------ value helpers
    def _number(self, word: Word, span: SourceSpan) -> float:
        value = word.value
        if type(value) is float:
            return value
        if value is None:
            raise fail(Code.NC_SYNTAX, f"{word.name} without a value", self._at(span, word))
        if isinstance(value, Expr):
            return self.variables.word_value(word, value, span)
        raise fail(Code.NC_SYNTAX, f"invalid value in {word.text!r}", self._at(span, word))

    def _integer(self, word: Word, span: SourceSpan) -> int:
        value = self._number(word, span)
        if value != int(value) or value < 0:
            raise fail(
                Code.NC_SYNTAX,
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
            if mode in ("AC", "IC") and isinstance(inner, Expr):
                inner = self.variables.word_value(word, inner, span)
            if mode in ("AC", "IC") and type(inner) is float:
                return inner * self.geom_scale, mode == "AC"
            raise fail(
                Code.NC_SYNTAX,
                f"invalid value in {word.text!r} (expected AC(..) or IC(..))",
                self._at(span, word),
            )
        return self._number(word, span) * self.geom_scale, default_absolute

    def _keyword(self, word: Word, span: SourceSpan) -> None:
        if word.value is not None:
            raise fail(Code.NC_SYNTAX, f"{word.name} takes no value", self._at(span, word))

    def _unsupported(self, word: Word, b: Block, span: SourceSpan) -> None:
        if word.name in _GEOMETRY_WORDS:
            raise fail(
                Code.NC_UNSUPPORTED,
                f"{word.name} is not supported by trcopt (it would change the geometry)",
                self._at(span, word),
            )
        if word.subscript is not None and word.assigned and not word.name.startswith("$"):
            raise fail(
                Code.NC_UNSUPPORTED,
                f"{word.text}: {word.name} is neither an R-parameter nor a DEF array; indexed addresses "
                "are not modelled by trcopt",
                self._at(span, word),
            )
        if word.name in _FLOW_WORDS:
            raise fail(
                Code.NC_SYNTAX,
                f"{word.text}: a program-flow word where it cannot stand (a control structure stands alone in its "
                "block; a jump ends its block with its destination: GOTOF LABEL)",
                self._at(span, word),
            )
        what = _motion_word(word)
        if what is not None:
            raise fail(
                Code.NC_UNSUPPORTED,
                f"{word.text} is {what}, which trcopt does not model: the planned path would not be the "
                "one the machine runs",
                self._at(span, word),
            )
        if word.value is None and word.subscript is None and len(word.name) == 1:
            raise fail(Code.NC_SYNTAX, f"{word.name} without a value", self._at(span, word))
        self._warn(
            Code.NC_UNSUPPORTED_WORD,
            f"{word.text} is not supported by trcopt (ignored)",
            self._at(span, word),
        )
        b.actions.append(word.text)

    def _index(self, word: Word, span: SourceSpan, count: int) -> tuple[int, ...]:
        parts = (word.subscript or "").split(",")
        try:
            values = tuple(int(p) for p in parts)
        except ValueError:  # an index written as an expression: $TC_DP6[R1,1]
            first = word.column + word.text.find("[") + 1
            numbers = []
            offset = 0
            for p in parts:
                numbers.append(self.variables.evaluate(p, span, first + offset))
                offset += len(p) + 1
            values = tuple(int(v) for v in numbers) if all(v == int(v) for v in numbers) else ()
        if len(values) != count or min(values) < 0:
            raise fail(
                Code.NC_SYNTAX,
                f"{word.name} needs {count} whole-number index"
                f"{'es' if count > 1 else ''}, got [{word.subscript}]",
                self._at(span, word),
            )
        return values


def _motion_word(word: Word) -> str | None:
    """What an unmodelled word that changes the motion does (None for a word that does not)."""
    if word.name == "G" and type(word.value) is float and word.value in _MOTION_G:
        return _MOTION_G[int(word.value)]
    if word.name in _MOTION_WORDS:
        return _MOTION_WORDS[word.name]
    if (
        word.subscript is not None and not word.name.startswith("$") and "(" in word.text
        and word.name not in _QUIET_CALLS
    ):
        return "a cycle or procedure call"  # CYCLE81(…), POCKET3(…), a program with parameters
    if (
        word.value is None and word.subscript is None and len(word.name) > 1 and word.name.isidentifier()
        and word.name not in _QUIET_KEYWORDS
    ):
        return "a subprogram call or an unknown keyword"
    return None
