"""SINUMERIK program branch ``CASE`` and the subprogram calls ``CALL`` and ``PCALL`` (Programming
Manual Job Planning, "Program branch", "Indirect subprogram call", "Subprogram call with path
specification and parameters"): their text read into what the runner executes.

* ``CASE(<expression>) OF <constant> GOTOF <label> … [DEFAULT GOTOF <label>]`` — the expression is
  compared with the INT (or CHAR, ``"A"``) constants in order; the first equal one jumps to its
  destination (``GOTOF``, ``GOTOB``, ``GOTO``, ``GOTOC`` as in a jump block); none equal: the
  ``DEFAULT`` destination, or without DEFAULT the block after the CASE block. A missing destination
  is alarm 14080 (the runner's jump).
* ``CALL "<name>"`` — the indirect call of the program named by a string: trcopt reads a string
  literal (STRING variables and string operations are not modelled: ``NC-UNSUPPORTED`` naming
  them). ``CALL BLOCK … TO …`` (a program section) is not modelled either.
* ``PCALL <path>/<name>(<arguments>)`` — a call with the program's path: trcopt calls ``<name>``
  (``_N_NAME_SPF`` read as ``NAME``) and looks for it as for any call, beside the calling program
  and the main program; the path itself is not a folder of this computer.

Errors are raised located (:func:`trcopt.nc.modal.fail`); nothing is evaluated here.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from trcopt.codes import Code
from trcopt.errors import AlarmError, SourceSpan
from trcopt.nc.modal import fail

__all__ = ["CaseBranch", "CASE_LINE", "CALL_LINE", "parse_case", "call_text"]

#: a CASE block (after block number and label)
CASE_LINE = re.compile(r"CASE(?![A-Z0-9_$])[ \t]*\(", re.I)
#: an indirect call or a call with a path (after block number and label)
CALL_LINE = re.compile(r"(?P<kw>CALL|PCALL)(?![A-Z0-9_$])[ \t]*(?P<rest>.*)\Z", re.I | re.S)
_CHOICE = re.compile(
    r"[ \t]*(?:(?P<default>DEFAULT)|(?P<const>[+-]?\d+|\"[^\"]\"|'[^']'))[ \t]+"
    r"(?P<kw>GOTOF|GOTOB|GOTOC|GOTO)[ \t]+(?P<target>[A-Z_0-9]+)(?![A-Z0-9_])",
    re.I,
)
_OF = re.compile(r"[ \t]*OF(?![A-Z0-9_])", re.I)
_LITERAL = re.compile(r"\"(?P<name>[^\"]*)\"[ \t]*\Z")
_PROGRAM = re.compile(r"(?:_N_)?(?P<name>[A-Z_][A-Z0-9_]*?)(?:_SPF|_MPF)?\Z", re.I)
_PATH_CALL = re.compile(r"(?P<path>[^( \t]+)[ \t]*(?P<args>\(.*\))?[ \t]*\Z", re.S)


@dataclass(frozen=True, slots=True)
class CaseBranch:
    """A read CASE block: the expression (text and 1-based column), the choices
    ``(constant, keyword, destination, column)`` in order, and the DEFAULT choice (or None)."""

    expression: str
    column: int
    choices: tuple[tuple[float, str, str, int], ...]
    default: tuple[str, str, int] | None


def parse_case(text: str, column: int, span: SourceSpan) -> CaseBranch:
    """Read ``text`` (``CASE(…) OF …``, starting at ``column`` of the line)."""
    open_at = text.index("(")
    depth, close = 0, -1
    for i in range(open_at, len(text)):
        if text[i] == "(":
            depth += 1
        elif text[i] == ")":
            depth -= 1
            if depth == 0:
                close = i
                break
    if close < 0:
        raise _syntax("CASE: unbalanced bracket '(' around the expression", span, column + open_at)
    expression = text[open_at + 1 : close]
    if not expression.strip():
        raise _syntax("CASE without an expression", span, column + open_at)
    of = _OF.match(text, close + 1)
    if of is None:
        raise _syntax("CASE(…) needs OF after the expression", span, column + close + 1)
    pos = of.end()
    choices: list[tuple[float, str, str, int]] = []
    default: tuple[str, str, int] | None = None
    while text[pos:].strip():
        m = _CHOICE.match(text, pos)
        at = column + pos + len(text[pos:]) - len(text[pos:].lstrip())
        if m is None:
            raise _syntax(
                "CASE: expected '<constant> GOTOF <label>' or 'DEFAULT GOTOF <label>' (constants INT or CHAR)",
                span,
                at,
            )
        if default is not None:
            raise _syntax("CASE: DEFAULT must be the last choice", span, at)
        kw, target, kw_column = m.group("kw").upper(), m.group("target").upper(), column + m.start("kw")
        if m.group("default"):
            default = (kw, target, kw_column)
        else:
            const = m.group("const")
            value = float(ord(const[1])) if const[0] in "\"'" else float(int(const))
            choices.append((value, kw, target, kw_column))
        pos = m.end()
    if not choices and default is None:
        raise _syntax("CASE(…) OF without a choice", span, column + of.end())
    return CaseBranch(expression, column + open_at + 1, tuple(choices), default)


def call_text(kw: str, rest: str, span: SourceSpan) -> str:
    """The call ``CALL "NAME"`` / ``PCALL path/NAME(args)`` makes, as a plain call ``NAME(args)``."""
    rest = rest.strip()
    if kw.upper() == "CALL":
        m = _LITERAL.match(rest)
        if m is None:
            what = "CALL BLOCK (a program section)" if rest.upper().startswith("BLOCK") else (
                f"CALL {rest or '…'} (an indirect call through a STRING expression)"
            )
            raise fail(Code.NC_UNSUPPORTED, f"{what} is not modelled by trcopt; write CALL \"NAME\" or NAME", span)
        name = m.group("name").strip()
        if _PROGRAM.match(name) is None:
            raise _syntax(f"CALL \"{name}\": not a program name", span, span.column)
        return _program_name(name)
    m = _PATH_CALL.match(rest)
    if m is None or not m.group("path"):
        raise _syntax("PCALL needs a program name (with or without its path)", span, span.column)
    last = re.split(r"[/\\]", m.group("path"))[-1]
    if _PROGRAM.match(last) is None:
        raise _syntax(f"PCALL {m.group('path')}: not a program name", span, span.column)
    return _program_name(last) + (m.group("args") or "")


def _program_name(text: str) -> str:
    m = _PROGRAM.match(text)
    assert m is not None
    return m.group("name").upper()


def _syntax(message: str, span: SourceSpan, column: int) -> AlarmError:
    return fail(Code.NC_SYNTAX, message, SourceSpan(span.file, span.line, column, span.block))
