"""The Klartext reader block by block (``controllers.stream_program``) gives the moves,
diagnostics, block count and extras of the whole-program read (``controllers.read_program``) —
on the problem suite, on generated programs with labels, repeats, jumps, called programs, corners,
leads, "tool radius too large" anywhere in a region and errors — and does not hold the program's
blocks, elements or moves while it runs."""

from __future__ import annotations

import gc
import random
import sys
from pathlib import Path

import pytest

from trcopt import controllers
from trcopt.codes import Code
from trcopt.controllers.heidenhain import contour, flow, lexer
from trcopt.errors import Severity
from trcopt.nc.ondemand import KEEP

ROOT = Path(__file__).resolve().parents[3]
sys.path.insert(0, str(ROOT / "benchmarks"))
from bench_read_scale import heidenhain_program  # noqa: E402

sys.path.insert(0, str(ROOT / "tests"))
from stream_equality import read_both_ways  # noqa: E402

PROBLEMS = sorted(p for p in (ROOT / "problems").rglob("*") if p.suffix.lower() == ".h")


def _same(source: str | Path, file: str | None = None) -> tuple[object, list[object]]:
    """Read both ways; assert they agree; the whole program and the streamed moves."""
    return read_both_ways(source, "heidenhain", file)


def _numbered(*lines: str) -> str:
    return "".join(f"{i} {line}\n" for i, line in enumerate(lines))


def test_the_heidenhain_controller_streams() -> None:
    assert controllers.get("heidenhain").stream is not None


@pytest.mark.parametrize("path", PROBLEMS, ids=lambda p: p.name)
def test_problem_programs_stream_as_read(path: Path) -> None:
    _same(path)


