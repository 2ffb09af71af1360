"""RS274NGC values as LinuxCNC's interpreter reads them: the normalised line, parameters and
expressions.

A line is first *normalised* as LinuxCNC does before it reads a word: comments ``( )`` and ``;``
are taken out, blanks and tabs outside comments removed and letters lower-cased, so that
``G 1 X 1 0`` is ``g1x10``; every character keeps the column it had in the file
(:class:`NgcLine`), so that errors point at the program text.

Values (:class:`ValueReader`) are LinuxCNC's ``read_real_value``: a number, a parameter (``#5``,
``##1``, ``#[1+2]``, ``#<name>``), a bracketed expression, a signed value (``-#1``) or a function
(``SIN[30]``, ``ATAN[1]/[2]``, ``EXISTS[#<name>]``). Binary operators have LinuxCNC's six levels —
``**``; ``* / MOD``; ``+ -``; ``EQ NE GT GE LT LE``; ``AND OR XOR`` — and operators of the same
level are applied left to right (``2**3**2`` is 64, ``1 OR 0 AND 0`` is 0); a leading ``-`` belongs
to the number (``[-2**2]`` is 4). Angles are degrees, comparisons use LinuxCNC's 1e-6 tolerance,
``MOD`` is never negative, ``ROUND`` rounds halves away from zero, ``FIX``/``FUP`` are floor and
ceiling. Errors are :class:`NgcError` with LinuxCNC's own message.

Parameters (:class:`Parameters`): numbered ``#1``…``#5601`` (unset ones read 0), global named
parameters ``#<_name>`` and named parameters local to the current subroutine call (``#<name>``);
reading a named parameter that was never set is LinuxCNC's "Named parameter #<name> not defined".
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field

from trcopt.codes import Code

__all__ = [
    "MAX_PARAMETERS",
    "NgcError",
    "NgcLine",
    "Parameters",
    "ValueReader",
    "normalise",
    "read_integer",
]

MAX_PARAMETERS = 5602  # LinuxCNC's RS274NGC_MAX_PARAMETERS: #1 … #5601
TOLERANCE_EQUAL = 1e-6  # LinuxCNC: EQ, NE, LE, GE compare within this
FIRST_SUB_PARAM, SUB_PARAMS = 1, 30  # subroutine arguments #1 … #30

# LinuxCNC's predefined read-only named parameters: the reader answers those it models
# (Parameters.readonly); reading another is an NC-UNSUPPORTED error, not LinuxCNC's "not defined"
_PREDEFINED = frozenset(
    "_vmajor _vminor _line _motion_mode _plane _ccomp _metric _imperial _absolute _incremental "
    "_inverse_time _units_per_minute _units_per_rev _coord_system _tool_offset _retract_r_plane "
    "_retract_old_z _spindle_rpm_mode _spindle_css_mode _ijk_absolute_mode _lathe_diameter_mode "
    "_lathe_radius_mode _spindle_on _spindle_cw _mist _flood _speed_override _feed_override "
    "_adaptive_feed _feed_hold _feed _rpm _x _y _z _a _b _c _u _v _w _abs_x _abs_y _abs_z _abs_a "
    "_abs_b _abs_c _current_tool _current_pocket _selected_tool _selected_pocket _task "
    "_call_level _remap_level".split()
)

_FUNCTIONS = ("abs", "acos", "asin", "atan", "cos", "exists", "exp", "fix", "fup", "ln", "round", "sin", "sqrt", "tan")
# binary operators: spelling -> precedence (LinuxCNC's levels 2…6)
_BINARY = {
    "**": 6, "*": 5, "/": 5, "mod": 5, "+": 4, "-": 4,
    "eq": 3, "ne": 3, "gt": 3, "ge": 3, "lt": 3, "le": 3,
    "and": 2, "or": 2, "xor": 2,
}  # fmt: skip
_NUMBER_CHARS = re.compile(r"[+-]*[0-9.]*")
_DECIMAL = re.compile(r"\d+\.?\d*|\.\d+")
_PLAIN_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)")
_DIGITS_POINT = frozenset("0123456789.")
_WORD_OPS = ("mod", "eq", "ne", "gt", "ge", "lt", "le", "and", "or", "xor")


class NgcError(Exception):
    """A problem in the program text; ``index`` is a position in the normalised line."""

    def __init__(
        self, message: str, index: int = 0, code: Code = Code.LCNC_EXPRESSION, column: int | None = None
    ) -> None:
        super().__init__(message)
        self.message, self.index, self.code = message, index, code
        self.column = column  # a column in the file, when the error is found before normalising


@dataclass(frozen=True, slots=True)
class NgcLine:
    """A normalised line: ``text`` lower-case without blanks or comments; ``cols[i]`` the 1-based
    column of ``text[i]`` in the file (``cols[len(text)]`` is one past the last character)."""

    text: str
    cols: tuple[int, ...]
    comment: str | None = None  # the last ( ) comment of the line, as written (LinuxCNC keeps only it)

    def col(self, index: int) -> int:
        return self.cols[min(max(index, 0), len(self.cols) - 1)]


_BLANKS = " \t\r\n\f\v"
_DROP_BLANKS = str.maketrans("", "", _BLANKS)
# an ASCII line's shape: its blanks kept, every other character an "x" (the columns of its
# characters without blanks depend on nothing else); the columns of recent shapes, and whether
# the shape's blanks are all spaces
_SHAPE = bytes(c if chr(c) in _BLANKS else ord("x") for c in range(256))
_COLUMNS: dict[bytes, tuple[tuple[int, ...], bool]] = {}
_COLUMNS_KEPT = 4096


def normalise(raw: str) -> NgcLine:
    """LinuxCNC's ``close_and_downcase`` (comments dropped rather than kept)."""
    if raw.isascii() and "(" not in raw and ";" not in raw:
        # the common line without comments: the same text, and the columns of a line read before
        # with the same blanks at the same places (the same shape), without a loop per character
        shape = raw.encode("ascii").translate(_SHAPE)
        known = _COLUMNS.get(shape)
        if known is None:
            found = [i for i, c in enumerate(raw, 1) if c not in _BLANKS]
            found.append((found[-1] + 1) if found else 1)
            known = (tuple(found), not any(b in shape for b in b"\t\r\n\f\v"))
            if len(_COLUMNS) >= _COLUMNS_KEPT:
                _COLUMNS.clear()
            _COLUMNS[shape] = known
        text = raw.replace(" ", "") if known[1] else raw.translate(_DROP_BLANKS)
        return NgcLine(text.lower(), known[0], None)
    out: list[str] = []
    cols: list[int] = []
    comment: str | None = None
    i, n = 0, len(raw)
    while i < n:
        c = raw[i]
        if c == ";":
            break
        if c == "(":
            close = raw.find(")", i + 1)
            if close < 0:
                raise NgcError("Unclosed comment found", 0, Code.NC_SYNTAX, i + 1)
            if "(" in raw[i + 1 : close]:
                raise NgcError("Nested comment found", 0, Code.NC_SYNTAX, i + 2 + raw[i + 1 : close].index("("))
            comment = raw[i + 1 : close]
            i = close + 1
            continue
        if c not in " \t\r\n\f\v":
            out.append(c.lower())
            cols.append(i + 1)
        i += 1
    cols.append((cols[-1] + 1) if cols else 1)
    return NgcLine("".join(out), tuple(cols), comment)


