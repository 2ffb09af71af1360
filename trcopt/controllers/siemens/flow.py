"""SINUMERIK program structure: what each line of a program is, before it runs.

:func:`scan` splits a program text into :class:`Statement` values and matches the control
structures (Programming Manual Job Planning, "Program flow control" / "Control structures"):

* ``IF cond`` … [``ELSE`` …] ``ENDIF``; ``WHILE cond`` … ``ENDWHILE``; ``FOR var = a TO b`` …
  ``ENDFOR``; ``REPEAT`` … ``UNTIL cond``; ``LOOP`` … ``ENDLOOP`` — each keyword alone in its
  block (with a block number or label); wrong nesting is alarm 12640;
* jumps ``GOTOF``/``GOTOB``/``GOTO``/``GOTOC`` to a label or block number, at the end of a block,
  with or without ``IF cond`` before them;
* program section repetition ``REPEAT l1 [l2] P=n``, ``REPEATB l P=n`` (``ENDLABEL:`` ends a
  section);
* the program branch ``CASE(expr) OF c GOTOF l … DEFAULT GOTOF l`` (``case``, read by
  :mod:`~trcopt.controllers.siemens.branch` when it runs);
* subprogram calls (a name alone in its block, with ``(arguments)`` and ``P=n``, ``L123 P2``;
  ``CALL "NAME"`` and ``PCALL path/NAME(args)``: ``indirect``), ``PROC`` and ``EXTERN``, ``MCALL``;
* ``DEF`` lines and ordinary blocks (lexed here; a lexing error is raised when the block runs).

Nothing here evaluates or runs; :mod:`trcopt.controllers.siemens.runner` does.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

from trcopt.controllers.siemens.branch import CALL_LINE, CASE_LINE
from trcopt.controllers.siemens.lexer import _FAST_LINE, _PREFIX, LexedBlock, LexError, lex_line
from trcopt.controllers.siemens.variables import DEF_LINE
from trcopt.errors import AlarmError, SourceSpan, alarm
from trcopt.nc.text import program_lines

__all__ = ["Statement", "Program", "scan", "match_structures", "strip_comment"]

_STRUCT = re.compile(
    r"(?P<kw>IF|ELSE|ENDIF|WHILE|ENDWHILE|FOR|ENDFOR|REPEATB|REPEAT|UNTIL|LOOP|ENDLOOP|PROC|EXTERN|MCALL)"
    r"(?![A-Z0-9_$])[ \t]*(?P<rest>.*)\Z",
    re.I | re.S,
)
_JUMP = re.compile(
    r"(?P<pre>.*?)(?:(?<![A-Z0-9_$])IF(?![A-Z0-9_])(?P<cond>.*?))?(?<![A-Z0-9_$])(?P<kw>GOTOF|GOTOB|GOTOC|GOTO)"
    r"[ \t]+(?P<target>[A-Z_0-9]+)[ \t]*\Z",
    re.I | re.S,
)
_FOR = re.compile(
    r"(?P<var>[A-Z_][A-Z0-9_]*(?:[ \t]*\[[^\]]*\])?)[ \t]*=(?P<start>.+?)[ \t]+TO[ \t]+(?P<end>.+)\Z", re.I | re.S
)
_SECTION = re.compile(
    r"(?P<a>[A-Z_][A-Z0-9_]*)(?:[ \t]+(?P<b>(?!P[ \t]*=)[A-Z_][A-Z0-9_]*))?(?:[ \t]+P[ \t]*=[ \t]*(?P<p>.+))?\Z",
    re.I | re.S,
)
_CALL = re.compile(
    r"(?P<name>[A-Z_][A-Z0-9_]*)[ \t]*(?:\((?P<args>.*)\))?(?:[ \t]*P[ \t]*=?[ \t]*(?P<p>[^ \t]+))?[ \t]*\Z",
    re.I | re.S,
)
_ADDRESS = re.compile(r"[A-Z]\d*(?:\.\d*)?\Z", re.I)  # M30, G0, X10: words, not program names
_STRUCT_PAIRS = {
    "ENDIF": "IF",
    "ELSE": "IF",
    "ENDWHILE": "WHILE",
    "ENDFOR": "FOR",
    "UNTIL": "REPEAT",
    "ENDLOOP": "LOOP",
}
_OPENERS = {"IF": "ENDIF", "WHILE": "ENDWHILE", "FOR": "ENDFOR", "REPEAT": "UNTIL", "LOOP": "ENDLOOP"}


@dataclass(slots=True)
class Statement:
    """One line of a program.

    ``kind``: ``block`` (``lexed``, or ``error``), ``def``, ``empty``, a structure keyword in lower
    case (``if``, ``else``, ``endif``, ``while``, ``endwhile``, ``for``, ``endfor``, ``repeat``,
    ``until``, ``loop``, ``endloop``), ``section`` (``REPEAT l P=n``/``REPEATB``), ``call``,
    ``indirect`` (``CALL``/``PCALL``), ``case``, ``proc``, ``extern``, ``mcall``. A block may end
    in a jump (``jump`` = (keyword, target, condition or None, column)). ``partner``: the index of
    the matching structure keyword (IF → ELSE or ENDIF, ELSE → ENDIF, loop start ↔ loop end).
    """

    index: int
    lineno: int
    text: str
    number: str | None
    label: str | None
    kind: str
    column: int  # 1-based column of the statement (after block number and label)
    rest: str = ""  # the text after the keyword (condition, arguments …)
    rest_column: int = 0
    lexed: LexedBlock | None = None
    error: LexError | None = None
    jump: tuple[str, str, str | None, int] | None = None
    partner: int = -1
    skip: bool = False

    def span(self, file: str, column: int | None = None) -> SourceSpan:
        return SourceSpan(file, self.lineno, self.column if column is None else column, self.number)


@dataclass(slots=True)
class Program:
    """A scanned program file: its statements, labels and block numbers (a list and dicts, or,
    for a program read block by block, sequences that make them when asked for:
    :mod:`trcopt.controllers.siemens.lazyscan`)."""

    file: str
    name: str
    statements: Sequence[Statement]
    labels: dict[str, list[int]] = field(default_factory=dict)  # label → its statements' indices
    numbers: Mapping[str, list[int]] = field(default_factory=dict)  # "N100" → indices


def strip_comment(text: str) -> str:
    """``text`` up to its comment (a ``;`` outside a string)."""
    quoted = False
    for i, ch in enumerate(text):
        if ch == '"':
            quoted = not quoted
        elif ch == ";" and not quoted:
            return text[:i]
    return text


def _is_call(name: str, args: str | None, known: frozenset[str]) -> bool:
    upper = name.upper()
    if upper in known:
        return False
    if _ADDRESS.match(upper):
        return upper[0] == "L" and len(upper) > 1  # L123: a program number
    return True


def scan(text: str, file: str, name: str, known: frozenset[str]) -> Program:
    """Scan a program (see the module docstring); ``known``: the names that are words, not calls.
    Raises :class:`AlarmError` for a control structure that does not close (alarm 12640)."""
    statements = [_statement(i, lineno, line, known) for i, (lineno, line) in enumerate(
        enumerate(program_lines(text), 1))]
    labels, partners = match_structures(statements, file)
    for index, partner in partners.items():
        statements[index].partner = partner
    numbers: dict[str, list[int]] = {}
    for st in statements:
        if st.number is not None:
            numbers.setdefault(st.number, []).append(st.index)
    return Program(file, name, statements, labels, numbers)


def match_structures(statements: Iterable[Statement], file: str) -> tuple[dict[str, list[int]], dict[int, int]]:
    """The labels (label → its statements' indices) and the partners of the structure keywords
    (index → index of the matching keyword, as :attr:`Statement.partner`) of ``statements`` in
    program order — every statement with a label or a structure keyword, others may be left out.
    Raises :class:`AlarmError` for a control structure that does not close (alarm 12640)."""
    labels: dict[str, list[int]] = {}
    partners: dict[int, int] = {}
    stack: list[Statement] = []
    for st in statements:
        if st.label is not None:
            labels.setdefault(st.label.upper(), []).append(st.index)
        kw = st.kind.upper()
        if kw in _OPENERS:
            stack.append(st)
        elif kw in _STRUCT_PAIRS:
            opener = stack[-1] if stack else None
            second_else = kw == "ELSE" and opener is not None and opener.index in partners
            if opener is None or opener.kind.upper() != _STRUCT_PAIRS[kw] or second_else:
                what = "a second ELSE" if opener is not None and kw == "ELSE" and opener.kind == "if" else kw
                raise AlarmError(
                    alarm(
                        12640,
                        f"invalid nesting of control structures: {what} without its {_STRUCT_PAIRS[kw]}",
                        st.span(file),
                    )
                )
            if kw == "ELSE":
                partners[opener.index] = st.index  # IF → ELSE; the IF stays open until ENDIF
                continue
            stack.pop()
            if kw == "ENDIF" and opener.index in partners:
                partners[partners[opener.index]] = st.index  # ELSE → ENDIF
            else:
                partners[opener.index] = st.index
            partners[st.index] = opener.index
    if stack:
        st = stack[-1]
        kw = st.kind.upper()
        raise AlarmError(
            alarm(12640, f"invalid nesting of control structures: {kw} without its {_OPENERS[kw]}", st.span(file))
        )
    return labels, partners


def _statement(index: int, lineno: int, line: str, known: frozenset[str]) -> Statement:
    if _FAST_LINE.match(line) is not None:  # only address letters and numbers: an ordinary block
        lexed = lex_line(line)
        if not lexed.words or lexed.words[0].name != "L":  # L123: a subprogram call
            kind = "block" if lexed.words else "empty"
            return Statement(
                index, lineno, line, lexed.number, None, kind, lexed.first_column, lexed=lexed, skip=lexed.skip
            )
    pm = _PREFIX.match(line)
    assert pm is not None
    number = None if pm.group("n") is None else "N" + str(int(pm.group("nnum")))
    label = pm.group("label")
    body = strip_comment(line[pm.end() :])
    lead = len(body) - len(body.lstrip(" \t"))
    column = pm.end() + lead + 1
    body = body.strip()
    st = Statement(index, lineno, line, number, label, "block", column, skip=pm.group("skip") is not None)
    if DEF_LINE.match(line) and not label:
        st.kind = "def"
        return st
    if not body:
        st.kind = "empty" if label is None else "block"
        if label is not None:
            st.lexed = LexedBlock(st.skip, number, [], column, None, label)
        return st
    if CASE_LINE.match(body) is not None:
        st.kind, st.rest, st.rest_column = "case", body, column
        return st
    c = CALL_LINE.match(body)
    if c is not None:
        st.kind, st.rest, st.rest_column = "indirect", body, column
        return st
    m = _STRUCT.match(body)
    if m is not None:
        kw = m.group("kw").upper()
        rest = m.group("rest").strip()
        st.rest, st.rest_column = rest, column + m.start("rest")
        if kw == "IF" and _JUMP.match(body):
            pass  # IF cond GOTOx: a conditional jump (below)
        elif kw in ("REPEAT", "REPEATB") and rest:
            st.kind = "section"
            st.rest = kw + " " + rest
            return st
        else:
            st.kind = kw.lower()
            return st
    j = _JUMP.match(body)
    if j is not None:
        pre = j.group("pre")
        cond = j.group("cond")
        st.jump = (
            j.group("kw").upper(),
            j.group("target").upper(),
            None if cond is None else cond.strip(),
            column + j.start("kw"),
        )
        if cond is not None:
            st.rest_column = column + j.start("cond") + len(cond) - len(cond.lstrip())
        body_text = line[: pm.end()] + " " * (column - 1 - pm.end()) + pre if pre.strip() else ""
        _lex(st, body_text if body_text else None, label, number)
        return st
    c = _CALL.match(body)
    if c is not None and _is_call(c.group("name"), c.group("args"), known):
        st.kind = "call"
        st.rest = body
        return st
    _lex(st, line, label, number)
    return st


def _lex(st: Statement, line: str | None, label: str | None, number: str | None) -> None:
    if line is None:
        st.lexed = LexedBlock(st.skip, number, [], st.column, None, label)
        return
    try:
        st.lexed = lex_line(line)
    except LexError as exc:
        st.error = exc
