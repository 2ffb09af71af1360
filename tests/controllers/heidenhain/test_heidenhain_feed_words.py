"""Heidenhain feeds that depend on the spindle or the tool (FU per revolution, FZ per tooth, M136 F per
revolution) are not modelled: the program stops at the word, never timed as mm/min."""

from __future__ import annotations

import pytest

from trcopt.controllers import read_program
from trcopt.errors import Severity


@pytest.mark.parametrize(
    ("block", "word", "what"),
    [
        ("L X+10 FU0.2", "FU0.2", "feed per spindle revolution"),
        ("L X+10 FZ0.05", "FZ0.05", "feed per tooth"),
        ("L X+10 F0.2 M136", "M136", "feed rate F per spindle revolution"),
    ],
)
def test_feed_per_revolution_or_tooth_stops_the_program(block: str, word: str, what: str) -> None:
    text = (
        f"0 BEGIN PGM T MM\n1 TOOL DEF 1 L+0 R+2\n2 TOOL CALL 1 Z S1000\n3 L X+0 Y+0 FMAX\n4 {block}\n5 END PGM T MM\n"
    )
    prog = read_program(text, file="t.h", dialect="heidenhain")
    (err,) = [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert err.code == "HH-NOT-MODELLED" and what in err.message
    assert (err.span.line, err.span.column) == (5, text.splitlines()[4].index(word) + 1)
