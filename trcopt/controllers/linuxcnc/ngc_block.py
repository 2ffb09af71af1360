"""One RS274NGC line as LinuxCNC reads it: the block number, then either an O-word control line
or words and parameter settings.

:func:`read_words` evaluates every word's value (``X#1``, ``F[#2*2]``, ``G[1]``) with the
parameter values from before the line; the line's parameter settings (``#1=…``, ``#<a>=…``) are
returned apart, for the caller to apply after the whole line is read — LinuxCNC's order, so that
``#1=5 G1 X#1`` moves to the old ``#1``. :func:`read_oword` reads the label and the command of an
O-line; its expressions are read later (:class:`~trcopt.controllers.linuxcnc.ngc_expr.ValueReader`
at ``OLine.rest``), and only when LinuxCNC reads them (not while it skips).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from trcopt.codes import Code
from trcopt.controllers.linuxcnc.ngc_expr import NgcError, NgcLine, Parameters, ValueReader, read_integer

__all__ = ["Block", "OLine", "O_COMMANDS", "block_number", "read_oword", "read_words", "read_words_general"]

# in LinuxCNC's order of trial ("do" before "while", "if" before "elseif", "else" before "endif")
O_COMMANDS = (
    "sub", "endsub", "call", "do", "while", "repeat", "if", "elseif", "else", "endif",
    "break", "continue", "endwhile", "endrepeat", "return",
)  # fmt: skip
# letters LinuxCNC reads as words (others: "Unknown word starting with …" / bad character)
_LETTERS = set("abcdfghijklmnpqrstuvwxyz")
# a word made of one of those letters and a plain decimal number (what ValueReader.value reads
# without an expression, parameter, function or unary sign of its own)
_PLAIN = r"[abcdfghijklmnpqrstuvwxyz][+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)"
_PLAIN_WORD = re.compile(_PLAIN)
_PLAIN_LINE = re.compile(f"(?:{_PLAIN})*")


@dataclass(slots=True)
class Block:
    """The words of a line (``(LETTER, value, column)``) and its parameter settings."""

    words: list[tuple[str, float, int]]
    settings: list[tuple[int | str, float]]
    comment: str | None = None  # the line's last ( ) comment (messages: MSG, DEBUG, PRINT, ABORT)


@dataclass(slots=True)
class OLine:
    """An O-line: its label (``"100"`` or ``"name"``), command and where its arguments start."""

    label: str
    command: str
    rest: int  # index in the normalised line after the command word
    at: int  # index of the 'o'


def block_number(line: NgcLine) -> tuple[int | None, int]:
    """The ``N`` number at the start of the line and the index after it."""
    text = line.text
    if not text.startswith("n"):
        return None, 0
    j = 1
    while j < len(text) and text[j].isdigit():
        j += 1
    if j == 1:
        raise NgcError("Bad format line number", 0, Code.NC_SYNTAX)
    return int(text[1:j]), j


def read_oword(line: NgcLine, start: int, params: Parameters) -> OLine:
    """The O-word at ``start`` (``o<name> …`` or ``o100 …``; the number may be an expression)."""
    text = line.text
    reader = ValueReader(text, params, start + 1)
    if text.startswith("<", start + 1):
        label = reader.name()
    else:
        label = str(read_integer(reader.value(), start))
    j = reader.pos
    for command in O_COMMANDS:
        if text.startswith(command, j):
            return OLine(label, command, j + len(command), start)
    if j == len(text) and not text.startswith("<", start + 1):
        return OLine(label, "", j, start)  # a Fanuc-style program number (called by M98)
    raise NgcError("Unknown control command in o word", j, Code.LCNC_OWORD)


def read_words(line: NgcLine, start: int, params: Parameters) -> Block:
    """Words and parameter settings of a (non-O) line from ``start``; values are evaluated. A
    line made only of letters with plain numbers (``g1x1.5y-.2``) is read in one pass; every
    other line (parameters, expressions, functions, signs before brackets, errors) word by word
    (:func:`read_words_general`), with the same words, values and columns."""
    if _PLAIN_LINE.fullmatch(line.text, start) is not None:
        fast = _plain_words(line, start)
        if fast is not None:
            return Block(fast, [], line.comment)
    return read_words_general(line, start, params)


def read_words_general(line: NgcLine, start: int, params: Parameters) -> Block:
    """:func:`read_words` one word at a time (every line; the fast path's reference)."""
    text = line.text
    reader = ValueReader(text, params, start)
    cols, n_cols = line.cols, len(line.cols)
    words: list[tuple[str, float, int]] = []
    settings: list[tuple[int | str, float]] = []
    while reader.pos < len(text):
        at = reader.pos
        c = text[at]
        if c == "#":
            reader.pos += 1
            key: int | str
            if text.startswith("<", reader.pos):
                key = reader.name()
                if params.get_named(key) is None:
                    params.set_named(key, 0.0)  # LinuxCNC makes it when it reads the setting
            else:
                key = read_integer(reader.value(), at)
                params.check_index(key, at)
            if not text.startswith("=", reader.pos):
                raise NgcError("Equal sign missing in parameter setting", reader.pos, Code.NC_SYNTAX)
            reader.pos += 1
            settings.append((key, reader.value()))
        elif c in _LETTERS:
            reader.pos += 1
            words.append((c.upper(), reader.value(), cols[at] if at < n_cols else line.col(at)))
        elif c.isalpha():
            words.append((c.upper(), 0.0, line.col(at)))  # the caller names the unsupported word
            reader.pos += 1
            break
        else:
            raise NgcError(f"Bad character '{c}' used", at, Code.NC_SYNTAX)
    return Block(words, settings, line.comment)


def _plain_words(line: NgcLine, start: int) -> list[tuple[str, float, int]] | None:
    """The words of a line from ``start`` that is only letters with plain numbers, as
    :func:`read_words` reads them; None when a value is infinite (read_words then raises)."""
    cols = line.cols
    words: list[tuple[str, float, int]] = []
    at = start  # the words follow one another without a gap (the whole line matched _PLAIN_LINE)
    for word in _PLAIN_WORD.findall(line.text, start):
        v = float(word[1:])
        if math.isinf(v):
            return None
        words.append((word[0].upper(), v, cols[at]))
        at += len(word)
    return words
