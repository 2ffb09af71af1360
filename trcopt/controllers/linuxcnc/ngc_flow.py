"""O-word control flow as LinuxCNC's interpreter runs it.

LinuxCNC reads a program line by line and never builds a tree: a false ``if``, a finished loop or
a subroutine definition sets a label to *skip to*, and lines are passed over unread (not even
checked) until an O-line with that label; a loop end or a call jumps back to the line where the
label was first seen (its *offset*). :class:`NgcFlow` does the same, so that LinuxCNC's quirks are
kept: labels of ``if``/``while``/``do``/``repeat`` are local to the subroutine and may be used once
per scope; a subroutine must be defined before a call reaches it, or is searched forward in the
file, or in ``<name>.ngc`` beside the program; ``#1``…``#30`` are the call's arguments and are
restored on return, and named parameters without ``_`` belong to the call.

:meth:`NgcFlow.blocks` yields every line to execute (block, file, line, N number) and applies the
line's parameter settings when the consumer asks for the next one. Errors are
:class:`FlowError` (file, line, column, N number, code, LinuxCNC's message). A loop that jumps back
more than :data:`LOOP_LIMIT` times without leaving, or a program that jumps back more than
:data:`TOTAL_JUMP_LIMIT` times in all (a finished loop entered again and again), stops with
``NC-LOOP-LIMIT``.
"""

from __future__ import annotations

import os
import re
from collections.abc import Generator, Sequence
from dataclasses import dataclass
from pathlib import Path

from trcopt.codes import Code
from trcopt.controllers.linuxcnc.ngc_block import Block, OLine, block_number, read_oword, read_words
from trcopt.controllers.linuxcnc.ngc_expr import (
    FIRST_SUB_PARAM,
    SUB_PARAMS,
    NgcError,
    NgcLine,
    Parameters,
    ValueReader,
    normalise,
)
from trcopt.controllers.linuxcnc.ngc_fanuc import CALL_LEVELS, Frame, m98_block, program_number
from trcopt.nc.text import decode_program, program_lines
from trcopt.textlines import TextLines

__all__ = ["LOOP_LIMIT", "TOTAL_JUMP_LIMIT", "CALL_LEVELS", "FlowError", "NgcFlow", "Step"]

LOOP_LIMIT = 100_000  # jumps back to one loop start before the loop is taken as endless
TOTAL_JUMP_LIMIT = 100_000  # jumps back in the whole program (a loop re-entered without end)
_BLOCK_NUMBER = re.compile(r"[Nn]\s*(\d+)")
_B = "[ \t\r\n\f\v]*"  # the blanks normalise() drops
_NUM = "([+-]?(?:[0-9]+\\.?[0-9]*|\\.[0-9]+))"
#: a plain motion line (see :class:`Step`): blanks only between words, never inside one
PLAIN_MOTION = re.compile(
    f"{_B}(?:[Nn]([0-9]+){_B})?(?:[Gg](0*[01](?:\\.0*)?){_B})?(?:[Xx]{_NUM}{_B})?(?:[Yy]{_NUM}{_B})?"
    f"(?:[Zz]{_NUM}{_B})?(?:[Ff]{_NUM}{_B})?"
).fullmatch
_UNREAD = Block([], [])  # the block of a plain motion line until it is read
# a plain line shorter than this holds no number a float cannot hold (10**308 has 309 digits):
# its words are read without an error
_PLAIN_MAX = 309
# a line that starts with an O-word (after a block delete and an N number): the program has
# control flow or subroutines, its lines may run more than once
_O_WORD_LINE = re.compile(r"^[ \t]*(?:/[ \t]*)?(?:[Nn][ \t]*[0-9]+[ \t]*)?[Oo]", re.M)
_NO_END = "File ended with no percent sign (%) or program end (M2)"


class _OpenAtEnd(Exception):
    def __init__(self, file: str, line: int) -> None:
        super().__init__(_NO_END)
        self.file, self.line = file, line


