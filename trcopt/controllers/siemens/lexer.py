"""Word lexer for address-style NC blocks (SINUMERIK syntax) with exact 1-based source columns.

A block is one line. The lexer splits it into an optional block-skip mark (``/``), an optional
block number (``N60`` or ``:60``), an optional jump label (``MARK1:``) and a list of :class:`Word`
values. It knows nothing about what the words mean; the dialect does. One compiled regular
expression drives the scan, so a block costs a handful of regex matches and no per-character
Python loop.

Word forms recognised (case-insensitive)::

    G1  X-10.5  X.5  M30            address letters + number (words may touch: G1X10Y20)
    Z=0  X=AC(10)  DISCL=AC(5)      name '=' value; value: number, MODE(number), "string",
    FAD=PM(200)  CR=-20  X=10+2*3   or a constant arithmetic expression
    FAD 500                         a bare number after a value-less word belongs to it
    NORM  CDOF2  CUT2D  TCOFRZ      keywords (no value)
    MSG("text")                     call form, kept verbatim
    $TC_DP6[1,1]=10  $TC_CARR23[1]="T"   system-variable assignment (subscript kept as text)

Malformed input raises :class:`LexError` carrying the message and the column of the word.
"""

from __future__ import annotations

import ast
import operator
import re
from typing import NamedTuple

__all__ = ["Word", "LexedBlock", "LexError", "Expr", "lex_line", "parse_number"]


class LexError(ValueError):
    """A syntax error inside one block; ``column`` is the 1-based column of the offending word."""

    def __init__(self, message: str, column: int, block: str | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.column = column
        self.block = block


class Expr(str):
    """A value the lexer could not reduce to a constant (uses variables such as ``R1``)."""

    __slots__ = ()


class Word(NamedTuple):
    """One NC word.

    ``name`` is upper case (``"G"``, ``"X"``, ``"DISCL"``, ``"$TC_DP6"``, ``"MSG"``). ``value`` is
    ``None`` (keyword), a ``float``, a ``str`` (quoted string, quotes removed), an :class:`Expr`, or
    ``(mode, float)`` for ``AC(..)``/``IC(..)``/``PM(..)``/``PR(..)`` and similar. ``subscript`` is
    the bracket content of a system variable (``"1,1"``) or the argument text of a call form.
    ``assigned`` tells whether the word was written with ``=``.
    """

    name: str
    value: object
    column: int
    text: str
    subscript: str | None = None
    assigned: bool = False


class LexedBlock(NamedTuple):
    """One lexed line: skip mark, block number (``"N60"``), label, words, and the comment text."""

    skip: bool
    number: str | None
    words: list[Word]
    first_column: int
    comment: str | None
    label: str | None = None


_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)\Z")

# keywords that contain digits and would otherwise split into address + number
_DIGIT_KEYWORDS = "CUT2DF|CUT2D|CUT3DCCD|CUT3DCC|CUT3DC|CUT3DFF|CUT3DFS|CUT3DF|CDOF2"

_TOKEN = re.compile(
    r"""
     (?P<ws>[ \t\r\f\v]+)
    |(?P<comment>;.*)
    |(?P<sys>\$[A-Z_][A-Z0-9_]*)
    |(?P<arr>[A-Z_][A-Z0-9_]*)(?=[ \t]*\[)
    |(?P<call>[A-Z_][A-Z0-9_]*)(?=\()
    |(?P<kw>(?:"""
    + _DIGIT_KEYWORDS
    + r"""))(?![A-Z0-9_.])
    |(?P<name>[A-Z_]{2}[A-Z0-9_]*|[A-Z_]+[0-9]*)[ \t]*=(?!=)[ \t]*
    |(?P<addr>[A-Z_]+)(?P<num>[-+]?[0-9.]*)
    |(?P<bare>[-+]?[0-9.]+)
    |(?P<bad>.)
    """,
    re.I | re.X,
)