HEAD = ("BEGIN PGM T MM", "TOOL DEF 5 L+50 R+20", "TOOL CALL 5 Z S3000", "L X-30 Y+0 R0 FMAX")
CASES = {
    # a small step the offsets run backwards over, then an arc whose offset radius is negative in
    # the same region: the arc is the answer (found first), the elements before it are kept
    "soft then hard": (*HEAD, "L X+0 Y+0 RR F200", "L X+50 Y+0", "L IY+0.5", "L IX+50", "L X+110 Y+0.5",
                       "CR X+120 Y-9.5 R+10 DR-", "L X+200 Y-9.5", "L X+220 Y-30 R0", "END PGM T MM"),
    "soft only": (*HEAD, "L X+0 Y+0 RR F200", "L X+50 Y+0", "L IY+0.5", "L IX+50", "L X+110 Y+0.5",
                  "L X+200 Y+0.5", "STOP M0", "L X+220 Y-30 R0", "L X+300 R0", "END PGM T MM"),
    "hard then syntax error": (*HEAD, "L X+0 Y+0 RR F200", "L X+50 Y+0", "CR X+60 Y-10 R+10 DR-", "L X+100",
                               "L X+120 Y-30 R0", "L X+0 Y+0 RL", "L Y+10 M90", "L X+5 Q", "END PGM T MM"),
    "two regions": (*HEAD, "L X+0 Y+0 RR F200", "L X+50 Y+0", "L X+60 Y-40 R0", "L X+0 Y-40 RL",
                    "L X+50 Y-40", "L IY+0.5", "L IX+50", "L X+100 Y-80 R0", "END PGM T MM"),
    "rnd chf": ("BEGIN PGM T MM", "TOOL DEF 1 L+50 R+2", "TOOL CALL 1 Z S3000", "L X+10 Y+60 R0 FMAX",
                "L X+10 Y+40 RL F300", "L X+40 Y+25", "RND R5 F100", "L X+10 Y+5", "CHF 3", "L X+40 Y-10",
                "L X+40 Y+0 M97", "L X+50 Y+0", "L X+60 Y-20 R0", "END PGM T MM"),
    "rnd too large": ("BEGIN PGM T MM", "TOOL DEF 1 L+50 R+2", "TOOL CALL 1 Z S3000", "L X+10 Y+60 R0 FMAX",
                      "L X+10 Y+40 RL F300", "L X+40 Y+25", "RND R500", "L X+10 Y+5", "END PGM T MM"),
    "rnd at the end": ("BEGIN PGM T MM", "TOOL DEF 1 L+50 R+2", "TOOL CALL 1 Z S3000", "L X+10 Y+60 R0 FMAX",
                       "L X+10 Y+40 RL F300", "L X+40 Y+25", "RND R5"),
    "appr dep": ("BEGIN PGM T MM", "TOOL DEF 1 L+50 R+2", "TOOL CALL 1 Z S3000", "L X-20 Y-20 Z+0 R0 FMAX",
                 "APPR LCT X+0 Y+0 R5 RL F800", "L Y+20", "CT X+20 Y+30", "L X+40", "DEP LCT X+60 Y+60 R5 F2000",
                 "APPR LT X+0 Y+0 LEN10 RR F500", "L X+30", "DEP LN LEN5", "L Z+50 R0 FMAX", "END PGM T MM"),
    "appr at the end": ("BEGIN PGM T MM", "TOOL DEF 1 L+50 R+2", "TOOL CALL 1 Z S3000", "L X-20 Y-20 R0 FMAX",
                        "APPR LCT X+0 Y+0 R5 RL F800"),
    "m120 and tolerance": ("BEGIN PGM T MM", "TOOL DEF 1 L+50 R+5", "TOOL CALL 1 Z S3000", "CYCL DEF 32.0 TOLERANCE",
                           "CYCL DEF 32.1 T0.02", "L X-10 Y+10 R0 FMAX", "L X+0 Y+0 RL F400 M120 LA3", "L X+20",
                           "L Y-20", "L X+26", "L Y+0", "L X+50", "L X+60 Y+10 R0", "CYCL DEF 32.1",
                           "L X+0 M90", "L Y+0", "END PGM T MM"),
    "labels and calls": ("BEGIN PGM T MM", "TOOL DEF 1 L+0 R+5", "TOOL CALL 1 Z S3000", "FN 0: Q1 = +0",
                         "L X-20 Y-10 Z+2 R0 FMAX", "LBL \"PASS\"", "FN 1: Q1 = +Q1 + +1", "L Z-Q1 F1000",
                         "CALL LBL 10", "FN 12: IF +Q1 LT +3 GOTO LBL \"PASS\"", "LBL 2", "L IX+10 F500",
                         "CALL LBL 2 REP 3", "L Z+50 R0 FMAX M30", "LBL 10", "L X+0 Y+0 RL F300", "L Y+20",
                         "CR X+40 Y+20 R+30 DR-", "L X+0", "L X-20 Y-10 R0", "LBL 0", "END PGM T MM"),
    "label twice": ("BEGIN PGM T MM", "TOOL DEF 1 L+0 R+5", "TOOL CALL 1 Z S3000", "L X+1 R0 FMAX", "LBL 3",
                    "L X+2", "LBL 3", "END PGM T MM"),
    "label missing": ("BEGIN PGM T MM", "TOOL DEF 1 L+0 R+5", "TOOL CALL 1 Z S3000", "L X+1 R0 FMAX",
                      "CALL LBL 7", "END PGM T MM"),
    "bad label": ("BEGIN PGM T MM", "L X+1 R0 FMAX", "lbl", "END PGM T MM"),
    "endless": ("BEGIN PGM T MM", "TOOL DEF 1 L+0 R+5", "TOOL CALL 1 Z S3000", "L X+0 Y+0 R0 F500", "LBL 1",
                "L IX+1", "FN 9: IF +0 EQU +0 GOTO LBL 1", "END PGM T MM"),
    "syntax error after moves": ("BEGIN PGM T MM", "TOOL DEF 1 L+50 R+2", "TOOL CALL 1 Z S3000",
                                 "L X+0 Y+0 R0 F500", "L X+10", "L X+20 Y+5", "L X+30 WHAT", "L X+40",
                                 "END PGM T MM"),
    "q error": ("BEGIN PGM T MM", "TOOL DEF 1 L+50 R+2", "TOOL CALL 1 Z S3000", "L X+0 Y+0 RL F500",
                "L X+10", "Q5 = Q3 / 0", "L X+30", "END PGM T MM"),
    "no end": ("BEGIN PGM T MM", "TOOL DEF 1 L+50 R+2", "TOOL CALL 1 Z S3000", "L X+0 Y+0 RL F500", "L X+10"),
    "lbl 0 without call": ("BEGIN PGM T MM", "L X+0 Y+0 R0 FMAX", "LBL 0", "L X+1", "END PGM T MM"),
    "range": ("BEGIN PGM T MM", "TOOL DEF 1 L+50 R+2", "TOOL CALL 1 Z S3000", "L X+0 Y+0 R0 F500", "L X+10",
              "L X+900000000", "STOP", "L X+5", "END PGM T MM"),
}