class FlowError(Exception):
    def __init__(self, code: Code, message: str, file: str, line: int, column: int, block: str | None) -> None:
        super().__init__(message)
        self.code, self.message = code, message
        self.file, self.line, self.column, self.block = file, line, column, block


@dataclass(slots=True)
class Step:
    """A line to execute: its words (values evaluated), where it is, and its ``N`` number.

    A *plain motion line* (:data:`PLAIN_MOTION`: an optional ``N`` number, then ``G0``/``G1``,
    ``X``, ``Y``, ``Z`` and ``F`` with plain numbers, each at most once and in this order, at least
    one axis; shorter than 309 characters, so that reading its words cannot fail) is not read
    into words: ``plain`` holds the numbers of G, X, Y, Z and F as written (None for a word the
    line does not have) and ``block`` is empty until :meth:`read_block` reads ``raw`` as any
    other line is read."""

    block: Block
    file: str
    line: int
    number: int | None
    plain: tuple[str | None, str | None, str | None, str | None, str | None] | None = None
    raw: str = ""

    def read_block(self, params: Parameters) -> Block:
        """The words of a plain motion line, read as :meth:`NgcFlow.blocks` reads every other line
        (its words hold no parameter or expression: ``params`` are not read)."""
        line = normalise(self.raw)
        _, start = block_number(line)
        self.block = read_words(line, start, params)
        self.plain = None
        return self.block


@dataclass(slots=True)
class _Offset:
    command: str
    file: str
    index: int  # line index of the O-line
    repeat_count: int = -1
    jumps: int = 0


