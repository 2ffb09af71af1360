"""Heidenhain Klartext lexer: one block per line → block number, statement and words with columns.

Lexical rules (spec ``heidenhain_trc.md`` §2): tokens are separated by blanks, a number is glued
to its address letter (``X+10``, ``IY-5``, ``LEN15``, ``CCA90``, ``R+20``, ``DR-0.05``); the literal
``R0`` means "no compensation" (a zero radius is ``R+0``), a bare ``R+``/``R-`` is paraxial
compensation, a bare ``DR+``/``DR-`` is the direction of rotation. ``;`` starts a comment, a line
starting with ``*`` is a structure (comment) block. The Unicode minus ``−`` is read as ``-``.

Q parameters: with a ``resolve`` function, an address followed by a (signed) Q parameter —
``X+Q1``, ``IY-Q2``, ``FQ5``, ``R Q5``, ``LEN Q3`` — is a word with the parameter's value (negated
for ``-``), and a bare ``Q4`` (``CHF Q4``) a bare number. ``FN``, ``Q… =``, ``LBL`` and ``CALL``
blocks get their statement here; the reader reads their text (``Block.source``) itself.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass

__all__ = ["Word", "Block", "lex_block", "STATEMENTS"]

# statements that take a second keyword
_TWO_WORD = {
    "BEGIN": ("PGM",),
    "END": ("PGM",),
    "TOOL": ("DEF", "CALL"),
    "BLK": ("FORM",),
    "PGM": ("CALL",),
    "CYCL": ("DEF", "CALL"),
    "CALL": ("LBL", "PGM"),
    "APPR": ("LT", "LN", "CT", "LCT", "PLT", "PLN", "PCT", "PLCT"),
    "DEP": ("LT", "LN", "CT", "LCT", "PLT", "PLN", "PCT", "PLCT"),
}
STATEMENTS = frozenset(
    {"L", "LP", "C", "CC", "CR", "CT", "CP", "CTP", "RND", "CHF", "STOP", "CYCL DEF", "FN", "Q", "LBL"} | set(_TWO_WORD)
)

_NUMBER = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)"
# longest addresses first: the regex alternation takes the first that matches
_ADDRESSES = (
    "IROT", "ROT", "SCL", "CCX", "CCY", "CCZ",
    "IPA", "IPR", "PA", "PR", "LEN", "LA", "CCA", "DR2", "DL2", "DR", "DL",
    "IX", "IY", "IZ", "IA", "IB", "IC", "X", "Y", "Z", "A", "B", "C", "R", "FU", "FZ", "F", "S", "M", "L",
)  # fmt: skip
_NUM = re.compile(_NUMBER)
_WORD = re.compile(rf"^({'|'.join(_ADDRESSES)})({_NUMBER})$")
_Q_WORD = re.compile(rf"^({'|'.join(_ADDRESSES)})?([+-]?)(Q[LR]?\d+)$")
_FLAGS = {"RL", "RR", "R0", "R+", "R-", "DR+", "DR-", "FMAX", "FAUTO", "MM", "INCH"}


@dataclass(frozen=True, slots=True)
class Word:
    """One token: ``address`` (``X``, ``IPA``, ``RL``, ``DR+``, ``FMAX`` …, or ``""`` for a bare
    token such as a tool number, axis or name), ``value`` (None for flags/bare) and 1-based column."""

    address: str
    value: float | None
    text: str
    column: int


@dataclass(frozen=True, slots=True)
class Block:
    """A lexed line: block number text (``"15"``), statement (``"L"``, ``"APPR LCT"`` …, ``""`` for
    a comment or empty line), its column and the words after it."""

    line: int
    number: str | None
    statement: str
    column: int
    words: tuple[Word, ...]
    comment: str = ""
    source: str = ""  # the line without its comment (columns as in the file)


def _tokens(text: str) -> list[tuple[str, int]]:
    return [(m.group(0), m.start() + 1) for m in re.finditer(r"\"[^\"]*\"|'[^']*'|\S+", text)]


def lex_block(text: str, line: int, resolve: Callable[[str, int], float] | None = None) -> Block:
    """Split one program line into a :class:`Block` (never raises but through ``resolve``, the
    value of a Q parameter at a column; unknown tokens become bare words with ``address == "?"``
    for the reader to reject with their column)."""
    text = text.replace("\u2212", "-").rstrip("\r\n")
    comment = ""
    cut = text.find(";")
    if cut >= 0:
        text, comment = text[:cut], text[cut + 1 :].strip()
    toks = _tokens(text)
    number = None
    if toks and toks[0][0].isdigit():
        number = toks.pop(0)[0]
    if not toks or toks[0][0].startswith("*"):
        return Block(line, number, "", toks[0][1] if toks else 1, (), comment, text)
    head, column = toks.pop(0)
    statement = head.upper()
    if re.fullmatch(r"FN\s*\d*:?", statement):
        statement = "FN"
    elif re.fullmatch(r"Q[LRS]?\d+=?", statement):
        statement = "Q"
    if statement in _TWO_WORD and toks and toks[0][0].upper() in _TWO_WORD[statement]:
        statement += " " + toks.pop(0)[0].upper()
    words = []
    merged: list[tuple[str, int]] = []
    for tok, col in toks:
        # "F MAX" / "F AUTO", as the TNC 426/430 manual's example programs write it, is FMAX / FAUTO
        if merged and merged[-1][0].upper() == "F" and tok.upper() in ("MAX", "AUTO"):
            merged[-1] = (merged[-1][0] + " " + tok, merged[-1][1])
            continue
        # "R Q5", "F Q5", "SCL 0.75", "LA 5": an address and its value written apart
        if merged and merged[-1][0].upper() in _ADDRESSES and (
            re.fullmatch(r"[+-]?Q[LR]?\d+", tok, re.I)
            or (merged[-1][0].upper() in ("SCL", "LA") and _NUM.fullmatch(tok))
        ):
            merged[-1] = (merged[-1][0] + tok, merged[-1][1])
            continue
        merged.append((tok, col))
    for tok, col in merged:
        up = tok.upper().replace(" ", "")
        if up in _FLAGS:
            words.append(Word(up, None, tok, col))
            continue
        q = _Q_WORD.match(up) if resolve is not None else None
        if q and resolve is not None:
            value = resolve(q.group(3), col + len(tok) - len(q.group(3)))
            value = -value if q.group(2) == "-" else value
            words.append(Word(q.group(1) or "", value, tok if q.group(1) else repr(value), col))
            continue
        m = _WORD.match(up)
        if m:
            words.append(Word(m.group(1), float(m.group(2)), tok, col))
        elif re.fullmatch(r"\d+(?:\.\d*)?|\"[^\"]*\"|'[^']*'|[A-Z_][A-Z0-9_.]*", up):
            words.append(Word("", None, tok, col))
        else:
            words.append(Word("?", None, tok, col))
    return Block(line, number, statement, column, tuple(words), comment, text)