# fast path: plain numbers of at most 15 + 15 digits (longer ones take the checked slow path)
_FAST_NUM = r"[-+]?(?:\d{1,15}(?:\.\d{0,15})?|\.\d{1,15})"
_FAST_WORD = re.compile(r"([ \t]*)([A-Z])(" + _FAST_NUM + ")", re.I)
_FAST_LINE = re.compile(
    r"[ \t]*(/[0-9]?)?[ \t]*(?:[N:](\d+)(?![0-9.]))?"
    r"((?:[ \t]*[A-Z]" + _FAST_NUM + r"(?![0-9.=]))*)[ \t]*(?:;(.*))?\Z",
    re.I,
)
_MAX_NUMBER = 1e15
_PREFIX = re.compile(  # leading white space as _TOKEN's (a form feed before N50 is white space)
    r"[ \t\r\f\v]*(?P<skip>/[0-9]?)?[ \t]*(?:(?P<n>[N:])(?P<nnum>\d+)(?![0-9.]))?[ \t]*"
    r"(?:(?P<label>[A-Z_][A-Z0-9_]*):(?!=))?",
    re.I,
)
_INDEX = re.compile(r"\[(?P<idx>[^\[\]\n]*)\](?P<eq>[ \t]*=[ \t]*)?")
_STRING = re.compile(r'"(?P<s>[^"\n]*)"')
_CALL = re.compile(r'\((?:"[^"\n]*"|[^()"\n]|\([^()\n]*\))*\)')
_MODE = re.compile(r"(?P<mode>[A-Z]{2,3})\((?P<inner>.*)\)\Z", re.I | re.S)
_CONST_EXPR = re.compile(r"[-+*/0-9. ()\t]+\Z")
_EXPR_HINT = re.compile(r"[A-Z_$<>=\[]", re.I)  # text the expression evaluator reads
#: position modes written ``X=AC(..)``, feed modes ``FAD=PM(..)``; any other NAME(..) is a function
_MODES = {"AC", "IC", "DC", "ACP", "ACN", "PM", "PR", "CAC", "CIC", "CDC", "CACP", "CACN"}
_VALUE_OPS = re.compile(
    r"[ \t]*(?:==|<>|<=|>=|[-+*/<>]|(?:DIV|MOD|AND|OR|XOR|B_AND|B_OR|B_XOR)(?![A-Z0-9_]))", re.I
)
_OPEN_END = re.compile(r"(?:[-+*/<>=(\[,]|(?<![A-Z0-9_])(?:DIV|MOD|AND|OR|XOR|NOT|B_AND|B_OR|B_XOR|B_NOT))\Z", re.I)

_BINOPS = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
}


def _eval_const(node: ast.AST) -> float:
    if isinstance(node, ast.Expression):
        return _eval_const(node.body)
    if isinstance(node, ast.Constant) and isinstance(node.value, int | float):
        return float(node.value)
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub | ast.UAdd):
        v = _eval_const(node.operand)
        return -v if isinstance(node.op, ast.USub) else v
    if isinstance(node, ast.BinOp) and type(node.op) in _BINOPS:
        return _BINOPS[type(node.op)](_eval_const(node.left), _eval_const(node.right))
    raise ValueError("not a constant expression")


def _checked(value: float, text: str) -> float:
    if not abs(value) < _MAX_NUMBER:  # also catches inf and nan
        raise ValueError(f"number {text!r} out of range")
    return value


def parse_number(text: str) -> float | Expr:
    """A number or constant arithmetic expression → float; text with variables → :class:`Expr`.

    Raises ``ValueError`` for malformed numbers (``1.2.3``), malformed expressions and numbers
    whose magnitude reaches 1e15.
    """
    if _NUMBER.match(text):
        return _checked(float(text), text)
    if _CONST_EXPR.match(text):
        try:
            value = _eval_const(ast.parse(text.strip(), mode="eval"))
        except ZeroDivisionError:
            return Expr(text)  # evaluated (and reported as division by zero) where it is used
        except (SyntaxError, ValueError, OverflowError, RecursionError):
            raise ValueError(f"invalid number {text!r}") from None
        return _checked(value, text)
    if _EXPR_HINT.search(text):
        return Expr(text)
    raise ValueError(f"invalid number {text!r}")


def _parse_value(text: str, column: int, name: str) -> object:
    """Interpret the text after ``name=``."""
    if text.startswith('"'):
        return text[1:-1]
    m = _MODE.match(text)
    if m and m.group("mode").upper() in _MODES and _balanced(m.group("inner")):
        inner = m.group("inner").strip()
        try:
            return (m.group("mode").upper(), parse_number(inner))
        except ValueError:
            raise LexError(f"invalid value {text!r} for {name}", column) from None
    try:
        return parse_number(text)
    except ValueError:
        raise LexError(f"invalid value {text!r} for {name}", column) from None


