"""Mutated part programs for the fuzz run: seeds from ``problems/`` in all three dialects.

A mutation is a seeded, deterministic edit of a correct program (a golden problem, or one of the
small RS274NGC programs below, since ``problems/`` holds no ``.ngc``): blocks deleted, duplicated
or swapped, numbers replaced by extremes (``1e300``, ``1e-300``, ``nan``, ``inf``, 1e12 mm
coordinates, 1e-12 mm moves), random words, random bytes, CRLF line ends, very long lines, deep or
unclosed comments and unicode. :func:`programs` yields ``(name, suffix, data)`` triples; the data
are bytes because some mutations are not text.
"""

from __future__ import annotations

import random
import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

__all__ = ["Seed", "FuzzProgram", "seeds", "mutate", "programs", "MUTATIONS", "ROOT"]

ROOT = Path(__file__).resolve().parents[2]

# RS274NGC seeds (the problems folder has none): a G41 square with D from the tool table, a G42.1
# contour with lines and arcs, a G41.1 circle pocket; lengths in mm (G21).
RS274_SEEDS: dict[str, str] = {
    "rs_square_g41": (
        "(square, G41 from the tool table)\nG21 G17 G90 F600\nT1 M6\nG0 X-20 Y-20\n"
        "G41 G1 X0 Y0\nG1 X40\nG1 Y40\nG1 X0\nG1 Y0\nG40 G1 X-20 Y-20\nM2\n"
    ),
    "rs_line_arc_g42": (
        "; lines and arcs, G42.1 with an explicit diameter\nG21 G17 G90\nG0 X0 Y-10 Z5\nG1 Z-1 F300\n"
        "G42.1 D6 G1 X0 Y0 F800\nG1 X30\nG2 X40 Y10 I0 J10\nG1 Y30\nG3 X30 Y40 I-10 J0\nG1 X0\n"
        "G1 Y0\nG40 G1 X-10 Y-10\nG0 Z5\nM2\n"
    ),
    "rs_circle_pocket": (
        "%\n(circle pocket)\nN10 G21 G90 G17\nN20 G0 X10 Y0\nN30 G41.1 D4 G1 X20 Y0 F500\n"
        "N40 G3 X20 Y0 I-20 J0\nN50 G40 G1 X10 Y0\nN60 M2\n%\n"
    ),
}
RS274_TOOL_TABLE = "T1 P1 D0.25 Z0 ;quarter-inch end mill\nT2 P2 D0.5 Z0\n"


@dataclass(frozen=True, slots=True)
class Seed:
    """A correct program to mutate: its name, file suffix and text."""

    name: str
    suffix: str
    text: str


@dataclass(frozen=True, slots=True)
class FuzzProgram:
    """One mutated program: a name saying how it was made, its suffix and its bytes."""

    name: str
    suffix: str
    data: bytes


def seeds() -> list[Seed]:
    """Every seed: the SINUMERIK and Heidenhain golden problems, the corner problems, RS274NGC."""
    out: list[Seed] = []
    for folder, pattern in (("siemens", "*.mpf"), ("heidenhain", "*.h"), ("corners", "*.mpf")):
        for path in sorted((ROOT / "problems" / folder).glob(pattern)):
            out.append(Seed(f"{folder}/{path.stem}", path.suffix, path.read_text(encoding="utf-8")))
    out.extend(Seed(f"rs274/{name}", ".ngc", text) for name, text in RS274_SEEDS.items())
    return out


_NUMBER = re.compile(r"(?<![A-Za-z_$\[])[-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?|(?<=[A-Z=])[-+]?\.\d+")
_EXTREMES = (
    "1e300", "-1e300", "1e-300", "-1e-300", "1e308", "1e309", "nan", "NaN", "inf", "-inf", "Infinity",
    "1e12", "-1e12", "1e-12", "0", "-0", "0.0000000001", "999999999999999999999", "1.7976931348623157e308",
    "1e+300", "12.34.56", "--5", "+", ".", "1e", "0x1F", "1_000", "٣",
)
_WORDS = (
    "G41", "G42", "G40", "G2", "G3", "G0", "G1", "KONT", "KONTC", "KONTT", "G450", "G451", "G147", "G247",
    "G347", "G148", "DISR=5", "DISCL=1", "D1", "D0", "T1", "F0", "F-5", "F1e300", "M30", "M2", "R0", "RL",
    "RR", "CR=", "AP=", "RP=", "I=AC(", "APPR", "DEP", "LT", "LN", "CT", "LCT", "LEN", "CC", "C", "CP",
    "RND", "CHF", "TOOL CALL", "TOOL DEF", "X", "Y", "Z", "IX+", "PR+", "PA+", "G41.1", "G42.1",
    "G91", "G90", "G20", "G21", "G17", "G18", "G19", "G64", "(", ")", ";", "[", "]", "#1=", "O100",
    "$TC_DP6[1,1]=", "$TC_DP1[1,1]=120", "N", "P", "Q", "L", "END PGM", "BEGIN PGM", "=", "*",
)
_UNICODE = ("Ø", "µ", "→", "ｘ", "\u200b", "\ufeff", "𝑋", "é", "\u0301", "\x00", "\x0c", "\t", "\r")


def _lines(text: str) -> list[str]:
    return text.splitlines()


def _delete(rng: random.Random, lines: list[str]) -> list[str]:
    if lines:
        for _ in range(rng.randint(1, 3)):
            if lines:
                del lines[rng.randrange(len(lines))]
    return lines