@pytest.mark.parametrize("name", CASES)
def test_programs_stream_as_read(name: str) -> None:
    _same(_numbered(*CASES[name]), "p.h")


@pytest.mark.parametrize("end", ["\r\n", "\r"])
@pytest.mark.parametrize("name", ["labels and calls", "soft then hard", "syntax error after moves"])
def test_other_line_ends_and_letters_stream_as_read(name: str, end: str) -> None:
    text = _numbered(*CASES[name]).replace("BEGIN PGM T MM\n", "BEGIN PGM T MM ; Außenkontur ÄÖÜ\n")
    _same(text.replace("\n", end), "p.h")


def test_a_cut_found_late_in_a_region_keeps_the_elements_before_it() -> None:
    whole, moves = _same(_numbered(*CASES["soft then hard"]), "p.h")
    errors = [d for d in whole.diagnostics if d.severity is Severity.ERROR]  # type: ignore[attr-defined]
    assert [d.code for d in errors] == [Code.HH_TOOL_RADIUS_TOO_LARGE] and errors[0].span.line == 10
    assert max(m.span.line for m in moves) == 9  # type: ignore[attr-defined]


def test_the_radius_error_replaces_a_later_syntax_error() -> None:
    whole, _ = _same(_numbered(*CASES["hard then syntax error"]), "p.h")
    errors = [d.code for d in whole.diagnostics if d.severity is Severity.ERROR]  # type: ignore[attr-defined]
    assert errors == [Code.HH_TOOL_RADIUS_TOO_LARGE]


def test_called_programs_stream_as_read(tmp_path: Path) -> None:
    (tmp_path / "part.h").write_text(_numbered("BEGIN PGM PART MM", "L X+0 Y+0 R0 F500", "L IX+10", "LBL 1",
                                               "L IY+5", "CALL LBL 1 REP 2", "END PGM PART MM"))
    main = tmp_path / "main.h"
    main.write_text(_numbered("BEGIN PGM MAIN MM", "TOOL DEF 1 L+50 R+2", "TOOL CALL 1 Z S3000",
                              "L X-10 Y-10 R0 FMAX", "CALL PGM part", "L X+0 Y+0 RL F300", "L X+20",
                              "CALL PGM part", "CALL PGM missing", "END PGM MAIN MM"))
    whole, moves = _same(main)
    assert len(moves) > 8 and any(d.code == Code.HH_PGM_MISSING for d in whole.diagnostics)  # type: ignore[attr-defined]


