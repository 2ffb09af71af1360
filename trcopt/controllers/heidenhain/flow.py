"""Program flow of the Klartext reader: Q parameters, labels, subprograms, repeats, jumps and
called programs — the blocks are *executed* in the order the TNC runs them.

* ``FN 0``–``FN 8``, ``FN 13`` and ``Q… = formula`` assign Q parameters
  (:mod:`~trcopt.controllers.heidenhain.qparams`); Q parameters in any value are resolved when the
  block runs (:func:`~.lexer.lex_block` with a resolver).
* ``FN 9``–``FN 12`` ``IF a EQU|NE|GT|LT b GOTO LBL n``: a jump (no return).
* ``LBL n`` / ``LBL "name"`` marks; ``LBL 0`` ends a subprogram.
* ``CALL LBL n``: subprogram call — runs from ``LBL n`` to ``LBL 0`` and returns after the call
  (the subprograms stand after the main program's ``M2``/``M30``).
* ``CALL LBL n REP m``: program-section repeat — the section from ``LBL n`` to this block runs
  again m times (m + 1 times in all), then the program goes on. ``REP 0`` is a subprogram call.
* ``CALL PGM name`` (also ``PGM CALL``): runs ``name`` (``.h`` added when it has no extension)
  found beside the calling program; its ``END PGM`` returns. ``QL`` parameters are local to it.
* ``M2``/``M30`` end the program run (in a called program: ``HH-NOT-MODELLED``).

Limits: at most :data:`MAX_DEPTH` nested calls, ``HeidenhainOptions.max_iterations`` loop
iterations (jumps back and section repeats, default 10 000) and ``HeidenhainOptions.max_blocks``
blocks run again after a jump back, a repeat or a call (default 1 000 000; a program read
straight through never counts, whatever its length): a program that does not end within them stops with
``HH-LOOP-LIMIT`` at the block where the limit is reached.
A jump or call to a label that is not in the program, a label defined twice and ``LBL 0`` outside
a call are ``HH-LABEL``; a missing program file ``HH-PGM-MISSING``.

A program read block by block (``output`` set) is not lexed before it runs: its lines are lexed as
they run (the last few kept), and only the lines with ``LBL`` in them are lexed first, for the labels.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Generator, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from trcopt.codes import Code
from trcopt.controllers.heidenhain.appr_dep import LeadError
from trcopt.controllers.heidenhain.contour import ContourError
from trcopt.controllers.heidenhain.lexer import Block, lex_block
from trcopt.controllers.heidenhain.motion import MotionBlocks
from trcopt.controllers.heidenhain.qparams import OPERAND, Q_REF, QError, eval_fn, evaluate
from trcopt.controllers.heidenhain.state import BlockError
from trcopt.errors import SourceSpan, TrcoptError
from trcopt.modes import Side
from trcopt.nc.model import Move
from trcopt.nc.ondemand import OnDemand, lines_matching
from trcopt.nc.text import decode_program, program_lines
from trcopt.textlines import TextLines

__all__ = ["FlowBlocks", "MAX_DEPTH"]

MAX_DEPTH = 8  # nested CALL LBL / CALL PGM (trcopt's limit)
_RELEASE = 512  # elements (read block by block) given as moves together: a few at a time run slower
_LABEL = r"(\d+|\"[^\"]*\"|'[^']*'|[A-Za-z_][\w]*)"
_CALL_LBL = re.compile(rf"CALL\s+LBL\s*{_LABEL}(?:\s+REP\s*(\d+)(?:\s*/\s*\d+)?)?\s*$", re.I)
_LBL = re.compile(rf"LBL\s*{_LABEL}\s*$", re.I)
_FN = re.compile(r"FN\s*(\d+)\s*:\s*(.*?)\s*$", re.I)
_ASSIGN = re.compile(rf"({Q_REF})\s*=\s*(.*?)\s*$", re.I)
_JUMP = re.compile(rf"IF\s*({OPERAND})\s+(EQU|NE|GT|LT)\s+({OPERAND})\s+GOTO\s+LBL\s*{_LABEL}\s*$", re.I)
_JUMP_OPS = {9: "EQU", 10: "NE", 11: "GT", 12: "LT"}
_LBL_TEXT = re.compile(rb"LBL")  # in every line whose statement is LBL (ASCII letters in upper case)
_PGM = re.compile(r"(?:CALL\s+PGM|PGM\s+CALL)\s+(\"[^\"]*\"|'[^']*'|\S+)\s*$", re.I)


def _label_key(text: str) -> str:
    text = text.strip("\"'")
    return str(int(text)) if text.isdigit() else text


@dataclass(slots=True)
class _Source:
    file: str
    path: Path | None
    blocks: Sequence[Block]
    labels: dict[str, int] = field(default_factory=dict)


@dataclass(slots=True)
class _Call:
    kind: str  # "lbl" (subprogram) or "pgm" (called program)
    source: _Source
    back: int  # index of the block to return to
    name: str
    unit: float = 1.0


class FlowBlocks(MotionBlocks):
    """Executes a program block by block (see the module docstring); ``_block`` (the reader)
    handles the blocks without control flow."""

    def _block(self, blk: Block, span: SourceSpan) -> None:  # pragma: no cover - the reader's
        raise NotImplementedError

    def _no_open_corner(self, what: str) -> None:  # pragma: no cover - the reader's
        raise NotImplementedError

    def _release(self) -> list[Move]:  # pragma: no cover - the reader's
        raise NotImplementedError

    def _source(self, text: str, file: str, path: Path | None) -> _Source:
        labelled: Iterable[int]
        block: Callable[[int], Block]
        if self.output is None:
            src = _Source(file, path, [lex_block(raw, n) for n, raw in enumerate(program_lines(text), start=1)])
            labelled, block = range(len(src.blocks)), src.blocks.__getitem__
        else:  # read block by block: the blocks lexed as they run, the labels found first
            lines = TextLines(text)

            def block(i: int) -> Block:
                return lex_block(lines[i], i + 1)

            src = _Source(file, path, OnDemand(len(lines), block))
            labelled = lines_matching(lines, _LBL_TEXT)
        for i in labelled:
            blk = block(i)
            if blk.statement != "LBL":
                continue
            m = _LBL.match(blk.source, blk.column - 1)
            if m is None:
                raise BlockError(Code.HH_SYNTAX, "LBL needs a label number or name", blk.column, self._span(src, i))
            key = _label_key(m.group(1))
            if key in src.labels and key != "0":
                first = src.labels[key] + 1
                raise BlockError(
                    Code.HH_LABEL, f"LBL {key} is defined twice (first in line {first})", blk.column, self._span(src, i)
                )
            if key != "0":
                src.labels[key] = i
        return src

    @staticmethod
    def _span(src: _Source, i: int) -> SourceSpan:
        blk = src.blocks[i]
        return SourceSpan(src.file, i + 1, blk.column, blk.number)

    def _q_value(self, name: str, column: int) -> float:
        try:
            return self.q.get(name, column)
        except QError as exc:
            raise BlockError(exc.code, exc.message, exc.column) from None

    # ------------------------------------------------------------------ the run
    def _run(self, text: str) -> Generator[Move, None, bool]:
        """Execute the program, giving the moves that are ready every few blocks (read block by
        block: ``output``); returns False when it stopped with an error (already reported)."""
        path = Path(self.file) if self.file and not self.file.startswith("<") else None
        try:
            src = self._source(text, self.file, path)
        except BlockError as exc:
            assert exc.span is not None
            self._error(
                exc.code, exc.message, SourceSpan(exc.span.file, exc.span.line, exc.column or 1, exc.span.block)
            )
            return False
        stack: list[_Call] = []
        counters: dict[tuple[int, int, int], int] = {}
        reached: dict[int, int] = {}  # per program text: the furthest block run so far
        again = 0  # blocks run again (jumps back, repeats, calls): a straight program never counts
        pc = 0
        while pc < len(src.blocks):
            blk = src.blocks[pc]
            if not blk.statement:
                pc += 1
                continue
            span = self._span(src, pc)
            self.blocks += 1
            self.seq += 1
            if pc > reached.get(id(src), -1):
                reached[id(src)] = pc
            else:
                again += 1
            n_before, mark = len(self.elems), len(self.diags)
            try:
                if again > self.opts.max_blocks:
                    raise BlockError(
                        Code.HH_LOOP_LIMIT,
                        f"the program does not end within {self.opts.max_blocks} blocks run again (endless loop?)",
                    )
                src, pc = self._step(src, pc, blk, span, stack, counters)
            except (BlockError, ContourError, LeadError) as exc:
                col = getattr(exc, "column", None) or blk.column
                where = getattr(exc, "span", None) or SourceSpan(src.file, span.line, col, blk.number)
                self._error(exc.code, exc.message, where)
                return False
            except (ArithmeticError, LookupError, TypeError, ValueError) as exc:  # a bug must not pass silently
                self._error(Code.NC_INTERNAL, f"internal error while reading this block: {exc!r}", span)
                return False
            for e in self.elems[n_before:]:
                e.extra.setdefault("plane", self.plane)
                e.extra.setdefault("seq", self.seq)
                e.extra.setdefault("diag_mark", mark)
                e.extra.setdefault("lookahead", self.lookahead)
            if self.output is not None and len(self.elems) > _RELEASE:
                yield from self._release()
            if self.ended:
                return True
        if stack:
            what = f"subprogram LBL {stack[-1].name}" if stack[-1].kind == "lbl" else f"PGM {stack[-1].name}"
            self._error(
                Code.HH_LABEL,
                f"{what} runs to the end of the file without LBL 0 / END PGM",
                self._span(src, len(src.blocks) - 1),
            )
            return False
        return True

    def _step(
        self,
        src: _Source,
        pc: int,
        blk: Block,
        span: SourceSpan,
        stack: list[_Call],
        counters: dict[tuple[int, int, int], int],
    ) -> tuple[_Source, int]:
        st, text = blk.statement, blk.source
        rest = blk.column - 1
        if st == "FN":
            return src, self._fn(src, pc, blk, text, rest)
        if st == "Q":
            self._assign(text, rest)
            return src, pc + 1
        if st == "LBL":
            m = _LBL.match(text, rest)
            assert m is not None  # checked when the program was loaded
            if _label_key(m.group(1)) != "0":
                return src, pc + 1
            if not stack or stack[-1].kind != "lbl":
                raise BlockError(
                    Code.HH_LABEL,
                    "LBL 0 (end of subprogram) reached without a CALL LBL (M2/M30 missing before the subprograms?)",
                )
            call = stack.pop()
            return call.source, call.back
        if st == "CALL LBL":
            return self._call_lbl(src, pc, blk, text, rest, stack, counters)
        if st in ("CALL PGM", "PGM CALL"):
            return self._call_pgm(src, pc, text, rest, span, stack)
        if st == "CYCL CALL":
            raise BlockError(Code.HH_NOT_MODELLED, "CYCL CALL: machining cycles are not modelled by trcopt")
        if st == "END PGM" and stack:
            call = stack.pop()
            if call.kind != "pgm":
                raise BlockError(Code.HH_LABEL, f"subprogram LBL {call.name} reaches END PGM without LBL 0")
            self.q.pop_local()
            self.unit = call.unit
            return call.source, call.back
        if "Q" in text or "q" in text:  # its Q parameters' values now
            run = lex_block(self._line_text(blk), blk.line, self._q_value)
        else:
            run = blk  # lexed as it would be again (without a Q parameter the values do not change)
        self._block(run, span)
        if any(w.address == "M" and w.value in (2.0, 30.0) for w in run.words):
            if any(c.kind == "pgm" for c in stack):
                raise BlockError(Code.HH_NOT_MODELLED, "M2/M30 in a called program (the TNC manual does not allow it)")
            self._block(lex_block("END PGM", blk.line), span)  # the end of the program run
        return src, pc + 1

    @staticmethod
    def _line_text(blk: Block) -> str:
        return blk.source + (f" ;{blk.comment}" if blk.comment else "")

    def _iteration(self) -> None:
        self.iterations += 1
        if self.iterations > self.opts.max_iterations:
            raise BlockError(
                Code.HH_LOOP_LIMIT,
                f"more than {self.opts.max_iterations} loop iterations (jumps back and section repeats): endless loop?",
            )

    def _jump_target(self, src: _Source, label: str, column: int) -> int:
        key = _label_key(label)
        if key == "0":
            raise BlockError(
                Code.HH_LABEL, "LBL 0 marks the end of a subprogram and cannot be jumped to or called", column
            )
        if key not in src.labels:
            raise BlockError(Code.HH_LABEL, f"label LBL {key} is not in the program", column)
        return src.labels[key]

    def _fn(self, src: _Source, pc: int, blk: Block, text: str, rest: int) -> int:
        m = _FN.match(text, rest)
        if m is None:
            raise BlockError(Code.HH_SYNTAX, "FN needs its number and a colon: FN 0: Q1 = …")
        fn, body, col = int(m.group(1)), m.group(2), m.start(2) + 1
        try:
            if fn in _JUMP_OPS:
                j = _JUMP.fullmatch(body)
                if j is None or j.group(2).upper() != _JUMP_OPS[fn]:
                    raise BlockError(Code.HH_SYNTAX, f"FN {fn}: expected IF a {_JUMP_OPS[fn]} b GOTO LBL n", col)
                target = self._jump_target(src, j.group(4), col + j.start(4))
                a = eval_fn(0, j.group(1), col + j.start(1), self.q)
                b = eval_fn(0, j.group(3), col + j.start(3), self.q)
                take = {9: a == b, 10: a != b, 11: a > b, 12: a < b}[fn]
                if take and target <= pc:
                    self._iteration()
                return target if take else pc + 1
            if fn in (0, 1, 2, 3, 4, 5, 6, 7, 8, 13):
                target_q = _ASSIGN.fullmatch(body)
                if target_q is None:
                    raise BlockError(Code.HH_SYNTAX, f"FN {fn}: expected Q… = …", col)
                self.q.set(target_q.group(1), eval_fn(fn, target_q.group(2), col + target_q.start(2), self.q))
                return pc + 1
        except QError as exc:
            raise BlockError(exc.code, exc.message, exc.column) from None
        raise BlockError(Code.HH_NOT_MODELLED, f"FN {fn} is not modelled by trcopt", m.start(1) + 1)

    def _assign(self, text: str, rest: int) -> None:
        m = _ASSIGN.match(text, rest)
        if m is None or not m.group(2):
            what = "string parameters (QS)" if text[rest:].upper().startswith("QS") else "this Q-parameter block"
            raise BlockError(Code.HH_NOT_MODELLED if "QS" in what else Code.HH_SYNTAX, f"{what}: expected Q… = formula")
        try:
            self.q.set(m.group(1), evaluate(m.group(2), m.start(2) + 1, self.q))
        except QError as exc:
            raise BlockError(exc.code, exc.message, exc.column) from None

    def _call_lbl(
        self,
        src: _Source,
        pc: int,
        blk: Block,
        text: str,
        rest: int,
        stack: list[_Call],
        counters: dict[tuple[int, int, int], int],
    ) -> tuple[_Source, int]:
        m = _CALL_LBL.match(text, rest)
        if m is None:
            raise BlockError(Code.HH_SYNTAX, "CALL LBL needs a label: CALL LBL n [REP m]")
        target = self._jump_target(src, m.group(1), m.start(1) + 1)
        rep = int(m.group(2)) if m.group(2) else 0
        key = _label_key(m.group(1))
        if rep > 0:
            if target > pc:
                raise BlockError(
                    Code.HH_NOT_MODELLED,
                    f"CALL LBL {key} REP {rep}: a program-section repeat needs LBL {key} before the call",
                    m.start(1) + 1,
                )
            ident = (id(src), pc, len(stack))
            left = counters.get(ident, rep)
            if left > 0:
                counters[ident] = left - 1
                self._iteration()
                return src, target
            counters.pop(ident, None)
            return src, pc + 1
        if len(stack) >= MAX_DEPTH:
            raise BlockError(Code.HH_LOOP_LIMIT, f"CALL LBL {key}: more than {MAX_DEPTH} nested calls")
        stack.append(_Call("lbl", src, pc + 1, key))
        return src, target

    def _call_pgm(
        self, src: _Source, pc: int, text: str, rest: int, span: SourceSpan, stack: list[_Call]
    ) -> tuple[_Source, int]:
        m = _PGM.match(text, rest)
        if m is None:
            raise BlockError(Code.HH_SYNTAX, "CALL PGM needs a program name")
        name = m.group(1).strip("\"'")
        base = re.split(r"[\\/:]", name)[-1]
        here = src.path.parent if src.path is not None else Path.cwd()
        candidates = [here / base] if Path(base).suffix else [here / f"{base}.h", here / f"{base}.H"]
        # os.path.isfile: False for a name the file system refuses (too long, …), where
        # Path.is_file raises
        found = next((p for p in candidates if os.path.isfile(p)), None)
        if found is None:
            raise BlockError(
                Code.HH_PGM_MISSING,
                f"CALL PGM {name}: no file {candidates[0].name} beside the program (in {here})",
                m.start(1) + 1,
            )
        if len(stack) >= MAX_DEPTH:
            raise BlockError(Code.HH_LOOP_LIMIT, f"CALL PGM {name}: more than {MAX_DEPTH} nested calls")
        self._no_open_corner("CALL PGM")
        if self.side is not Side.OFF:
            self._warn(Code.HH_PGM_CALL, "CALL PGM while RL/RR is active: compensation is cancelled at the call", span)
        self.side = self.last_on_side = Side.OFF
        self._m120_off()
        try:
            called = self._source(decode_program(found.read_bytes(), str(found)), str(found), found)
        except (OSError, TrcoptError) as exc:
            raise BlockError(
                Code.HH_PGM_MISSING, f"CALL PGM {name}: {found} cannot be read: {exc}", m.start(1) + 1
            ) from None
        stack.append(_Call("pgm", src, pc + 1, name, self.unit))
        self.q.push_local()
        return called, 0
