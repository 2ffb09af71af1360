"""The state of the Klartext reader and how it reads a block's words.

:class:`ReaderState` is the base of :class:`~trcopt.controllers.heidenhain.reader.HeidenhainReader`
(through :class:`~.leads.LeadBlocks` and :class:`~.motion.MotionBlocks`): it holds everything the
reader tracks between blocks (position, plane, unit, pole, feeds, compensation side, tool, the open
RND/CHF corner and APPR block, the elements read so far) and reads the words of one block — which
words a statement allows (:data:`ALLOWED_WORDS`), the target point of absolute, incremental and
polar coordinates, the feed (mm/s), the compensation word and value, the M functions.

A problem in a block raises :class:`BlockError` with the spec's code; the reader turns it into a
diagnostic. Coordinates are absolute mm; the pole and the elements are in plane coordinates
(u, v, w).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from trcopt.codes import Code
from trcopt.config import Tolerances
from trcopt.controllers.heidenhain.contour import Elem
from trcopt.controllers.heidenhain.emit import ElementOutput
from trcopt.controllers.heidenhain.frames import Frame
from trcopt.controllers.heidenhain.lexer import Block, Word
from trcopt.controllers.heidenhain.qparams import QParams
from trcopt.controllers.heidenhain.tooltable import HhTool, compensation_value
from trcopt.errors import Diagnostic, Severity, SourceSpan
from trcopt.geometry import vec
from trcopt.geometry.plane import Plane
from trcopt.geometry.vec import Vec3
from trcopt.modes import ApprRadius, Side, parse_enum
from trcopt.nc.limits import MAX_COORDINATE_MM
from trcopt.nc.model import PathControl

__all__ = [
    "BlockError",
    "HeidenhainOptions",
    "PendingApproach",
    "ReaderState",
    "number",
    "COMPENSATION_WORDS",
    "FEED_WORDS",
    "COORDINATE_WORDS",
    "ALLOWED_WORDS",
    "AXIS_INDEX",
    "NOT_MODELLED_M",
    "MAX_LOOKAHEAD",
]

COMPENSATION_WORDS = {"RL", "RR", "R0", "R+", "R-"}
MAX_WORD_VALUE = 1e9  # no word of a part program exceeds this (coordinates are bounded later at 1e5 mm)
FEED_WORDS = {"F", "FMAX", "FAUTO"}
COORDINATE_WORDS = {"X", "Y", "Z", "IX", "IY", "IZ"}
_POLAR_WORDS = {"PR", "IPR", "PA", "IPA"}
_TAIL = COMPENSATION_WORDS | FEED_WORDS | {"M", "LA"}  # what every motion block may carry besides its geometry
#: The words each statement allows (APPR/DEP: :data:`~.leads.LEAD_WORDS`).
ALLOWED_WORDS: dict[str, set[str]] = {
    "L": COORDINATE_WORDS | _TAIL,
    "LP": _POLAR_WORDS | COORDINATE_WORDS | _TAIL,
    "C": COORDINATE_WORDS | {"DR+", "DR-"} | _TAIL,
    "CR": COORDINATE_WORDS | {"R", "DR+", "DR-"} | _TAIL,
    "CT": COORDINATE_WORDS | _TAIL,
    "CP": {"PA", "IPA"} | COORDINATE_WORDS | {"DR+", "DR-"} | _TAIL,
    "CTP": _POLAR_WORDS | COORDINATE_WORDS | _TAIL,
    "CC": COORDINATE_WORDS,
    "RND": {"R", "F"},
    "CHF": {"", "F"},
    "STOP": {"M"},
    "TOOL DEF": {"", "L", "R", "DL", "DR", "R2"},
    "TOOL CALL": {"", "S", "F", "DL", "DR", "DR2"},
}
#: The coordinate index of an axis letter.
AXIS_INDEX = {"X": 0, "Y": 1, "Z": 2}
#: M functions that change the path or positioning and are not modelled: an error naming them.
NOT_MODELLED_M = {
    91: "positioning in the machine coordinate system",
    92: "positioning in the M92 coordinate system",
    98: "completing corners of open contours",
    112: "contour transition filter",
    114: "tool-tilt compensation",
    124: "contour filter",
    128: "TCPM",
    130: "positioning in the untilted system",
    140: "retraction along the tool axis",
    136: "feed rate F per spindle revolution",
}
#: Feed words that are not modelled (the feed per minute they give depends on the spindle or the tool).
NOT_MODELLED_FEED = {"FU": "feed per spindle revolution", "FZ": "feed per tooth"}


#: The largest M120 look-ahead LA (TNC manual: "maximum: 99").
MAX_LOOKAHEAD = 99
#: The statements M120 may be programmed in (a positioning block; it needs RL/RR in force).
_M120_STATEMENTS = {"L", "LP", "C", "CR", "CT", "CP", "CTP"}


class BlockError(Exception):
    """A problem in the block being read: ``code`` (the spec's), ``message``, and where — a
    column of the block, or another block's ``span`` (an APPR or RND waiting for its contour)."""

    def __init__(self, code: Code, message: str, column: int | None = None, span: SourceSpan | None = None) -> None:
        super().__init__(message)
        self.code, self.message, self.column, self.span = code, message, column, span


@dataclass(frozen=True, slots=True)
class HeidenhainOptions:
    """Reader settings: ``appr_radius`` is the APPR/DEP CT/LCT radius reading (spec R9; a string
    is accepted and checked); ``tools`` preset tool table; ``max_iterations`` (loop iterations:
    jumps back and section repeats) and ``max_blocks`` (blocks run again after a jump back, a repeat
    or a call: a program read straight through never counts, whatever its length) after which a
    program that has not ended stops with ``HH-LOOP-LIMIT``."""

    appr_radius: ApprRadius = ApprRadius.CENTRE
    tools: dict[int, HhTool] = field(default_factory=dict)
    max_iterations: int = 10_000
    max_blocks: int = 1_000_000

    def __post_init__(self) -> None:
        object.__setattr__(self, "appr_radius", parse_enum(ApprRadius, self.appr_radius, "APPR/DEP radius reading"))


@dataclass(slots=True)
class PendingApproach:
    """An APPR block waiting for the contour element that fixes its lead: the lead kind (``LT``,
    ``LN``, ``CT``, ``LCT``), start point PS and APPR point PA (mm), side and compensation value r
    (mm), its LEN/CCA/R values, the feeds before and in the block (mm/s) and its M functions."""

    kind: str
    ps: Vec3
    pa: Vec3
    side: Side
    r: float
    words: dict[str, float]
    feed_before: float | None
    feed: float | None
    feed_in_block: bool
    span: SourceSpan
    actions: tuple[str, ...]
    scale: float = 1.0  # mm per programmed length unit in the plane (unit × scaling cycles)


def number(word: Word) -> float:
    """The number of an address word (the lexer gives every address word one)."""
    assert word.value is not None
    return word.value


class ReaderState:
    """What the Klartext reader tracks between blocks, and how it reads one block's words."""

    def __init__(
        self, file: str = "<program>", tolerances: Tolerances | None = None, options: HeidenhainOptions | None = None
    ) -> None:
        self.file = file
        self.tol = tolerances or Tolerances()
        self.opts = options or HeidenhainOptions()
        self.diags: list[Diagnostic] = []
        self.elems: list[Elem] = []
        self.pos: Vec3 = (0.0, 0.0, 0.0)
        self.plane = Plane.G17
        self.unit = 1.0
        self.pole: tuple[float, float] | None = None
        self.last_pa: float | None = None
        self.last_pr: float | None = None
        self.feed: float | None = None
        self.feed_auto: float | None = None
        self.last_rapid = False
        self.side = Side.OFF
        self.last_on_side = Side.OFF  # for the R0-between-RL-and-RR rule
        self.direction: bool | None = None  # last DR+/DR− (True = CCW)
        self.tools = dict(self.opts.tools)
        self.tool: HhTool | None = None
        self.dr_call = 0.0
        self.corner: tuple[str, float, float | None, SourceSpan] | None = None
        self.appr: PendingApproach | None = None
        self.blocks = 0
        # the words of blocks without motion (TOOL CALL, STOP), for the G-code writer
        self.word_blocks: list[tuple[SourceSpan, tuple[str, ...]]] = []
        self.ended = False
        self.controls: list[tuple[int, PathControl]] = []  # (executed block, path control from there on)
        self.iterations = 0  # loop iterations so far (FN 9–12 jumps back, section repeats)
        self.seq = 0  # executed blocks so far (the order of the run, also across jumps and calls)
        self.frame = Frame()
        self.q = QParams(self._preset_q)
        self.lookahead = 0  # M120 LA in force (0: M120 off)
        self.output: ElementOutput | None = None  # the moves given block by block (None: read whole)

    def _preset_q(self, name: str) -> float | None:
        """The TNC's preassigned Q parameters: Q108 compensation value, Q113 unit (0 mm, 1 inch)."""
        if name == "Q108" and self.tool is not None:
            return compensation_value(self.tool.radius, self.tool.dr, self.dr_call) / self.unit
        if name == "Q113":
            return 0.0 if self.unit == 1.0 else 1.0
        return None

    def _error(self, code: Code, message: str, span: SourceSpan) -> None:
        self.diags.append(Diagnostic(Severity.ERROR, code, message, span))

    def _warn(self, code: Code, message: str, span: SourceSpan) -> None:
        self.diags.append(Diagnostic(Severity.WARNING, code, message, span))

    # ------------------------------------------------------------------ words
    def _words(self, blk: Block, allowed: set[str]) -> dict[str, Word]:
        out: dict[str, Word] = {}
        for w in blk.words:
            m = int(w.value or 0) if w.address == "M" else None
            if m in NOT_MODELLED_M:
                what = f"M{m} ({NOT_MODELLED_M[m]})"
                raise BlockError(Code.HH_NOT_MODELLED, f"{what} is not modelled by trcopt", w.column)
            if w.address in NOT_MODELLED_FEED:
                what = f"{w.text} ({NOT_MODELLED_FEED[w.address]})"
                raise BlockError(Code.HH_NOT_MODELLED, f"{what} is not modelled by trcopt", w.column)
        self._m120_allowed(blk)
        for w in blk.words:
            if w.address == "?":
                raise BlockError(Code.HH_SYNTAX, f"unknown word {w.text!r}", w.column)
            if w.value is not None and not (math.isfinite(w.value) and abs(w.value) <= MAX_WORD_VALUE):
                # the geometry of APPR/DEP, CT, RND … loses every digit on such numbers before the
                # moves' range check (trcopt.nc.limits) sees them
                raise BlockError(
                    Code.NC_RANGE,
                    f"word {w.text!r}: {w.value:.6g} is not a finite number within ±{MAX_WORD_VALUE:g} "
                    "(trcopt.controllers.heidenhain.state.MAX_WORD_VALUE; a coordinate must lie within "
                    f"±{MAX_COORDINATE_MM:g} mm, trcopt.nc.limits.MAX_COORDINATE_MM)",
                    w.column,
                )
            key = w.address
            if key not in allowed:
                what = f"word {w.text!r}" if key else f"{w.text!r}"
                raise BlockError(Code.HH_SYNTAX, f"{what} not allowed in a {blk.statement} block", w.column)
            if key == "M":
                out[f"M{int(w.value or 0)}"] = w
                continue
            if key in out and key:
                raise BlockError(Code.HH_SYNTAX, f"word {key} programmed twice", w.column)
            if key in COMPENSATION_WORDS and any(k in COMPENSATION_WORDS for k in out):
                raise BlockError(Code.HH_SYNTAX, "more than one compensation word (RL/RR/R0/R+/R-)", w.column)
            out[key or f"#{len(out)}"] = w
        return out

    # ------------------------------------------------------------------ M120 LA (look-ahead)
    @staticmethod
    def _m120_allowed(blk: Block) -> None:
        """M120 only in a positioning block (L, LP, C, CR, CT, CP, CTP, APPR), LA only with M120."""
        m120 = next((w for w in blk.words if w.address == "M" and w.value == 120.0), None)
        la = next((w for w in blk.words if w.address == "LA"), None)
        if la is not None and m120 is None:
            raise BlockError(Code.HH_M120, "LA (look-ahead) without M120 in the block", la.column)
        if m120 is not None and blk.statement not in _M120_STATEMENTS and not blk.statement.startswith("APPR"):
            raise BlockError(
                Code.HH_M120,
                f"M120 in a {blk.statement} block: M120 LA belongs in a positioning block with RL or RR",
                m120.column,
            )

    def _m120(self, words: dict[str, Word], side: Side) -> None:
        """``M120 LA n`` (1 ≤ n ≤ 99) switches the radius-compensated look-ahead on from the start
        of this block, which must carry RL/RR; ``M120 LA0`` or ``M120`` without LA switch it off.
        R0 (and DEP, CALL PGM) switch it off too (:meth:`_m120_off`)."""
        if "M120" not in words:
            return
        la = words.get("LA")
        n = 0.0 if la is None else number(la)
        if n != int(n) or not 0 <= n <= MAX_LOOKAHEAD:
            assert la is not None
            raise BlockError(
                Code.HH_M120, f"M120 LA{n:g}: the look-ahead must be a whole number of blocks 0…{MAX_LOOKAHEAD}",
                la.column,
            )
        if n and side is Side.OFF:
            raise BlockError(
                Code.HH_M120,
                "M120 LA needs radius compensation RL or RR in its block (R0 is in force)",
                words["M120"].column,
            )
        self.lookahead = int(n)

    def _m120_off(self) -> None:
        """Radius compensation cancelled: M120 is cancelled with it."""
        self.lookahead = 0

    # ------------------------------------------------------------------ frames (CYCL DEF 7/8/10/11/26)
    def _prog(self, p: Vec3) -> Vec3:
        return self.frame.to_prog(p, self.plane)

    def _work(self, p: Vec3) -> Vec3:
        return self.frame.to_work(p, self.plane)

    def _mirrored(self) -> bool:
        return self.frame.mirrored(self.plane)

    def _side_of(self, comp: str) -> Side:
        """RL/RR as sides of the transformed contour (a mirror reverses them)."""
        left = (comp == "RL") != self._mirrored()
        return Side.LEFT if left else Side.RIGHT

    def _length(self, value: float, what: str = "a length") -> float:
        """A programmed length in the working plane (radius, LEN, RND, CHF) in mm of the work
        system: times the unit and the scale factor."""
        f = self.frame.plane_scale(self.plane)
        if f is None:
            raise BlockError(
                Code.HH_NOT_MODELLED,
                f"{what} under CYCL DEF 26 with different factors in the working plane (circles would become ellipses)",
            )
        return value * self.unit * f

    def _pole_work(self) -> tuple[float, float]:
        assert self.pole is not None
        self._length(1.0, "a circle")
        c = self._uvw(self._work(self.plane.to_xyz((self.pole[0], self.pole[1], 0.0))))
        return (c[0], c[1])

    def _target(self, words: dict[str, Word]) -> Vec3:
        return self._work(self._prog_target(words))

    def _prog_target(self, words: dict[str, Word]) -> Vec3:
        p = list(self._prog(self.pos))
        for key, w in words.items():
            axis = key[-1] if key in COORDINATE_WORDS else None
            if axis is None:
                continue
            v = number(w) * self.unit
            i = AXIS_INDEX[axis]
            p[i] = p[i] + v if key.startswith("I") else v
        return (p[0], p[1], p[2])

    def _polar_target(self, words: dict[str, Word], line: bool) -> Vec3:
        if self.pole is None:
            raise BlockError(Code.HH_NO_POLE, "polar coordinates need a pole (CC)")
        s = self._uvw(self._prog(self.pos))
        cur_angle = math.degrees(math.atan2(s[1] - self.pole[1], s[0] - self.pole[0]))
        cur_r = math.hypot(s[0] - self.pole[0], s[1] - self.pole[1])
        pa = self.last_pa if self.last_pa is not None else cur_angle
        pr = self.last_pr if self.last_pr is not None else cur_r
        if "PA" in words:
            pa = number(words["PA"])
        elif "IPA" in words:
            pa = pa + number(words["IPA"])
        if "PR" in words:
            pr = number(words["PR"]) * self.unit
        elif "IPR" in words:
            pr = pr + number(words["IPR"]) * self.unit
        if not line:
            pr = cur_r  # CP: radius = distance start–pole
        self.last_pa, self.last_pr = pa, pr
        w = self._uvw(self._prog_target({k: v for k, v in words.items() if k in COORDINATE_WORDS}))[2]
        e = vec.polar(self.pole, pr, math.radians(pa))
        return self._work(self.plane.to_xyz((e[0], e[1], w)))

    def _feed_of(self, words: dict[str, Word]) -> tuple[float | None, bool]:
        """Feed of this block (mm/s, None = FMAX) and whether it is a rapid; updates the modal F."""
        if "FMAX" in words:
            return None, True
        if "FAUTO" in words:
            if self.feed_auto is None:
                raise BlockError(Code.HH_NO_FEED, "FAUTO without a feed in TOOL CALL", words["FAUTO"].column)
            return self.feed_auto, False
        if "F" in words:
            f = number(words["F"]) * self.unit / 60.0
            if self.unit != 1.0:
                f /= 10.0  # inch programs: F in 0.1 inch/min
            if f <= 0:
                raise BlockError(Code.HH_SYNTAX, "feed must be > 0", words["F"].column)
            self.feed = f
        return self.feed, False

    @staticmethod
    def _comp_word(words: dict[str, Word]) -> str | None:
        for k in words:
            if k in COMPENSATION_WORDS:
                return k
        return None

    def _radius(self, column: int | None = None) -> float:
        """The compensation value R + DR_TAB + DR_CALL (mm) of the called tool."""
        if self.tool is None:
            raise BlockError(Code.HH_NO_TOOL, "radius compensation without a TOOL CALL", column)
        r = compensation_value(self.tool.radius, self.tool.dr, self.dr_call)
        if r < 0:
            raise BlockError(
                Code.HH_TRC_NEG_RADIUS,
                f"compensation value R + DR_TAB + DR_CALL = {r:g} mm is negative",
                column,
            )
        return r

    @staticmethod
    def _actions(words: dict[str, Word]) -> tuple[str, ...]:
        """The block's M functions for the output, but M120: its look-ahead is in the tool-centre
        path already (a tool-centre program has no RL/RR for it)."""
        return tuple(k for k in words if k.startswith("M") and k[1:].isdigit() and k != "M120")

    def _uvw(self, p: Vec3) -> Vec3:
        return self.plane.to_uvw(p)