@dataclass(slots=True)
class Parameters:
    """LinuxCNC's parameter store: numbered, global named and per-call local named parameters."""

    numbered: list[float] = field(default_factory=lambda: [0.0] * MAX_PARAMETERS)
    globals: dict[str, float] = field(default_factory=dict)
    frames: list[dict[str, float]] = field(default_factory=lambda: [{}])  # locals of each call level
    # the predefined read-only parameters (#<_x>, #<_metric>…) the reader models: name -> value
    # (None: not one of them); raises NgcError where LinuxCNC's value is not modelled
    readonly: Callable[[str], float | None] | None = None
    comp_on: bool = False  # #5420…#5428 cannot be read while cutter radius compensation is on

    def get_named(self, name: str) -> float | None:
        if name.startswith("_"):
            if self.readonly is not None and name in _PREDEFINED:
                value = self.readonly(name)
                if value is not None:
                    return value
            return self.globals.get(name)
        return self.frames[-1].get(name)

    def set_named(self, name: str, value: float) -> None:
        (self.globals if name.startswith("_") else self.frames[-1])[name] = value

    def check_index(self, index: int, at: int) -> None:
        if not 1 <= index < MAX_PARAMETERS:
            raise NgcError("Parameter number out of range", at, Code.LCNC_PARAMETER)


