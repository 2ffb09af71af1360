"""The rs274 reader block by block (``controllers.stream_program``) gives the moves, diagnostics
and block count of the whole-program read (``controllers.read_program``), errors included."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from trcopt import controllers
from trcopt.codes import Code
from trcopt.errors import Severity

sys.path.insert(0, str(Path(__file__).resolve().parent))
from rs274diff import SIM_TBL as TABLE  # noqa: E402
from rs274gen import program  # noqa: E402


def _both(text: str, **kw: object) -> tuple[object, object, object]:
    whole = controllers.read_program(text, file="p.ngc", dialect="rs274", **kw)  # type: ignore[arg-type]
    stream = controllers.stream_program(text, file="p.ngc", dialect="rs274", **kw)  # type: ignore[arg-type]
    moves = list(stream)
    return whole, moves, stream.program


@pytest.mark.parametrize("seed", range(40))
def test_random_programs_stream_as_read(seed: int) -> None:
    kw = {"tool_table": str(TABLE), "tool_unit": "inch"} if TABLE.exists() else {}
    whole, moves, prog = _both(program(seed), **kw)
    assert moves == list(whole.moves)  # type: ignore[attr-defined]
    assert prog.diagnostics == whole.diagnostics  # type: ignore[attr-defined]
    assert prog.blocks == whole.blocks  # type: ignore[attr-defined]


def test_the_moves_of_an_erroneous_block_are_kept_as_read_keeps_them() -> None:
    text = "G21 G90\nG1 F600 X10 Y0\nG1 X20 Y5\nG1 X30 Q\nG1 X40\nM2\n"
    whole, moves, prog = _both(text)
    assert moves == list(whole.moves) and len(moves) >= 3  # type: ignore[attr-defined]
    assert [d.code for d in prog.diagnostics] == [d.code for d in whole.diagnostics]  # type: ignore[attr-defined]
    assert any(d.severity is Severity.ERROR and d.span.line == 4 for d in prog.diagnostics)  # type: ignore[attr-defined]


def test_a_move_out_of_range_ends_the_stream_with_its_error() -> None:
    text = "G21 G90\nG1 F600 X10\n(MSG, later)\nG1 X10000000\n(MSG, after)\nG1 X5\nM2\n"
    whole, moves, prog = _both(text)
    assert moves == list(whole.moves)  # type: ignore[attr-defined]
    assert prog.diagnostics == whole.diagnostics  # type: ignore[attr-defined]
    assert prog.diagnostics[-1].code == Code.NC_RANGE and prog.diagnostics[-1].span.line == 4  # type: ignore[attr-defined]
    assert not any("after" in d.message for d in prog.diagnostics)  # type: ignore[attr-defined]


def test_a_reader_that_cannot_stream_is_streamed_from_its_list() -> None:
    """A controller without ``stream`` (here the SINUMERIK one with it taken away) is read whole
    and its moves are streamed from the list."""
    import dataclasses

    text = "N10 G90 G0 X0 Y0\nN20 G1 X10 F100\nN30 M30\n"
    whole = controllers.read_program(text, file="p.mpf", dialect="siemens")
    plain = dataclasses.replace(controllers.get("siemens"), name="siemens-whole", dialect="siemens-whole", stream=None)
    controllers.register(plain)
    try:
        stream = controllers.stream_program(text, file="p.mpf", dialect="siemens-whole")
        assert list(stream) == list(whole.moves) and stream.program.blocks == whole.blocks
    finally:
        controllers.unregister("siemens-whole")
