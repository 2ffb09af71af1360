"""SINUMERIK program execution: the program counter, control structures, jumps, section repetition
and subprogram calls over the statements of :mod:`trcopt.controllers.siemens.flow`.

* Jumps: ``GOTOF`` searches towards the program end, ``GOTOB`` towards its start (the jumping
  block included), ``GOTO`` forwards then backwards, ``GOTOC`` as ``GOTO`` without alarm 14080 when
  the destination is missing. A destination is a label or a block number (``N100``).
* Iteration limit: every backward jump, loop iteration, section repetition and subprogram
  repetition counts; more than :data:`MAX_ITERATIONS` in one run is ``NC-LOOP-LIMIT`` (taken as an
  endless loop), as is more than :data:`MAX_BLOCKS` blocks run again (a block runs again after a
  jump back, in a repetition or another call of its subprogram; a program read straight through
  never counts, whatever its length).
* Subprograms: ``NAME``, ``NAME(args)``, ``NAME P=n``, ``L123 P2``; the file ``NAME.SPF`` (then
  ``.MPF``, any letter case, also ``_N_NAME_SPF``) in the calling program's folder, else the main
  program's; a missing file is alarm 14011 naming where it was looked for. ``PROC NAME(REAL A, VAR
  INT B) SAVE``: parameters by value (``VAR``: the value is copied back into the caller's variable at
  the return); DEF variables are local to their program level, R-parameters global. ``RET``,
  ``M17``, ``M2``, ``M30`` (and the end of the file) return. Modal state set in a subprogram stays
  in force after the return, except under ``SAVE`` (G codes, frames, zero offset, path control are
  restored). At most :data:`MAX_LEVELS` program levels.
"""

from __future__ import annotations

import bisect
import os
import re
from collections.abc import Callable, Generator
from dataclasses import dataclass, field

from trcopt.codes import Code
from trcopt.controllers.siemens.branch import CALL_LINE, call_text, parse_case
from trcopt.controllers.siemens.flow import _FOR, _SECTION, Program, Statement
from trcopt.controllers.siemens.lexer import Word
from trcopt.controllers.siemens.variables import DEF_LINE, Variable, Variables, _split, _store
from trcopt.errors import AlarmError, Diagnostic, Severity, SourceSpan, TrcoptError, alarm
from trcopt.nc.modal import fail
from trcopt.nc.model import Move
from trcopt.nc.text import decode_program

__all__ = ["ProgramRunner", "MAX_ITERATIONS", "MAX_BLOCKS", "MAX_LEVELS"]

#: backward jumps, loop iterations and repetitions in one program run before it is taken as endless
MAX_ITERATIONS = 100_000
#: blocks run again in one program run (the first run of each block of a program text is free)
MAX_BLOCKS = 2_000_000
#: program levels (the main program and 15 nested subprogram calls)
MAX_LEVELS = 16
_BATCH = 512  # moves given together (a few at a time run slower: the reader and its consumer take turns)
_PROC = re.compile(r"(?P<name>[A-Z_][A-Z0-9_]*)[ \t]*(?:\((?P<params>[^)]*)\))?(?P<attrs>.*)\Z", re.I | re.S)
_PARAM = re.compile(
    r"(?P<var>VAR[ \t]+)?(?P<type>REAL|INT|BOOL|CHAR|STRING|AXIS|FRAME)[ \t]+(?P<name>[A-Z_][A-Z0-9_]*)\Z", re.I
)
_NAME = re.compile(r"[A-Z_][A-Z0-9_]*\Z", re.I)
_ATTRIBUTES = {"SAVE", "DISPLOF", "DISPLON", "SBLOF", "ICYCOF", "ICYCON", "ACTBLOCNO", "PREPRO"}


@dataclass(eq=False, slots=True)
class Level:
    """One program level: a program, its counter and local variables."""

    program: Program
    variables: Variables
    pc: int = 0
    repeats: int = 1  # runs of this call still to do, this one included
    executable: bool = False
    save: tuple[object, ...] | None = None
    copy_back: list[tuple[str, str]] = field(default_factory=list)  # (caller variable, local name)
    args: dict[str, float] = field(default_factory=dict)
    params: list[tuple[str, str, bool]] = field(default_factory=list)
    sections: list[list[int]] = field(default_factory=list)  # [start, end, remaining, return_to, at]
    for_end: dict[int, float] = field(default_factory=dict)
    call: Statement | None = None


