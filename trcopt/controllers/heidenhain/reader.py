"""Heidenhain TNC conversational (Klartext) front end: program text → canonical moves.

Spec ``heidenhain_trc.md``. The reader builds the contour-level elements (L, LP, C, CR, CT, CP, CTP;
RND/CHF resolved between their neighbours; APPR/DEP through :mod:`trcopt.controllers.heidenhain.appr_dep`) and hands
them to the shared compensation engine as :class:`~trcopt.nc.model.Move` values with the Klartext
semantics mapped onto the engine's modes (see :mod:`trcopt.controllers.heidenhain.profile`):

* RL/RR switch on in a straight-line block (the engine's NORM selection: the tool ends
  perpendicular to the next element), R0 switches off (perpendicular start), DEP and PGM CALL too;
* outside corners: transition arc; ``M97`` in the block that ends at the corner: intersection;
* paraxial ``R+``/``R−`` are not TRC: the reader lengthens/shortens the one-axis move by r;
* "tool radius too large" is checked here on the contour (:func:`.contour.radius_too_large`)
  so the program stops at that block as the control does — except under ``M120 LA n``, where the
  engine's collision detection leaves out what the tool cannot machine (:mod:`.m120`).

Block labels are the TNC block numbers (``"15"``). Coordinates absolute mm, feeds mm/s.

The reader is one class built in layers: :class:`~.state.ReaderState` (state, word access,
frames), :class:`~.leads.LeadBlocks` (APPR/DEP), :class:`~.motion.MotionBlocks` (contour elements,
RND/CHF), :class:`~.flow.FlowBlocks` (the run: Q parameters, labels, subprograms, repeats, jumps,
called programs) and :class:`HeidenhainReader` here (the statements without motion, TOOL DEF/CALL,
the cycles, the radius check and the moves). Coordinate transformation cycles are
:mod:`~trcopt.controllers.heidenhain.frames`.

:meth:`HeidenhainReader.read` reads the whole program, then checks the radius and makes the moves;
:meth:`HeidenhainReader.iter_moves` gives the same moves block by block: the program's blocks are
lexed as they run and its elements become moves as soon as they are final (:mod:`.emit`).
"""

from __future__ import annotations

from collections.abc import Generator, Iterator

from trcopt.codes import Code
from trcopt.config import Tolerances
from trcopt.controllers.heidenhain.contour import TOOL_RADIUS_TOO_LARGE, Elem, radius_too_large
from trcopt.controllers.heidenhain.emit import ElementOutput, MoveMaker
from trcopt.controllers.heidenhain.flow import FlowBlocks
from trcopt.controllers.heidenhain.frames import FRAME_CYCLES, FrameError, apply_cycle
from trcopt.controllers.heidenhain.lexer import Block, Word
from trcopt.controllers.heidenhain.state import ALLOWED_WORDS, BlockError, HeidenhainOptions
from trcopt.controllers.heidenhain.tooltable import HhTool, find_tool_table, load_tool_table
from trcopt.errors import ConfigError, Diagnostic, Severity, SourceSpan
from trcopt.geometry import vec
from trcopt.geometry.plane import Plane
from trcopt.modes import PathMode, Side, ToleranceKind
from trcopt.nc.modal import ReadOptions
from trcopt.nc.model import EXACT_PATH, Move, MoveKind, NcProgram, PathControl
from trcopt.nc.stream import MoveStream, ReadSummary

__all__ = ["HeidenhainReader", "read_heidenhain", "read_klartext", "stream_klartext"]

_AXIS_PLANE = {"Z": Plane.G17, "Y": Plane.G18, "X": Plane.G19}
_MOTION = {"L", "LP", "C", "CR", "CT", "CP", "CTP"}