def _read_value(line: str, pos: int, column: int, name: str) -> tuple[object, int, str]:
    """Read the value starting at ``pos`` (after ``=``); return (value, new pos, value text)."""
    if pos < len(line) and line[pos] == '"':
        m = _STRING.match(line, pos)
        if m is None:
            raise LexError(f"unterminated string in {name}", column)
        return m.group("s"), m.end(), m.group(0)
    end = _value_end(line, pos)
    if end is None:
        raise LexError(f"unbalanced bracket in value of {name}", column)
    if end == pos:
        raise LexError(f"{name}= without a value", column)
    text = line[pos:end]
    return _parse_value(text, column, name), end, text


def _bracket_end(line: str, pos: int) -> int | None:
    """Index after the bracket that closes the one at ``pos`` (None: not closed)."""
    depth = 0
    for i in range(pos, len(line)):
        if line[i] in "([":
            depth += 1
        elif line[i] in ")]":
            depth -= 1
            if depth == 0:
                return i + 1
    return None


def _balanced(text: str) -> bool:
    """The brackets of ``text`` close in order and never go below zero."""
    depth = 0
    for ch in text:
        if ch in "([":
            depth += 1
        elif ch in ")]":
            depth -= 1
            if depth < 0:
                return False
    return depth == 0


def _value_end(line: str, pos: int) -> int | None:
    """End of the value starting at ``pos``: brackets balanced, white space only around operators
    (``X=R1 * 2`` is one value, ``X=R1 Y=2`` two words); None for an unclosed bracket."""
    n = len(line)
    depth = 0
    i = pos
    while i < n:
        ch = line[i]
        if ch in "([":
            depth += 1
        elif ch in ")]":
            if depth == 0:
                break
            depth -= 1
        elif depth == 0:
            if ch == ";" or ch == '"':
                break
            if ch == "=" and not (i + 1 < n and line[i + 1] == "=") and line[i - 1] not in "<>=":
                break
            if ch in " \t":
                if _OPEN_END.search(line, pos, i) is not None:
                    i += 1
                    continue
                m = _VALUE_OPS.match(line, i)
                if m is None:
                    break
                i = m.end()
                continue
        i += 1
    if depth:
        return None
    end = i
    while end > pos and line[end - 1] in " \t":
        end -= 1
    return end


def lex_line(line: str) -> LexedBlock:
    """Split one NC line into words.

    Parameters
    ----------
    line:
        The text of one block without its line terminator.

    Returns
    -------
    LexedBlock
        ``words`` is empty for an empty or comment-only line.

    Raises
    ------
    LexError
        Malformed number, missing value, unbalanced bracket, unknown character, misplaced ``$``.
    """
    fast = _FAST_LINE.match(line)
    if fast is not None:
        # fast path: only single-letter address + plain number words (G1X10 Y-2.5 F600 ; ...)
        number = None if fast[2] is None else "N" + str(int(fast[2]))
        column = fast.start(3) + 1
        words: list[Word] = []
        append = words.append
        for ws, address, value in _FAST_WORD.findall(fast[3]):
            column += len(ws)
            append(Word(address.upper(), float(value), column, address + value))
            column += len(address) + len(value)
        first_column = words[0].column if words else column
        return LexedBlock(fast[1] is not None, number, words, first_column, fast[4], None)
    pm = _PREFIX.match(line)
    assert pm is not None  # every part of the prefix is optional: it matches every line
    skip = pm.group("skip") is not None
    number = None
    if pm.group("n") is not None:
        number = "N" + str(int(pm.group("nnum")))
    label = pm.group("label")
    pos = pm.end()
    first_column = pos + 1
    words = []
    try:
        comment = _scan(line, pos, words)
    except LexError as exc:
        exc.block = number
        raise
    return LexedBlock(skip, number, words, first_column, comment, label)


