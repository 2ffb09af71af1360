"""A program read whole and read block by block: the same moves, diagnostics, blocks and extras."""

from __future__ import annotations

from pathlib import Path

from trcopt import controllers


def read_both_ways(source: str | Path, dialect: str, file: str | None = None) -> tuple[object, list[object]]:
    """Read ``source`` both ways in ``dialect``; assert they agree; (the whole program, the streamed moves)."""
    kw = {"file": file} if file else {}
    whole = controllers.read_program(source, dialect=dialect, **kw)  # type: ignore[arg-type]
    stream = controllers.stream_program(source, dialect=dialect, **kw)  # type: ignore[arg-type]
    moves = list(stream)
    prog = stream.program
    assert moves == list(whole.moves)
    assert prog.diagnostics == whole.diagnostics
    assert prog.blocks == whole.blocks
    assert prog.extras == whole.extras
    return whole, moves
