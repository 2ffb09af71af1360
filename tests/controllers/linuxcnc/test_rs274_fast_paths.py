"""The fast paths of the rs274 reader and of LinuxCNC's compensation against their general paths.

* a plain motion line (``N… G0/G1 X… Y… Z… F…``) is executed without decoding its words
  (:mod:`trcopt.controllers.linuxcnc.ngc_plain`); with the pattern that finds such lines
  disabled every line is read and executed word by word — the same moves (every field, spans
  included), diagnostics and block count;
* the compensation sends the common contour move straight to its straight-move rule
  (``_block``); through the general dispatch (``_any_block``) the segments and diagnostics are
  the same;
* :func:`~trcopt.compensation.engine.programmed_segment` of a straight G17 move equals the
  general construction;
* the unit of a program (its first G20/G21) is found without normalising the lines that cannot
  hold one.

The programs are the stored random corpus of :mod:`rs274gen` and random programs made mostly of
plain lines in varied states (units, distance modes, planes, compensation, offsets, modal arcs
and cycles, a zero feed, loops, skipped lines, numbers too long for a float).
"""

from __future__ import annotations

import dataclasses
import json
import random
import sys
from pathlib import Path

import pytest

from trcopt.compensation import engine
from trcopt.controllers.linuxcnc import compensation, ngc_flow, reader
from trcopt.controllers.linuxcnc.compensation import compensate_linuxcnc
from trcopt.controllers.linuxcnc.ngc_expr import NgcError, normalise
from trcopt.controllers.linuxcnc.reader import read_rs274
from trcopt.nc.model import NcProgram

sys.path.insert(0, str(Path(__file__).resolve().parent))
from rs274diff import SETTINGS  # noqa: E402

CORPUS = Path(__file__).resolve().parents[2] / "data" / "rs274_corpus.json"
SIM_TBL = (
    "T1 P1 D0.125000 Z+0.511000 ;1/8 end mill\n"
    "T2 P2 D0.062500 Z+0.100000 ;1/16 end mill\n"
    "T3 P3 D0.201000 Z+1.273000 ;#7 tap drill\n"
)


def _number(r: random.Random, lo: float, hi: float) -> str:
    text = f"{r.uniform(lo, hi):.{r.choice((0, 1, 3, 4))}f}"
    style = r.random()
    if style < 0.1:
        text = text.lstrip("-").lstrip("0") or "0"  # ".5" / "0"
        text = ("-" if r.random() < 0.3 else "+" if r.random() < 0.2 else "") + text
    elif style < 0.15 and "." not in text:
        text += "."
    elif style < 0.2:
        text = "00" + text.lstrip("-") if not text.startswith("-") else text
    return text


def _plain(r: random.Random, x: float, y: float) -> str:
    words = []
    if r.random() < 0.15:
        words.append(f"N{r.randrange(1, 9999)}")
    if r.random() < 0.6:
        words.append(r.choice(["G1", "G01", "G0", "G00", "g1", "G1.0", "G0.", "G1.04"]))
    if r.random() < 0.85:
        words.append(f"X{x:.4f}" if r.random() < 0.8 else "X" + _number(r, -20, 20))
    if r.random() < 0.75:
        words.append(f"Y{y:.4f}" if r.random() < 0.8 else "Y" + _number(r, -20, 20))
    if r.random() < 0.2:
        words.append("Z" + _number(r, -2, 5))
    if r.random() < 0.1:
        words.append("F" + r.choice(["0", "300", "1500.5", ".5"]))
    if r.random() < 0.05:
        r.shuffle(words)  # another order: read word by word
    sep = r.choice(["", " ", " ", "  ", "\t"])
    line = sep.join(words)
    if r.random() < 0.05:
        line = line.lower() if r.random() < 0.5 else " " + line + " "
    return line


_STATE = [
    "G91", "G90", "G20", "G21", "G18", "G17", "G0 X0 Y0", "F600", "F1200", "G41.1 D0.2",
    "G42.1 D0.1", "G40", "G40", "G40 G1 X0 Y0", "G92 X1 Y2", "G92.1", "G54", "G55", "G10 L2 P2 X5 Y-3",
    "#1=2.5", "G1 X#1 Y[#1*2]", "M3 S1000", "G43 H1", "G49", "(MSG, plain lines follow)",
    "G2 X10 Y0 I5 J0", "G81 X1 Y1 Z-1 R1", "G61", "G1 Y1 ; comment", "/G1 X3 Y3", "G4 P0.5",
]  # fmt: skip
_RARE = [  # most stop the program (an error) or change much
    "F0", "G80", "G19", "G41 D1", "T1 M6", "G3 X0 Y0 R5", "G64 P0.1", "G1 X" + "9" * 400, "X-" + "1" * 330 + ".5",
    "G1 X1 Y2 X3", "G93", "G1 X1e3", "G1 X" + "9" * 300 + "Y1", "G95 F0.2", "G94 F600", "S0",
]  # fmt: skip


