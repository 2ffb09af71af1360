"""``TextLines`` is ``program_lines`` (the lines an editor numbers) without the list."""

from __future__ import annotations

import random

import pytest

from trcopt.nc.text import program_lines
from trcopt.textlines import TextLines


@pytest.mark.parametrize(
    "text", ["", "a", "a\n", "a\nb", "\n", "\n\n", "a\r\nb\rc\x85d\u2028e", "x\r", "x\r\n\r\n", "N10 G1 X1\fY2\x1c"]
)
def test_lines_as_program_lines(text: str) -> None:
    lines = TextLines(text)
    assert list(lines) == program_lines(text) and len(lines) == len(program_lines(text))
    assert lines[:2] == program_lines(text)[:2]


def test_random_texts() -> None:
    r = random.Random(7)
    for _ in range(2000):
        text = "".join(r.choice("ab \n\r\x0b\x85\u2029") for _ in range(r.randint(0, 40)))
        lines = TextLines(text)
        assert list(lines) == program_lines(text)
        if len(lines):
            assert lines[-1] == program_lines(text)[-1]
    with pytest.raises(IndexError):
        TextLines("a\nb")[2]


def test_the_whole_array_line_ends_of_an_ascii_text(monkeypatch: pytest.MonkeyPatch) -> None:
    import trcopt.textlines as textlines

    monkeypatch.setattr(textlines, "_VECTOR_FROM", 0)
    monkeypatch.setattr(textlines, "_CHUNK", 7)  # many chunks: every kind of line end meets a chunk end
    r = random.Random(11)
    for _ in range(3000):
        text = "".join(r.choice("ab \n\r") for _ in range(r.randint(0, 40)))
        assert list(TextLines(text)) == program_lines(text), repr(text)
    long = "".join(r.choice(["G1 X1\n", "G1 Y2\r\n", "(c)\r", "\n", " "]) for _ in range(30_000))
    assert list(TextLines(long)) == program_lines(long)


def test_iter_lines_as_program_lines() -> None:
    from trcopt.textlines import iter_lines

    r = random.Random(5)
    for _ in range(3000):
        text = "".join(r.choice("ab \n\r\x0c") for _ in range(r.randint(0, 30)))
        assert list(iter_lines(text)) == program_lines(text), repr(text)
