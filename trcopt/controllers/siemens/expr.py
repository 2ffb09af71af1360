"""SINUMERIK 840D sl arithmetic: evaluates the text of an expression in double precision.

The operators and their priority follow the Programming Manual Job Planning, "Priority of the
operations" (highest first; equal priority evaluates left to right; parentheses override)::

    NOT B_NOT - + (unary)        negation, bit-serial negation, sign
    *  /  DIV  MOD               multiplication, division, integer division, remainder
    +  -                         addition, subtraction
    B_AND, B_XOR, B_OR           bit-serial AND, exclusive OR, OR
    AND, XOR, OR                 logical AND, exclusive OR, OR (result 1 or 0)
    ==  <>  >  <  >=  <=         comparison (result 1 or 0) -- the lowest priority

Operands: numbers (``1.5``, ``.5``, ``2EX-3`` = 0.002), ``R<n>`` and ``R[<expr>]`` parameters,
user variables and their elements (``LEN``, ``TAB[2,1]``), ``TRUE``/``FALSE``, and the functions
``SIN COS TAN ASIN ACOS ATAN2 SQRT POT ABS TRUNC ROUND MINVAL MAXVAL LN EXP`` (angles in degrees).
Where a value comes from is the caller's: :class:`Scope` resolves a name.

Every problem raises :class:`ExprError` with the 0-based offset of the token in the text.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from typing import Protocol

__all__ = ["ExprError", "Scope", "evaluate", "FUNCTIONS", "OPERATOR_WORDS", "is_parameter"]

#: kinds of :class:`ExprError`
SYNTAX, UNDEFINED, UNSET, ARITHMETIC, UNSUPPORTED = "syntax", "undefined", "unset", "arithmetic", "unsupported"


class ExprError(ValueError):
    """An expression that cannot be evaluated; ``offset`` is 0-based in the expression text."""

    def __init__(self, kind: str, message: str, offset: int = -1) -> None:
        super().__init__(message)
        self.kind = kind
        self.message = message
        self.offset = offset


class Scope(Protocol):
    """Resolves a name (``"R"`` for ``R<n>``/``R[..]``, else a user variable) to its value."""

    def value(self, name: str, index: tuple[float, ...] | None) -> float: ...


_TOKEN = re.compile(
    r"""[ \t]*(?:
      (?P<num>(?:\d+\.?\d*|\.\d+)(?:EX[-+]?\d+)?)
     |(?P<name>\$?[A-Z_][A-Z0-9_]*)
     |(?P<op><>|<=|>=|==|[-+*/()<>,\[\]])
     |(?P<end>\Z)
     |(?P<bad>.)
    )""",
    re.I | re.X,
)
_PARAM = re.compile(r"R(\d+)\Z", re.I)
_RELATIVE_EQUALITY = 1e-12  # comparisons test relative, not absolute, equality (see module docs)


def is_parameter(name: str) -> int | None:
    """``R17`` → 17; any other name → None."""
    m = _PARAM.match(name)
    return int(m.group(1)) if m else None


def _deg(f: Callable[[float], float]) -> Callable[[float], float]:
    return lambda x: f(math.radians(math.fmod(x, 360.0)))


def _tan(x: float) -> float:
    if abs(math.fmod(x, 180.0)) == 90.0:
        raise ArithmeticError(f"TAN({x:g}) is undefined")
    return math.tan(math.radians(math.fmod(x, 360.0)))


def _arc(f: Callable[[float], float], name: str) -> Callable[[float], float]:
    def g(x: float) -> float:
        if not -1.0 <= x <= 1.0:
            raise ArithmeticError(f"{name}({x:g}): the argument must lie in [-1, 1]")
        return math.degrees(f(x))

    return g


def _atan2(y: float, x: float) -> float:
    if x == 0.0 and y == 0.0:
        raise ArithmeticError("ATAN2(0, 0) is undefined")
    return math.degrees(math.atan2(y, x))


def _sqrt(x: float) -> float:
    if x < 0.0:
        raise ArithmeticError(f"SQRT({x:g}) of a negative number")
    return math.sqrt(x)


def _ln(x: float) -> float:
    if x <= 0.0:
        raise ArithmeticError(f"LN({x:g}) of a number that is not positive")
    return math.log(x)


def _round(x: float) -> float:
    """Nearest whole number, halves away from zero (ROUND(2.5) = 3, ROUND(-2.5) = -3)."""
    return math.copysign(math.floor(abs(x) + 0.5), x)


#: name → (number of arguments, function)
FUNCTIONS: dict[str, tuple[int, Callable[..., float]]] = {
    "SIN": (1, _deg(math.sin)),
    "COS": (1, _deg(math.cos)),
    "TAN": (1, _tan),
    "ASIN": (1, _arc(math.asin, "ASIN")),
    "ACOS": (1, _arc(math.acos, "ACOS")),
    "ATAN2": (2, _atan2),
    "SQRT": (1, _sqrt),
    "POT": (1, lambda x: x * x),
    "ABS": (1, abs),
    "TRUNC": (1, lambda x: float(math.trunc(x))),
    "ROUND": (1, _round),
    "MINVAL": (2, min),
    "MAXVAL": (2, max),
    "LN": (1, _ln),
    "EXP": (1, math.exp),
}


def _equal(a: float, b: float) -> bool:
    return a == b or abs(a - b) <= _RELATIVE_EQUALITY * max(abs(a), abs(b))


def _whole(x: float, op: str) -> int:
    if x != math.trunc(x):
        raise ArithmeticError(f"{op} needs whole numbers, got {x:g}")
    return int(x)


def _divide(a: float, b: float, op: str) -> float:
    if b == 0.0:
        raise ArithmeticError(f"division by zero ({op})")
    if op == "/":
        return a / b
    if op == "DIV":  # result type INT: the quotient truncated towards zero
        return float(math.trunc(a / b))
    return math.fmod(a, b)  # MOD: remainder with the sign of the dividend (a = (a DIV b)*b + a MOD b)


_BINARY: dict[str, tuple[int, Callable[[float, float, str], float]]] = {
    "==": (0, lambda a, b, op: float(_equal(a, b))),
    "<>": (0, lambda a, b, op: float(not _equal(a, b))),
    "<": (0, lambda a, b, op: float(a < b and not _equal(a, b))),
    ">": (0, lambda a, b, op: float(a > b and not _equal(a, b))),
    "<=": (0, lambda a, b, op: float(a < b or _equal(a, b))),
    ">=": (0, lambda a, b, op: float(a > b or _equal(a, b))),
    "OR": (1, lambda a, b, op: float(a != 0.0 or b != 0.0)),
    "XOR": (2, lambda a, b, op: float((a != 0.0) != (b != 0.0))),
    "AND": (3, lambda a, b, op: float(a != 0.0 and b != 0.0)),
    "B_OR": (4, lambda a, b, op: float(_whole(a, op) | _whole(b, op))),
    "B_XOR": (5, lambda a, b, op: float(_whole(a, op) ^ _whole(b, op))),
    "B_AND": (6, lambda a, b, op: float(_whole(a, op) & _whole(b, op))),
    "+": (7, lambda a, b, op: a + b),
    "-": (7, lambda a, b, op: a - b),
    "*": (8, lambda a, b, op: a * b),
    "/": (8, _divide),
    "DIV": (8, _divide),
    "MOD": (8, _divide),
}
#: words that are operators (not names) inside an expression
OPERATOR_WORDS = frozenset({"OR", "XOR", "AND", "B_OR", "B_XOR", "B_AND", "DIV", "MOD", "NOT", "B_NOT"})
_CONSTANTS = {"TRUE": 1.0, "FALSE": 0.0}
_MAX_DEPTH = 64


class _Parser:
    """Recursive-descent evaluation: one pass over the tokens, no tree."""

    def __init__(self, text: str, scope: Scope | None) -> None:
        self.text = text
        self.scope = scope
        self.pos = 0
        self.depth = 0
        self._next()

    def _next(self) -> None:
        m = _TOKEN.match(self.text, self.pos)
        assert m is not None  # the pattern ends in a catch-all
        self.start = m.start(m.lastindex or 0)
        self.pos = m.end()
        self.kind = m.lastgroup or "end"
        tok = m.group(self.kind) if self.kind != "end" else ""
        self.tok = tok.upper()
        if self.kind == "name" and self.tok in OPERATOR_WORDS:
            self.kind = "op"
        if self.kind == "bad":
            raise ExprError(SYNTAX, f"unexpected character {tok!r}", self.start)

    def _expect(self, op: str) -> None:
        if self.tok != op or self.kind != "op":
            found = f"{self.tok!r}" if self.kind != "end" else "the end"
            raise ExprError(SYNTAX, f"expected {op!r}, found {found}", self.start)
        self._next()

    def expression(self, min_prec: int = 0) -> float:
        self.depth += 1
        if self.depth > _MAX_DEPTH:
            raise ExprError(SYNTAX, "expression nested too deeply", self.start)
        left = self.unary()
        while self.kind == "op" and self.tok in _BINARY:
            prec, fn = _BINARY[self.tok]
            if prec < min_prec:
                break
            op, at = self.tok, self.start
            self._next()
            right = self.expression(prec + 1)
            try:
                left = fn(left, right, op)
            except ArithmeticError as exc:
                raise ExprError(ARITHMETIC, str(exc), at) from None
        self.depth -= 1
        return left

    def unary(self) -> float:
        if self.kind == "op" and self.tok in ("-", "+", "NOT", "B_NOT"):
            op, at = self.tok, self.start
            self._next()
            value = self.unary()
            if op == "-":
                return -value
            if op == "NOT":
                return float(value == 0.0)
            if op == "B_NOT":
                try:
                    return float(~_whole(value, op))
                except ArithmeticError as exc:
                    raise ExprError(ARITHMETIC, str(exc), at) from None
            return value
        return self.primary()

    def _arguments(self) -> list[float]:
        self._expect("(")
        args = [self.expression()]
        while self.tok == "," and self.kind == "op":
            self._next()
            args.append(self.expression())
        self._expect(")")
        return args

    def primary(self) -> float:
        at = self.start
        if self.kind == "num":
            text = self.tok
            self._next()
            mantissa, _, exponent = text.partition("EX")
            return float(f"{mantissa}e{exponent}") if exponent else float(text)  # correctly rounded
        if self.kind == "op" and self.tok == "(":
            self._next()
            value = self.expression()
            self._expect(")")
            return value
        if self.kind != "name":
            found = f"{self.tok!r}" if self.kind != "end" else "the end"
            raise ExprError(SYNTAX, f"expected a value, found {found}", at)
        name = self.tok
        self._next()
        if name.startswith("$"):
            raise ExprError(UNSUPPORTED, f"system variable {name} in an expression is not modelled by trcopt", at)
        if self.kind == "op" and self.tok == "(":
            if name not in FUNCTIONS:
                raise ExprError(UNDEFINED, f"name {name} not defined (no such function)", at)
            count, fn = FUNCTIONS[name]
            args = self._arguments()
            if len(args) != count:
                raise ExprError(SYNTAX, f"{name} takes {count} argument{'s' * (count > 1)}, got {len(args)}", at)
            try:
                return float(fn(*args))
            except (ArithmeticError, ValueError) as exc:
                raise ExprError(ARITHMETIC, str(exc), at) from None
        index: tuple[float, ...] | None = None
        if self.kind == "op" and self.tok == "[":
            self._next()
            parts = [self.expression()]
            while self.tok == "," and self.kind == "op":
                self._next()
                parts.append(self.expression())
            self._expect("]")
            index = tuple(parts)
        elif name in _CONSTANTS:
            return _CONSTANTS[name]
        elif name in FUNCTIONS:
            raise ExprError(SYNTAX, f"function {name} without its arguments (…)", at)
        param = is_parameter(name)
        if param is not None:
            if index is not None:
                raise ExprError(SYNTAX, f"{name}[…]: an R-parameter takes no index", at)
            name, index = "R", (float(param),)
        if self.scope is None:
            raise ExprError(UNDEFINED, f"name {name} not defined", at)
        try:
            return self.scope.value(name, index)
        except ExprError as exc:
            if exc.offset < 0:
                exc.offset = at
            raise


def evaluate(text: str, scope: Scope | None = None) -> float:
    """Evaluate ``text``; names are resolved by ``scope`` (none: only constants)."""
    parser = _Parser(text, scope)
    value = parser.expression()
    if parser.kind != "end":
        raise ExprError(SYNTAX, f"unexpected {parser.tok!r} in the expression", parser.start)
    if not math.isfinite(value):
        raise ExprError(ARITHMETIC, "the result is not a finite number", 0)
    return value
