"""SINUMERIK ``CASE(expr) OF c GOTOF l … DEFAULT GOTOF l``, ``CALL "NAME"`` and ``PCALL path/NAME(args)``:
where they lead, and the located errors of bad input."""

from __future__ import annotations

from pathlib import Path

import pytest

from trcopt.controllers import read_program
from trcopt.errors import Severity
from trcopt.nc import MoveKind

TAIL = "L1: G0 X1\nL2: G0 X2\nL3: G0 X3\nM30\n"


def ends(text: str, file: str = "p.mpf") -> list[float]:
    prog = read_program(text, file=file)
    errs = [d.format() for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert errs == []
    return [m.end[0] for m in prog.moves if m.kind is not MoveKind.NONE]


def error_of(text: str, file: str = "p.mpf"):
    prog = read_program(text, file=file)
    errs = [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert len(errs) == 1, [d.format() for d in prog.diagnostics]
    return errs[0]


@pytest.mark.parametrize(
    ("r1", "expected"),
    [
        (1, [1.0, 2.0, 3.0]),  # first constant
        (2, [2.0, 3.0]),  # second constant
        (7, [3.0]),  # DEFAULT
    ],
)
def test_case_jumps_to_the_destination_of_the_equal_constant(r1, expected):
    assert ends(f"R1={r1}\nCASE(R1) OF 1 GOTOF L1 2 GOTOF L2 DEFAULT GOTOF L3\n" + TAIL) == expected


def test_case_without_an_equal_constant_and_without_default_runs_the_next_block():
    assert ends("R1=5\nCASE(R1*2) OF 1 GOTOF L2 2 GOTOF L3\nG0 X9\n" + TAIL) == [9.0, 1.0, 2.0, 3.0]


def test_case_evaluates_its_expression_and_jumps_back():
    text = "R1=0\nL0: R1=R1+1\nG0 X=R1*10\nCASE(R1+1) OF 2 GOTOB L0 3 GOTOB L0 DEFAULT GOTOF L3\n" + TAIL
    assert ends(text) == [10.0, 20.0, 30.0, 3.0]


def test_case_char_constant():
    assert ends("DEF CHAR CC=65\nCASE(CC) OF \"A\" GOTOF L2 DEFAULT GOTOF L3\n" + TAIL) == [2.0, 3.0]


@pytest.mark.parametrize(
    ("line", "code", "column", "words"),
    [
        ("CASE(R1) OF 1 GOTOF L1 2 GOTOF LX", "14080", 26, "LX not found"),  # the chosen label is missing
        ("CASE(R1) OF 1 GOTOF L1 2 GOTOF", "NC-SYNTAX", 24, "expected"),
        ("CASE(R1 OF 1 GOTOF L1", "NC-SYNTAX", 5, "unbalanced"),
        ("CASE(R1) 1 GOTOF L1", "NC-SYNTAX", 9, "OF"),
        ("CASE(R1) OF DEFAULT GOTOF L3 2 GOTOF L1", "NC-SYNTAX", 30, "DEFAULT must be the last"),
        ("CASE(R9) OF 1 GOTOF L1", "NC-PARAM-UNSET", 6, "R9"),
        ("CASE(1/0) OF 1 GOTOF L1", "NC-EXPRESSION", None, "division"),
    ],
)
def test_bad_case_is_a_located_error(line, code, column, words):
    err = error_of(f"R1=2\n{line}\n" + TAIL)
    assert str(err.code) == code and err.span.line == 2
    if column is not None:
        assert err.span.column == column
    assert words.lower() in err.message.lower()


@pytest.fixture()
def folder(tmp_path: Path) -> Path:
    (tmp_path / "SIDE.spf").write_text("G1 X=IC(20) F100\nM17\n")
    (tmp_path / "STEP.spf").write_text("PROC STEP(REAL _DX, REAL _DY)\nG1 X=IC(_DX) Y=IC(_DY) F100\nM17\n")
    return tmp_path


@pytest.mark.parametrize(
    "call",
    ['CALL "SIDE"', 'CALL "_N_SIDE_SPF"', "PCALL SIDE", "PCALL /_N_WKS_DIR/_N_PART_WPD/_N_SIDE_SPF"],
)
def test_call_and_pcall_run_the_subprogram(folder, call):
    main = folder / "main.mpf"
    assert ends(f"G0 X0 Y0\n{call}\nG0 X1\nM30\n", file=str(main)) == [0.0, 20.0, 1.0]


def test_pcall_passes_its_arguments(folder):
    main = folder / "main.mpf"
    prog = read_program("G0 X0 Y0\nPCALL /_N_WKS_DIR/_N_STEP_SPF(5, 7)\nM30\n", file=str(main))
    assert [m.end[:2] for m in prog.moves if m.kind is not MoveKind.NONE] == [(0.0, 0.0), (5.0, 7.0)]


@pytest.mark.parametrize(
    ("call", "code", "words"),
    [
        ('CALL "NOPE"', "14011", "program NOPE not found"),
        ("PCALL /_N_WKS_DIR/NOPE(1)", "14011", "program NOPE not found"),
        ("CALL _PROGNAME", "NC-UNSUPPORTED", "STRING"),
        ("CALL BLOCK A TO B", "NC-UNSUPPORTED", "CALL BLOCK"),
        ("PCALL", "NC-SYNTAX", "PCALL needs a program name"),
        ('PCALL "X"', "NC-SYNTAX", "not a program name"),
    ],
)
def test_bad_calls_are_located_errors(folder, call, code, words):
    err = error_of(f"G0 X0\n{call}\nM30\n", file=str(folder / "main.mpf"))
    assert (str(err.code), err.span.line) == (code, 2)
    assert words in err.message
    if code == "14011":
        assert str(folder) in err.message  # where it was looked for
