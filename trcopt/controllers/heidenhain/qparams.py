"""Q parameters of the Klartext reader: storage, ``FN 0``–``FN 13`` and ``Q… = formula``.

Q parameters are numbers (the TNC's ``Q0``–``Q1999``, global to the called programs), ``QL``
(local to one program) and ``QR`` (remanent; global here). A parameter that was never assigned is
*undefined* (the TNC 640's state; the TNC 426 manuals say nothing about a default): reading one is
the error ``HH-Q-UNDEFINED`` instead of a guessed value. ``Q108`` is the compensation value of the
called tool (R + DR_TAB + DR_CALL) and ``Q113`` the unit of the main program (0 mm, 1 inch), as the
TNC preassigns them.

Formula (``Q1 = 5 + Q2 * SIN 30``): ``+ - * /``, ``^`` (power), functions ``SQ SQRT SIN COS TAN
ASIN ACOS ATAN ABS INT FRAC SGN NEG LN LOG EXP`` applied to the value after them (``SQ 10 - 3^3``
is 73), ``PI``, brackets. Angles in degrees. Precedence: brackets, functions, ``^``, ``* /``,
``+ -``. A division by zero, a root of a negative number and the like are ``HH-Q-MATH`` (the TNC
stops with an error); so is a result outside the TNC's ±999 999 999.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable

from trcopt.codes import Code

__all__ = ["QError", "QParams", "evaluate", "eval_fn", "Q_REF", "OPERAND", "Q_LIMIT"]

#: A Q-parameter reference: ``Q5``, ``QL5``, ``QR5``.
Q_REF = r"Q[LR]?\d+"
#: An operand of an FN function: a signed number or a signed Q parameter.
OPERAND = rf"[+-]?\s*(?:{Q_REF}|\d+(?:\.\d*)?|\.\d+)"
Q_LIMIT = 999_999_999.0  # the TNC's Q-parameter value range

_TOKEN = re.compile(rf"\s*(?:(?P<num>\d+(?:\.\d*)?|\.\d+)|(?P<q>{Q_REF})\b|(?P<name>[A-Z]+)|(?P<op>[-+*/^()]))", re.I)
_FUNCS: dict[str, Callable[[float], float]] = {
    "SQ": lambda x: x * x,
    "SQRT": math.sqrt,
    "SIN": lambda x: math.sin(math.radians(x)),
    "COS": lambda x: math.cos(math.radians(x)),
    "TAN": lambda x: math.tan(math.radians(x)),
    "ASIN": lambda x: math.degrees(math.asin(x)),
    "ACOS": lambda x: math.degrees(math.acos(x)),
    "ATAN": lambda x: math.degrees(math.atan(x)),
    "ABS": abs,
    "INT": lambda x: float(math.trunc(x)),
    "FRAC": lambda x: x - math.trunc(x),
    "SGN": lambda x: float((x > 0) - (x < 0)),
    "NEG": lambda x: -x,
    "LN": math.log,
    "LOG": math.log10,
    "EXP": math.exp,
}


class QError(Exception):
    """A Q-parameter problem: ``code`` (``HH-Q-UNDEFINED``, ``HH-Q-MATH``, ``HH-SYNTAX``),
    ``message`` and the 1-based ``column`` in the program line."""

    def __init__(self, code: Code, message: str, column: int) -> None:
        super().__init__(message)
        self.code, self.message, self.column = code, message, column


def _checked(value: float, what: str, column: int) -> float:
    if not math.isfinite(value) or abs(value) > Q_LIMIT:
        raise QError(Code.HH_Q_MATH, f"{what}: result {value!r} outside the TNC's range ±999 999 999", column)
    return value


class QParams:
    """The Q parameters of a run: ``get(name, column)`` and ``set(name, value)``; ``QL`` values
    live in the innermost program (``push_local``/``pop_local`` around ``CALL PGM``)."""

    def __init__(self, preset: Callable[[str], float | None] | None = None) -> None:
        self.values: dict[str, float] = {}
        self.local: list[dict[str, float]] = [{}]
        self.preset = preset

    @staticmethod
    def key(name: str) -> str:
        name = name.upper()
        prefix = name[:2] if name[:2] in ("QL", "QR") else "Q"
        return f"{prefix}{int(name[len(prefix) :])}"

    def get(self, name: str, column: int) -> float:
        k = self.key(name)
        store = self.local[-1] if k.startswith("QL") else self.values
        if k in store:
            return store[k]
        if self.preset is not None:
            v = self.preset(k)
            if v is not None:
                return v
        raise QError(Code.HH_Q_UNDEFINED, f"{k} is used before a value was assigned to it", column)

    def set(self, name: str, value: float) -> None:
        k = self.key(name)
        (self.local[-1] if k.startswith("QL") else self.values)[k] = value

    def push_local(self) -> None:
        self.local.append({})

    def pop_local(self) -> None:
        self.local.pop()


class _Parser:
    def __init__(self, text: str, column: int, q: QParams) -> None:
        self.q, self.column = q, column
        self.toks: list[tuple[str, str, int]] = []
        pos = 0
        while pos < len(text):
            if text[pos:].strip() == "":
                break
            m = _TOKEN.match(text, pos)
            if m is None or m.end() == pos:
                bad = pos + len(text[pos:]) - len(text[pos:].lstrip())
                raise QError(Code.HH_SYNTAX, f"formula: cannot read {text[bad : bad + 8]!r}", column + bad)
            kind = m.lastgroup or ""
            self.toks.append((kind, m.group(kind).upper(), column + m.start(kind)))
            pos = m.end()
        self.i = 0

    def peek(self) -> tuple[str, str, int]:
        return self.toks[self.i] if self.i < len(self.toks) else ("end", "", self.column + 1)

    def take(self) -> tuple[str, str, int]:
        t = self.peek()
        self.i += 1
        return t

    def expr(self) -> float:
        v = self.term()
        while self.peek()[1] in ("+", "-"):
            _, op, _ = self.take()
            v = v + self.term() if op == "+" else v - self.term()
        return v

    def term(self) -> float:
        v = self.power()
        while self.peek()[1] in ("*", "/"):
            _, op, col = self.take()
            w = self.power()
            if op == "/" and w == 0.0:
                raise QError(Code.HH_Q_MATH, "division by zero", col)
            v = v * w if op == "*" else v / w
        return v

    def power(self) -> float:
        base = self.unary()
        if self.peek()[1] == "^":
            _, _, col = self.take()
            exp = self.power()
            try:
                value = math.pow(base, exp)
            except (ValueError, OverflowError, ZeroDivisionError):
                raise QError(Code.HH_Q_MATH, f"{base:g} ^ {exp:g} is not defined", col) from None
            return _checked(value, "^", col)
        return base

    def unary(self) -> float:
        kind, text, col = self.peek()
        if text in ("+", "-"):
            self.take()
            v = self.unary()
            return -v if text == "-" else v
        if kind == "name" and text in _FUNCS:
            self.take()
            arg = self.unary()
            try:
                return _checked(_FUNCS[text](arg), text, col)
            except (ValueError, OverflowError, ZeroDivisionError):
                raise QError(Code.HH_Q_MATH, f"{text} {arg:g} is not defined", col) from None
        return self.primary()

    def primary(self) -> float:
        kind, text, col = self.take()
        if kind == "num":
            return float(text)
        if kind == "q":
            return self.q.get(text, col)
        if kind == "name" and text == "PI":
            return math.pi
        if text == "(":
            v = self.expr()
            if self.take()[1] != ")":
                raise QError(Code.HH_SYNTAX, "formula: missing ')'", col)
            return v
        what = "end of the formula" if kind == "end" else repr(text)
        raise QError(Code.HH_SYNTAX, f"formula: a value expected, not {what}", col)


def evaluate(text: str, column: int, q: QParams) -> float:
    """The value of a formula; ``column`` is where ``text`` starts in the program line."""
    p = _Parser(text, column, q)
    v = p.expr()
    kind, rest, col = p.peek()
    if kind != "end":
        raise QError(Code.HH_SYNTAX, f"formula: unexpected {rest!r}", col)
    return _checked(v, "formula", column)


_FN_OPS = {1: "+", 2: "-", 3: "*", 4: "DIV", 8: "LEN", 13: "ANG"}
_FN_FUNCS = {5: "SQRT", 6: "SIN", 7: "COS"}


def eval_fn(fn: int, rhs: str, column: int, q: QParams) -> float:
    """The value of ``FN fn: Q… = rhs`` for FN 0–8 and 13 (``rhs`` starts at ``column``)."""

    def operand(text: str, col: int) -> float:
        t = text.replace(" ", "")
        if not re.fullmatch(OPERAND, t, re.I):
            raise QError(Code.HH_SYNTAX, f"FN {fn}: {text.strip()!r} is not a number or Q parameter", col)
        sign = -1.0 if t.startswith("-") else 1.0
        body = t.lstrip("+-")
        return sign * (q.get(body, col) if body.upper().startswith("Q") else float(body))

    if fn == 0:
        return operand(rhs, column)
    if fn in _FN_FUNCS:
        m = re.fullmatch(rf"\s*{_FN_FUNCS[fn]}\s*(.+?)\s*", rhs, re.I)
        if m is None:
            raise QError(Code.HH_SYNTAX, f"FN {fn}: expected '{_FN_FUNCS[fn]} value'", column)
        x = operand(m.group(1), column + m.start(1))
        try:
            return _checked(_FUNCS[_FN_FUNCS[fn]](x), f"FN {fn}", column)
        except ValueError:
            raise QError(Code.HH_Q_MATH, f"FN {fn}: square root of the negative number {x:g}", column) from None
    op = _FN_OPS[fn]
    pattern = rf"\s*({OPERAND})\s*{re.escape(op)}\s*({OPERAND})\s*"
    m = re.fullmatch(pattern, rhs, re.I)
    if m is None:
        raise QError(Code.HH_SYNTAX, f"FN {fn}: expected 'value {op} value'", column)
    a, b = operand(m.group(1), column + m.start(1)), operand(m.group(2), column + m.start(2))
    if fn == 1:
        v = a + b
    elif fn == 2:
        v = a - b
    elif fn == 3:
        v = a * b
    elif fn == 4:
        if b == 0.0:
            raise QError(Code.HH_Q_MATH, "FN 4: division by zero", column + m.start(2))
        v = a / b
    elif fn == 8:
        v = math.hypot(a, b)
    else:  # FN 13: the angle of (a, b) — arc tangent of b/a in 0°…360°
        if a == 0.0 and b == 0.0:
            raise QError(Code.HH_Q_MATH, "FN 13: the angle of (0, 0) is not defined", column)
        v = math.degrees(math.atan2(b, a)) % 360.0
    return _checked(v, f"FN {fn}", column)
