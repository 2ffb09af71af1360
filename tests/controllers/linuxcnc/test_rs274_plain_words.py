"""The one-pass reading of plain lines (letters with plain numbers) and of lines whose blanks are
spaces against the general word-by-word reading: the same words, values, columns, parameter
settings and errors on varied lines."""

from __future__ import annotations

import math
import random

import pytest

from trcopt.controllers.linuxcnc.ngc_block import block_number, read_words, read_words_general
from trcopt.controllers.linuxcnc.ngc_expr import NgcError, NgcLine, Parameters, normalise
from trcopt.controllers.linuxcnc.reader import read_rs274

EDGE_LINES = [
    "G1 X1. Y.5 Z-0",
    "g1 x+1 y-2.25 f600",
    "G1X1Y2Z3",
    "N10 G1 X1 Y2",
    "n20g2x1y1i.5j0",
    "  G1   X 1 . 5   Y - 2 ",
    "G1 X1.5.2",
    "G1 X1..",
    "G1 X--1",
    "G1 X+-1",
    "G1 X-+1",
    "G1 X-.",
    "G1 X.",
    "G1 X",
    "G1 X1e5",
    "G1 X1E5",
    "G1 X1" + "0" * 400,
    "G1 X-1" + "0" * 400 + ".5",
    "G1 X0." + "0" * 400 + "1",
    "G1 X#1",
    "#1=2 G1 X#1",
    "G1 X[1+2]",
    "G1 X-[1]",
    "G1 Xsin[0]",
    "G1 X1 Y2 ; comment",
    "G1 X1 (comment) Y2",
    "G1\tX1\tY2",
    "G1 X1 Y2\r",
    "G1 X1 U2",
    "G1 X1 E2",
    "G1 X1 O2",
    "G1 X1 $2",
    "G1 X1 Y2 N5",
    "M3 S1000",
    "G41.1 D2 G1 X4244.13182 Y0.00000",
    "x00001.00000y-000.0",
    "G1 X1 Y2 Z3 X4",
    "",
    "   ",
    "n",
    "n5",
    "n5 ",
]

_LETTERS = "abcdfghijklmnpqrstuvwxyzABCDFGHIJKLMNPQRSTUVWXYZeEoO"
_NUMBER_PARTS = ["0", "1", "25", "007", ".", "..", "+", "-", "--", " ", "\t", "e", "#", "[", "]"]


def _random_line(r: random.Random) -> str:
    words = []
    for _ in range(r.randrange(0, 6)):
        letter = r.choice(_LETTERS)
        if r.random() < 0.8:
            sign = r.choice(["", "", "+", "-"])
            whole = "".join(r.choice("0123456789") for _ in range(r.randrange(0, 4)))
            frac = r.choice(["", ".", "." + "".join(r.choice("0123456789") for _ in range(r.randrange(1, 5)))])
            number = sign + whole + frac
        else:
            number = "".join(r.choice(_NUMBER_PARTS) for _ in range(r.randrange(0, 4)))
        words.append(letter + number)
    sep = r.choice(["", " ", "  ", "\t", " \t"])
    line = sep.join(words)
    if r.random() < 0.2:
        line = f"N{r.randrange(1000)} " + line
    if r.random() < 0.1:
        line = " " + line + " "
    return line


def _outcome(fn, line: NgcLine, start: int):
    params = Parameters()
    params.numbered[1] = 3.5
    try:
        block = fn(line, start, params)
    except NgcError as exc:
        return ("error", exc.message, exc.index, exc.code, exc.column)
    words = [(k, v, math.copysign(1.0, v), c) for k, v, c in block.words]
    return ("ok", words, block.settings, block.comment, params.numbered[1])


def _both(raw: str):
    try:
        line = normalise(raw)
        _, start = block_number(line)
    except NgcError:
        return None
    return _outcome(read_words, line, start), _outcome(read_words_general, line, start)


@pytest.mark.parametrize("raw", EDGE_LINES)
def test_plain_line_reading_equals_the_general_reading_on_edge_lines(raw: str) -> None:
    both = _both(raw)
    if both is not None:
        assert both[0] == both[1]


def test_plain_line_reading_equals_the_general_reading_on_random_lines() -> None:
    r = random.Random(20260)
    compared = plain = 0
    for _ in range(20_000):
        both = _both(_random_line(r))
        if both is None:
            continue
        fast, general = both
        assert fast == general
        compared += 1
        plain += fast[0] == "ok"
    assert compared > 10_000 and plain > 2_000  # both kinds of line were compared


def _columns_one_by_one(raw: str) -> tuple[int, ...]:
    cols = [i for i, c in enumerate(raw, 1) if c not in " \t\r\n\f\v"]
    cols.append((cols[-1] + 1) if cols else 1)
    return tuple(cols)


def test_normalised_columns_equal_the_columns_character_by_character() -> None:
    r = random.Random(7)
    lines = ["", " ", "  ", "G1", " G1 ", "G1  X1", "G1\tX1", "G1 \tX1 ", "\r", "a b  c   d"]
    for _ in range(5_000):
        lines.append("".join(r.choice("gx1. -\t\r\f\v  ") for _ in range(r.randrange(0, 30))))
    for raw in lines:
        line = normalise(raw)
        assert line.cols == _columns_one_by_one(raw), repr(raw)
        assert line.text == "".join(c for c in raw if c not in " \t\r\n\f\v").lower()


def test_programs_of_plain_and_general_lines_read_alike() -> None:
    """A program read as written and with every line made non-plain (a trailing parameter
    setting of an unused parameter read by the general path) gives the same moves."""
    r = random.Random(3)
    lines = ["G21 G17 G90 G40 F600", "G0 X0 Y0 Z1", "G1 Z0", "G41.1 D2 G1 X10 Y0"]
    x, y = 10.0, 0.0
    for k in range(300):
        x, y = x + r.uniform(0.1, 2.0), y + r.uniform(-1.0, 1.0)
        word = r.choice(["G1 X{:.4f} Y{:.4f}", "g1x{:.3f}y{:.3f}", "X{:.5f} Y{:.5f}", "G1 X {:.2f} Y {:.2f}"])
        lines.append(word.format(x, y))
        if k % 50 == 25:
            lines.append(f"G2 X{x + 2:.4f} Y{y:.4f} I1 J0")
            x += 2
    lines += [f"G40 G1 X{x + 5:.3f} Y{y + 5:.3f}", "M2"]
    plain = read_rs274("\n".join(lines) + "\n", file="p.ngc")
    general = read_rs274("\n".join(line + " #4999=0" for line in lines) + "\n", file="p.ngc")
    assert plain.diagnostics == general.diagnostics
    assert [(m.kind, m.start, m.end, m.center, m.actions, m.comp) for m in plain.moves] == [
        (m.kind, m.start, m.end, m.center, m.actions, m.comp) for m in general.moves
    ]