def _program(r: random.Random) -> str:
    lines = ["%", r.choice(["G21", "G20"]) + " G17 G90 G94 G40 G49 G80", f"F{r.choice(['300', '900'])}", "G0 X0 Y0"]
    x, y = 0.0, 0.0
    loop = 0
    for _ in range(r.randrange(30, 120)):
        k = r.random()
        if k < 0.7:
            x, y = x + r.uniform(-3, 3), y + r.uniform(-3, 3)
            lines.append(_plain(r, x, y))
        elif k < 0.93:
            lines.append(r.choice(_STATE))
        elif k < 0.95:
            lines.append(r.choice(_RARE))
        elif k < 0.975:
            loop += 1
            n = 100 + loop
            body = [_plain(r, r.uniform(-5, 5), r.uniform(-5, 5)) for _ in range(r.randrange(1, 4))]
            lines += [f"o{n} repeat [{r.randrange(0, 3)}]", *body, f"o{n} endrepeat"]
        else:
            loop += 1
            n = 100 + loop
            lines += [f"o{n} if [{r.randrange(0, 2)}]", _plain(r, 1, 1), f"o{n} endif"]
    lines += ["M2", "%"]
    return "\n".join(lines) + "\n"


@pytest.fixture(scope="module")
def programs() -> list[str]:
    corpus = [e["program"] for e in json.loads(CORPUS.read_text())["programs"]]
    r = random.Random(41)
    return corpus + [_program(r) for _ in range(300)]


def _read(text: str, folder: Path) -> NcProgram:
    return read_rs274(text, file=str(folder / "p.ngc"), tools=str(folder / "sim.tbl"), tool_unit="inch")


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("rs274")
    (path / "sim.tbl").write_text(SIM_TBL)
    (path / "rs274ngc.toml").write_text(SETTINGS)
    return path


def test_plain_motion_lines_give_what_the_general_reading_gives(
    programs: list[str], folder: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    ran = [0, 0]  # plain lines run fast / passed on to the general path
    fast_run = reader.execute_plain

    def counted(*args):  # type: ignore[no-untyped-def]
        done = fast_run(*args)
        ran[0 if done else 1] += 1
        return done

    monkeypatch.setattr(reader, "execute_plain", counted)
    fast = [_read(text, folder) for text in programs]
    monkeypatch.setattr(ngc_flow, "PLAIN_MOTION", lambda raw: None)
    general = [_read(text, folder) for text in programs]
    for text, a, b in zip(programs, fast, general, strict=True):
        assert a.moves == b.moves, text
        assert a.diagnostics == b.diagnostics, text
        assert a.blocks == b.blocks, text
    assert ran[0] > 5_000 and ran[1] > 50  # both outcomes of the fast path were compared
    assert sum(any(d.severity.value == "error" for d in p.diagnostics) for p in fast) > 50
    assert sum(len(p.moves) for p in fast) > 10_000


def test_common_contour_moves_compensate_as_the_general_dispatch(
    programs: list[str], folder: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    read = [_read(text, folder).moves for text in programs]

    def run(moves: tuple) -> tuple[list, list]:  # type: ignore[type-arg]
        diags: list = []  # type: ignore[type-arg]
        return list(compensate_linuxcnc(moves, None, diags)), diags

    fast = [run(m) for m in read]
    monkeypatch.setattr(compensation._LinuxCncCompensator, "_block", compensation._LinuxCncCompensator._any_block)
    general = [run(m) for m in read]
    assert fast == general
    assert sum(len(s) for s, _ in fast) > 10_000
    assert sum(any(s.side.value != "off" for s in segs) for segs, _ in fast) > 100  # compensated paths
    assert sum(bool(d) for _, d in fast) > 5  # and compensation errors


def test_programmed_segment_of_straight_moves_is_the_general_one(programs: list[str], folder: Path) -> None:
    moves = [m for text in programs for m in _read(text, folder).moves]
    moves += [dataclasses.replace(m, origin=origin) for m in moves[:2000] for origin in ("approach", "retract")]
    for tol in (1e-3, 0.5):
        for m in moves:
            assert engine.programmed_segment(m, tol) == engine._any_programmed_segment(m, tol)
    kinds = {(m.kind.value, m.plane.value) for m in moves}
    assert {("line", "G17"), ("rapid", "G17"), ("line", "G18"), ("arc", "G17")} <= kinds


def _program_unit_line_by_line(text: str) -> float:
    """:func:`~trcopt.controllers.linuxcnc.reader.program_unit` normalising every line."""
    for raw in text.splitlines():
        try:
            line = normalise(raw).text
        except NgcError:
            continue
        m = reader._UNIT_WORD.search(line)
        if m and not line.startswith("o"):
            return 25.4 if m.group(1) == "0" else 1.0
    return 1.0


def test_program_unit_skips_only_lines_without_a_unit_word() -> None:
    r = random.Random(5)
    parts = ["G", "g", "0", "2", "1", "20", "21", " ", "\t", "(", ")", ";", "X", "1.5", "o", "N1", "G1", "(c)"]
    texts = ["G1 X1\nG20\n", "g 0 2 0 x1", "G(c)20", "G 2 1;", "o100 G20\nG21", "G1 X2.21 G20", "G2(x)1"]
    for _ in range(20_000):
        texts.append("\n".join("".join(r.choice(parts) for _ in range(r.randrange(0, 8))) for _ in range(3)))
    units = [reader.program_unit(t) for t in texts]
    assert units == [_program_unit_line_by_line(t) for t in texts]
    assert 300 < units.count(25.4) and 300 < sum(u == 1.0 and "2" in t for u, t in zip(units, texts, strict=True))
