"""Word lexer (exact columns, word forms, syntax errors) and dialect detection."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from trcopt.controllers import detect, read_program
from trcopt.controllers.siemens.lexer import Expr, LexError, lex_line
from trcopt.errors import Severity


def names(line):
    return [(w.name, w.value, w.column) for w in lex_line(line).words]


def test_adjacent_words_and_columns():
    assert names("G1X10Y-20.5 F.5") == [
        ("G", 1.0, 1), ("X", 10.0, 3), ("Y", -20.5, 6), ("F", 0.5, 13)
    ]  # fmt: skip


def test_block_number_skip_comment():
    b = lex_line("/N0060 G0 X1 ; go (fast)")
    assert b.skip and b.number == "N60" and b.first_column == 8
    assert b.comment == " go (fast)"
    assert [w.text for w in b.words] == ["G0", "X1"]
    empty = lex_line("   ; only a comment")
    assert empty.words == [] and empty.comment == " only a comment"
    assert lex_line(":10 X1").number == "N10"


def test_assignment_forms():
    b = lex_line("Z=0 X=AC(10) I=ic(-2.5) CR=-20 DISCL=AC(5) FAD=PM(200) X1=3*(2+1)")
    assert [(w.name, w.value, w.assigned) for w in b.words] == [
        ("Z", 0.0, True), ("X", ("AC", 10.0), True), ("I", ("IC", -2.5), True),
        ("CR", -20.0, True), ("DISCL", ("AC", 5.0), True), ("FAD", ("PM", 200.0), True),
        ("X1", 9.0, True),
    ]  # fmt: skip


def test_fad_with_space_and_keywords_with_digits():
    b = lex_line("FAD 500 CDOF2 CUT2D CUT2DF norm TCOFRZ")
    assert [(w.name, w.value) for w in b.words] == [
        ("FAD", 500.0), ("CDOF2", None), ("CUT2D", None), ("CUT2DF", None), ("NORM", None),
        ("TCOFRZ", None),
    ]  # fmt: skip
    assert b.words[0].text == "FAD 500"


def test_system_variables_and_calls():
    b = lex_line('$TC_DP6[1, 2]=10 $TC_CARR23[1]="T" MSG("a; (b)") TCARR=1')
    w0, w1, w2, w3 = b.words
    assert (w0.name, w0.subscript, w0.value, w0.column) == ("$TC_DP6", "1, 2", 10.0, 1)
    assert (w1.name, w1.subscript, w1.value) == ("$TC_CARR23", "1", "T")
    assert (w2.name, w2.subscript, w2.column) == ("MSG", '"a; (b)"', 36)
    assert (w3.name, w3.value) == ("TCARR", 1.0)


def test_expressions_with_variables_are_kept_as_text():
    (w,) = lex_line("X=R1+5").words
    assert isinstance(w.value, Expr) and w.value == "R1+5"


def test_label():
    b = lex_line("N5 LOOP1: G1 X2")
    assert b.label == "LOOP1" and b.number == "N5" and b.words[0].column == 11


@pytest.mark.parametrize(
    ("line", "column", "fragment"),
    [
        ("G1 X1.2.3", 4, "1.2.3"),
        ("G1 X=AC(5", 4, "unbalanced"),
        ("G1 X=AC(5))", 11, "unbalanced"),
        ("G1 X5 ?", 7, "unexpected character"),
        ("$TC_DP6 X1", 1, "assignment"),
        ("$TC_DP6[1,1 = 3", 1, "unbalanced"),
        ("G1 X=", 4, "without a value"),
        ('MSG("abc"', 1, "unbalanced"),
        ("G1 12", 4, "without an address"),
        ("G1 X5 100", 7, "without an address"),
        ('MSG("x) Y1', 1, "unbalanced"),
    ],
)
def test_syntax_errors_name_the_column(line, column, fragment):
    with pytest.raises(LexError) as info:
        lex_line(line)
    assert info.value.column == column
    assert fragment in info.value.message


def test_lex_error_carries_block_number():
    with pytest.raises(LexError) as info:
        lex_line("N70 G1 X1..")
    assert info.value.block == "N70" and info.value.column == 8


# ---------------------------------------------------------------- dialect detection
@pytest.mark.parametrize(
    ("text", "filename", "dialect"),
    [
        ("G1 X1", "part.mpf", "siemens"),
        ("G1 X1", "SUB.SPF", "siemens"),
        ("G1 X1", "part.MPF", "siemens"),
        ("0 BEGIN PGM P1 MM\n1 L X0 R0 FMAX", None, "heidenhain"),
        ("L X0", "p.h", "heidenhain"),
        ("G1 X1 (cut)\nM2", None, "rs274"),
        ("G1 X1", "a.ngc", "rs274"),
        ("(header)\nG0 X0", "prog.txt", "rs274"),
        ('G1 X=AC(5) MSG("x (y)") ; note (z)', None, "siemens"),
        ("G1 X1", None, "siemens"),
        ("G1 X1 (cut)", "p.mpf", "siemens"),
    ],
)
def test_detect_dialect(text, filename, dialect):
    assert detect(filename, text).dialect == dialect


# ---------------------------------------------------------------- robustness
nc_tokens = list("GXYZIJKFNMTDR0123456789.-+= ;()$[],\"/\n") + [
    "AC(", "CR=", "G2 ", "G3 ", "G41 ", "G18 ", "$TC_DP6[1,1]=", "T1 D1 ", "M30", "G147 ", "DISR="
]  # fmt: skip
nc_text = st.lists(st.sampled_from(nc_tokens), max_size=40).map("".join)


@settings(max_examples=300, deadline=None)
@given(nc_text)
def test_read_program_never_raises(text):
    prog = read_program(text, file="fuzz.mpf")
    errors = [d for d in prog.diagnostics if d.severity is Severity.ERROR]
    assert len(errors) <= 1
    for d in prog.diagnostics:
        assert d.span.file == "fuzz.mpf" and d.span.line >= 1 and d.span.column >= 1
    assert all(m.span.line >= 1 for m in prog.moves)
