"""The SINUMERIK reader block by block (``controllers.stream_program``) gives the moves,
diagnostics, block count and extras of the whole-program read (``controllers.read_program``) —
on the problem suite, on generated programs with control flow, subprograms and errors — and does
not hold the program's statements or moves while it runs."""

from __future__ import annotations

import gc
import random
import sys
from pathlib import Path

import pytest

from trcopt import controllers
from trcopt.codes import Code
from trcopt.controllers.siemens import flow, lazyscan
from trcopt.errors import Severity
from trcopt.nc.ondemand import KEEP

ROOT = Path(__file__).resolve().parents[3]
sys.path.insert(0, str(ROOT / "benchmarks"))
from bench_read_scale import siemens_program  # noqa: E402

sys.path.insert(0, str(ROOT / "tests"))
from stream_equality import read_both_ways  # noqa: E402

PROBLEMS = sorted(p for p in (ROOT / "problems").rglob("*") if p.suffix.lower() in (".mpf", ".spf"))


def _same(source: str | Path, file: str | None = None) -> tuple[object, list[object]]:
    """Read both ways; assert they agree; the whole program and the streamed moves."""
    return read_both_ways(source, "siemens", file)


def test_the_siemens_controller_streams() -> None:
    assert controllers.get("siemens").stream is not None


@pytest.mark.parametrize("path", PROBLEMS, ids=lambda p: p.name)
def test_problem_programs_stream_as_read(path: Path) -> None:
    _same(path)


HEAD = (
    "DEF INT KK, SH=2\nDEF REAL DEPTH=-2\n$TC_DP1[1,1]=120 $TC_DP6[1,1]=2\nN10 G17 G90 T1 D1 G0 X-20 Y-20 Z5\n"
    "R1=0 R2=0 R3=0 R5=0 R6=0 R7=0\n"
)

FLOW = {
    "labels and jumps": HEAD + "R1=0\nN20 GOTOF CONT\nN30 G0 Z-50\nN40 CONT: G1 Z=DEPTH F500\n"
    "N50 G42 X0 Y0\nBACK: X10\nR1=R1+1\nIF R1<3 GOTOB BACK\nN60 GOTOF N80\nN70 X99\nN80 G40 X-20 Y-20\nM30\n",
    "structures": HEAD + "G1 F300 G41 X0 Y0\nFOR KK=1 TO 3\nG91 X5\nG90\nENDFOR\nIF KK>2\nY10\nELSE\nY20\nENDIF\n"
    "R2=3\nWHILE R2>0\nR2=R2-1\nX=R2*5\nENDWHILE\nREPEAT\nR3=R3+1\nUNTIL R3>=2\nLOOP\nIF R3>=4 GOTOF OUT\n"
    "R3=R3+1\nY=R3\nENDLOOP\nOUT: G40 X-20 Y-20\nM30\n",
    "sections": HEAD + "G1 F300 X0 Y0\nHOP: G91 X5\nG90\nREPEAT HOP P=3\nA1: Y5\nA2: Y6\nREPEAT A1 A2 P=2\n"
    "REPEATB A1 P=2\nX0\nENDLABEL: Y0\nREPEAT A2 P=2\nM30\n",
    "case": HEAD + "G1 F300 X0 Y0\nCASE(SH) OF 1 GOTOF S1 2 GOTOF S2 DEFAULT GOTOF S1\nS1: X50\n"
    "GOTOF CL\nS2: X30\nCL: Y40\nM30\n",
    "no end": HEAD + "G1 F300 X0 Y0\nX10\n\n; a comment\n",
    "syntax error after moves": HEAD + "G1 F300 X0 Y0\nX10\nX20 Y5\nX30 Y=(\nX40\nM30\n",
    "error in a loop": HEAD + "G1 F300 X0 Y0\nFOR KK=1 TO 5\nX=KK*3\nIF KK==4\nG2 X1 Y1 CR=0.1\nENDIF\nENDFOR\nM30\n",
    "nesting error": HEAD + "G1 F300 X0 Y0\nIF R1==0\nX10\nENDWHILE\nM30\n",
    "second else": HEAD + "IF R1==0\nX1\nELSE\nX2\nELSE\nX3\nENDIF\nM30\n",
    "open structure": HEAD + "G1 F300 X0 Y0\nWHILE R1==0\nX1\nM30\n",
    "missing label": HEAD + "G1 F300 X0 Y0\nX10\nGOTOF NOWHERE\nM30\n",
    "missing number": HEAD + "G1 F300 X0 Y0\nN100 X10\nGOTOB N200\nM30\n",
    "gotoc": HEAD + "G1 F300 X0 Y0\nGOTOC NOWHERE\nN15 X3\n:20 X4 R1=R1+1\nIF R1<3 GOTOB N0015\nGOTOF N20\nM30\n",
    "endless loop": HEAD + "G1 F300 X0 Y0\nAGAIN: X1\nX2\nGOTOB AGAIN\nM30\n",
    "ct": HEAD + "G1 F300 X0 Y0\nX10\nCT X20 Y5\nG1 X30\nM30\n",
    "cycle": HEAD + "G1 F300 X0 Y0\nMCALL CYCLE81(5, 0, 2, -12, )\nX10 Y10\nX20\nMCALL\nM30\n",
    "proc late": HEAD + "G1 F300 X0 Y0\nX1\nPROC LATE\nM30\n",
    "def late": HEAD + "G1 F300 X0 Y0\nDEF INT LATE\nM30\n",
    "labels in comments": HEAD + "G1 F300 X0 Y0 ; IF: WHILE FOR LOOP\nX5 ; ELSE: UNTIL\nM30\n",
    "range": HEAD + "G1 F300 X0 Y0\nX10\nMSG(\"A\")\nX1000000000\nMSG(\"B\")\nX5\nM30\n",
}