class HeidenhainReader(FlowBlocks):
    """Reads one Klartext program (``read(text) -> NcProgram``); see the module docstring."""

    name = "heidenhain"

    # ------------------------------------------------------------------ driver
    def read(self, text: str) -> NcProgram:
        self._load_table()
        if _returned(self._run(text)) and not self.ended:
            self._open_at_end()
        self._check_radius()
        moves = self._moves()
        extras: dict[str, object] = {"words": self.word_blocks}
        return NcProgram(self.file, "heidenhain", tuple(moves), tuple(self.diags), self.blocks, extras)

    def iter_moves(self, text: str) -> Iterator[Move]:
        """The moves of ``text`` block by block (:mod:`~.emit`: the program's blocks, elements
        and moves are never all held); when it ends, ``diags`` and ``blocks`` are those
        :meth:`read` returns."""
        self._load_table()
        late: list[Diagnostic] = []
        maker = MoveMaker(
            self.controls, lambda: self.plane, lambda c, m, s: late.append(Diagnostic(Severity.WARNING, c, m, s))
        )
        out = self.output = ElementOutput(maker)
        if (yield from self._run(text)) and not self.ended:
            self._open_at_end()
        for e in self.elems:
            out.add(e)
        self.elems.clear()
        yield from out.end()
        self.diags = out.diagnostics(self.diags) + late

    def _release(self) -> list[Move]:
        """The moves that are ready: every element but the last is final (:class:`~.emit.ElementOutput`)."""
        elems, out = self.elems, self.output
        assert out is not None
        if len(elems) > 1:
            for e in elems[:-1]:
                out.add(e)
            del elems[:-1]
        return out.ready()

    def _open_at_end(self) -> None:
        """The program ran to its end with an APPR or RND/CHF waiting for its contour element."""
        if self.appr is not None:
            self._error(Code.HH_APPR_NO_CONTOUR, "APPR without a following contour element", self.appr.span)
        elif self.corner is not None:
            self._error(Code.HH_SYNTAX, f"{self.corner[0]} without a following contour element", self.corner[3])

    def _load_table(self) -> None:
        path = find_tool_table(self.file)
        if path is None:
            return
        try:
            table = load_tool_table(path)
        except ConfigError as exc:
            self._warn(
                Code.HH_TOOL_TABLE, f"tool table ignored: {exc.message}", SourceSpan(self.file, 1, 1)
            )
            return
        self.tools = {**table, **self.tools}

    # ------------------------------------------------------------------ statements
    def _block(self, blk: Block, span: SourceSpan) -> None:
        st = blk.statement
        if st == "BEGIN PGM":
            units = [w.address for w in blk.words if w.address in ("MM", "INCH")]
            self.unit = 25.4 if units == ["INCH"] else 1.0
            return
        if st == "END PGM":
            self.ended = True
            if self.corner is not None:
                raise BlockError(
                    Code.HH_SYNTAX,
                    f"{self.corner[0]} without a following contour element",
                    span=self.corner[3],
                )
            if self.appr is not None:
                raise BlockError(
                    Code.HH_APPR_NO_CONTOUR,
                    "APPR without a following contour element",
                    span=self.appr.span,
                )
            return
        if st.startswith("BLK FORM"):
            return
        if st in ("TOOL DEF", "TOOL CALL"):
            words = self._words(blk, ALLOWED_WORDS[st])
            self._tool(blk, words, span)
            if st == "TOOL CALL":
                tool = next(w.text.strip("\"'") for k, w in words.items() if k.startswith("#"))
                speed = [f"S{float(words['S'].value or 0.0):g}"] if "S" in words else []
                self.word_blocks.append((span, (f"T{tool}" if tool.isdigit() else f'T="{tool}"', *speed)))
            return
        if st.startswith("APPR"):
            self._no_open_corner(st)
            self._appr_block(blk, span)
            return
        if st.startswith("DEP"):
            self._no_open_corner(st)
            self._dep_block(blk, span)
            return
        if st in ("RND", "CHF"):
            self._corner_block(blk, span)
            return
        if st == "CC":
            words = self._words(blk, ALLOWED_WORDS["CC"])
            c = self._uvw(self._prog_target(words))  # the pole in program coordinates
            self.pole = (c[0], c[1])
            self.last_pa = self.last_pr = None
            return
        if st == "STOP":
            self.word_blocks.append((span, ("M0", *self._actions(self._words(blk, ALLOWED_WORDS["STOP"])))))
            return
        if st == "CYCL DEF":
            self._cycle(blk, span)
            return
        if st in _MOTION:
            self._motion(blk, self._words(blk, ALLOWED_WORDS[st]), span)
            return
        raise BlockError(Code.HH_SYNTAX, f"unknown or unsupported statement {blk.statement!r}", blk.column)

    def _cycle(self, blk: Block, span: SourceSpan) -> None:
        """``CYCL DEF 32.0 TOLERANCE`` / ``32.1 T…`` / ``32.2 HSC-MODE:… TA…``: the contour
        tolerance of the following blocks (``32.1`` without ``T``, or ``T0``: cancelled); the
        coordinate transformations 7, 8, 10, 11, 26 (:mod:`.frames`). Other cycles are not
        modelled and stop the program (``HH-NOT-MODELLED``)."""
        words = blk.words
        number = words[0].text if words else ""
        if number.split(".")[0] in FRAME_CYCLES:
            try:
                apply_cycle(self.frame, number, words[1:], self.unit, self.plane, blk.column)
            except FrameError as exc:
                raise BlockError(exc.code, exc.message, exc.column) from None
            return
        if self.lookahead and number.split(".")[0] in ("32", "19"):
            raise BlockError(
                Code.HH_M120, f"CYCL DEF {number}: cancel M120 (and the radius compensation) before this cycle",
                words[0].column,
            )
        if number.split(".")[0] != "32":
            raise BlockError(
                Code.HH_NOT_MODELLED,
                f"CYCL DEF {number or '?'}: this cycle is not modelled by trcopt",
                words[0].column if words else blk.column,
            )
        if number == "32.1":
            tol = None
            for w in words[1:]:
                t = w.text.upper()
                if t.startswith("T") and t[1:]:
                    try:
                        tol = float(t[1:]) * self.unit
                    except ValueError:
                        raise BlockError(Code.HH_SYNTAX, f"invalid tolerance {w.text!r}", w.column) from None
                    if not (tol >= 0.0 and tol < 1e5):
                        raise BlockError(Code.HH_SYNTAX, f"invalid tolerance {w.text!r}", w.column)
            text = " ".join(w.text for w in words)
            control = (
                PathControl(PathMode.BLEND, tol, ToleranceKind.CONTOUR, f"CYCL DEF {text}") if tol else EXACT_PATH
            )
            self.controls.append((self.seq, control))
        elif number not in ("32.0", "32.2", "32"):
            raise BlockError(Code.HH_SYNTAX, f"CYCL DEF {number}: unknown block of cycle 32", words[0].column)

    def _no_open_corner(self, what: str) -> None:
        if self.corner is not None:
            raise BlockError(
                Code.HH_SYNTAX, f"{self.corner[0]} must be followed by a contour element, not {what}"
            )
        if self.appr is not None and not what.startswith("CC"):
            raise BlockError(
                Code.HH_APPR_NO_CONTOUR,
                f"APPR without a following contour element ({what} follows)",
                span=self.appr.span,
            )

    def _tool(self, blk: Block, words: dict[str, Word], span: SourceSpan) -> None:
        bare = [w for k, w in words.items() if k.startswith("#")]
        if not bare:
            raise BlockError(Code.HH_SYNTAX, f"{blk.statement} needs a tool number or name", blk.column)
        ident = bare[0].text.strip("\"'")
        if blk.statement == "TOOL DEF":
            if not ident.isdigit():
                raise BlockError(Code.HH_SYNTAX, "TOOL DEF needs a tool number", bare[0].column)
            n = int(ident)
            val = {
                k: float(w.value or 0.0) * self.unit
                for k, w in words.items()
                if not k.startswith("#")
            }
            if val.get("R", 0.0) < 0.0:
                raise BlockError(
                    Code.NC_TOOL_RADIUS, f"negative tool radius R{val['R']:g} mm in TOOL DEF {n}", words["R"].column
                )
            self.tools[n] = HhTool(n, "", val.get("L", 0.0), val.get("R", 0.0), 0.0, 0.0)
            return
        if len(bare) < 2 or bare[1].text.upper() not in _AXIS_PLANE:
            raise BlockError(Code.HH_SYNTAX, "TOOL CALL needs the tool axis X, Y or Z", blk.column)
        if ident.isdigit() and int(ident) == 0:
            tool = HhTool(0)
        else:
            found = [
                t
                for t in self.tools.values()
                if (ident.isdigit() and t.number == int(ident)) or t.name == ident
            ]
            if not found:
                raise BlockError(
                    Code.HH_TOOL_UNKNOWN,
                    f"tool {ident} is neither defined (TOOL DEF) nor in the tool table",
                    bare[0].column,
                )
            tool = found[0]
        self._no_open_corner("TOOL CALL")
        self.tool = tool
        self.plane = _AXIS_PLANE[bare[1].text.upper()]
        self.dr_call = float(words["DR"].value or 0.0) * self.unit if "DR" in words else 0.0
        if "F" in words:
            self.feed_auto = float(words["F"].value or 0.0) * self.unit / 60.0

    # ------------------------------------------------------------------ checks and output
    def _check_radius(self) -> None:
        regions: list[list[Elem]] = []
        cur: list[Elem] | None = None
        for e in self.elems:
            moving = e.kind is MoveKind.ARC or vec.dist(e.start[:2], e.end[:2]) > 1e-9
            if e.side is Side.OFF:
                if moving:
                    cur = None
                continue
            if cur is None:
                cur = []
                regions.append(cur)
                continue  # the selection line
            if e.extra.get("lookahead"):
                # under M120 the look-ahead leaves out what the tool cannot machine (engine CDON)
                cur = []
                regions.append(cur)
                continue
            if moving:
                cur.append(e)
        for region in regions:
            found = radius_too_large(region)
            if found is None:
                continue
            bad = region[found[0]]
            cut = next(i for i, e in enumerate(self.elems) if e is bad)
            seq = bad.extra.get("seq")
            while cut > 0 and self.elems[cut - 1].span == bad.span and self.elems[cut - 1].extra.get("seq") == seq:
                cut -= 1  # the whole block goes
            mark = self.elems[cut].extra.get("diag_mark", len(self.diags))
            assert isinstance(mark, int)
            del self.elems[cut:]
            self.diags = [d for i, d in enumerate(self.diags) if d.severity is not Severity.ERROR or i < mark]
            self._error(Code.HH_TOOL_RADIUS_TOO_LARGE, f"{TOOL_RADIUS_TOO_LARGE}: {found[1]}", bad.span)
            return

    def _moves(self) -> list[Move]:
        maker = MoveMaker(self.controls, lambda: self.plane, self._warn)
        return [maker.move(e) for e in self.elems]