def read_integer(value: float, at: int) -> int:
    """LinuxCNC's ``read_integer_value`` test: within 1e-4 of a whole number."""
    n = math.floor(value)
    if value - n > 0.9999:
        return math.ceil(value)
    if value - n > 0.0001:
        raise NgcError("Non integer value for integer", at)
    return int(n)


class ValueReader:
    """Reads values from a normalised line at ``pos`` (LinuxCNC's ``read_real_value`` family)."""

    def __init__(self, text: str, params: Parameters, pos: int = 0, defining_sub: bool = False) -> None:
        self.text, self.params, self.pos = text, params, pos
        self.defining_sub = defining_sub

    def _peek(self, k: int = 0) -> str:
        j = self.pos + k
        return self.text[j] if j < len(self.text) else ""

    def _starts(self, word: str) -> bool:
        return self.text.startswith(word, self.pos)

    # -- values -------------------------------------------------------------------------------
    def value(self) -> float:
        at = self.pos
        plain = _PLAIN_NUMBER.match(self.text, at)
        if plain is not None:
            # a plain decimal number not followed by more digits or points: what number() reads
            end = plain.end()
            if end == len(self.text) or self.text[end] not in _DIGITS_POINT:
                v = float(plain.group())
                if math.isinf(v):
                    raise NgcError("Calculation resulted in 'infinity'", at)
                self.pos = end
                return v
        c, c1 = self._peek(), self._peek(1)
        if c == "":
            raise NgcError("No characters found in reading real value", at, Code.NC_SYNTAX)
        if c == "[":
            v = self.expression()
        elif c == "#":
            v = self.parameter()
        elif c in "+-" and c1 and not c1.isdigit() and c1 != ".":
            self.pos += 1
            v = self.value()
            v = -v if c == "-" else v
        elif "a" <= c <= "z":
            v = self.function()
        else:
            v = self.number()
        if math.isnan(v):
            raise NgcError("Calculation resulted in 'not a number'", at)
        if math.isinf(v):
            raise NgcError("Calculation resulted in 'infinity'", at)
        return v

    def number(self) -> float:
        """LinuxCNC's ``read_real_number``: signs, then digits and points."""
        start = self.pos
        token = _NUMBER_CHARS.match(self.text, start).group(0)  # type: ignore[union-attr]
        self.pos = start + len(token)
        body = token.lstrip("+-")
        signs = len(token) - len(body)
        whole = _DECIMAL.match(body)
        if signs > 1 or whole is None:
            raise NgcError(f"bad number format (conversion failed) parsing '{token}'", start, Code.NC_SYNTAX)
        if whole.end() != len(body):
            raise NgcError(f"bad number format (trailing characters) parsing '{token}'", start, Code.NC_SYNTAX)
        return float(token)

    def parameter(self) -> float:
        at = self.pos
        self.pos += 1  # '#'
        if self._peek() == "<":
            name = self.name()
            value = self.params.get_named(name)
            if value is None:
                if name in _PREDEFINED:
                    raise NgcError(f"the predefined parameter #<{name}> is not modelled", at, Code.NC_UNSUPPORTED)
                if self.defining_sub:
                    return 0.0
                raise NgcError(f"Named parameter #<{name}> not defined", at, Code.LCNC_PARAMETER)
            return value
        index = read_integer(self.value(), at)
        self.params.check_index(index, at)
        if 5420 <= index <= 5428 and self.params.comp_on:
            raise NgcError("Cannot read current position with cutter radius compensation on", at, Code.LCNC_PARAMETER)
        return self.params.numbered[index]

    def name(self) -> str:
        """``<name>`` at ``pos`` (LinuxCNC's ``read_name``), without the brackets."""
        close = self.text.find(">", self.pos)
        if close < 0:
            raise NgcError("Named parameter not terminated", self.pos, Code.NC_SYNTAX)
        name = self.text[self.pos + 1 : close]
        self.pos = close + 1
        return name

    def expression(self) -> float:
        """``[ … ]``: values joined by binary operators, each level left to right."""
        at = self.pos
        self.pos += 1  # '['
        values = [self.value()]
        ops: list[str] = []
        while True:
            op = self._operation()
            if op == "]":
                break
            while ops and _BINARY[ops[-1]] >= _BINARY[op]:
                right = values.pop()
                values[-1] = _binary(values[-1], ops.pop(), right, at)
            ops.append(op)
            values.append(self.value())
        while ops:
            right = values.pop()
            values[-1] = _binary(values[-1], ops.pop(), right, at)
        return values[0]

    def _operation(self) -> str:
        c = self._peek()
        at = self.pos
        if c == "]":
            self.pos += 1
            return "]"
        if self._starts("**"):
            self.pos += 2
            return "**"
        if c and c in "*/+-":
            self.pos += 1
            return c
        for word in _WORD_OPS:
            if self._starts(word):
                self.pos += len(word)
                return word
        if c and c in "aeglmnox":
            raise NgcError(f"Unknown operation name starting with {c}", at, Code.NC_SYNTAX)
        raise NgcError("Unknown operation", at, Code.NC_SYNTAX)

    def function(self) -> float:
        at = self.pos
        for name in _FUNCTIONS:
            if self._starts(name):
                break
        else:
            raise NgcError(f"Unknown word starting with {self._peek()}", at, Code.NC_SYNTAX)
        self.pos += len(name)
        if self._peek() != "[":
            raise NgcError("Left bracket missing after unary operation name", at, Code.NC_SYNTAX)
        if name == "exists":
            return self._exists()
        arg = self.expression()
        if name == "atan":
            if self._peek() != "/":
                raise NgcError("Slash missing after first atan argument", self.pos, Code.NC_SYNTAX)
            self.pos += 1
            if self._peek() != "[":
                raise NgcError("Left bracket missing after slash with atan", self.pos, Code.NC_SYNTAX)
            return math.degrees(math.atan2(arg, self.expression()))
        return _unary(name, arg, at)

    def _exists(self) -> float:
        self.pos += 1  # '['
        if self._peek() != "#":
            raise NgcError("Expected # reading parameter", self.pos, Code.NC_SYNTAX)
        at = self.pos
        self.pos += 1
        if self._peek() == "<":
            found = self.params.get_named(self.name()) is not None
        else:
            index = read_integer(self.value(), at)
            found = 1 <= index < MAX_PARAMETERS
        if self._peek() != "]":
            raise NgcError("Expected ] reading bracketed parameter", self.pos, Code.NC_SYNTAX)
        self.pos += 1
        return 1.0 if found else 0.0