@pytest.mark.parametrize("name", FLOW)
def test_control_flow_and_errors_stream_as_read(name: str) -> None:
    _same(FLOW[name], "p.mpf")


@pytest.mark.parametrize("end", ["\r\n", "\r"])
@pytest.mark.parametrize("name", ["labels and jumps", "structures", "syntax error after moves"])
def test_other_line_ends_and_letters_stream_as_read(name: str, end: str) -> None:
    text = FLOW[name].replace("M30\n", "; Außenkontur fertig ÄÖÜ\nM30\n").replace("\n", end)
    _same(text, "p.mpf")


def test_a_syntax_error_mid_program_keeps_the_moves_before_it() -> None:
    whole, moves = _same(FLOW["syntax error after moves"], "p.mpf")
    assert len(moves) >= 3
    errors = [d for d in whole.diagnostics if d.severity is Severity.ERROR]  # type: ignore[attr-defined]
    assert errors and errors[0].span.line == 9


def test_subprograms_stream_as_read(tmp_path: Path) -> None:
    (tmp_path / "SIDE.SPF").write_text("PROC SIDE(REAL DY) SAVE\nG91 G1 Y=DY\nRET\n")
    (tmp_path / "L77.SPF").write_text("G1 X0 Y0\nX3\nM17\n")
    main = tmp_path / "main.mpf"
    main.write_text(HEAD + "G1 F300 G42 X0 Y0\nSIDE(5) P=2\nL77\nCALL \"SIDE\"\nSIDE(-3)\nG40 X-20 Y-20\nNOPE\nM30\n")
    whole, _ = _same(main)
    assert any(d.code == Code.NC_CALL or d.severity is Severity.ERROR for d in whole.diagnostics)  # type: ignore[attr-defined]


