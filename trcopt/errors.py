"""One error tree for trcopt, and the diagnostics (controller alarms, warnings) with source spans.

Every failure a user can cause (a bad program, a bad machine file, an infeasible problem) is a
``TrcoptError``; leaves also inherit the matching builtin so ``except ValueError`` keeps working.
Controller alarms are :class:`Diagnostic` values; an error-severity diagnostic stops a plan the way
the controller would (:class:`AlarmError` carries it).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field

from trcopt.codes import Code

__all__ = [
    "Severity",
    "SourceSpan",
    "Diagnostic",
    "TrcoptError",
    "NcSyntaxError",
    "NcUnsupportedError",
    "ConfigError",
    "GeometryError",
    "AlarmError",
    "SolverError",
    "TimingError",
]


class Severity(enum.Enum):
    """How serious a diagnostic is: ``ERROR`` stops the plan, the others are collected."""

    INFO = "info"
    WARNING = "warning"
    ERROR = "error"


@dataclass(frozen=True, slots=True, init=False)
class SourceSpan:
    """Where something came from: file, 1-based line and column, and the block number (``N60``).

    A frozen dataclass made by ``__new__`` (see :class:`_SpanSlots`): every block of a program
    gets one, and the dataclass constructor, which sets each field through
    ``object.__setattr__``, costs three times as much.
    """

    file: str = "<program>"
    line: int = 0
    column: int = 0
    block: str | None = None
    end_column: int | None = None
    #: a block in machine coordinates (SINUMERIK G53/G153/SUPA): the programmed machine position of
    #: each axis (None: not programmed); the G-code writer writes the block as such
    machine: tuple[float | None, float | None, float | None] | None = None
    #: how many times the block ran before (loops, jumps, repetitions, subprogram calls; 0 the first
    #: time): tells the runs of one block apart
    run: int = 0

    def __new__(
        cls,
        file: str = "<program>",
        line: int = 0,
        column: int = 0,
        block: str | None = None,
        end_column: int | None = None,
        machine: tuple[float | None, float | None, float | None] | None = None,
        run: int = 0,
    ) -> SourceSpan:
        span = _SpanSlots()
        span.file, span.line, span.column, span.block = file, line, column, block
        span.end_column, span.machine, span.run = end_column, machine, run
        span.__class__ = cls  # type: ignore[assignment]
        return span  # type: ignore[return-value]

    def label(self) -> str:
        """``file:line:col`` as compilers print it (just ``file`` when there is no position)."""
        if not self.line:
            return self.file
        return f"{self.file}:{self.line}:{self.column}"

    def block_label(self) -> str:
        """The block number if there is one, else ``line <n>``."""
        return self.block if self.block else f"line {self.line}"


class _SpanSlots:
    """The slots of :class:`SourceSpan` (the same layout) without its frozen ``__setattr__``: a
    span is filled in as one of these, then becomes a :class:`SourceSpan`."""

    __slots__ = SourceSpan.__slots__
    file: str
    line: int
    column: int
    block: str | None
    end_column: int | None
    machine: tuple[float | None, float | None, float | None] | None
    run: int


@dataclass(frozen=True, slots=True)
class Diagnostic:
    """A controller alarm, warning or note tied to a source span.

    ``code`` is a stable code of :class:`~trcopt.codes.Code` (the alarm number for controller
    alarms, e.g. ``"10763"``, or a trcopt code such as ``"TRC-CONTOUR-VIOLATION"``; given as text it
    is looked up, and a code that is not catalogued is rejected); ``alarm`` is the controller's
    number when there is one.
    """

    severity: Severity
    code: Code
    message: str
    span: SourceSpan = field(default_factory=SourceSpan)
    alarm: int | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "code", Code(self.code))

    def format(self) -> str:
        """Compiler-style one-liner: ``prog.mpf:6:1: warning 10763 (N60): message``."""
        kind = self.severity.value
        code = str(self.alarm) if self.alarm is not None else self.code
        block = f" ({self.span.block})" if self.span.block else ""
        return f"{self.span.label()}: {kind} {code}{block}: {self.message}"

    def to_json(self) -> dict[str, object]:
        return {
            "severity": self.severity.value,
            "code": self.code,
            "alarm": self.alarm,
            "message": self.message,
            "line": self.span.line,
            "column": self.span.column,
            "block": self.span.block,
        }


def alarm(number: int, message: str, span: SourceSpan, severity: Severity = Severity.ERROR) -> Diagnostic:
    """A controller alarm with its number as code."""
    return Diagnostic(severity, Code(str(number)), message, span, number)


class TrcoptError(Exception):
    """Root of every error trcopt raises on purpose."""

    def __init__(self, message: str, span: SourceSpan | None = None, code: Code | str = Code.TRCOPT) -> None:
        super().__init__(message)
        self.message = message
        self.span = span
        self.code = Code(code)  # a code that is not catalogued is a programming error (ValueError)

    def __str__(self) -> str:
        if self.span is not None and self.span.line:
            block = f" ({self.span.block})" if self.span.block else ""
            return f"{self.span.label()}{block}: {self.message}"
        return self.message

    def to_diagnostic(self) -> Diagnostic:
        return Diagnostic(Severity.ERROR, self.code, self.message, self.span or SourceSpan())

    def format(self, file: str | None = None) -> str:
        """The error as a diagnostic line, ``file:line:col: error CODE (N…): message``; an error
        without a position in a file is placed at ``file`` (the file it concerns, else ``trcopt``)."""
        span = self.span
        if span is None or (not span.line and span.file == "<program>"):
            span = SourceSpan(file or "trcopt")
        return Diagnostic(Severity.ERROR, self.code, self.message, span).format()


class NcSyntaxError(TrcoptError, ValueError):
    """The part program cannot be read (bad word, bad number, unbalanced brackets, truncated)."""

    def __init__(self, message: str, span: SourceSpan | None = None, code: Code | str = Code.NC_SYNTAX) -> None:
        super().__init__(message, span, code)


class NcUnsupportedError(TrcoptError, NotImplementedError):
    """The program uses a feature trcopt does not implement (named in the message)."""

    def __init__(self, message: str, span: SourceSpan | None = None, code: Code | str = Code.NC_UNSUPPORTED) -> None:
        super().__init__(message, span, code)


class ConfigError(TrcoptError, ValueError):
    """A machine, tool-table or settings file is invalid (names the key)."""

    def __init__(self, message: str, span: SourceSpan | None = None, code: Code | str = Code.CONFIG) -> None:
        super().__init__(message, span, code)


class GeometryError(TrcoptError, ValueError):
    """Invalid geometry (zero-length element, arc whose end radius does not match, ...)."""

    def __init__(self, message: str, span: SourceSpan | None = None, code: Code | str = Code.GEOMETRY) -> None:
        super().__init__(message, span, code)


class AlarmError(TrcoptError, RuntimeError):
    """An error-severity controller alarm stopped the plan; ``diagnostic`` holds it."""

    def __init__(self, diagnostic: Diagnostic) -> None:
        super().__init__(diagnostic.message, diagnostic.span, diagnostic.code)
        self.diagnostic = diagnostic

    def to_diagnostic(self) -> Diagnostic:
        return self.diagnostic


class SolverError(TrcoptError, RuntimeError):
    """An optimisation problem failed (infeasible, solver error); names the binding constraint."""

    def __init__(self, message: str, span: SourceSpan | None = None, code: Code | str = Code.SOLVER) -> None:
        super().__init__(message, span, code)


class TimingError(TrcoptError, RuntimeError):
    """Time parameterisation failed for a section (names section, s and source block)."""

    def __init__(self, message: str, span: SourceSpan | None = None, code: Code | str = Code.TIMING) -> None:
        super().__init__(message, span, code)
