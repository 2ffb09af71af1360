"""``SourceLines`` is ``str.splitlines()`` without the list (every line break it knows)."""

from __future__ import annotations

import random

import pytest

from trcopt.io.source_lines import SourceLines


@pytest.mark.parametrize(
    "text", ["", "a", "a\n", "a\nb", "\n", "\n\n", "a\r\nb\rc\x85d\u2028e", "x\r", "x\r\n\r\n", "N10 G1 X1\fY2\x1c"]
)
def test_lines_as_splitlines(text: str) -> None:
    lines = SourceLines(text)
    assert list(lines) == text.splitlines() and len(lines) == len(text.splitlines())
    assert lines[:2] == text.splitlines()[:2]


def test_random_texts() -> None:
    r = random.Random(7)
    for _ in range(2000):
        text = "".join(r.choice("ab \n\r\x0b\x85\u2029") for _ in range(r.randint(0, 40)))
        lines = SourceLines(text)
        assert list(lines) == text.splitlines()
        if len(lines):
            assert lines[-1] == text.splitlines()[-1]
    with pytest.raises(IndexError):
        SourceLines("a\nb")[2]