def _random_program(seed: int) -> str:
    """A program of lines, arcs and structures nested at random (some of them wrong)."""
    rnd = random.Random(seed)
    out = [HEAD, "G1 F400 X0 Y0\n"]
    depth: list[str] = []
    labels = 0
    for _ in range(rnd.randint(10, 80)):
        r = rnd.random()
        x, y = rnd.uniform(-30, 30), rnd.uniform(-30, 30)
        if r < 0.35:
            out.append(f"X{x:.3f} Y{y:.3f}\n")
        elif r < 0.42:
            out.append(f"G{rnd.choice((2, 3))} X{x:.3f} Y{y:.3f} CR={rnd.uniform(20, 60):.3f}\nG1\n")
        elif r < 0.48:
            out.append(rnd.choice(("G41 ", "G42 ", "G40 ")) + f"X{x:.3f} Y{y:.3f}\n")
        elif r < 0.55 and len(depth) < 4:
            kw = rnd.choice(("IF", "WHILE", "FOR", "REPEAT", "LOOP"))
            out.append({"IF": f"IF R1<{rnd.randint(0, 3)}\n", "WHILE": "R5=0\nWHILE R5<2\nR5=R5+1\n",
                        "FOR": "FOR KK=1 TO 2\n", "REPEAT": "R6=0\nREPEAT\nR6=R6+1\n",
                        "LOOP": "R7=0\nLOOP\nR7=R7+1\nIF R7>2 GOTOF OUT" + str(seed) + "_" + str(len(out)) + "\n"}[kw])
            depth.append(kw if kw != "LOOP" else "LOOP:OUT" + str(seed) + "_" + str(len(out) - 1))
        elif r < 0.65 and depth:
            kw = depth.pop()
            if kw == "IF" and rnd.random() < 0.3:
                out.append(f"ELSE\nX{x:.3f}\n")
            out.append({"IF": "ENDIF\n", "WHILE": "ENDWHILE\n", "FOR": "ENDFOR\n", "REPEAT": "UNTIL R6>=2\n"}.get(
                kw, "ENDLOOP\n" + kw.partition(":")[2] + ": X0\n"))
        elif r < 0.7:
            labels += 1
            out.append(f"L{seed}_{labels}: R1=R1+1 X{x:.3f}\n")
        elif r < 0.74 and labels:
            out.append(f"IF R1<3 GOTOB L{seed}_{rnd.randint(1, labels)}\n")
        elif r < 0.77 and labels:
            out.append(f"REPEAT L{seed}_{rnd.randint(1, labels)} P=2\n")
        elif r < 0.8:
            out.append(f"N{rnd.randint(1, 9) * 10} Y{y:.3f}\n")
        elif r < 0.83:
            out.append(f"GOTOF N{rnd.randint(1, 9) * 10}\n")
        elif r < 0.85:
            out.append(rnd.choice(("X10 Y=(\n", "G2 X5 Y5\n", "Q7=3\n", "T9 D1 G41 X1\n", "X=R99\n")))
        else:
            out.append(f"G91 X{x / 10:.3f}\nG90\n")
    while depth and rnd.random() < 0.9:
        kw = depth.pop()
        out.append({"IF": "ENDIF\n", "WHILE": "ENDWHILE\n", "FOR": "ENDFOR\n", "REPEAT": "UNTIL R6>=2\n"}.get(
            kw, "ENDLOOP\n" + kw.partition(":")[2] + ": X0\n"))
    if rnd.random() < 0.8:
        out.append("G40 X-20 Y-20\nM30\n")
    return "".join(out)


@pytest.mark.parametrize("seed", range(60))
def test_random_programs_stream_as_read(seed: int) -> None:
    _same(_random_program(seed), "p.mpf")


def test_a_generated_cam_program_streams_as_read() -> None:
    whole, moves = _same(siemens_program(3000), "cam.mpf")
    assert len(moves) > 2900 and not whole.diagnostics  # type: ignore[attr-defined]


def test_the_streamed_reader_does_not_hold_the_program(monkeypatch: pytest.MonkeyPatch) -> None:
    """The first move comes before the program's lines are scanned, and while it runs the reader
    holds a bounded number of statements (the whole-program scan holds one a line)."""
    n = 3 * KEEP
    text = siemens_program(n)
    made = [0]
    real = flow._statement

    def counting(*args: object) -> flow.Statement:
        made[0] += 1
        return real(*args)  # type: ignore[arg-type]

    monkeypatch.setattr(lazyscan, "_statement", counting)
    stream = controllers.stream_program(text, file="big.mpf", dialect="siemens")
    first = next(stream)
    assert first is not None and made[0] < n // 8  # of the n lines
    for _ in range(n // 2):
        next(stream)
    gc.collect()
    alive = sum(1 for o in gc.get_objects() if type(o) is flow.Statement)
    assert alive <= KEEP + 10, alive
    rest = sum(1 for _ in stream)
    assert rest > n // 3 and made[0] <= n + 10
    assert not stream.program.diagnostics


def test_a_long_subprogram_is_not_held_either(tmp_path: Path) -> None:
    n = 3 * KEEP
    (tmp_path / "CONTOUR.SPF").write_text(siemens_program(n).replace("M30", "M17"))
    main = tmp_path / "main.mpf"
    main.write_text("N10 G17 G90 G0 X0 Y0 Z5\nN20 CONTOUR\nN30 G0 Z50\nN40 M30\n")
    stream = controllers.stream_program(main, dialect="siemens")
    for _ in range(n // 2):
        next(stream)
    gc.collect()
    alive = sum(1 for o in gc.get_objects() if type(o) is flow.Statement)
    assert alive <= KEEP + 10, alive
    moves = sum(1 for _ in stream) + n // 2
    whole = controllers.read_program(main, dialect="siemens")
    assert moves == len(whole.moves) and stream.program.diagnostics == whole.diagnostics