class NgcFlow:
    """Runs the O-word control flow of one program (see the module docstring)."""

    def __init__(self, file: str, text: str, params: Parameters | None = None) -> None:
        self.main = file
        # the main program's lines cut from its text on demand (no list of a million strings)
        self.sources: dict[str, Sequence[str]] = {file: TextLines(text)}
        # a line is normalised once and kept for when it runs again; only a program with O-words
        # runs a line again (the called files' lines are always kept)
        self._reruns = _O_WORD_LINE.search(text) is not None
        self.params = params if params is not None else Parameters()
        self.file, self.index = file, 0
        self.skipping: str | None = None
        self.skipping_to_sub: str | None = None
        self.skip_start = 0
        self.executed_if = self.doing_break = self.doing_continue = False
        self.defining_sub = False
        self.sub_name: str | None = None
        self.offsets: dict[str, _Offset] = {}
        self.frames: list[Frame] = [Frame()]
        self.value = 0.0  # a subroutine's return value (#<_value>)
        self.jumps = 0  # jumps back so far (TOTAL_JUMP_LIMIT)
        self._lines: dict[tuple[str, int], tuple[NgcLine, int | None, int]] = {}  # normalised once
        self.raw = ""  # the O-line being run, as written (LinuxCNC quotes it in messages)
        self.opened: tuple[str, int] = (file, 0)  # the O-line that opened the skip or definition

    # -- driving --------------------------------------------------------------------------------
    def blocks(self) -> Generator[Step, None, None]:
        number: int | None = None
        line_no = 0
        line = NgcLine("", (1,))
        try:
            while True:
                lines = self.sources[self.file]
                if self.index >= len(lines):
                    self._end_of_file()
                    return
                raw = lines[self.index]
                self.index += 1
                line_no = self.index
                number = None
                if self.skipping is None and len(raw) < _PLAIN_MAX:
                    plain = PLAIN_MOTION(raw)
                    if plain is not None:
                        n, g, x, y, z, f = plain.groups()
                        if x is not None or y is not None or z is not None:
                            number = None if n is None else int(n)
                            yield Step(_UNREAD, self.file, line_no, number, (g, x, y, z, f), raw)
                            continue
                stripped = raw.strip()
                if not stripped or stripped.startswith(("%", "/")):
                    continue  # % delimiters; block delete (the switch taken as on)
                cached = self._lines.get((self.file, self.index))
                if cached is None:
                    try:
                        line = normalise(raw)
                        number, start = block_number(line)
                    except NgcError:
                        early = _BLOCK_NUMBER.match(stripped)  # the number an error names
                        number = None if early is None else int(early.group(1))
                        raise
                    if self._reruns or self.file != self.main:
                        self._lines[(self.file, self.index)] = (line, number, start)
                else:
                    line, number, start = cached
                if line.text.startswith("o", start):
                    self.raw = stripped
                    self._oline(line, start, read_oword(line, start, self.params))
                    continue
                if self.skipping is not None:
                    continue  # LinuxCNC does not read a skipped line
                block = read_words(line, start, self.params)
                if m98_block(self, block):
                    continue
                yield Step(block, self.file, line_no, number)
                for key, value in block.settings:
                    if isinstance(key, int):
                        self.params.numbered[key] = value
                    else:
                        self.params.set_named(key, value)
        except _OpenAtEnd as end:
            raise FlowError(Code.LCNC_OWORD, _NO_END, end.file, end.line, 1, None) from None
        except NgcError as exc:
            tag = None if number is None else f"N{number}"
            column = exc.column if exc.column is not None else line.col(exc.index)
            raise FlowError(exc.code, exc.message, self.file, line_no, column, tag) from None

    def _end_of_file(self) -> None:
        """At the end of a file: an error if a skip, a definition or a call is still open (the
        message is LinuxCNC's; the location is the O-line left open)."""
        if self.skipping_to_sub is not None:
            raise NgcError(
                f"EOF in file:{os.path.basename(self.file)} seeking o-word: o<{self.skipping_to_sub}> "
                f"from line: {self.skip_start}",
                0,
                Code.LCNC_OWORD,
            )
        if self.defining_sub or len(self.frames) > 1 or self.skipping is not None:
            file, line = self.opened if len(self.frames) == 1 else (self.file, len(self.sources[self.file]))
            raise _OpenAtEnd(file, line)

    # -- O-lines --------------------------------------------------------------------------------
    def _oline(self, line: NgcLine, start: int, o: OLine) -> None:
        cmd = o.command
        level = len(self.frames) - 1
        if cmd == "":
            program_number(self, o)
            return
        if cmd in ("sub", "endsub", "call", "return"):
            name = o.label
        else:
            scope = self.frames[-1].sub if level else (self.sub_name if self.defining_sub else "")
            name = f"{scope or ''}#{o.label}"
        reader = ValueReader(line.text, self.params, o.rest, self.defining_sub)
        test = 0.0
        args: list[float] = []
        if cmd == "sub":
            if self.defining_sub:
                raise NgcError("Nested subroutine definition", o.at, Code.LCNC_OWORD)
            if level and self.skipping is None and self.frames[-1].sub != name:
                raise NgcError(
                    f"Nested subroutine definition: 'O{name} sub' found inside called subroutine "
                    f"'O{self.frames[-1].sub}'",
                    o.at,
                    Code.LCNC_OWORD,
                )
        elif cmd in ("endsub", "return"):
            if self.skipping is not None and self.skipping != name:
                return
            if level and reader.pos < len(line.text) and line.text[reader.pos] == "[":
                self.value = reader.expression()
                self.params.globals["_value"], self.params.globals["_value_returned"] = self.value, 1.0
            elif level:
                self.params.globals["_value"], self.params.globals["_value_returned"] = 0.0, 0.0
        elif self.defining_sub:
            return
        elif cmd == "call":
            if self.skipping is not None:
                return
            while reader.pos < len(line.text) and line.text[reader.pos] == "[":
                if len(args) >= SUB_PARAMS:
                    raise NgcError("Too many subroutine parameters", reader.pos, Code.LCNC_OWORD)
                args.append(reader.expression())
        elif cmd in ("while", "repeat", "if", "elseif"):
            if self.skipping is not None and self.skipping != name:
                return
            if reader.pos >= len(line.text) or line.text[reader.pos] != "[":
                raise NgcError(f"Left bracket missing after '{cmd}'", reader.pos, Code.LCNC_OWORD)
            test = reader.expression()
        if self.skipping is None and reader.pos < len(line.text):
            raise NgcError("Unexpected character after O-word", reader.pos, Code.NC_SYNTAX)
        self._control(o, name, test, args, line)

    def _control(self, o: OLine, name: str, test: float, args: list[float], line: NgcLine) -> None:
        """LinuxCNC's ``convert_control_functions``."""
        cmd = o.command
        if self.skipping is not None and self.skipping != name:
            return
        if self.skipping_to_sub is not None and cmd != "sub":
            return
        level = len(self.frames) - 1
        seq = self.index  # 1-based line of this O-line
        where = f"'{self.raw}'"
        if cmd == "sub":
            if self.skipping is not None:
                self._save_offset(o, name)
                self.skipping = None
            self.skipping_to_sub = None
            if level == 0:
                self._save_offset(o, name)
                self._skip(name)
                self.defining_sub, self.sub_name = True, name
        elif cmd in ("endsub", "return"):
            if level == 0 and self.sub_name is None:
                raise NgcError(f"{seq}: not in a subroutine definition: {where}", o.at, Code.LCNC_OWORD)
            if self.skipping is not None and cmd == "endsub":
                self.skipping = None
            if level:
                self._return()
            elif cmd == "endsub":
                if not self.defining_sub:
                    raise NgcError("Not in subroutine definition", o.at, Code.LCNC_OWORD)
                self.skipping, self.defining_sub, self.sub_name = None, False, None
        elif cmd == "call":
            self._call(name, args, o)
        elif cmd == "do":
            self.skipping = None
            if name not in self.offsets:
                self._save_offset(o, name)
        elif cmd in ("repeat", "while"):
            op = self.offsets.get(name)
            if op is None:
                op = self._save_offset(o, name)
            elif not (cmd == "while" and op.command == "do") and op.index != self.index - 1:
                raise NgcError(
                    f"{seq}: duplicate O-word label: {where} - defined in line {op.index + 1}", o.at, Code.LCNC_OWORD
                )
            self.skipping = None
            if op.command == cmd and cmd == "repeat":
                if op.repeat_count == -1:
                    op.repeat_count = round(test)
                if op.repeat_count > 0:
                    op.repeat_count -= 1
                else:
                    self._skip(name)
                    op.repeat_count, op.jumps = -1, 0
            elif op.command == cmd:  # while … endwhile
                if test == 0.0:
                    self._skip(name)
                    op.jumps = 0
            elif test != 0.0 and not self.doing_break:  # the end of a do … while
                self._back_to(name, o)
            else:
                self.doing_break = False
                op.jumps = 0
        elif cmd == "if":
            op = self.offsets.get(name)
            if op is None:
                self._save_offset(o, name)
            elif op.index != self.index - 1:
                raise NgcError(
                    f"{seq}: duplicate O-word label - already defined in line {op.index + 1}: {where}",
                    o.at,
                    Code.LCNC_OWORD,
                )
            if test != 0.0:
                self.skipping, self.executed_if = None, True
            else:
                self._skip(name)
                self.executed_if = False
        elif cmd in ("elseif", "else"):
            self._match(name, o, ("if",), "no matching 'if' label", line)
            if self.executed_if:
                self._skip(name)
            elif cmd == "else" or test != 0.0:
                self.skipping, self.executed_if = None, True
        elif cmd == "endif":
            self._match(name, o, ("if",), "no matching label", line)
            self.skipping, self.executed_if = None, True
        elif cmd in ("break", "continue"):
            self._match(name, o, ("while", "do"), "no matching while/do label", line)
            if cmd == "continue" and self.skipping == name:
                return
            self._skip(name)
            if cmd == "break":
                self.doing_break = True
            else:
                self.doing_continue = True
        else:  # endwhile, endrepeat
            op = self._match(name, o, ("while",) if cmd == "endwhile" else ("repeat",), "no matching label", line)
            if self.skipping == name:
                self.skipping = None
                if self.doing_continue:
                    self.doing_continue = False
                    self._back_to(name, o)
                else:
                    op.jumps = 0
            else:
                self._back_to(name, o)

    def _match(self, name: str, o: OLine, kinds: tuple[str, ...], what: str, line: NgcLine) -> _Offset:
        op = self.offsets.get(name)
        seq = self.index
        if op is None:
            raise NgcError(f"{seq}: undefined O-word label: '{self.raw}'", o.at, Code.LCNC_OWORD)
        if op.command not in kinds:
            raise NgcError(
                f"{seq}: {what}: '{self.raw}' (found '{op.command}' in line {op.index + 1})", o.at, Code.LCNC_OWORD
            )
        return op

    def _skip(self, name: str) -> None:
        self.skipping, self.skip_start = name, self.index
        self.opened = (self.file, self.index)

    def _save_offset(self, o: OLine, name: str) -> _Offset:
        op = self.offsets.get(name)
        if op is not None:
            base = os.path.basename(self.file)
            if op.index == self.index - 1:
                message = f"File:{base} line:{self.index} sub: o|{name}| found in illegal location"
            else:
                message = (
                    f"File:{base} line:{self.index} redefining sub: o|{name}| already defined in file:"
                    f"{os.path.basename(op.file)}"
                )
            raise NgcError(message, o.at, Code.LCNC_OWORD)
        op = _Offset(o.command, self.file, self.index - 1)
        self.offsets[name] = op
        return op

    def _back_to(self, name: str, o: OLine) -> None:
        op = self.offsets[name]
        op.jumps += 1
        self.jumps += 1
        if self.jumps > TOTAL_JUMP_LIMIT:
            raise NgcError(
                f"more than {TOTAL_JUMP_LIMIT} jumps back in the program (o{name.rpartition('#')[2]} "
                f"{op.command}); it is taken as endless",
                o.at,
                Code.NC_LOOP_LIMIT,
            )
        if op.jumps > LOOP_LIMIT:
            raise NgcError(
                f"o{name.rpartition('#')[2]} {op.command}: more than {LOOP_LIMIT} iterations; the loop is "
                "taken as endless",
                o.at,
                Code.NC_LOOP_LIMIT,
            )
        self.file, self.index = op.file, op.index

    # -- calls ----------------------------------------------------------------------------------
    def _call(self, name: str, args: list[float], o: OLine) -> None:
        if len(self.frames) >= CALL_LEVELS:
            raise NgcError("Too many subroutine levels", o.at, Code.LCNC_OWORD)
        caller = self.frames[-1]
        numbered = self.params.numbered
        caller.saved = numbered[FIRST_SUB_PARAM : FIRST_SUB_PARAM + SUB_PARAMS]
        caller.file, caller.index = self.file, self.index
        values = args + [0.0] * (SUB_PARAMS - len(args))
        numbered[FIRST_SUB_PARAM : FIRST_SUB_PARAM + SUB_PARAMS] = values
        self.frames.append(Frame(name))
        self.params.frames.append({})
        self.skipping = None
        op = self.offsets.get(name)
        if op is not None:
            self.file, self.index = op.file, op.index
            return
        path = self._sub_file(name)
        if path is not None:
            self.file, self.index = path, 0
        elif self.file != self.main:
            raise NgcError(
                f"Subroutine 'O{name}' not found -- not in offset table and no file '{name}.ngc' found",
                o.at,
                Code.LCNC_OWORD,
            )
        self.skipping = self.skipping_to_sub = name
        self.skip_start = self.index

    def _sub_file(self, name: str) -> str | None:
        """``<name>.ngc`` beside the program (read once)."""
        if not os.path.isfile(self.main):
            return None
        path = str(Path(self.main).parent / f"{name}.ngc")
        if path not in self.sources:
            if not os.path.isfile(path):
                return None
            self.sources[path] = program_lines(decode_program(Path(path).read_bytes(), path))
        return path

    def _return(self) -> None:
        self.frames.pop()
        self.params.frames.pop()
        caller = self.frames[-1]
        self.params.numbered[FIRST_SUB_PARAM : FIRST_SUB_PARAM + SUB_PARAMS] = caller.saved
        self.file, self.index = caller.file, caller.index
        self.sub_name = caller.sub