class ProgramRunner:
    """The execution part of :class:`~trcopt.controllers.siemens.reader.SiemensReader`."""

    # provided by the reader
    file: str
    moves: list[Move]
    scan: Callable[[str, str, str, frozenset[str]], Program]  # the scan of a program file
    variables: Variables
    diagnostics: list[Diagnostic]
    blocks: int
    _executable: bool

    def _run(self, program: Program) -> Generator[Move, None, bool]:
        """Run ``program``, giving the moves of the statements that have run (``moves``, emptied
        every :data:`_BATCH` moves: those left when it ends are the caller's); returns True when
        it ended with M2/M30 (False at its last line)."""
        self.levels = [Level(program, self.variables)]
        self._programs: dict[str, Program] = {}
        self.iterations = 0
        executed = 0  # statements run again (loops, repeats, calls): a straight program never counts
        reached: dict[int, int] = {}  # per program text: the furthest statement run so far
        moves = self.moves
        while True:
            if len(moves) >= _BATCH:
                yield from moves
                moves.clear()
            level = self.levels[-1]
            stmts = level.program.statements
            if level.pc >= len(stmts):
                if len(self.levels) == 1:
                    return False
                self._leave_level()
                continue
            st = stmts[level.pc]
            key = id(stmts)
            if level.pc > reached.get(key, -1):
                reached[key] = level.pc
            else:
                executed += 1
            level.pc += 1
            if executed > MAX_BLOCKS:
                raise fail(
                    Code.NC_LOOP_LIMIT,
                    f"more than {MAX_BLOCKS} blocks run again (loops, repeats, calls): taken as an endless loop",
                    st.span(self.file),
                )
            if self._statement(level, st):
                if len(self.levels) == 1:
                    return True
                self._leave_level()
                continue
            if level.sections and level.sections[-1][1] == st.index and level.pc == st.index + 1:
                section = level.sections[-1]
                section[2] -= 1
                if section[2] > 0:
                    self._iterate(level.program.statements[section[4]])
                    level.pc = section[0]
                else:
                    level.pc = section[3]
                    level.sections.pop()

    # ------------------------------------------------------------------ statements
    def _statement(self, level: Level, st: Statement) -> bool:
        kind = st.kind
        if kind == "empty":
            return False
        self.blocks += 1
        span = st.span(self.file)
        if kind == "block":
            level.executable = True
            if st.error is not None:
                at = SourceSpan(self.file, st.lineno, st.error.column, st.number)
                raise AlarmError(Diagnostic(Severity.ERROR, Code.NC_SYNTAX, st.error.message, at))
            assert st.lexed is not None
            ended = self._block(st.lexed, st.lineno)  # type: ignore[attr-defined]
            if not ended and st.jump is not None:
                self._jump(level, st)
            return ended
        if kind == "def":
            self._executable = level.executable
            m = DEF_LINE.match(st.text)
            assert m is not None
            self._define(st.text, st.lineno, m)  # type: ignore[attr-defined]
            return False
        if kind in ("proc", "extern"):
            stmts = level.program.statements
            if kind == "proc" and any(stmts[i].kind != "empty" for i in range(st.index)):
                raise fail(Code.NC_CALL, "PROC must be the first line of a program", span)
            if level.executable:
                raise fail(Code.NC_CALL, f"{kind.upper()} after the first executable block", span)
            return False
        level.executable = True
        stmts = level.program.statements
        if kind in ("if", "while", "until"):
            value = self.variables.evaluate(st.rest, span, st.rest_column) if st.rest else None
            if value is None:
                raise fail(Code.NC_SYNTAX, f"{kind.upper()} without a condition", span)
            if kind == "until":
                if value == 0.0:
                    self._iterate(st)
                    level.pc = st.partner + 1
            elif value == 0.0:
                level.pc = st.partner + 1
        elif kind == "else":
            level.pc = st.partner + 1  # the true branch is done: after ENDIF
        elif kind == "endwhile":
            self._iterate(st)
            level.pc = st.partner
        elif kind == "endloop":
            self._iterate(st)
            level.pc = st.partner + 1
        elif kind == "for":
            self._for(level, st, span)
        elif kind == "endfor":
            opener = stmts[st.partner]
            var, _, _ = self._for_parts(opener, span)
            value = self._read_var(var, opener, span) + 1.0
            self._assign_var(var, value, opener, span)
            if value <= level.for_end[opener.index]:
                self._iterate(st)
                level.pc = opener.index + 1
        elif kind == "section":
            self._section(level, st, span)
        elif kind == "call":
            self._call(level, st, span, st.rest)
        elif kind == "indirect":
            m = CALL_LINE.match(st.rest)
            assert m is not None
            self._call(level, st, span, call_text(m.group("kw"), m.group("rest"), span))
        elif kind == "case":
            self._case(level, st, span)
        elif kind == "mcall":
            self._mcall(st, span)  # type: ignore[attr-defined]
        return False

    def _iterate(self, st: Statement) -> None:
        self.iterations += 1
        if self.iterations > MAX_ITERATIONS:
            raise fail(
                Code.NC_LOOP_LIMIT,
                f"more than {MAX_ITERATIONS} loop iterations, backward jumps or repetitions: the program does not "
                "end (trcopt's iteration limit)",
                st.span(self.file),
            )

    # ------------------------------------------------------------------ FOR
    def _for_parts(self, st: Statement, span: SourceSpan) -> tuple[str, str, str]:
        m = _FOR.match(st.rest)
        if m is None:
            raise fail(Code.NC_SYNTAX, "FOR needs the form FOR variable = start TO end", span)
        return m.group("var").strip(), m.group("start").strip(), m.group("end").strip()

    def _for(self, level: Level, st: Statement, span: SourceSpan) -> None:
        var, start, end = self._for_parts(st, span)
        first = self.variables.evaluate(start, span, st.rest_column + st.rest.find(start))
        last = self.variables.evaluate(end, span, st.rest_column + st.rest.rfind(end))
        self._assign_var(var, first, st, span)
        level.for_end[st.index] = last
        if first > last:
            level.pc = st.partner + 1

    def _read_var(self, var: str, st: Statement, span: SourceSpan) -> float:
        return self.variables.evaluate(var, span, st.rest_column)

    def _assign_var(self, var: str, value: float, st: Statement, span: SourceSpan) -> None:
        name, _, sub = var.partition("[")
        word = Word(name.strip().upper(), value, st.rest_column, var, sub.rstrip("] \t") if sub else None, True)
        if not self.variables.is_assignment(word):
            raise AlarmError(
                alarm(12550, f"name {word.name} not defined (the FOR counter needs a DEF or an R-parameter)", span)
            )
        self.variables.assign(word, value, span)

    # ------------------------------------------------------------------ jumps and sections
    def _find(self, program: Program, target: str, at: int, direction: str) -> int | None:
        if re.fullmatch(r"N\d+", target):
            where = program.numbers.get("N" + str(int(target[1:])), [])
        else:
            where = program.labels.get(target, [])
        if direction == "F":
            k = bisect.bisect_right(where, at)
            return where[k] if k < len(where) else None
        k = bisect.bisect_right(where, at)  # backwards: the jumping block included
        return where[k - 1] if k > 0 else None

    def _jump(self, level: Level, st: Statement) -> None:
        assert st.jump is not None
        kw, target, cond, column = st.jump
        span = st.span(self.file, column)
        if cond is not None:
            if not cond:
                raise fail(Code.NC_SYNTAX, "IF without a condition", span)
            if self.variables.evaluate(cond, span, st.rest_column) == 0.0:
                return
        self._goto(level, st, kw, target, span)

    def _case(self, level: Level, st: Statement, span: SourceSpan) -> None:
        """CASE: the first constant equal to the expression jumps, else DEFAULT, else the next block."""
        branch = parse_case(st.rest, st.rest_column, span)
        value = self.variables.evaluate(branch.expression, span, branch.column)
        chosen = next(((kw, t, c) for const, kw, t, c in branch.choices if const == value), branch.default)
        if chosen is not None:
            self._goto(level, st, chosen[0], chosen[1], st.span(self.file, chosen[2]))

    def _goto(self, level: Level, st: Statement, kw: str, target: str, span: SourceSpan) -> None:
        program = level.program
        if kw == "GOTOF":
            dest = self._find(program, target, st.index, "F")
        elif kw == "GOTOB":
            dest = self._find(program, target, st.index, "B")
        else:
            dest = self._find(program, target, st.index, "F")
            if dest is None:
                dest = self._find(program, target, st.index, "B")
        if dest is None:
            if kw == "GOTOC":
                return
            where = {"GOTOF": "towards the program end", "GOTOB": "towards the program start"}.get(kw, "in the program")
            raise AlarmError(alarm(14080, f"jump destination {target} not found ({kw} searches {where})", span))
        if dest <= st.index:
            self._iterate(st)
        level.pc = dest

    def _section(self, level: Level, st: Statement, span: SourceSpan) -> None:
        kw, _, rest = st.rest.partition(" ")
        m = _SECTION.match(rest.strip())
        if m is None:
            raise fail(Code.NC_SYNTAX, f"{kw} needs the form {kw} label [label] P=n", span)
        count = 1
        if m.group("p") is not None:
            value = self.variables.evaluate(m.group("p"), span, st.rest_column)
            if value != int(value) or value < 1:
                raise fail(Code.NC_SYNTAX, f"{kw} … P={value:g}: P must be a whole number ≥ 1", span)
            count = int(value)
        program = level.program
        start_label = m.group("a").upper()
        start = self._find(program, start_label, st.index - 1, "B")
        if kw == "REPEATB":
            if start is None:
                start = self._find(program, start_label, st.index, "F")
            end = start
        elif m.group("b") is not None:
            end = self._find(program, m.group("b").upper(), st.index - 1, "B") if start is not None else None
            if end is None or end < (start or 0):
                raise AlarmError(
                    alarm(14080, f"jump destination {m.group('b').upper()} not found ({kw} end label)", span)
                )
        else:
            endlabel = self._find(program, "ENDLABEL", st.index - 1, "B")
            end = endlabel if endlabel is not None and start is not None and endlabel > start else st.index - 1
        if start is None or end is None:
            raise AlarmError(alarm(14080, f"jump destination {start_label} not found ({kw} start label)", span))
        self._iterate(st)
        level.sections.append([start, end, count, st.index + 1, st.index])
        level.pc = start

    # ------------------------------------------------------------------ subprograms
    def _call(self, level: Level, st: Statement, span: SourceSpan, text: str) -> None:
        from trcopt.controllers.siemens.flow import _CALL

        m = _CALL.match(text)
        if m is None:
            raise fail(Code.NC_SYNTAX, f"subprogram call {text!r}: expected NAME[(arguments)] [P=n]", span)
        name = m.group("name").upper()
        repeats = 1
        if m.group("p") is not None:
            value = self.variables.evaluate(m.group("p"), span, st.column + st.rest.rfind(m.group("p")))
            if value != int(value) or not 1 <= value <= 9999:
                raise fail(Code.NC_CALL, f"{name} P={value:g}: the number of runs is a whole number 1…9999", span)
            repeats = int(value)
        if len(self.levels) >= MAX_LEVELS:
            raise fail(Code.NC_CALL, f"calling {name}: more than {MAX_LEVELS} program levels (recursion?)", span)
        program = self._program(name, level.program.file, span)
        params, save = self._proc(program, name, span)
        args_text = m.group("args")
        args = [] if args_text is None or not args_text.strip() else _split(args_text)
        if len(args) > len(params):
            raise fail(Code.NC_CALL, f"{name} takes {len(params)} parameter(s), called with {len(args)}", span)
        values: dict[str, float] = {}
        copy_back: list[tuple[str, str]] = []
        open_at = st.column + st.rest.find("(") + 1
        for (pname, ptype, by_ref), (text, offset) in zip(params, args, strict=False):
            if not text.strip():
                continue  # an omitted argument: the parameter's default, 0
            if ptype not in ("REAL", "INT", "BOOL", "CHAR"):
                raise fail(Code.NC_UNSUPPORTED, f"{name}: {ptype} parameter {pname} is not modelled by trcopt", span)
            values[pname] = self.variables.evaluate(text, span, open_at + offset)
            if by_ref and _NAME.match(text.strip()):
                copy_back.append((text.strip().upper(), pname))
        callee = Level(program, self._locals(), repeats=repeats, args=values, params=params, call=st)
        callee.copy_back = copy_back
        if save:
            callee.save = self._snapshot()  # type: ignore[attr-defined]
        self._enter(callee)

    def _locals(self) -> Variables:
        local = Variables(self.variables.reserved)
        local.r = self.variables.r  # R-parameters are global
        return local

    def _enter(self, callee: Level) -> None:
        for pname, ptype, _ in callee.params:
            var = Variable(ptype)
            var.values[()] = _store(var, callee.args.get(pname, 0.0))
            callee.variables.user[pname] = var
        self.levels[-1].executable = self._executable or self.levels[-1].executable
        self.levels.append(callee)
        self.variables = callee.variables
        self.file = callee.program.file
        self._executable = False

    def _leave_level(self) -> None:
        callee = self.levels.pop()
        caller = self.levels[-1]
        for target, local in callee.copy_back:
            word = Word(target, None, 1, target, None, True)
            if caller.variables.is_assignment(word):
                value = callee.variables.value(local, None)
                caller.variables.assign(word, value, callee.call.span(caller.program.file))  # type: ignore[union-attr]
                callee.args[local] = value  # a further run starts from the variable's new value
        if callee.save is not None:
            self._restore(callee.save)  # type: ignore[attr-defined]
        self.variables = caller.variables
        self.file = caller.program.file
        self._executable = caller.executable
        if callee.repeats > 1:
            assert callee.call is not None
            self._iterate(callee.call)
            again = Level(callee.program, self._locals(), repeats=callee.repeats - 1, args=callee.args,
                          params=callee.params, call=callee.call, save=callee.save)  # fmt: skip
            again.copy_back = callee.copy_back
            self._enter(again)

    def _proc(self, program: Program, name: str, span: SourceSpan) -> tuple[list[tuple[str, str, bool]], bool]:
        """The parameters ``(name, type, by reference)`` and SAVE of a subprogram's PROC line."""
        proc = next((s for s in program.statements if s.kind != "empty"), None)
        if proc is None or proc.kind != "proc":
            return [], False
        at = proc.span(program.file)
        m = _PROC.match(proc.rest)
        if m is None:
            raise fail(Code.NC_SYNTAX, "PROC needs a program name", at)
        params = []
        if m.group("params") and m.group("params").strip():
            for part in m.group("params").split(","):
                pm = _PARAM.match(part.strip())
                if pm is None:
                    raise fail(Code.NC_SYNTAX, f"PROC parameter {part.strip()!r}: expected [VAR] type name", at)
                params.append((pm.group("name").upper(), pm.group("type").upper(), pm.group("var") is not None))
        attrs = set(m.group("attrs").upper().replace(",", " ").split())
        unknown = attrs - _ATTRIBUTES
        if unknown:
            raise fail(Code.NC_UNSUPPORTED, f"PROC attribute {sorted(unknown)[0]} is not modelled by trcopt", at)
        return params, "SAVE" in attrs

    def _program(self, name: str, caller_file: str, span: SourceSpan) -> Program:
        if name in self._programs:
            return self._programs[name]
        folders = []
        for f in (caller_file, self.main_file):  # type: ignore[attr-defined]
            folder = os.path.dirname(os.path.abspath(f))
            if folder not in folders:
                folders.append(folder)
        wanted = [f"{name}.SPF", f"{name}.MPF", f"_N_{name}_SPF", f"_N_{name}_MPF"]
        for folder in folders:
            try:
                entries = {e.upper(): e for e in sorted(os.listdir(folder))}
            except OSError:
                continue
            for cand in wanted:
                if cand in entries and os.path.isfile(os.path.join(folder, entries[cand])):
                    path = os.path.join(folder, entries[cand])
                    shown = os.path.join(os.path.dirname(caller_file), entries[cand]) if folder == folders[0] else path
                    try:
                        with open(path, "rb") as fh:
                            text = decode_program(fh.read(), shown)
                    except OSError as exc:
                        raise AlarmError(
                            alarm(14011, f"program {name}: cannot read {shown}: {exc.strerror}", span)
                        ) from None
                    except TrcoptError as exc:
                        raise fail(Code.NC_NOT_TEXT, exc.message, span) from None
                    program = self.scan(text, shown, name, self.known_words)  # type: ignore[attr-defined]
                    self._programs[name] = program
                    return program
        looked = ", ".join(folders) or "(no folder)"
        raise AlarmError(
            alarm(
                14011,
                f"program {name} not found: looked for {name}.spf, {name}.mpf (any letter case) in {looked}"
                + (
                    " (of the standard cycles trcopt expands CYCLE81…CYCLE83 and records CYCLE832)"
                    if name.startswith(("CYCLE", "POCKET", "SLOT", "LONGHOLE", "HOLES"))
                    else ""
                ),
                span,
            )
        )