def _scan(line: str, pos: int, words: list[Word]) -> str | None:
    """Append the words of ``line[pos:]`` to ``words``; return the comment text (or None)."""
    comment: str | None = None
    n = len(line)
    match = _TOKEN.match
    while pos < n:
        m = match(line, pos)
        assert m is not None  # the token pattern ends in a catch-all ("bad") and a line has no newline
        kind = m.lastgroup  # "num" for address words
        start = pos
        pos = m.end()
        if kind == "ws":
            continue
        column = start + 1
        if kind == "num":
            name = m.group("addr").upper()
            num = m.group("num")
            if num:
                try:
                    value = parse_number(num) if _NUMBER.match(num) else None
                except ValueError as exc:
                    raise LexError(f"{exc} after {name}", column) from None
                if value is None:
                    raise LexError(f"invalid number {num!r} after {name}", column)
                words.append(Word(name, value, column, line[start:pos]))
            elif pos < n and line[pos] == "(":
                cm = _CALL.match(line, pos)
                if cm is None:
                    raise LexError(f"unbalanced bracket in {name}(", column)
                pos = cm.end()
                words.append(Word(name, None, column, line[start:pos], cm.group(0)[1:-1]))
            else:
                words.append(Word(name, None, column, line[start:pos]))
        elif kind == "name":
            name = m.group("name").upper()
            assigned, pos, _ = _read_value(line, pos, column, name)
            words.append(Word(name, assigned, column, line[start:pos], None, True))
        elif kind == "arr":
            # an indexed assignment: R[2*R1]=5, TAB[1,2]=R3 (the index text is the subscript)
            name = m.group("arr").upper()
            bracket = line.index("[", pos)
            end = _bracket_end(line, bracket)
            if end is None:
                raise LexError(f"unbalanced bracket in {name}[", column)
            index = line[bracket + 1 : end - 1].strip()
            eq = re.compile(r"[ \t]*=(?!=)[ \t]*").match(line, end)
            if eq is None:
                raise LexError(f"{name}[{index}] is not in an assignment form", column)
            assigned, pos, _ = _read_value(line, eq.end(), column, name)
            words.append(Word(name, assigned, column, line[start:pos], index, True))
        elif kind == "call":
            # a procedure call (``CYCLE832(0.01, 1, 1)``, ``MSG("…")``): the argument text is the
            # subscript; the handler of the name reads it
            name = m.group("call").upper()
            cm = _CALL.match(line, pos)
            if cm is None:
                raise LexError(f"unbalanced bracket in {name}(", column)
            pos = cm.end()
            words.append(Word(name, None, column, line[start:pos], cm.group(0)[1:-1]))
        elif kind == "comment":
            comment = line[start + 1 :]
            break
        elif kind == "bare":
            text = m.group("bare")
            if words and words[-1].value is None and words[-1].subscript is None:
                prev = words[-1]
                try:
                    value = parse_number(text) if _NUMBER.match(text) else None
                except ValueError as exc:
                    raise LexError(f"{exc} after {prev.name}", prev.column) from None
                if value is None:
                    raise LexError(f"invalid number {text!r} after {prev.name}", prev.column)
                words[-1] = Word(prev.name, value, prev.column, line[prev.column - 1 : pos])
            else:
                raise LexError(f"number {text!r} without an address", column)
        elif kind == "kw":
            words.append(Word(m.group("kw").upper(), None, column, line[start:pos]))
        elif kind == "sys":
            name = m.group("sys").upper()
            im = _INDEX.match(line, pos)
            if im is None:
                if pos < n and line[pos] == "[":
                    raise LexError(f"unbalanced bracket in {name}[", column)
                eq = re.compile(r"[ \t]*=[ \t]*").match(line, pos)
                if eq is None:
                    raise LexError(f"system variable {name} is not in an assignment form", column)
                index = None
                pos = eq.end()
            else:
                if im.group("eq") is None:
                    raise LexError(f"system variable {name} is not in an assignment form", column)
                index = im.group("idx").strip()
                pos = im.end()
            assigned, pos, _ = _read_value(line, pos, column, name)
            words.append(Word(name, assigned, column, line[start:pos], index, True))
        else:  # bad
            ch = line[start]
            if ch in "()[]":
                raise LexError(f"unbalanced bracket {ch!r}", column)
            raise LexError(f"unexpected character {ch!r}", column)
    return comment
