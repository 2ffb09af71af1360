"""SINUMERIK R-parameters and local user variables (``DEF``): definition, assignment, evaluation.

* ``R<n>=<expr>`` and ``R[<expr>]=<expr>`` set an R-parameter. Reading one the program has not set
  is an error (``NC-PARAM-UNSET``): on the machine it keeps the value it had before the program
  started, which trcopt does not know.
* ``DEF REAL|INT|BOOL|CHAR <name>[=<expr>], <name>[<n>[,<m>]], …`` defines local user variables
  (initial value 0); only in the definition part of the program, before its first executable
  block (alarm 14500). ``DEF STRING|AXIS|FRAME`` variables may be defined; reading them is
  ``NC-UNSUPPORTED-EXPR``, assigning a STRING is a warning, an AXIS or FRAME an error.
* A name neither an R-parameter nor defined: alarm 12550. Division by zero and a function argument
  outside its domain: ``NC-EXPRESSION``.

INT variables round what is assigned to them (halves away from zero), BOOL ones store 1 or 0.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from trcopt.codes import Code
from trcopt.controllers.siemens.expr import (
    ARITHMETIC,
    FUNCTIONS,
    OPERATOR_WORDS,
    SYNTAX,
    UNDEFINED,
    UNSET,
    UNSUPPORTED,
    ExprError,
    _round,
    evaluate,
    is_parameter,
)
from trcopt.controllers.siemens.lexer import Word
from trcopt.errors import AlarmError, SourceSpan, alarm
from trcopt.nc.modal import fail

__all__ = ["Variables", "DEF_LINE"]

#: a definition block: optional skip mark and block number, then DEF
DEF_LINE = re.compile(r"[ \t]*(?:/[0-9]?)?[ \t]*(?:N(?P<n>\d+)(?![0-9.]))?[ \t]*DEF(?![A-Z0-9_])[ \t]*", re.I)
_TYPE = re.compile(
    r"(?P<type>REAL|INT|BOOL|CHAR|STRING|AXIS|FRAME)(?![A-Z0-9_])[ \t]*(?:\[[ \t]*\d+[ \t]*\])?[ \t]*", re.I
)
_NAME = re.compile(r"(?P<name>[A-Z_][A-Z0-9_]*)[ \t]*(?:\[(?P<dims>[^\]\n]*)\])?[ \t]*(?P<eq>=)?[ \t]*", re.I)
_VALID_NAME = re.compile(r"[A-Z_]{2}[A-Z0-9_]{0,29}\Z")
_NUMERIC = ("REAL", "INT", "BOOL", "CHAR")
_MAX_ELEMENTS = 100_000
_MAX_R = 99_999


@dataclass
class Variable:
    type: str
    dims: tuple[int, ...] = ()
    values: dict[tuple[int, ...], float] = field(default_factory=dict)


def _store(var: Variable, value: float) -> float:
    if var.type in ("INT", "CHAR"):
        return _round(value)
    if var.type == "BOOL":
        return float(value != 0.0)
    return value


class Variables:
    """The R-parameters and user variables of one program run (the :class:`Scope` of expressions)."""

    def __init__(self, reserved: frozenset[str]) -> None:
        self.r: dict[int, float] = {}
        self.user: dict[str, Variable] = {}
        self.reserved = reserved | OPERATOR_WORDS | frozenset(FUNCTIONS) | {"TRUE", "FALSE", "DEF"}

    # ------------------------------------------------------------------ Scope
    def value(self, name: str, index: tuple[float, ...] | None) -> float:
        if name == "R":
            r = self._r_index(index)
            if r not in self.r:
                raise ExprError(
                    UNSET, f"R{r} is read before the program sets it: its value on the machine is not known to trcopt"
                )
            return self.r[r]
        var = self.user.get(name)
        if var is None:
            raise ExprError(UNDEFINED, f"name {name} not defined (no DEF before its use)")
        if var.type not in _NUMERIC:
            raise ExprError(UNSUPPORTED, f"{var.type} variable {name} in an expression is not modelled by trcopt")
        return var.values.get(self._element(name, var, index), 0.0)

    @staticmethod
    def _r_index(index: tuple[float, ...] | None) -> int:
        if index is None or len(index) != 1 or index[0] != int(index[0]) or not 0 <= index[0] <= _MAX_R:
            raise ExprError(SYNTAX, f"R[…] needs one whole-number index 0…{_MAX_R}, got {index}")
        return int(index[0])

    @staticmethod
    def _element(name: str, var: Variable, index: tuple[float, ...] | None) -> tuple[int, ...]:
        if not var.dims:
            if index is not None:
                raise ExprError(SYNTAX, f"{name} is not an array")
            return ()
        if index is None or len(index) != len(var.dims):
            raise ExprError(SYNTAX, f"array {name} needs {len(var.dims)} index{'es' * (len(var.dims) > 1)}")
        for i, n in zip(index, var.dims, strict=True):
            if i != int(i) or not 0 <= i < n:
                raise ExprError(SYNTAX, f"array index {i:g} of {name} outside 0…{n - 1}")
        return tuple(int(i) for i in index)

    # ------------------------------------------------------------------ evaluation with a place
    def evaluate(self, text: str, span: SourceSpan, column: int) -> float:
        """Evaluate ``text`` that starts at ``column`` of the block; errors are located in it."""
        try:
            return evaluate(text, self)
        except ExprError as exc:
            raise self._error(exc, text, span, column) from None

    def _error(self, exc: ExprError, text: str, span: SourceSpan, column: int) -> Exception:
        at = SourceSpan(span.file, span.line, column + max(exc.offset, 0), span.block)
        if exc.kind == UNDEFINED:
            return AlarmError(alarm(12550, exc.message, at))
        code = {
            SYNTAX: Code.NC_SYNTAX,
            UNSET: Code.NC_PARAM_UNSET,
            ARITHMETIC: Code.NC_EXPRESSION,
            UNSUPPORTED: Code.NC_UNSUPPORTED_EXPR,
        }[exc.kind]
        return fail(code, f"{exc.message} (in {text.strip()!r})", at)

    def word_value(self, word: Word, text: str, span: SourceSpan) -> float:
        """Evaluate the expression ``text`` written in ``word`` (located inside the word)."""
        eq = word.text.find("=")
        offset = word.text.find(text, eq + 1 if eq >= 0 else 0)
        return self.evaluate(text, span, word.column + max(offset, 0))

    # ------------------------------------------------------------------ assignment
    def is_assignment(self, word: Word) -> bool:
        return word.assigned and (
            is_parameter(word.name) is not None or (word.name == "R" and word.subscript is not None)
            or word.name in self.user
        )

    def assign(self, word: Word, value: float, span: SourceSpan) -> bool:
        """Store ``value`` into the target of ``word``; False for a STRING (nothing to store)."""
        at = SourceSpan(span.file, span.line, word.column, span.block)
        index = None
        if word.subscript is not None:
            open_at = word.text.find("[") + 1
            index = tuple(
                self.evaluate(part, span, word.column + open_at + start)
                for part, start in _split(word.subscript)
            )
        try:
            r = is_parameter(word.name)
            if r is not None or word.name == "R":
                if r is not None and index is not None:
                    raise ExprError(SYNTAX, f"{word.name}[…]: an R-parameter takes no index")
                self.r[self._r_index((float(r),) if r is not None else index)] = value
                return True
            var = self.user[word.name]
            if var.type == "STRING":
                return False
            if var.type not in _NUMERIC:
                raise fail(Code.NC_UNSUPPORTED, f"{var.type} variable {word.name} is not modelled by trcopt", at)
            var.values[self._element(word.name, var, index)] = _store(var, value)
            return True
        except ExprError as exc:
            raise fail(Code.NC_SYNTAX, exc.message, at) from None

    # ------------------------------------------------------------------ DEF
    def define(self, line: str, start: int, span: SourceSpan) -> None:
        """Read the definition after ``DEF`` (``line[start:]``)."""
        tm = _TYPE.match(line, start)
        if tm is None:
            raise fail(
                Code.NC_SYNTAX,
                "DEF needs a data type: REAL, INT, BOOL, CHAR, STRING, AXIS or FRAME",
                SourceSpan(span.file, span.line, start + 1, span.block),
            )
        vtype = tm.group("type").upper()
        pos = tm.end()
        while True:
            nm = _NAME.match(line, pos)
            at = SourceSpan(span.file, span.line, pos + 1, span.block)
            if nm is None:
                raise fail(Code.NC_SYNTAX, f"DEF {vtype}: a variable name expected", at)
            name = nm.group("name").upper()
            self._check_name(name, at)
            dims = self._dims(nm.group("dims"), name, at)
            var = Variable(vtype, dims)
            pos = nm.end()
            if nm.group("eq"):
                end = _value_end(line, pos)
                text = line[pos:end]
                if dims or vtype not in _NUMERIC:
                    raise fail(Code.NC_UNSUPPORTED, f"DEF {vtype} {name}=…: this initial value is not modelled", at)
                if not text.strip():
                    raise fail(Code.NC_SYNTAX, f"DEF {name}= without a value", at)
                var.values[()] = _store(var, self.evaluate(text, span, pos + 1))
                pos = end
            self.user[name] = var
            if pos < len(line) and line[pos] == ",":
                pos += 1
                while pos < len(line) and line[pos] in " \t":
                    pos += 1
                continue
            if pos >= len(line) or line[pos] == ";":
                return
            raise fail(
                Code.NC_SYNTAX,
                f"unexpected {line[pos]!r} in DEF (one data type per block; names separated by commas)",
                SourceSpan(span.file, span.line, pos + 1, span.block),
            )

    def _check_name(self, name: str, at: SourceSpan) -> None:
        if not _VALID_NAME.match(name):
            raise fail(
                Code.NC_SYNTAX,
                f"invalid variable name {name}: at most 31 characters, the first two letters or '_'",
                at,
            )
        if name in self.reserved or is_parameter(name) is not None:
            raise fail(Code.NC_SYNTAX, f"variable name {name} is already an NC address or keyword", at)
        if name in self.user:
            raise fail(Code.NC_SYNTAX, f"variable {name} is defined twice", at)

    @staticmethod
    def _dims(text: str | None, name: str, at: SourceSpan) -> tuple[int, ...]:
        if text is None:
            return ()
        try:
            dims = tuple(int(p) for p in text.split(","))
        except ValueError:
            dims = ()
        count = 1
        for n in dims:
            count *= max(n, 0)
        if not dims or len(dims) > 3 or min(dims) < 1 or count > _MAX_ELEMENTS:
            raise fail(Code.NC_SYNTAX, f"array {name}[{text}]: one to three positive whole-number sizes", at)
        return dims


def _split(text: str) -> list[tuple[str, int]]:
    """Split at top-level commas: [(part, offset)]."""
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        if ch in "([":
            depth += 1
        elif ch in ")]":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append((text[start:i], start))
            start = i + 1
    parts.append((text[start:], start))
    return parts


def _value_end(line: str, pos: int) -> int:
    """End of an initial value: the next top-level comma, the comment or the end of the line."""
    depth = 0
    for i in range(pos, len(line)):
        ch = line[i]
        if ch in "([":
            depth += 1
        elif ch in ")]":
            depth -= 1
        elif depth == 0 and ch in ",;":
            return i
    return len(line)
