"""Line numbers count LF, CR LF and CR only, as an editor does: a form feed, a vertical tab or a
0x85 byte read as Latin-1 (NEL) inside a line no longer shifts every later line (fuzz finding)."""

from __future__ import annotations

import pytest

from trcopt.nc.text import program_lines
from trcopt.pipeline import PlanOptions, plan


def test_program_lines_splits_at_line_ends_only() -> None:
    assert program_lines("a\r\nb\rc\nd\x85e\x0cf\x0bg\x1ch\u2028i\n") == ["a", "b", "c", "d\x85e\x0cf\x0bg\x1ch\u2028i"]
    assert program_lines("") == [] and program_lines("x\n\n") == ["x", ""]


@pytest.mark.parametrize(
    ("text", "file"),
    [
        ("; title \x85 \x0c\r\nN10 G1 X1 F100\r\nN20 G1 X2 Q?\r\nM30\r\n", "p.mpf"),
        ("(title \x85 \x0c)\nN10 G1 X1 F100\nN20 G1 X2 @\nM2\n", "p.ngc"),
    ],
)
def test_errors_after_a_stray_separator_keep_the_editor_line(text: str, file: str) -> None:
    result = plan(text, file=file, options=PlanOptions(timing=False))
    err = result.errors[0]
    assert (err.span.line, err.span.block) == (3, "N20")