def _random_program(seed: int) -> str:
    """Blocks of most statements at random, mostly valid where they stand (compensation switched
    on and off in straight lines, RND/CHF and APPR followed by a contour element, DEP after one),
    now and then a wrong one; with a tool of 0.5 to 6 mm on random contours, the "tool radius too
    large" check cuts some."""
    rnd = random.Random(seed)
    lines = ["BEGIN PGM R MM", f"TOOL DEF 1 L+50 R+{rnd.choice((0.5, 2.0, 6.0)):g}", "TOOL CALL 1 Z S3000",
             "Q1 = 5", "Q2 = -3", "L X+0 Y+0 Z+0 R0 F500"]
    side, labels, x, y = "R0", 0, 0.0, 0.0
    for _ in range(rnd.randint(10, 90)):
        nx, ny = x + rnd.uniform(-30, 30), y + rnd.uniform(-30, 30)
        r = rnd.random()
        block = f"L X{nx:+.3f} Y{ny:+.3f}"
        if r < 0.04:
            labels += 1
            lines.append(f"LBL {labels}")
            continue
        if r < 0.07 and labels:
            lines.append(f"CALL LBL {rnd.randint(1, labels)} REP {rnd.randint(1, 2)}")
            continue
        if r < 0.1:
            lines.append(rnd.choice(("L X+1 WHAT", "CR X+0 R+1 DR+", "L X+Q9", "RND", "CT X+0 Y+0", "FN 99: Q1 = 2")))
            continue
        if r < 0.14:
            lines.append(rnd.choice(("STOP M0", "Q3 = Q1 * 2", "L Z+Q2", "CC X+0 Y+0", "CYCL DEF 32.1 T0.05",
                                     "L IZ+1 M90")))
            continue
        if side == "R0":
            if r < 0.35:
                side = rnd.choice(("RL", "RR"))
                lines.append(f"{block} {side}")
            elif r < 0.42:
                side = rnd.choice(("RL", "RR"))
                lines.append(f"APPR LT {block[2:]} LEN{rnd.uniform(2, 8):.2f} {side} F300")
                x, y = nx, ny
                nx, ny = x + rnd.uniform(-30, 30), y + rnd.uniform(-30, 30)
                lines.append(f"L X{nx:+.3f} Y{ny:+.3f}")
            else:
                lines.append(block + (" FMAX" if rnd.random() < 0.3 else ""))
        elif r < 0.45:
            lines.append(block + (" M97" if rnd.random() < 0.1 else ""))
        elif r < 0.55:
            chord = ((nx - x) ** 2 + (ny - y) ** 2) ** 0.5
            lines.append(f"CR X{nx:+.3f} Y{ny:+.3f} R+{chord * rnd.uniform(0.55, 3):.3f} DR{rnd.choice('+-')}")
        elif r < 0.6:
            lines.append(f"CT X{nx:+.3f} Y{ny:+.3f}")
        elif r < 0.7:
            lines.append(rnd.choice((f"RND R{rnd.uniform(0.5, 4):.2f}", f"CHF {rnd.uniform(0.5, 3):.2f}")))
            lines.append(block)
        elif r < 0.78:
            side = "R0"
            lines.append(f"{block} R0")
        elif r < 0.83:
            side = "R0"
            lines.append(f"DEP LT LEN{rnd.uniform(2, 8):.2f}")
            lines.append(f"L X{x:+.3f} Y{y + 20:+.3f} R0 FMAX")
            ny = y + 20
            nx = x
        elif r < 0.86:
            lines.append(f"{block} M120 LA2")
        else:
            lines.append(block)
        x, y = nx, ny
    lines += ["L X+80 Y+80 R0", "END PGM R MM"]
    return _numbered(*lines)


@pytest.mark.parametrize("seed", range(100))
def test_random_programs_stream_as_read(seed: int) -> None:
    _same(_random_program(seed), "p.h")


def test_a_generated_cam_program_streams_as_read() -> None:
    whole, moves = _same(heidenhain_program(3000), "cam.h")
    assert len(moves) > 2900 and not whole.diagnostics  # type: ignore[attr-defined]


def test_the_streamed_reader_does_not_hold_the_program(monkeypatch: pytest.MonkeyPatch) -> None:
    """The first move comes before the program's lines are lexed, and while it runs the reader
    holds a bounded number of blocks and elements (the whole-program read holds them all)."""
    n = 3 * KEEP
    text = heidenhain_program(n)
    lexed = [0]
    real = lexer.lex_block

    def counting(*args: object, **kw: object) -> lexer.Block:
        lexed[0] += 1
        return real(*args, **kw)  # type: ignore[arg-type]

    monkeypatch.setattr(flow, "lex_block", counting)
    stream = controllers.stream_program(text, file="big.h", dialect="heidenhain")
    first = next(stream)
    assert first is not None and lexed[0] < n // 8  # of the n lines
    for _ in range(n // 2):
        next(stream)
    gc.collect()
    blocks = sum(1 for o in gc.get_objects() if type(o) is lexer.Block)
    elems = sum(1 for o in gc.get_objects() if type(o) is contour.Elem)
    assert blocks <= KEEP + 10 and elems < 20, (blocks, elems)
    rest = sum(1 for _ in stream)
    assert rest > n // 3 and lexed[0] <= 2 * n + 10
    assert not stream.program.diagnostics