def _duplicate(rng: random.Random, lines: list[str]) -> list[str]:
    if lines:
        i = rng.randrange(len(lines))
        lines[i:i] = [lines[i]] * rng.randint(1, 3)
    return lines


def _swap(rng: random.Random, lines: list[str]) -> list[str]:
    if len(lines) > 1:
        i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
    return lines


def _replace_numbers(rng: random.Random, lines: list[str], choices: tuple[str, ...]) -> list[str]:
    for _ in range(rng.randint(1, 3)):
        if not lines:
            break
        i = rng.randrange(len(lines))
        found = list(_NUMBER.finditer(lines[i]))
        if found:
            m = rng.choice(found)
            lines[i] = lines[i][: m.start()] + rng.choice(choices) + lines[i][m.end() :]
    return lines


def _extreme(rng: random.Random, lines: list[str]) -> list[str]:
    return _replace_numbers(rng, lines, _EXTREMES)


def _huge(rng: random.Random, lines: list[str]) -> list[str]:
    return _replace_numbers(rng, lines, ("1e12", "-1e12", "1e9", "123456789012.5", "1e15"))


def _tiny(rng: random.Random, lines: list[str]) -> list[str]:
    """Moves of 1e-12 mm: a number nudged by a tiny amount, or a block repeated a hair apart."""
    if lines:
        i = rng.randrange(len(lines))
        found = list(_NUMBER.finditer(lines[i]))
        if found:
            m = rng.choice(found)
            try:
                value = float(m.group()) + rng.choice((1e-12, -1e-12, 1e-9))
            except ValueError:
                return lines
            lines.insert(i + 1, lines[i][: m.start()] + repr(value) + lines[i][m.end() :])
    return lines


def _random_words(rng: random.Random, lines: list[str]) -> list[str]:
    for _ in range(rng.randint(1, 4)):
        i = rng.randrange(len(lines) + 1)
        words = " ".join(rng.choice(_WORDS) + rng.choice(("", "", str(rng.randint(-99, 999)))) for _ in range(3))
        if i < len(lines) and rng.random() < 0.6:
            lines[i] = f"{lines[i]} {words}"
        else:
            lines.insert(i, words)
    return lines


def _long_line(rng: random.Random, lines: list[str]) -> list[str]:
    i = rng.randrange(len(lines) + 1)
    unit = rng.choice(("X1 ", "G1 X1 Y2 ", "A", "(", "; comment ", "N10 ", "9" * 50))
    lines.insert(i, unit * rng.randint(2_000, 20_000))
    return lines


def _comments(rng: random.Random, lines: list[str]) -> list[str]:
    i = rng.randrange(len(lines) + 1)
    depth = rng.randint(1, 3_000)
    text = rng.choice(("(" * depth + "x" + ")" * depth, "(" * depth, "(unclosed G41 X1", ";" * depth, "((a)b)c)"))
    if i < len(lines) and rng.random() < 0.5:
        lines[i] = lines[i] + text
    else:
        lines.insert(i, text)
    return lines


def _unicode(rng: random.Random, lines: list[str]) -> list[str]:
    for _ in range(rng.randint(1, 5)):
        if not lines:
            break
        i = rng.randrange(len(lines))
        j = rng.randrange(len(lines[i]) + 1)
        lines[i] = lines[i][:j] + rng.choice(_UNICODE) + lines[i][j:]
    return lines


MUTATIONS: dict[str, Callable[[random.Random, list[str]], list[str]]] = {
    "delete": _delete,
    "duplicate": _duplicate,
    "swap": _swap,
    "extreme": _extreme,
    "huge": _huge,
    "tiny": _tiny,
    "words": _random_words,
    "long": _long_line,
    "comments": _comments,
    "unicode": _unicode,
}


def mutate(seed: Seed, rng: random.Random) -> FuzzProgram:
    """One mutated program from ``seed``: one to three line mutations, then perhaps a byte-level one."""
    lines = _lines(seed.text)
    names = []
    for _ in range(rng.choice((1, 1, 2, 3))):
        name = rng.choice(list(MUTATIONS))
        names.append(name)
        lines = MUTATIONS[name](rng, lines)
    eol = "\r\n" if rng.random() < 0.15 else "\n"
    if eol == "\r\n":
        names.append("crlf")
    data = (eol.join(lines) + (eol if rng.random() < 0.9 else "")).encode("utf-8", "surrogatepass")
    roll = rng.random()
    if roll < 0.08:  # random bytes somewhere
        names.append("bytes")
        buf = bytearray(data)
        for _ in range(rng.randint(1, 20)):
            buf.insert(rng.randrange(len(buf) + 1), rng.randrange(256))
        data = bytes(buf)
    elif roll < 0.10:  # a binary file
        names.append("binary")
        data = bytes(rng.randrange(256) for _ in range(rng.randint(16, 4096)))
    elif roll < 0.12:  # another encoding
        names.append("utf16")
        data = data.decode("utf-8", "replace").encode("utf-16")
    return FuzzProgram(f"{seed.name}:{'+'.join(names)}", seed.suffix, data)


def programs(count: int, seed: int = 0) -> Iterator[FuzzProgram]:
    """``count`` mutated programs, deterministic for a given ``seed``, cycling over the seeds."""
    rng = random.Random(seed)
    pool = seeds()
    for i in range(count):
        yield mutate(pool[i % len(pool)], rng)