def _binary(left: float, op: str, right: float, at: int) -> float:
    if op == "/":
        if right == 0.0:
            raise NgcError("Attempt to divide by zero", at)
        return left / right
    if op == "mod":
        if right == 0.0:
            return math.nan  # C fmod(x, 0): "Calculation resulted in 'not a number'"
        r = math.fmod(left, right)
        return r + abs(right) if r < 0.0 else r
    if op == "**":
        if left < 0.0 and math.floor(right) != right:
            raise NgcError("Attempt to raise negative to non integer power", at)
        try:
            return math.pow(left, right)
        except (OverflowError, ValueError):  # C pow: overflow or 0 ** negative
            return math.inf
    if op == "*":
        return left * right
    if op == "+":
        return left + right
    if op == "-":
        return left - right
    a, b = left != 0.0, right != 0.0
    close = abs(left - right) < TOLERANCE_EQUAL
    result = {
        "and": a and b,
        "or": a or b,
        "xor": a != b,
        "eq": close,
        "ne": not close,
        "lt": left < right,
        "gt": left > right,
        "le": close or left <= right,
        "ge": close or left >= right,
    }[op]
    return 1.0 if result else 0.0


def _unary(name: str, x: float, at: int) -> float:
    if name in ("asin", "acos"):
        if not -1.0 <= x <= 1.0:
            raise NgcError(f"Argument to {name} out of range", at)
        return math.degrees(math.asin(x) if name == "asin" else math.acos(x))
    if name == "ln":
        if x <= 0.0:
            raise NgcError("Zero or negative argument to ln", at)
        return math.log(x)
    if name == "sqrt":
        if x < 0.0:
            raise NgcError("Negative argument to sqrt", at)
        return math.sqrt(x)
    if name == "exp":
        try:
            return math.exp(x)
        except OverflowError:
            return math.inf
    if name == "round":
        return float(math.trunc(x + (-0.5 if x < 0.0 else 0.5)))
    simple: dict[str, Callable[[float], float]] = {
        "abs": abs,
        "fix": math.floor,
        "fup": math.ceil,
        "sin": lambda v: math.sin(math.radians(v)),
        "cos": lambda v: math.cos(math.radians(v)),
        "tan": lambda v: math.tan(math.radians(v)),
    }
    return float(simple[name](x))
