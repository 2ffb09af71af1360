"""A program's moves as they are read: :class:`MoveStream`.

A reader that can run block by block (:attr:`trcopt.controllers.base.Controller.stream`) gives
its moves one at a time, so a program of a million blocks is never held as a list of moves; the
range check of :func:`trcopt.nc.limits.check_moves` is applied to each move as it passes (the
stream stops at the first move out of range, with its ``NC-RANGE`` error; the reader still runs to
the program's end for its block count and extras, and the diagnostics of later blocks are dropped
as ``check_moves`` drops them). When the stream is exhausted,
:attr:`MoveStream.program` is the :class:`~trcopt.nc.model.NcProgram` the reader would have
returned, without its moves.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field

from trcopt.codes import Code
from trcopt.errors import Diagnostic, Severity
from trcopt.nc.limits import out_of_range
from trcopt.nc.model import Move, NcProgram

__all__ = ["MoveStream", "ReadSummary"]


@dataclass(slots=True)
class ReadSummary:
    """What a reader knows once its moves are exhausted."""

    diagnostics: list[Diagnostic]
    blocks: int
    extras: dict[str, object] = field(default_factory=dict)


class MoveStream(Iterator[Move]):
    """Iterator of a program's moves; :attr:`program` once it is exhausted.

    Parameters
    ----------
    file, dialect:
        As :class:`~trcopt.nc.model.NcProgram`.
    moves:
        The reader's moves in program order (a generator).
    finish:
        Called once, when ``moves`` is exhausted: the reader's diagnostics, blocks and extras.
    """

    def __init__(self, file: str, dialect: str, moves: Iterable[Move], finish: Callable[[], ReadSummary]) -> None:
        self.file, self.dialect = file, dialect
        self._moves = iter(moves)
        self._finish = finish
        self._range: Diagnostic | None = None
        self._program: NcProgram | None = None

    def __iter__(self) -> MoveStream:
        return self

    def __next__(self) -> Move:
        if self._program is not None:
            raise StopIteration
        move = next(self._moves, None)
        if move is not None:
            problem = out_of_range(move)
            if problem is None:
                return move
            self._range = Diagnostic(Severity.ERROR, Code.NC_RANGE, problem, move.span)
            for _ in self._moves:  # the reader runs to its end, as read_program's does (blocks, extras)
                pass
        self._end()
        raise StopIteration

    def _end(self) -> None:
        summary = self._finish()
        diags = summary.diagnostics
        if self._range is not None:  # as check_moves: the blocks after the offending one are not run
            line = max(self._range.span.line, 1)
            diags = [d for d in diags if d.span.line < line or not d.span.line] + [self._range]
        self._program = NcProgram(self.file, self.dialect, (), tuple(diags), summary.blocks, summary.extras)

    @property
    def failed(self) -> bool:
        """An error-severity diagnostic so far (the reader's ones are known at the end)."""
        return self._range is not None or (
            self._program is not None and any(d.severity is Severity.ERROR for d in self._program.diagnostics)
        )

    @property
    def program(self) -> NcProgram:
        """The program without its moves (diagnostics, blocks, extras); read to the end first."""
        if self._program is None:
            for _ in self:
                pass
        assert self._program is not None
        return self._program

    @classmethod
    def of(cls, program: NcProgram) -> MoveStream:
        """The stream of a program read whole (a reader that cannot stream)."""
        summary = ReadSummary(list(program.diagnostics), program.blocks, program.extras)
        return cls(program.file, program.dialect, program.moves, lambda: summary)