def _returned(run: Generator[Move, None, bool]) -> bool:
    """What a run that gives no moves returns."""
    while True:
        try:
            next(run)
        except StopIteration as stop:
            return stop.value


def read_heidenhain(
    text: str, file: str = "<program>", tolerances: Tolerances | None = None, options: HeidenhainOptions | None = None
) -> NcProgram:
    """Read a Klartext program; never raises for a problem in the program (see the module docstring)."""
    return HeidenhainReader(file, tolerances, options).read(text)


def read_klartext(text: str, options: ReadOptions) -> NcProgram:
    """The controller's reader: ``options.tool_table`` is a TOML tool table (default: the one
    beside the program, see :func:`~trcopt.controllers.heidenhain.tooltable.find_tool_table`)."""
    return _reader(options).read(text)


def stream_klartext(text: str, options: ReadOptions) -> MoveStream:
    """:func:`read_klartext` block by block (:meth:`HeidenhainReader.iter_moves`)."""
    reader = _reader(options)
    return MoveStream(
        options.file,
        reader.name,
        reader.iter_moves(text),
        lambda: ReadSummary(list(reader.diags), reader.blocks, {"words": reader.word_blocks}),
    )


def _reader(options: ReadOptions) -> HeidenhainReader:
    tools = {} if options.tool_table is None else load_tool_table(options.tool_table)
    hh = HeidenhainOptions(appr_radius=options.appr_radius, tools=tools)  # type: ignore[arg-type]
    return HeidenhainReader(options.file, options.tolerances, hh)
